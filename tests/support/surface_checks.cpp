// Post-pass invariants and the synthetic terrain measures. See surface_checks.h.
#include "support/surface_checks.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/mesh_checks.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <set>

namespace pcl_vts {
namespace test {

std::size_t pinchVertexCount(const TriangleMesh& mesh)
{
  const std::size_t n = mesh.vertexCount();
  std::vector<std::size_t> incident(n, 0);
  std::vector<HalfedgeId> some_out(n, INVALID_ID);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    ++incident[mesh.triangles[e]];
    some_out[mesh.triangles[e]] = e;
  }
  std::size_t pinches = 0;
  for (VertexId v = 0; v < n; ++v) {
    if (some_out[v] == INVALID_ID)
      continue;
    // Rotate one way (twin of the outgoing edge), then the other (twin of the
    // incoming edge), counting the triangles of this fan.
    std::size_t fan = 1;
    bool closed = false;
    HalfedgeId f = some_out[v];
    while (mesh.halfedges[f] != INVALID_ID) {
      f = nextHalfedge(mesh.halfedges[f]);
      if (f == some_out[v]) {
        closed = true;
        break;
      }
      ++fan;
    }
    if (!closed) {
      HalfedgeId g = prevHalfedge(some_out[v]);
      while (mesh.halfedges[g] != INVALID_ID) {
        g = prevHalfedge(mesh.halfedges[g]);
        ++fan;
      }
    }
    if (fan != incident[v])
      ++pinches;
  }
  return pinches;
}

bool expectValidSurfaceMesh(const TriangleMesh& mesh)
{
  bool ok = true;
  std::string why;
  if (!isEdgeManifold(mesh, &why)) {
    ADD_FAILURE() << "not edge-manifold: " << why;
    ok = false;
  }
  if (!halfedgesConsistent(mesh, &why)) {
    ADD_FAILURE() << "twins: " << why;
    ok = false;
  }
  if (!allTrianglesCcw(mesh, &why)) {
    ADD_FAILURE() << "orientation: " << why;
    ok = false;
  }
  std::set<std::array<VertexId, 3>> seen;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    std::array<VertexId, 3> key = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1],
                                   mesh.triangles[3 * t + 2]};
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {
      ADD_FAILURE() << "duplicate triangle " << t;
      ok = false;
    }
  }
  const std::size_t pinches = pinchVertexCount(mesh);
  if (pinches != 0) {
    ADD_FAILURE() << pinches << " pinch vertices";
    ok = false;
  }
  if (!ok)
    return false;
  BoundaryLoops loops;
  const Status status = findBoundaryLoops(mesh, loops);
  if (!status.ok()) {
    ADD_FAILURE() << status.toString();
    return false;
  }
  std::vector<int> positive(loops.componentCount(), 0);
  for (const BoundaryLoop& loop : loops.loops) {
    if (loop.twice_area > 0.0)
      ++positive[loop.component];
    if ((loop.twice_area > 0.0) != loop.is_outer) {
      ADD_FAILURE() << "loop of area " << loop.twice_area / 2 << " classified "
                    << (loop.is_outer ? "outer" : "hole");
      ok = false;
    }
  }
  for (std::size_t c = 0; c < positive.size(); ++c)
    if (positive[c] != 1) {
      ADD_FAILURE() << "piece " << c << " has " << positive[c] << " outer loops";
      ok = false;
    }
  return ok;
}

void forEachCoveredSample(const TriangleMesh& mesh, std::size_t first, double step,
                          const std::function<void(double, double, std::size_t)>& visit,
                          const double* clip)
{
  for (std::size_t t = first; t < mesh.triangleCount(); ++t) {
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    const double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
    const double y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
    if (clip && (x1 < clip[0] || y1 < clip[1] || x0 > clip[2] || y0 > clip[3]))
      continue;
    const auto i0 = static_cast<long>(std::floor(x0 / step - 0.5));
    const auto i1 = static_cast<long>(std::ceil(x1 / step - 0.5));
    const auto j0 = static_cast<long>(std::floor(y0 / step - 0.5));
    const auto j1 = static_cast<long>(std::ceil(y1 / step - 0.5));
    auto edge = [](const Point2& p, const Point2& q, double x, double y) {
      return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
    };
    auto owns = [](double w, const Point2& p, const Point2& q) {
      // Top-left style rule so that shared edges count once.
      return w > 0.0 || (w == 0.0 && (q.y < p.y || (q.y == p.y && q.x > p.x)));
    };
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) {
        const double x = (static_cast<double>(i) + 0.5) * step;
        const double y = (static_cast<double>(j) + 0.5) * step;
        if (owns(edge(a, b, x, y), a, b) && owns(edge(b, c, x, y), b, c) &&
            owns(edge(c, a, x, y), c, a))
          visit(x, y, t);
      }
  }
}

CoverageFigures measureCoverage(const TriangleMesh& mesh, const SyntheticTerrain& t,
                                double step)
{
  CoverageFigures f;
  const auto cells = static_cast<long>(std::llround(t.size / step));
  for (long j = 0; j < cells; ++j)
    for (long i = 0; i < cells; ++i)
      if (t.inFootprint((static_cast<double>(i) + 0.5) * step,
                        (static_cast<double>(j) + 0.5) * step))
        f.footprint_area += step * step;
  forEachCoveredSample(mesh, 0, step, [&](double x, double y, std::size_t) {
    if (t.inFootprint(x, y))
      f.covered_footprint += step * step;
    else
      f.spill += step * step;
  });
  return f;
}

double discCoverage(const TriangleMesh& mesh, const Disc& d, double step)
{
  // Same sample lattice as forEachCoveredSample(): centres of step cells from the
  // origin.
  double inside = 0.0, covered = 0.0;
  const auto i0 = static_cast<long>(std::floor((d.cx - d.r) / step));
  const auto i1 = static_cast<long>(std::ceil((d.cx + d.r) / step));
  const auto j0 = static_cast<long>(std::floor((d.cy - d.r) / step));
  const auto j1 = static_cast<long>(std::ceil((d.cy + d.r) / step));
  for (long j = j0; j <= j1; ++j)
    for (long i = i0; i <= i1; ++i)
      if (std::hypot((static_cast<double>(i) + 0.5) * step - d.cx,
                     (static_cast<double>(j) + 0.5) * step - d.cy) < d.r)
        inside += 1.0;
  const double clip[4] = {d.cx - d.r, d.cy - d.r, d.cx + d.r, d.cy + d.r};
  forEachCoveredSample(
      mesh, 0, step,
      [&](double x, double y, std::size_t) {
        if (std::hypot(x - d.cx, y - d.cy) < d.r)
          covered += 1.0;
      },
      clip);
  return inside > 0.0 ? covered / inside : 1.0;
}

ZError vertexZError(const TriangleMesh& mesh, const std::vector<std::uint8_t>& flags)
{
  ZError e;
  double sum = 0.0;
  for (std::size_t v = 0; v < flags.size() && v < mesh.vertexCount(); ++v) {
    if (!flags[v])
      continue;
    const double d = mesh.z[v] - SyntheticTerrain::height(mesh.xy[v].x, mesh.xy[v].y);
    sum += d * d;
    e.max = std::max(e.max, std::fabs(d));
    ++e.samples;
  }
  e.rms = e.samples ? std::sqrt(sum / static_cast<double>(e.samples)) : 0.0;
  return e;
}

ZError patchZError(const TriangleMesh& mesh, std::size_t first_triangle, double step)
{
  ZError e;
  double sum = 0.0;
  forEachCoveredSample(
      mesh, first_triangle, step, [&](double x, double y, std::size_t t) {
        const Point2& a = mesh.xy[mesh.triangles[3 * t]];
        const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
        const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
        const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        const double u = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
        const double v = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
        const double z = (1.0 - u - v) * mesh.z[mesh.triangles[3 * t]] +
                         u * mesh.z[mesh.triangles[3 * t + 1]] +
                         v * mesh.z[mesh.triangles[3 * t + 2]];
        const double d = z - SyntheticTerrain::height(x, y);
        sum += d * d;
        e.max = std::max(e.max, std::fabs(d));
        ++e.samples;
      });
  e.rms = e.samples ? std::sqrt(sum / static_cast<double>(e.samples)) : 0.0;
  return e;
}

} // namespace test
} // namespace pcl_vts
