// The reconstruction post-passes in their order: trim outward triangles, then fill
// the holes that trimming opened (and any the input had). One call for the pipeline
// and the CLI; each pass can be turned off. docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct ReconstructionOptions {
  bool trim = true; ///< run trimOutwardTriangles
  bool fill = true; ///< run fillHoles
  TrimOptions trim_options;
  FillOptions fill_options;
  /// Verify the output (edge-manifold, twins, CCW) before returning; a failure is
  /// INTERNAL_ERROR. Linear.
  bool check_output = true;
  /// Threads for the spacing, the triangle classification, the hole patches and the
  /// checks; 0 = all hardware threads. The output is identical for every value.
  /// runVtsPipeline sets it to VtsOptions::threads.
  unsigned threads = 1;
};

/// Checks the options of the enabled passes.
PCL_VTS_CORE_EXPORT Status
validateReconstructionOptions(const ReconstructionOptions& options);

struct ReconstructionDiagnostics {
  std::size_t triangles_in = 0;
  std::size_t triangles_out = 0;
  TrimResult trim; ///< zero when trimming is off
  FillResult fill; ///< zero when filling is off (inserted: all 0)
  double seconds_trim = 0.0;
  double seconds_fill = 0.0;
};

/// Trims then fills mesh in place. Input vertex ids are kept (vertices are never
/// removed; ones left without triangles are counted in trim.vertices_lost);
/// inserted points are appended and flagged in fill.inserted (one per output
/// vertex). On error the mesh may be partly processed and the status says why.
PCL_VTS_CORE_EXPORT Status reconstructSurface(TriangleMesh& mesh,
                                              const ReconstructionOptions& options,
                                              ReconstructionDiagnostics& diagnostics);

} // namespace pcl_vts
