// Template bodies of pcl::VTSGridTriangulation (declared in vts_grid_triangulation.h).
// Thin by design: select points, copy to doubles, run the core, map ids back. No
// geometric decision is made here (STYLE.md 2.2).
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/export.h>
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/PCLPointField.h>
#include <pcl/console/print.h>
#include <pcl/types.h>

#include <cstddef>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

template <typename PointInT>
void pcl::VTSGridTriangulation<PointInT>::reconstruct(pcl::PolygonMesh& output)
{
  if (!checkInput()) {
    output.cloud.width = output.cloud.height = 0;
    output.cloud.data.clear();
    output.polygons.clear();
    return;
  }
  SurfaceReconstruction<PointInT>::reconstruct(output);
}

template <typename PointInT>
void pcl::VTSGridTriangulation<PointInT>::reconstruct(
    PointCloudIn& points, std::vector<pcl::Vertices>& polygons)
{
  if (!checkInput()) {
    points.clear();
    polygons.clear();
    return;
  }
  SurfaceReconstruction<PointInT>::reconstruct(points, polygons);
}

template <typename PointInT>
bool pcl::VTSGridTriangulation<PointInT>::checkInput()
{
  // SurfaceReconstruction::reconstruct reads input_->header before initCompute()
  // checks input_, so a missing cloud must be caught here.
  if (input_)
    return true;
  diagnostics_ = pcl_vts::Diagnostics{};
  fail(pcl_vts::Status::error(pcl_vts::StatusCode::EMPTY_INPUT,
                              "no input cloud: call setInputCloud() first"),
       "reconstruct");
  return false;
}

template <typename PointInT>
void pcl::VTSGridTriangulation<PointInT>::performReconstruction(
    pcl::PolygonMesh& output)
{
  // The base class has already copied the whole input_ into output.cloud.
  pcl_vts::VtsResult result;
  if (!triangulate(output.polygons, result))
    return;
  const pcl::PCLPointField* z_field = nullptr;
  for (const pcl::PCLPointField& field : output.cloud.fields)
    if (field.name == "z")
      z_field = &field;
  // Every PCL xyz point type has a float z, so this guard never fires in practice.
  if (!z_field || z_field->datatype != pcl::PCLPointField::FLOAT32)
    return;
  unsigned char* data = output.cloud.data.data();
  const std::size_t point_step = output.cloud.point_step;
  forEachChangedZ(result, [&](std::size_t id, float z) {
    std::memcpy(data + id * point_step + z_field->offset, &z, sizeof(float));
  });
}

template <typename PointInT>
void pcl::VTSGridTriangulation<PointInT>::performReconstruction(
    PointCloudIn& points, std::vector<pcl::Vertices>& polygons)
{
  points = *input_;
  pcl_vts::VtsResult result;
  if (!triangulate(polygons, result))
    return;
  forEachChangedZ(result, [&](std::size_t id, float z) { points[id].z = z; });
}

template <typename PointInT>
bool pcl::VTSGridTriangulation<PointInT>::triangulate(
    std::vector<pcl::Vertices>& polygons, pcl_vts::VtsResult& result)
{
  polygons.clear();
  diagnostics_ = pcl_vts::Diagnostics{};

  pcl_vts::VtsOptions options;
  options.cell_size = cell_size_;
  options.duplicate_rule = duplicate_rule_;
  options.threads = threads_;
  pcl_vts::Status status = pcl_vts::validateOptions(options);
  if (!status.ok()) {
    fail(std::move(status));
    return false;
  }

  // float -> double is exact and the core is translation-exact: no offset here.
  const pcl::Indices& indices = *indices_;
  const std::size_t cloud_size = input_->size();
  std::vector<double> xyz(3 * indices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const pcl::index_t id = indices[i];
    if (id < 0 || static_cast<std::size_t>(id) >= cloud_size) {
      fail(pcl_vts::Status::error(pcl_vts::StatusCode::INVALID_PARAMETER,
                                  "indices[" + std::to_string(i) +
                                      "] = " + std::to_string(id) +
                                      " is outside the input cloud of " +
                                      std::to_string(cloud_size) + " points"));
      return false;
    }
    const PointInT& p = (*input_)[static_cast<std::size_t>(id)];
    xyz[3 * i] = p.x;
    xyz[3 * i + 1] = p.y;
    xyz[3 * i + 2] = p.z;
  }

  // Handed over: the core frees it before it returns, not after the polygons below.
  status = pcl_vts::runVtsPipeline(std::move(xyz), options, result);
  diagnostics_ = result.diagnostics;
  if (!status.ok()) {
    fail(std::move(status));
    return false;
  }

  // Mesh vertex -> position in indices -> id in input_.
  const std::vector<pcl_vts::VertexId>& triangles = result.mesh.triangles;
  polygons.resize(triangles.size() / 3);
  for (std::size_t t = 0; t < polygons.size(); ++t) {
    pcl::Indices& ids = polygons[t].vertices;
    ids.resize(3);
    for (std::size_t k = 0; k < 3; ++k)
      ids[k] = indices[result.source_index[triangles[3 * t + k]]];
  }
  last_status_ = pcl_vts::Status::success();
  return true;
}

template <typename PointInT>
template <typename Apply>
void pcl::VTSGridTriangulation<PointInT>::forEachChangedZ(
    const pcl_vts::VtsResult& result, Apply apply) const
{
  const pcl::Indices& indices = *indices_;
  for (std::size_t v = 0; v < result.source_index.size(); ++v) {
    const auto id = static_cast<std::size_t>(indices[result.source_index[v]]);
    const auto z = static_cast<float>(result.mesh.z[v]);
    if (z != (*input_)[id].z)
      apply(id, z);
  }
}

template <typename PointInT>
void pcl::VTSGridTriangulation<PointInT>::fail(pcl_vts::Status status,
                                               const char* method)
{
  last_status_ = std::move(status);
  PCL_ERROR("[pcl::%s::%s] %s\n", getClassName().c_str(), method,
            last_status_.toString().c_str());
}

// Exported explicitly: with -fvisibility=hidden, an instantiation over PCL's point
// types (hidden here like every PCL type) would otherwise stay inside the library.
#define PCL_INSTANTIATE_VTSGridTriangulation(T) \
  template class PCL_VTS_EXPORT pcl::VTSGridTriangulation<T>;
