// Trim -> fill, timed and checked. See reconstruct_surface.h.
#include "post_pass_scratch.h"
#include "post_pass_spacing.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/stopwatch.h>

#include <string>

namespace pcl_vts {

Status validateReconstructionOptions(const ReconstructionOptions& options)
{
  if (options.trim) {
    Status status = validateTrimOptions(options.trim_options);
    if (!status.ok())
      return status;
  }
  if (options.fill)
    return validateFillOptions(options.fill_options);
  return Status::success();
}

Status reconstructSurface(TriangleMesh& mesh, const ReconstructionOptions& options,
                          ReconstructionDiagnostics& diagnostics)
{
  return detail::reconstructSurface(mesh, options, diagnostics, {});
}

Status detail::reconstructSurface(TriangleMesh& mesh,
                                  const ReconstructionOptions& options,
                                  ReconstructionDiagnostics& diagnostics,
                                  ScratchBlock scratch)
{
  diagnostics = ReconstructionDiagnostics{};
  Status status = validateReconstructionOptions(options);
  if (!status.ok())
    return status;
  if (mesh.xy.size() != mesh.z.size() || mesh.triangles.size() % 3 != 0 ||
      mesh.halfedges.size() != mesh.triangles.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "mesh arrays disagree: " + std::to_string(mesh.xy.size()) +
                             " xy, " + std::to_string(mesh.z.size()) + " z, " +
                             std::to_string(mesh.triangles.size()) + " corners, " +
                             std::to_string(mesh.halfedges.size()) + " halfedges");
  // The trim checks the corners in its rows' count pass, before it changes anything
  // (the same error); without it, a pass of their own.
  if (!options.trim) {
    status = detail::checkCorners(mesh);
    if (!status.ok())
      return status;
  }
  diagnostics.triangles_in = mesh.triangleCount();
  const unsigned threads = options.threads > 0 ? options.threads : allCores();
  // The trim hands the trimmed mesh's spacing to the fill (post_pass_spacing.h).
  detail::VertexSpacing spacing;
  const bool handed = options.trim && options.fill;
  if (options.trim) {
    const Stopwatch watch;
    status =
        detail::trimOutwardTriangles(mesh, options.trim_options, diagnostics.trim,
                                     handed ? &spacing : nullptr, threads, scratch);
    diagnostics.seconds_trim = watch.seconds();
    if (!status.ok()) {
      diagnostics = ReconstructionDiagnostics{}; // as when the corners fail first
      return status;
    }
  }
  if (options.fill) {
    const Stopwatch watch;
    status =
        detail::fillHolesOfPart(mesh, options.fill_options, nullptr,
                                handed ? &spacing : nullptr, diagnostics.fill, threads);
    diagnostics.seconds_fill = watch.seconds();
    if (!status.ok())
      return status;
  } else {
    diagnostics.fill.inserted.assign(mesh.vertexCount(), 0);
  }
  diagnostics.triangles_out = mesh.triangleCount();
  if (options.check_output) {
    std::string why;
    if (!isValidSurfaceMesh(mesh, &why, threads))
      return Status::error(StatusCode::INTERNAL_ERROR,
                           "reconstructed mesh check failed: " + why);
  }
  return Status::success();
}

} // namespace pcl_vts
