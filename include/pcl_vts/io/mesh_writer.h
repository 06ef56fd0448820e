// Writes a TriangleMesh to .ply, .obj or .vtk without losing a bit of the vertex
// coordinates: binary PLY uses double properties whenever float would round, text
// formats print the shortest decimal that reads back to the same double (never
// PCL's 5 significant digits). Atomic: a temp file in the target folder, then rename.
// PCL-free (std + POSIX).
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

enum class MeshFileFormat { PLY, OBJ, VTK };

/// "PLY", "OBJ", "VTK".
PCL_VTS_IO_EXPORT const char* meshFileFormatName(MeshFileFormat format);

/// Format from the path's extension, case-insensitive: .ply, .obj, .vtk.
/// \return INVALID_PARAMETER naming the path for any other extension (or none).
PCL_VTS_IO_EXPORT Status meshFileFormatFromPath(const std::string& path,
                                                MeshFileFormat& format);

struct MeshWriteOptions {
  /// PLY only: ASCII instead of binary little-endian (.obj and .vtk are always text).
  bool ascii = false;
  /// PLY and VTK: declare double vertex coordinates even when float is exact.
  bool force_double = false;
  /// One line written as a comment in the file header (PLY, OBJ, VTK title).
  std::string comment = "pcl_vts";
  /// Optional per-vertex 0/1 marks (one per vertex), written as a `uchar inserted`
  /// vertex property (PLY) or point scalars named "inserted" (VTK); OBJ has no
  /// per-vertex field and writes only their count in a comment.
  const std::vector<std::uint8_t>* inserted = nullptr;
};

/// What writeMesh did, for the caller's summary.
struct MeshWriteInfo {
  MeshFileFormat format = MeshFileFormat::PLY;
  bool ascii = false;           ///< text output (always for OBJ and VTK)
  bool double_vertices = false; ///< vertex coordinates declared as double
  std::uint64_t bytes = 0;      ///< size of the file written
};

/// True when every x, y and z of the mesh converts to float and back unchanged.
PCL_VTS_IO_EXPORT bool verticesExactInFloat(const TriangleMesh& mesh);

/// A mesh read in order, one element at a time: the writer's view of a mesh that is
/// never held whole (the tiled path streams it back from temporary files). Both
/// visits may be called more than once (VTK writes the inserted flags last).
class PCL_VTS_IO_EXPORT MeshSource {
 public:
  using VertexVisit = std::function<void(double x, double y, double z, bool inserted)>;
  using TriangleVisit = std::function<void(VertexId a, VertexId b, VertexId c)>;
  virtual ~MeshSource() = default;
  virtual std::uint64_t vertexCount() const = 0;
  virtual std::uint64_t triangleCount() const = 0;
  /// True when every x, y and z converts to float and back unchanged.
  virtual bool exactInFloat() const = 0;
  /// True when vertices carry an "inserted" mark (hole filling).
  virtual bool hasInsertedFlags() const = 0;
  /// Visits every vertex in order; a failure (e.g. a temporary file that cannot be
  /// read back) is returned and stops the write.
  virtual Status forEachVertex(const VertexVisit& visit) const = 0;
  /// Visits every triangle in order (CCW vertex ids).
  virtual Status forEachTriangle(const TriangleVisit& visit) const = 0;
};

/// Writes a streamed mesh with the same bytes writeMesh(TriangleMesh) gives for the
/// same vertices and triangles; same atomicity and errors. Triangle ids are checked
/// against vertexCount() as they stream: a bad one fails the write (nothing appears).
PCL_VTS_IO_EXPORT Status writeMesh(const std::string& path, const MeshSource& mesh,
                                   const MeshWriteOptions& options,
                                   MeshWriteInfo* info = nullptr);

/// Writes mesh.xy/z as vertices and mesh.triangles (CCW, 3 per triangle) as faces.
/// The file appears complete or not at all: the data goes to ".<name>.tmp.<pid>" in
/// the same folder, is flushed and synced, then renamed over path; on any failure
/// the temp file is removed.
/// \return INVALID_PARAMETER for an unknown extension or an inconsistent mesh
///         (index out of range, xy/z sizes differ, > 2^31-1 vertices);
///         IO_ERROR naming the path and the system's reason when writing fails.
PCL_VTS_IO_EXPORT Status writeMesh(const std::string& path, const TriangleMesh& mesh,
                                   const MeshWriteOptions& options,
                                   MeshWriteInfo* info = nullptr);

} // namespace pcl_vts
