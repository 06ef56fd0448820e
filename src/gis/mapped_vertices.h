// The vertices of a streamed mesh in a temporary file, mapped read-only: the
// out-of-core DEM and contours look triangle corners up by id without holding the
// vertices (pages already read are dropped as the triangles pass).
#pragma once

#include <pcl_vts/core/mapped_file.h>
#include <pcl_vts/gis/mesh_stream.h>

#include <cstdint>
#include <string>

namespace pcl_vts {

class MappedVertices {
 public:
  MappedVertices() = default;
  MappedVertices(const MappedVertices&) = delete;
  MappedVertices& operator=(const MappedVertices&) = delete;
  ~MappedVertices() { release(); }

  /// Writes the vertices of mesh to `path` (x, y, z doubles, 24 B each) and maps
  /// them; no vertex maps nothing (count() 0). IO_ERROR messages start with `what`.
  Status map(const MeshStream& mesh, const std::string& path, const std::string& what);
  std::uint64_t count() const { return count_; }
  /// x, y, z of vertex v < count().
  const double* xyz(VertexId v) const
  {
    return reinterpret_cast<const double*>(file_.data()) + 3 * std::uint64_t{v};
  }
  /// Drops the pages read so far (read back from the file when needed again).
  void dropPages() const { file_.dropPages(); }
  /// Unmaps and removes the file.
  void release();

 private:
  std::string path_;
  MappedFile file_;
  std::uint64_t count_ = 0;
};

} // namespace pcl_vts
