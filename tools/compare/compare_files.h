// Files that carry data between compare_methods and the method processes it starts:
// the input points (raw little-endian doubles with a small header) and each method's
// mesh (binary PLY, double vertices plus the source input index per vertex, so
// nothing is rounded on the way back). Written to a temp file, then renamed.
// PCL-free: the Open3D runner links it too.
#pragma once

#include "compare_mesh.h"

#include <pcl_vts/core/status.h>

#include <string>

namespace pcl_vts {
namespace compare {

/// Writes points (local xyz and offset) to path, atomically.
Status writePointSet(const std::string& path, const PointSet& points);
/// Reads a file written by writePointSet; IO_ERROR names the path and the reason.
Status readPointSet(const std::string& path, PointSet& points);

/// Binary little-endian PLY: vertex (double x, y, z, int source), face (uchar count,
/// uint ids). source is written as -1 where mesh.source is empty.
Status writeMeshPly(const std::string& path, const CompareMesh& mesh);
/// Reads exactly the layout writeMeshPly writes; IO_ERROR otherwise.
Status readMeshPly(const std::string& path, CompareMesh& mesh);

/// Writes text to path atomically (temp file in the same folder, then rename).
Status writeTextFile(const std::string& path, const std::string& text);

} // namespace compare
} // namespace pcl_vts
