#include "lattice_triangulation.h"
#include "post_pass_scratch.h"
#include "release_memory.h"

#include <pcl_vts/core/convex_hull.h>
#include <pcl_vts/core/grid_stage.h>
#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {
namespace {

/// z per vertex: the representative's input z, or the mean over its merged points.
/// input_to_vertex may be empty when no duplicate was merged. Each vertex's z is
/// written by one thread (the reads of the input are scattered: cache misses that
/// threads overlap); the means over merged points are summed in input order.
std::vector<double> vertexHeights(const double* xyz, std::size_t n,
                                  const std::vector<VertexId>& input_to_vertex,
                                  const std::vector<std::uint32_t>& source,
                                  DuplicateRule rule, unsigned threads)
{
  std::vector<double> z(source.size());
  // One point a vertex under MEAN_Z: the mean's own arithmetic, (0 + z) / 1, so that
  // a -0.0 height becomes +0.0 as in the sum below.
  const bool one_point_mean = rule == DuplicateRule::MEAN_Z && input_to_vertex.empty();
  parallelRanges(threads, source.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      const double h = xyz[3 * static_cast<std::size_t>(source[v]) + 2];
      z[v] = one_point_mean ? (0.0 + h) / 1.0 : h;
    }
  });
  if (rule != DuplicateRule::MEAN_Z || input_to_vertex.empty())
    return z;
  std::vector<std::uint32_t> count(source.size(), 0);
  std::fill(z.begin(), z.end(), 0.0);
  for (std::size_t k = 0; k < n; ++k)
    if (input_to_vertex[k] != INVALID_ID) {
      z[input_to_vertex[k]] += xyz[3 * k + 2];
      ++count[input_to_vertex[k]];
    }
  for (std::size_t v = 0; v < z.size(); ++v)
    z[v] /= static_cast<double>(count[v]);
  return z;
}

/// Output checks and post-passes, after either triangulation path; the trim's rows
/// inside `scratch` when they fit there.
Status finishPipeline(const VtsOptions& options, VtsResult& result,
                      detail::ScratchBlock scratch)
{
  if (!options.input_map) // before the post-passes allocate
    std::vector<VertexId>().swap(result.input_to_vertex);
  TriangleMesh& mesh = result.mesh;
  Diagnostics& diag = result.diagnostics;
  if (options.check_output) {
    // When the post-passes check their output, every surviving triangle's
    // orientation is checked there: here only the twins, which the trim walks.
    const bool post_checked =
        (options.reconstruction.trim || options.reconstruction.fill) &&
        options.reconstruction.check_output;
    const unsigned threads = options.threads > 0 ? options.threads : allCores();
    std::string why;
    if (!halfedgesConsistent(mesh, &why, threads) ||
        (!post_checked && !allTrianglesCcw(mesh, &why, threads))) {
      result.mesh = TriangleMesh{};
      return Status::error(StatusCode::INTERNAL_ERROR, "output check failed: " + why);
    }
  }

  // Trim boundary, fill holes (each optional).
  if (options.reconstruction.trim || options.reconstruction.fill) {
    ReconstructionOptions post = options.reconstruction;
    post.check_output = post.check_output && options.check_output;
    post.threads = options.threads;
    if (Status s =
            detail::reconstructSurface(mesh, post, result.reconstruction, scratch);
        !s.ok()) {
      result.mesh = TriangleMesh{};
      return s;
    }
    result.source_index.resize(mesh.vertexCount(), INVALID_ID); // inserted points
    diag.triangles = mesh.triangleCount();
  }
  return Status::success();
}

} // namespace

Status validateOptions(const VtsOptions& options)
{
  if (Status s =
          checkFiniteNonNegative("cell_size", options.cell_size, " (0 = automatic)");
      !s.ok())
    return s;
  switch (options.duplicate_rule) {
  case DuplicateRule::LOWEST_Z:
  case DuplicateRule::HIGHEST_Z:
  case DuplicateRule::MEAN_Z:
  case DuplicateRule::FIRST:
    break;
  default:
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "duplicate_rule = " + std::to_string(static_cast<int>(options.duplicate_rule)) +
            " is not a DuplicateRule");
  }
  if ((options.strip_columns & (options.strip_columns - 1)) != 0)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "strip_columns = " + std::to_string(options.strip_columns) +
                             " must be 0 (automatic) or a power of two");
  if (options.reconstruction.trim || options.reconstruction.fill)
    return validateReconstructionOptions(options.reconstruction);
  return Status::success();
}

namespace {

/// runVtsPipeline; with `input` (xyz's own array), its memory is handed to the
/// post-passes once the heights are read from it.
Status runPipeline(const double* xyz, std::size_t n, const VtsOptions& options,
                   VtsResult& result, std::vector<double>* input)
{
  result = VtsResult{};
  Diagnostics& diag = result.diagnostics;
  diag.points_in = n;
  if (Status s = validateOptions(options); !s.ok())
    return s;
  if (n >= INVALID_ID)
    return Status::error(StatusCode::CAPACITY_EXCEEDED,
                         std::to_string(n) +
                             " points exceed the 32-bit vertex ids (at most " +
                             std::to_string(INVALID_ID - 1) + " points)");
  if (n > 0 && xyz == nullptr)
    return Status::error(StatusCode::INVALID_PARAMETER, "null point array");
  // The input is not read after the heights (vertexHeights, or the lattice path's).
  const detail::ScratchBlock scratch =
      input != nullptr
          ? detail::ScratchBlock{input->data(), input->size() * sizeof(double), input}
          : detail::ScratchBlock{};
  if (options.lattice) { // DEM rasters: no search in complete cells (section 7)
    bool handled = false;
    const Status s = triangulateLattice(xyz, n, options, result, handled);
    if (handled)
      return s.ok() ? finishPipeline(options, result, scratch) : s;
  }

  Stopwatch watch;
  const unsigned threads = options.threads > 0 ? options.threads : allCores();
  GridStage stage;
  // The per-input map only where it is kept (input_map) or read (the mean heights).
  const bool map_needed =
      options.input_map || options.duplicate_rule == DuplicateRule::MEAN_Z;
  if (Status s =
          buildGridStage(xyz, n, options.cell_size, options.duplicate_rule, threads,
                         stage, map_needed ? &result.input_to_vertex : nullptr, diag);
      !s.ok())
    return s;
  const CellGrid& grid = stage.grid;
  diag.seconds_grid = watch.seconds();
  // Without merged duplicates input_to_vertex is the inverse of stage.source: dropped
  // here and rebuilt after the triangulation, 4 bytes a point less while the strips
  // grow.
  const bool rebuild_input_map = diag.duplicates_merged == 0;
  if (rebuild_input_map)
    std::vector<VertexId>().swap(result.input_to_vertex);

  watch.restart();
  { // the candidates released before the triangulation allocates
    const std::vector<VertexId> hull_candidates =
        gridHullCandidates(grid, &stage.pyramid);
    if (Status s = convexHull(grid.points, result.hull, &hull_candidates); !s.ok()) {
      result.input_to_vertex.clear();
      return s;
    }
  }
  // The strips' peak holds the cells: compact on sparse (clustered) grids.
  compactCellStarts(stage.grid);
  diag.hull_vertices = result.hull.size();
  diag.seconds_hull = watch.seconds();

  watch.restart();
  TriangleMesh& mesh = result.mesh;
  SearchStats stats;
  // The cells, the pyramid and the subdivision are not needed once the strips are
  // grown: released (and their pages handed back) before the border pairing, so that
  // they do not add to the peak.
  const bool release = grid.points.size() >= detail::RELEASE_MIN_POINTS;
  const auto release_grid = [&stage, &mesh, release] {
    mesh.xy = std::move(stage.grid.points);
    stage.grid = CellGrid{};
    stage.pyramid = CellPyramid{};
    stage.subdivision = CellSubdivision{};
    if (release)
      detail::releaseFreedMemory();
  };
  Status grown =
      triangulateGrid(grid, stage.pyramid, stage.subdivision, result.hull,
                      mesh.triangles, mesh.halfedges, stats, threads,
                      options.strip_columns, options.cache_blocks, release_grid);
  diag.seconds_triangulate = watch.seconds();
  diag.local_searches = stats.local;
  diag.widened_searches = stats.widened;
  diag.cells_visited = stats.cells_visited;
  diag.points_tested = stats.points_tested;
  if (!grown.ok()) {
    result.mesh = TriangleMesh{};
    return grown;
  }
  if (release)
    detail::releaseFreedMemory(); // the merge's border records
  if (rebuild_input_map && options.input_map) {
    result.input_to_vertex.assign(n, INVALID_ID);
    const std::vector<std::uint32_t>& source = stage.source;
    parallelFor(threads, source.size(), [&](std::size_t v) { // distinct inputs
      result.input_to_vertex[source[v]] = static_cast<VertexId>(v);
    });
  }
  mesh.z = vertexHeights(xyz, n, result.input_to_vertex, stage.source,
                         options.duplicate_rule, threads);
  result.source_index = std::move(stage.source);
  diag.triangles = mesh.triangleCount();

  return finishPipeline(options, result, scratch);
}

} // namespace

Status runVtsPipeline(const double* xyz, std::size_t n, const VtsOptions& options,
                      VtsResult& result)
{
  return runPipeline(xyz, n, options, result, nullptr);
}

Status runVtsPipeline(std::vector<double>&& xyz, const VtsOptions& options,
                      VtsResult& result)
{
  std::vector<double> input = std::move(xyz);
  if (input.size() % 3 != 0) {
    result = VtsResult{};
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "point array of " + std::to_string(input.size()) +
                             " values is not x, y, z triples");
  }
  const Status status =
      runPipeline(input.data(), input.size() / 3, options, result, &input);
  std::vector<double>().swap(input);
  return status;
}

} // namespace pcl_vts
