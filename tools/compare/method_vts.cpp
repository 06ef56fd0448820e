// VTS rows of the comparison (methods.h): runVtsPipeline as pcd_to_mesh runs it, on
// one thread like the other methods.
#include "methods.h"

#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/core/vts_pipeline.h>

namespace pcl_vts {
namespace compare {

Status runVtsMethod(const std::string& name, const PointSet& points, CompareMesh& mesh,
                    MethodReport& report)
{
  VtsOptions options;
  options.threads = 1;
  options.input_map = false; // as pcd_to_mesh
  options.reconstruction =
      name == "vts-raw" ? noPostPasses() : ReconstructionOptions{}; // trim + fill
  VtsResult result;
  const Stopwatch watch;
  Status status = runVtsPipeline(points.xyz.data(), points.size(), options, result);
  report.seconds = watch.seconds();
  if (!status.ok())
    return status;
  const TriangleMesh& tm = result.mesh;
  mesh.xyz.resize(3 * tm.vertexCount());
  mesh.source.resize(tm.vertexCount());
  for (std::size_t v = 0; v < tm.vertexCount(); ++v) {
    mesh.xyz[3 * v] = tm.xy[v].x;
    mesh.xyz[3 * v + 1] = tm.xy[v].y;
    mesh.xyz[3 * v + 2] = tm.z[v];
    const std::uint32_t s =
        v < result.source_index.size() ? result.source_index[v] : INVALID_ID;
    mesh.source[v] = s == INVALID_ID ? -1 : static_cast<std::int32_t>(s);
  }
  mesh.triangles = tm.triangles;
  report.parameters = "1 thread, cell size automatic, duplicates: lowest z";
  if (name == "vts") {
    const ReconstructionOptions defaults;
    report.parameters += ", trim factor " +
                         formatValue(defaults.trim_options.trim_factor) +
                         ", holes filled up to 500 x spacing^2";
    const ReconstructionDiagnostics& d = result.reconstruction;
    report.notes.push_back("trimmed " + std::to_string(d.trim.triangles_removed) +
                           " triangles, filled " + std::to_string(d.fill.holes_filled) +
                           " of " + std::to_string(d.fill.holes_found) +
                           " holes with " + std::to_string(d.fill.points_inserted) +
                           " new points");
  }
  return Status::success();
}

} // namespace compare
} // namespace pcl_vts
