// XY overlap (xy_overlap.h).
#include "mesh_topology.h"
#include "xy_overlap.h"

#include <pcl_vts/core/parallel_for.h>

#include <cmath>
#include <vector>

namespace pcl_vts {
namespace compare {
namespace {

const double* corner(const CompareMesh& mesh, std::size_t t, int k)
{
  return &mesh.xyz[3 * mesh.triangles[3 * t + k]];
}

double orient(const double* a, const double* b, const double* c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Some edge line of s has all of t on its outer side (or on it).
bool separatedByEdgeOf(const CompareMesh& mesh, std::size_t s, std::size_t t)
{
  const double sign = signedXyArea(mesh, s) > 0.0 ? 1.0 : -1.0;
  for (int e = 0; e < 3; ++e) {
    const double* p = corner(mesh, s, e);
    const double* q = corner(mesh, s, (e + 1) % 3);
    bool all_outside = true;
    for (int k = 0; k < 3 && all_outside; ++k)
      all_outside = sign * orient(p, q, corner(mesh, t, k)) <= 0.0;
    if (all_outside)
      return true;
  }
  return false;
}

/// (x, y) strictly inside triangle t's XY projection (either orientation).
bool strictlyInside(const CompareMesh& mesh, std::size_t t, const double* p)
{
  const double* a = corner(mesh, t, 0);
  const double* b = corner(mesh, t, 1);
  const double* c = corner(mesh, t, 2);
  const double o1 = orient(a, b, p), o2 = orient(b, c, p), o3 = orient(c, a, p);
  return (o1 > 0.0 && o2 > 0.0 && o3 > 0.0) || (o1 < 0.0 && o2 < 0.0 && o3 < 0.0);
}

} // namespace

bool xyInteriorsIntersect(const CompareMesh& mesh, std::size_t s, std::size_t t)
{
  if (signedXyArea(mesh, s) == 0.0 || signedXyArea(mesh, t) == 0.0)
    return false;
  return !separatedByEdgeOf(mesh, s, t) && !separatedByEdgeOf(mesh, t, s);
}

XyOverlap measureXyOverlap(const CompareMesh& mesh, const TriangleGrid& grid,
                           const SurfaceSamples& samples, unsigned threads)
{
  XyOverlap result;
  const std::size_t nt = mesh.triangleCount();
  for (std::size_t t = 0; t < nt; ++t)
    result.xy_area += std::fabs(signedXyArea(mesh, t));

  // Pairs: each thread marks into its own array; the last tested partner per
  // triangle avoids testing a pair once per shared cell.
  std::vector<std::vector<std::uint8_t>> marks(threads);
  parallelChunks(threads, nt, [&](std::size_t begin, std::size_t end, unsigned thread) {
    std::vector<std::uint8_t>& mark = marks[thread];
    mark.assign(nt, 0);
    std::vector<std::uint32_t> last_partner(nt, UINT32_MAX);
    for (std::size_t s = begin; s < end; ++s) {
      if (signedXyArea(mesh, s) == 0.0)
        continue;
      long x0, y0, x1, y1;
      grid.cellRange(static_cast<std::uint32_t>(s), x0, y0, x1, y1);
      for (long cy = y0; cy <= y1; ++cy)
        for (long cx = x0; cx <= x1; ++cx)
          grid.forEachInCellIndex(cx, cy, [&](std::uint32_t t) {
            if (t <= s || last_partner[t] == s)
              return;
            last_partner[t] = static_cast<std::uint32_t>(s);
            if (xyInteriorsIntersect(mesh, s, t))
              mark[s] = mark[t] = 1;
          });
    }
  });
  std::vector<std::uint8_t> overlapping(nt, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    for (const std::vector<std::uint8_t>& mark : marks)
      overlapping[t] = overlapping[t] || (!mark.empty() && mark[t]);
    result.overlapping_triangles += overlapping[t];
  }
  marks.clear();

  // Area: samples inside other triangles.
  std::vector<double> area(threads, 0.0);
  const double per_sample = samples.areaPerSample();
  parallelChunks(threads, samples.size(),
                 [&](std::size_t begin, std::size_t end, unsigned thread) {
                   for (std::size_t i = begin; i < end; ++i) {
                     const double* p = &samples.xyz[3 * i];
                     const std::uint32_t own = samples.triangle[i];
                     // Inside another triangle means the interiors intersect: only
                     // samples of triangles found overlapping above can be.
                     if (!overlapping[own])
                       continue;
                     int cover = 1;
                     grid.forEachInCell(p[0], p[1], [&](std::uint32_t t) {
                       if (t != own && strictlyInside(mesh, t, p))
                         ++cover;
                     });
                     if (cover > 1) {
                       // This sample's 3D area share, projected to XY.
                       const double area3 = triangleArea(mesh, own);
                       const double cos_z =
                           area3 > 0.0 ? std::fabs(signedXyArea(mesh, own)) / area3
                                       : 0.0;
                       area[thread] += per_sample * cos_z / cover;
                     }
                   }
                 });
  for (double a : area)
    result.overlap_area += a;
  return result;
}

} // namespace compare
} // namespace pcl_vts
