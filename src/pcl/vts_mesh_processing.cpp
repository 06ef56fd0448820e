// pcl::VTSMeshProcessing and the PolygonMesh <-> array conversion. No geometry here
// beyond the exact orientation of each input triangle (STYLE.md 2.2).
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/vts_mesh_processing.h>

#include <pcl/PCLPointField.h>
#include <pcl/console/print.h>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

namespace pcl {

void VTSMeshProcessing::process(pcl::PolygonMesh& output)
{
  output.polygons.clear();
  if (!input_mesh_) {
    last_status_ = pcl_vts::Status::error(pcl_vts::StatusCode::EMPTY_INPUT,
                                          "no input mesh: call setInputMesh() first");
    PCL_ERROR("[pcl::%s::process] %s\n", getClassName().c_str(),
              last_status_.toString().c_str());
    return;
  }
  const pcl::PolygonMesh::ConstPtr input = input_mesh_; // output may alias it
  pcl_vts::TriangleMesh mesh;
  last_status_ = vts_detail::polygonMeshToArrays(*input, mesh);
  if (last_status_.ok()) {
    if (&output != input.get()) {
      output.header = input->header;
      output.cloud = input->cloud;
    }
    output.polygons.clear();
    last_status_ = performProcessing(mesh, output);
  }
  if (!last_status_.ok()) {
    output.polygons.clear();
    PCL_ERROR("[pcl::%s::process] %s\n", getClassName().c_str(),
              last_status_.toString().c_str());
  }
}

namespace vts_detail {

namespace {

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& cloud, const char* name)
{
  for (const pcl::PCLPointField& field : cloud.fields)
    if (field.name == name && field.count >= 1 &&
        (field.datatype == pcl::PCLPointField::FLOAT32 ||
         field.datatype == pcl::PCLPointField::FLOAT64))
      return &field;
  return nullptr;
}

double readValue(const std::uint8_t* record, const pcl::PCLPointField& field)
{
  if (field.datatype == pcl::PCLPointField::FLOAT32) {
    float v;
    std::memcpy(&v, record + field.offset, sizeof(v));
    return static_cast<double>(v);
  }
  double v;
  std::memcpy(&v, record + field.offset, sizeof(v));
  return v;
}

void writeValue(std::uint8_t* record, const pcl::PCLPointField& field, double value)
{
  if (field.datatype == pcl::PCLPointField::FLOAT32) {
    const auto v = static_cast<float>(value);
    std::memcpy(record + field.offset, &v, sizeof(v));
  } else {
    std::memcpy(record + field.offset, &value, sizeof(value));
  }
}

} // namespace

pcl_vts::Status polygonMeshToArrays(const pcl::PolygonMesh& input,
                                    pcl_vts::TriangleMesh& mesh,
                                    std::size_t* reoriented)
{
  using pcl_vts::Status;
  using pcl_vts::StatusCode;
  mesh = pcl_vts::TriangleMesh{};
  const pcl::PCLPointCloud2& cloud = input.cloud;
  const pcl::PCLPointField* fx = findField(cloud, "x");
  const pcl::PCLPointField* fy = findField(cloud, "y");
  const pcl::PCLPointField* fz = findField(cloud, "z");
  if (!fx || !fy || !fz)
    return Status::error(StatusCode::EMPTY_INPUT,
                         "the mesh cloud has no float x, y and z fields");
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (cloud.data.size() < n * cloud.point_step)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "the mesh cloud holds " + std::to_string(cloud.data.size()) +
                             " bytes, fewer than width * height * point_step");
  mesh.xy.resize(n);
  mesh.z.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* record = cloud.data.data() + i * cloud.point_step;
    mesh.xy[i] = {readValue(record, *fx), readValue(record, *fy)};
    mesh.z[i] = readValue(record, *fz);
  }
  std::size_t flipped = 0;
  mesh.triangles.reserve(3 * input.polygons.size());
  for (std::size_t p = 0; p < input.polygons.size(); ++p) {
    const auto& ids = input.polygons[p].vertices;
    if (ids.size() != 3)
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "polygon " + std::to_string(p) + " has " +
                               std::to_string(ids.size()) + " vertices, not 3");
    for (const auto id : ids)
      if (id < 0 || static_cast<std::size_t>(id) >= n ||
          !std::isfinite(mesh.xy[static_cast<std::size_t>(id)].x) ||
          !std::isfinite(mesh.xy[static_cast<std::size_t>(id)].y))
        return Status::error(StatusCode::INVALID_PARAMETER,
                             "polygon " + std::to_string(p) + " uses point " +
                                 std::to_string(id) + ", not a finite point of the " +
                                 std::to_string(n) + "-point cloud");
    auto a = static_cast<pcl_vts::VertexId>(ids[0]);
    auto b = static_cast<pcl_vts::VertexId>(ids[1]);
    auto c = static_cast<pcl_vts::VertexId>(ids[2]);
    const pcl_vts::Sign s = pcl_vts::orient2d(mesh.xy[a], mesh.xy[b], mesh.xy[c]);
    if (s == pcl_vts::Sign::ZERO)
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "polygon " + std::to_string(p) +
                               " has zero area in XY: not a 2.5D surface mesh");
    if (s == pcl_vts::Sign::NEGATIVE) {
      std::swap(b, c);
      ++flipped;
    }
    mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
  }
  if (reoriented)
    *reoriented = flipped;
  if (!mesh.rebuildHalfedges())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "the mesh is not edge-manifold (an edge has more than two "
                         "triangles, or two triangles overlap)");
  return Status::success();
}

void arraysToPolygons(const pcl_vts::TriangleMesh& mesh,
                      std::vector<pcl::Vertices>& polygons)
{
  polygons.resize(mesh.triangleCount());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
    polygons[t].vertices = {static_cast<pcl::index_t>(mesh.triangles[3 * t]),
                            static_cast<pcl::index_t>(mesh.triangles[3 * t + 1]),
                            static_cast<pcl::index_t>(mesh.triangles[3 * t + 2])};
}

void appendVertices(const pcl_vts::TriangleMesh& mesh, std::size_t first,
                    pcl::PCLPointCloud2& cloud)
{
  const pcl::PCLPointField* fx = findField(cloud, "x");
  const pcl::PCLPointField* fy = findField(cloud, "y");
  const pcl::PCLPointField* fz = findField(cloud, "z");
  if (!fx || !fy || !fz || first >= mesh.vertexCount())
    return;
  const std::size_t old_count = static_cast<std::size_t>(cloud.width) * cloud.height;
  const std::size_t added = mesh.vertexCount() - first;
  cloud.data.resize((old_count + added) * cloud.point_step, 0);
  for (std::size_t k = 0; k < added; ++k) {
    std::uint8_t* record = cloud.data.data() + (old_count + k) * cloud.point_step;
    writeValue(record, *fx, mesh.xy[first + k].x);
    writeValue(record, *fy, mesh.xy[first + k].y);
    writeValue(record, *fz, mesh.z[first + k]);
  }
  cloud.width = static_cast<std::uint32_t>(old_count + added);
  cloud.height = 1;
  cloud.row_step = cloud.width * cloud.point_step;
}

bool xyIsFloat(const pcl::PCLPointCloud2& cloud)
{
  const pcl::PCLPointField* fx = findField(cloud, "x");
  const pcl::PCLPointField* fy = findField(cloud, "y");
  return (fx && fx->datatype == pcl::PCLPointField::FLOAT32) ||
         (fy && fy->datatype == pcl::PCLPointField::FLOAT32);
}

} // namespace vts_detail
} // namespace pcl
