// Hole filling: loops -> lattice points -> polygon CDT -> spline z -> append.
// See fill_holes.h and docs/reconstruction.md.
#include "post_pass_spacing.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/polygon_triangulation.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/thin_plate_spline.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <unordered_set>
#include <utility>

namespace pcl_vts {

Status validateFillOptions(const FillOptions& options)
{
  for (const auto& [name, value] : {std::pair{"max_hole_area", options.max_hole_area},
                                    std::pair{"point_spacing", options.point_spacing}})
    if (Status s = checkFiniteNonNegative(name, value, " (0 = automatic)"); !s.ok())
      return s;
  if (!(options.rim_clearance >= 0.1 && options.rim_clearance <= 1.0))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "rim_clearance = " + formatValue(options.rim_clearance) +
                             " must be in [0.1, 1]");
  if (options.rim_rings > 4)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "rim_rings = " + std::to_string(options.rim_rings) +
                             " must be in [0, 4]");
  return Status::success();
}

namespace {

/// Winding number of the closed polygon around p, exact (orient2d); p on an edge
/// counts as outside (0) only when the crossing rule says so: callers keep points
/// away from the rim.
int windingNumber(const std::vector<Point2>& polygon, std::size_t size, const Point2& p)
{
  int winding = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % size];
    if (a.y <= p.y) {
      if (b.y > p.y && orient2d(a, b, p) == Sign::POSITIVE)
        ++winding;
    } else if (b.y <= p.y && orient2d(a, b, p) == Sign::NEGATIVE) {
      --winding;
    }
  }
  return winding;
}

double segmentDistance(const Point2& a, const Point2& b, const Point2& p)
{
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

/// Vertex neighbours, measurePointSpacing's rows (the ends of the halfedges leaving
/// a vertex and the starts of the boundary ones entering it): compressed rows of the
/// whole mesh, or walked around each vertex's fan from a halfedge leaving it (its
/// seed), which costs no pass over the mesh, and gives the same row when the fan
/// holds every triangle of the vertex (checked against its count of triangles, which
/// the trim hands over: VertexSpacing::triangle_count).
class Neighbours {
 public:
  static Neighbours rows(const TriangleMesh& mesh)
  {
    Neighbours adj(mesh);
    const std::size_t n = mesh.vertexCount();
    adj.start_.assign(n + 1, 0);
    for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
      ++adj.start_[mesh.triangles[e] + 1];
      if (mesh.halfedges[e] == INVALID_ID)
        ++adj.start_[mesh.triangles[nextHalfedge(e)] + 1];
    }
    for (std::size_t v = 0; v < n; ++v)
      adj.start_[v + 1] += adj.start_[v];
    adj.ring_.resize(adj.start_[n]);
    std::vector<std::size_t> fill(adj.start_.begin(), adj.start_.end() - 1);
    for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
      const VertexId a = mesh.triangles[e];
      const VertexId b = mesh.triangles[nextHalfedge(e)];
      adj.ring_[fill[a]++] = b;
      if (mesh.halfedges[e] == INVALID_ID)
        adj.ring_[fill[b]++] = a;
    }
    return adj;
  }

  /// counts: each vertex's triangles, up to detail::MANY_TRIANGLES (not trusted).
  static Neighbours fans(const TriangleMesh& mesh,
                         const std::vector<std::uint8_t>& counts)
  {
    Neighbours adj(mesh);
    adj.counts_ = &counts;
    return adj;
  }

  /// v's row in out (replaced), walked from seed (a halfedge leaving v) unless the
  /// rows are built; with seeds, a halfedge leaving each entry (INVALID_ID from the
  /// rows). false when its fan does not hold all its triangles.
  bool row(VertexId v, HalfedgeId seed, std::vector<VertexId>& out,
           std::vector<HalfedgeId>* seeds = nullptr) const
  {
    out.clear();
    if (seeds != nullptr)
      seeds->clear();
    if (counts_ == nullptr) {
      out.assign(ring_.begin() + static_cast<std::ptrdiff_t>(start_[v]),
                 ring_.begin() + static_cast<std::ptrdiff_t>(start_[v + 1]));
      if (seeds != nullptr)
        seeds->assign(out.size(), INVALID_ID);
      return true;
    }
    const unsigned count = (*counts_)[v];
    if (count == 0)
      return true;
    if (count >= detail::MANY_TRIANGLES || seed == INVALID_ID)
      return false;
    // Back to the open end, if any; a closed fan starts at its largest halfedge (the
    // walk gives the same row from any seed).
    HalfedgeId f = seed, largest = seed;
    bool closed = false;
    for (unsigned steps = 0;; ++steps) {
      const HalfedgeId twin = mesh_->halfedges[prevHalfedge(f)];
      if (twin == INVALID_ID)
        break;
      f = twin;
      largest = std::max(largest, f);
      if (f == seed) {
        closed = true;
        break;
      }
      if (steps > count)
        return false;
    }
    const HalfedgeId start = closed ? largest : f;
    f = start;
    unsigned walked = 0;
    for (;;) {
      out.push_back(mesh_->triangles[nextHalfedge(f)]);
      if (seeds != nullptr)
        seeds->push_back(nextHalfedge(f));
      if (++walked > count)
        return false;
      const HalfedgeId twin = mesh_->halfedges[f];
      if (twin == INVALID_ID)
        break;
      f = nextHalfedge(twin);
      if (f == start)
        break;
    }
    if (!closed) {
      out.push_back(mesh_->triangles[prevHalfedge(start)]);
      if (seeds != nullptr)
        seeds->push_back(prevHalfedge(start));
    }
    return walked == count;
  }

 private:
  explicit Neighbours(const TriangleMesh& mesh)
      : mesh_(&mesh)
  {}
  const TriangleMesh* mesh_;
  std::vector<std::size_t> start_; ///< rows
  std::vector<VertexId> ring_;
  const std::vector<std::uint8_t>* counts_ = nullptr; ///< fans
};

/// Hexagonal lattice points of spacing h strictly inside polygon[0..size) and at
/// least clearance from its edges, appended to polygon. The lattice is anchored at
/// multiples of h, so it does not depend on where the loop starts.
void addLatticePoints(std::vector<Point2>& polygon, std::size_t size, double h,
                      double clearance, bool snap_to_float)
{
  double x0 = polygon[0].x, x1 = x0, y0 = polygon[0].y, y1 = y0;
  for (std::size_t i = 0; i < size; ++i) {
    x0 = std::min(x0, polygon[i].x);
    x1 = std::max(x1, polygon[i].x);
    y0 = std::min(y0, polygon[i].y);
    y1 = std::max(y1, polygon[i].y);
  }
  const double dy = h * std::sqrt(3.0) / 2.0;
  const auto j0 = static_cast<long long>(std::floor(y0 / dy));
  const auto j1 = static_cast<long long>(std::ceil(y1 / dy));
  for (long long j = j0; j <= j1; ++j) {
    const double y = static_cast<double>(j) * dy;
    const double shift = (j % 2 != 0) ? 0.5 * h : 0.0;
    const auto i0 = static_cast<long long>(std::floor((x0 - shift) / h));
    const auto i1 = static_cast<long long>(std::ceil((x1 - shift) / h));
    for (long long i = i0; i <= i1; ++i) {
      Point2 p{static_cast<double>(i) * h + shift, y};
      if (snap_to_float)
        p = {static_cast<double>(static_cast<float>(p.x)),
             static_cast<double>(static_cast<float>(p.y))};
      if (p.x <= x0 || p.x >= x1 || p.y <= y0 || p.y >= y1)
        continue;
      if (windingNumber(polygon, size, p) == 0)
        continue;
      bool clear = true;
      for (std::size_t k = 0; k < size && clear; ++k)
        clear = segmentDistance(polygon[k], polygon[(k + 1) % size], p) >= clearance;
      if (clear)
        polygon.push_back(p);
    }
  }
}

/// Rim vertices and rings of neighbours around them (breadth first, loop order);
/// rim_seeds: a halfedge leaving each rim vertex. Its own set of seen vertices: holes
/// are measured on several threads at once. false when a row could not be walked
/// (Neighbours::row).
bool rimRings(const Neighbours& adj, const std::vector<VertexId>& rim,
              const std::vector<HalfedgeId>& rim_seeds, std::size_t rings,
              std::vector<VertexId>& samples)
{
  samples.clear();
  std::vector<HalfedgeId> sample_seeds;
  std::unordered_set<VertexId> seen;
  for (std::size_t k = 0; k < rim.size(); ++k)
    if (seen.insert(rim[k]).second) {
      samples.push_back(rim[k]);
      sample_seeds.push_back(rim_seeds[k]);
    }
  std::size_t level_begin = 0;
  std::vector<VertexId> row;
  std::vector<HalfedgeId> row_seeds;
  for (std::size_t r = 0; r < rings; ++r) {
    const std::size_t level_end = samples.size();
    for (std::size_t k = level_begin; k < level_end; ++k) {
      if (!adj.row(samples[k], sample_seeds[k], row, &row_seeds))
        return false;
      for (std::size_t i = 0; i < row.size(); ++i)
        if (seen.insert(row[i]).second) {
          samples.push_back(row[i]);
          sample_seeds.push_back(row_seeds[i]);
        }
    }
    level_begin = level_end;
  }
  return true;
}

/// The samples in position order: the spline's sums then run in an order that does
/// not depend on ids, so the same hole gets the same z in any mesh holding it.
void sortByPosition(const TriangleMesh& mesh, std::vector<VertexId>& samples)
{
  std::sort(samples.begin(), samples.end(),
            [&](VertexId a, VertexId b) { return lexLess(mesh.xy[a], mesh.xy[b]); });
}

/// One point strictly inside a triangle of each piece, the one along the start of its
/// outer loop: a piece lies inside a hole of another piece entirely or not at all
/// (pieces do not overlap).
template <typename Real>
std::vector<Point2> pieceProbes(const TriangleMesh& mesh, const BoundaryLoops& loops,
                                const Real& real)
{
  std::vector<Point2> probes;
  for (const BoundaryLoop& loop : loops.loops) {
    if (!real(loop) || !(loop.twice_area > 0.0))
      continue;
    const TriangleId t = triangleOf(loop.halfedges.front());
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& d = mesh.xy[mesh.triangles[3 * t + 2]];
    probes.push_back({(a.x + b.x + d.x) / 3.0, (a.y + b.y + d.y) / 3.0});
  }
  return probes;
}

/// The local spacing at the rim vertices: measurePointSpacing's (dense), or one
/// figure per rim vertex in increasing order (sparse).
struct RimSpacing {
  const std::vector<double>* dense = nullptr;
  std::vector<std::pair<VertexId, double>> sparse;
  double at(VertexId v) const
  {
    if (dense != nullptr)
      return (*dense)[v];
    const auto it = std::lower_bound(
        sparse.begin(), sparse.end(), v,
        [](const std::pair<VertexId, double>& a, VertexId b) { return a.first < b; });
    return it != sparse.end() && it->first == v ? it->second : 0.0;
  }
};

/// What one hole becomes: left open, skipped, or filled by a patch over the rim
/// polygon and the lattice points (with their z).
struct HolePatch {
  enum class Outcome { LEFT_OPEN, SKIPPED, FILLED };
  Outcome outcome = Outcome::SKIPPED;
  std::vector<VertexId> rim;
  std::vector<Point2> points;
  PolygonTriangulation patch;
  std::vector<double> z; ///< per point after the rim's (0 for those the patch skips)
};

/// Fills the holes of one mesh: each hole's lattice points, patch and heights on
/// their own (measure, from the unchanged mesh: several holes at once), then every
/// patch appended in loop order (append, finish).
class HoleFiller {
 public:
  HoleFiller(TriangleMesh& mesh, const FillOptions& options, const RimSpacing& spacing,
             double global_h, std::vector<Point2> piece_probe, Neighbours adjacency,
             FillResult& result)
      : mesh_(mesh)
      , options_(options)
      , spacing_(spacing)
      , global_h_(global_h)
      , piece_probe_(std::move(piece_probe))
      , result_(result)
      , adj_(std::move(adjacency))
      , input_vertices_(mesh.vertexCount())
      , input_corners_(mesh.triangles.size())
  {}

  /// One hole loop (clockwise), measured: left open, skipped or its patch. Reads
  /// the mesh only, so holes can be measured on several threads.
  HolePatch measure(const BoundaryLoop& loop) const
  {
    HolePatch hole;
    const double area = -0.5 * loop.twice_area;
    if (area > result_.max_hole_area) {
      hole.outcome = HolePatch::Outcome::LEFT_OPEN;
      return hole;
    }
    if (loop.has_repeated_vertex)
      return hole;
    // The hole runs clockwise (mesh on its left): reversed, it is a CCW polygon whose
    // edges are the twins of the rim halfedges.
    const std::size_t size = loop.vertices.size();
    hole.rim.assign(loop.vertices.rbegin(), loop.vertices.rend());
    hole.points.reserve(size);
    for (const VertexId v : hole.rim)
      hole.points.push_back(mesh_.xy[v]);
    if (enclosesPiece(hole.points, size))
      return hole;
    const double h = latticeSpacing(hole.rim);
    if (h > 0.0)
      addLatticePoints(hole.points, size, h, options_.rim_clearance * h,
                       options_.snap_to_float);
    if (!triangulatePolygon(hole.points, size, hole.patch).ok())
      return hole;
    std::vector<HalfedgeId> rim_seeds(loop.halfedges.rbegin(), loop.halfedges.rend());
    const HoleHeights heights = fitHeights(hole.rim, rim_seeds);
    hole.z.assign(hole.points.size() - size, 0.0);
    for (std::size_t k = size; k < hole.points.size(); ++k) {
      if (!hole.patch.steiner_used[k - size])
        continue;
      double z = options_.z_method == HoleZMethod::THIN_PLATE_SPLINE
                     ? heights.spline.evaluate(hole.points[k])
                     : heights.rim_mean;
      if (options_.snap_to_float)
        z = static_cast<double>(static_cast<float>(z));
      hole.z[k - size] = z;
    }
    hole.outcome = HolePatch::Outcome::FILLED;
    return hole;
  }

  /// The measured hole of loop, counted and, if filled, appended (in loop order).
  Status append(const BoundaryLoop& loop, const HolePatch& hole)
  {
    ++result_.holes_found;
    if (hole.outcome == HolePatch::Outcome::LEFT_OPEN) {
      ++result_.holes_left_open;
      return Status::success();
    }
    if (hole.outcome == HolePatch::Outcome::SKIPPED) {
      ++result_.holes_skipped;
      return Status::success();
    }
    if (Status s = appendPatch(loop, hole); !s.ok())
      return s;
    result_.triangles_added += hole.patch.triangles.size() / 3;
    ++result_.holes_filled;
    return Status::success();
  }

  /// Whether a fan could not be walked during measure(): the holes are measured
  /// again after useRows().
  bool unwalked() const { return unwalked_; }
  void useRows()
  {
    adj_ = Neighbours::rows(mesh_);
    unwalked_ = false;
  }

  /// The patches' triangles after the mesh's; the inserted-point flags.
  void finish()
  {
    mesh_.triangles.insert(mesh_.triangles.end(), new_triangles_.begin(),
                           new_triangles_.end());
    mesh_.halfedges.insert(mesh_.halfedges.end(), new_halfedges_.begin(),
                           new_halfedges_.end());
    result_.inserted.assign(mesh_.vertexCount(), 0);
    std::fill(result_.inserted.begin() + static_cast<std::ptrdiff_t>(input_vertices_),
              result_.inserted.end(), 1);
  }

 private:
  /// The z of a hole's new points: the thin-plate spline through its samples, or the
  /// rim's mean height.
  struct HoleHeights {
    ThinPlateSpline spline;
    double rim_mean = 0.0;
  };

  /// Whether the hole polygon points[0..size) holds another piece (its own piece's
  /// probe is outside it).
  bool enclosesPiece(const std::vector<Point2>& points, std::size_t size) const
  {
    return std::any_of(piece_probe_.begin(), piece_probe_.end(), [&](const Point2& p) {
      return windingNumber(points, size, p) != 0;
    });
  }

  /// The lattice spacing of a hole: the option, else the median local spacing along
  /// its rim, else the global one.
  double latticeSpacing(const std::vector<VertexId>& rim) const
  {
    std::vector<double> rim_spacing;
    for (const VertexId v : rim)
      rim_spacing.push_back(spacing_.at(v));
    double h =
        options_.point_spacing > 0.0 ? options_.point_spacing : medianOf(rim_spacing);
    if (!(h > 0.0))
      h = global_h_;
    return h;
  }

  /// The spline through the rim and rim_rings rings around it (at most
  /// MAX_SPLINE_SAMPLES of them, in position order), and the rim's mean z.
  HoleHeights fitHeights(const std::vector<VertexId>& rim,
                         const std::vector<HalfedgeId>& rim_seeds) const
  {
    HoleHeights heights;
    const bool spline = options_.z_method == HoleZMethod::THIN_PLATE_SPLINE;
    std::vector<Point2> sample_xy;
    std::vector<double> sample_z;
    std::vector<VertexId> samples;
    if (!rimRings(adj_, rim, rim_seeds, spline ? options_.rim_rings : 0, samples))
      unwalked_ = true; // measured again with the rows

    sortByPosition(mesh_, samples);
    const std::size_t stride = (samples.size() + FillOptions::MAX_SPLINE_SAMPLES - 1) /
                               FillOptions::MAX_SPLINE_SAMPLES;
    for (std::size_t k = 0; k < samples.size(); k += std::max<std::size_t>(stride, 1)) {
      sample_xy.push_back(mesh_.xy[samples[k]]);
      sample_z.push_back(mesh_.z[samples[k]]);
    }
    for (const VertexId v : rim)
      heights.rim_mean += mesh_.z[v] / static_cast<double>(rim.size());
    if (spline)
      heights.spline.fit(sample_xy, sample_z);
    return heights;
  }

  /// The lattice points the patch uses become mesh vertices (with z); the patch's
  /// triangles are queued, twinned inside the patch and with the rim halfedges.
  Status appendPatch(const BoundaryLoop& loop, const HolePatch& hole)
  {
    const std::vector<VertexId>& rim = hole.rim;
    const std::vector<Point2>& points = hole.points;
    const PolygonTriangulation& patch = hole.patch;
    const std::size_t size = rim.size();
    std::vector<VertexId> global(points.size());
    std::copy(rim.begin(), rim.end(), global.begin());
    for (std::size_t k = size; k < points.size(); ++k) {
      if (!patch.steiner_used[k - size])
        continue;
      global[k] = static_cast<VertexId>(mesh_.xy.size());
      mesh_.xy.push_back(points[k]);
      mesh_.z.push_back(hole.z[k - size]);
      ++result_.points_inserted;
    }
    // Twins: inside the patch from its own arrays; a patch edge rim[w-1] -> rim[w]
    // is the twin of the loop halfedge leaving rim[w], loop.halfedges[size-1-w].
    TriangleMesh local;
    local.triangles.assign(patch.triangles.begin(), patch.triangles.end());
    if (!local.rebuildHalfedges())
      return Status::error(StatusCode::INTERNAL_ERROR, "hole patch is not manifold");
    const auto base = static_cast<HalfedgeId>(input_corners_ + new_triangles_.size());
    for (HalfedgeId e = 0; e < local.triangles.size(); ++e) {
      new_triangles_.push_back(global[local.triangles[e]]);
      if (local.halfedges[e] != INVALID_ID) {
        new_halfedges_.push_back(base + local.halfedges[e]);
        continue;
      }
      const VertexId u = local.triangles[e];
      const VertexId w = local.triangles[nextHalfedge(e)];
      if (u >= size || w >= size || w != (u + 1) % size)
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "hole patch boundary is not its polygon");
      const HalfedgeId rim_edge = loop.halfedges[size - 1 - w];
      new_halfedges_.push_back(rim_edge);
      mesh_.halfedges[rim_edge] = base + e;
    }
    return Status::success();
  }

  TriangleMesh& mesh_;
  const FillOptions& options_;
  const RimSpacing& spacing_;
  const double global_h_;
  const std::vector<Point2> piece_probe_;
  FillResult& result_;
  Neighbours adj_;
  mutable std::atomic<bool> unwalked_{false};
  const std::size_t input_vertices_;
  const std::size_t input_corners_;
  std::vector<VertexId> new_triangles_;
  std::vector<HalfedgeId> new_halfedges_;
};

} // namespace

Status fillHoles(TriangleMesh& mesh, const FillOptions& options, FillResult& result)
{
  return fillHolesOfPart(mesh, options, nullptr, result);
}

Status fillHolesOfPart(TriangleMesh& mesh, const FillOptions& options,
                       const MeshPart* part, FillResult& result)
{
  return detail::fillHolesOfPart(mesh, options, part, nullptr, result);
}

Status detail::fillHolesOfPart(TriangleMesh& mesh, const FillOptions& options,
                               const MeshPart* part, VertexSpacing* known,
                               FillResult& result, unsigned threads)
{
  threads = threads > 0 ? threads : allCores();
  result = FillResult{};
  Status status = validateFillOptions(options);
  if (!status.ok())
    return status;
  BoundaryLoops loops; // the pieces are not needed: holes run clockwise
  // The trim's list of the boundary halfedges spares a scan of all of them.
  status = detail::traceBoundaryLoops(
      mesh, loops.loops,
      known != nullptr && known->boundary_known ? &known->boundary : nullptr);
  if (!status.ok())
    return status;
  // A loop runs counter-clockwise around its piece's outside, clockwise inside a
  // hole; in a part of a mesh, loops through cut edges are neither.
  auto real = [&](const BoundaryLoop& loop) {
    return part == nullptr || std::all_of(loop.halfedges.begin(), loop.halfedges.end(),
                                          part->real_boundary);
  };
  auto is_hole = [&](const BoundaryLoop& loop) {
    return real(loop) && !(loop.twice_area > 0.0);
  };
  if (std::none_of(loops.loops.begin(), loops.loops.end(), is_hole)) {
    result.inserted.assign(mesh.vertexCount(), 0);
    return Status::success();
  }
  // The local spacing is read at hole rims only: their vertices, each once in
  // increasing order, with a halfedge leaving each (its loop's).
  std::vector<std::pair<VertexId, HalfedgeId>> rim;
  for (const BoundaryLoop& loop : loops.loops)
    if (is_hole(loop))
      for (std::size_t k = 0; k < loop.vertices.size(); ++k)
        rim.emplace_back(loop.vertices[k], loop.halfedges[k]);
  std::sort(rim.begin(), rim.end());
  rim.erase(
      std::unique(rim.begin(), rim.end(),
                  [](const auto& a, const auto& b) { return a.first == b.first; }),
      rim.end());
  // With the trim's spacing, the rows are walked around the fans from the loops'
  // halfedges (no pass over the whole mesh); a fan that does not hold all its
  // vertex's triangles (not from VTS) takes the compressed rows.
  Neighbours adjacency =
      known != nullptr && known->triangle_count.size() == mesh.vertexCount()
          ? Neighbours::fans(mesh, known->triangle_count)
          : Neighbours::rows(mesh);
  PointSpacing spacing;
  RimSpacing rim_spacing;
  if (known != nullptr) {
    known->settle(mesh, threads);
    // measurePointSpacing's local figure at the rims, from the known own medians
    // and the same rows.
    spacing.global_median = known->global_median;
    std::vector<double> values;
    std::vector<VertexId> row;
    for (bool walked = false; !walked;) {
      walked = true;
      rim_spacing.sparse.clear();
      for (std::size_t k = 0; k < rim.size() && walked; ++k) {
        const VertexId v = rim[k].first;
        walked = adjacency.row(v, rim[k].second, row);
        double local = 0.0;
        if (!row.empty()) {
          values.assign(1, known->own[v]);
          for (const VertexId u : row)
            values.push_back(known->own[u]);
          local = medianOf(values);
        }
        rim_spacing.sparse.emplace_back(v, local);
      }
      if (!walked)
        adjacency = Neighbours::rows(mesh);
    }
  } else {
    std::vector<bool> on_rim(mesh.vertexCount(), false);
    for (const auto& [v, out] : rim)
      on_rim[v] = true;
    spacing = detail::measurePointSpacing(mesh, &on_rim, nullptr, threads);
    rim_spacing.dense = &spacing.local;
  }
  const double global_h =
      part != nullptr ? part->global_spacing : spacing.global_median;
  result.max_hole_area = options.max_hole_area > 0.0
                             ? options.max_hole_area
                             : FillOptions::AUTO_HOLE_AREA_FACTOR * global_h * global_h;

  HoleFiller filler(mesh, options, rim_spacing, global_h,
                    pieceProbes(mesh, loops, real), std::move(adjacency), result);
  // Holes are independent once found: measured on the threads (each taking the next
  // hole: their sizes differ), then appended in loop order, so the output does not
  // depend on the thread count.
  std::vector<const BoundaryLoop*> holes;
  for (const BoundaryLoop& loop : loops.loops)
    if (is_hole(loop))
      holes.push_back(&loop);
  std::vector<HolePatch> patches(holes.size());
  for (bool again = true; again;) {
    std::atomic<std::size_t> next{0};
    runTeam(static_cast<unsigned>(std::min<std::size_t>(threads, holes.size())),
            [&](unsigned) {
              for (std::size_t k = next++; k < holes.size(); k = next++)
                patches[k] = filler.measure(*holes[k]);
            });
    again = filler.unwalked();
    if (again)
      filler.useRows();
  }
  for (std::size_t k = 0; k < holes.size(); ++k) {
    if (Status s = filler.append(*holes[k], patches[k]); !s.ok())
      return s;
    patches[k] = HolePatch{}; // appended: its memory goes back
  }
  filler.finish();
  return Status::success();
}

} // namespace pcl_vts
