// The synthetic inputs of the benchmarks (bench_triangulation, bench_threads): the
// same generator, so that their figures are on the same points.
//   jittered: a unit grid with +-0.2 jitter; grid: the exact unit grid; uniform:
//   uniform in the same square; clustered: 64 gaussian clusters in a square 4x wider;
//   raster: a square DEM-like lattice (spacing 1, rows from the top) with NODATA
//   ellipses (one per 20000 cells, radii 0.5 to 12.5 cells) and 0.1 % dropouts.
// Heights from a smooth terrain function, so the inputs are 2.5D surfaces. meshHash
// fingerprints an output, to check that it is the same for every thread count.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts::bench {

/// Terrain-like heights so the inputs are 2.5D surfaces.
inline double terrain(double x, double y)
{
  return 50.0 * std::sin(x * 0.01) * std::cos(y * 0.013) + 0.02 * x;
}

inline std::vector<double> generate(const std::string& dist, std::size_t n,
                                    unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  const auto side =
      static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  const auto push = [&xyz](double x, double y) {
    xyz.push_back(x);
    xyz.push_back(y);
    xyz.push_back(terrain(x, y));
  };
  if (dist == "jittered" || dist == "grid") {
    const double jitter = dist == "grid" ? 0.0 : 0.4;
    for (std::size_t k = 0; k < n; ++k) {
      const double i = static_cast<double>(k % side), j = static_cast<double>(k / side);
      push(i + jitter * (unit(rng) - 0.5), j + jitter * (unit(rng) - 0.5));
    }
  } else if (dist == "raster") {
    std::vector<std::uint8_t> nodata(side * side, 0);
    const auto mark = [&](double cx, double cy, double rx, double ry) {
      const auto lo = [&](double v) {
        return static_cast<std::size_t>(std::max(0.0, std::floor(v)));
      };
      const auto hi = [&](double v) {
        return std::min(side, static_cast<std::size_t>(std::max(0.0, std::ceil(v))));
      };
      for (std::size_t j = lo(cy - ry); j < hi(cy + ry + 1); ++j)
        for (std::size_t i = lo(cx - rx); i < hi(cx + rx + 1); ++i) {
          const double u = (static_cast<double>(i) - cx) / rx,
                       v = (static_cast<double>(j) - cy) / ry;
          if (u * u + v * v <= 1.0)
            nodata[j * side + i] = 1;
        }
    };
    for (std::size_t h = 0; h < std::max<std::size_t>(1, n / 20000); ++h)
      mark(unit(rng) * static_cast<double>(side), unit(rng) * static_cast<double>(side),
           0.5 + 12.0 * unit(rng), 0.5 + 12.0 * unit(rng));
    for (std::uint8_t& cell : nodata)
      if (unit(rng) < 0.001)
        cell = 1;
    for (std::size_t r = 0; r < side; ++r) {
      const std::size_t j = side - 1 - r;
      for (std::size_t i = 0; i < side; ++i)
        if (nodata[j * side + i] == 0)
          push(static_cast<double>(i), static_cast<double>(j));
    }
  } else if (dist == "uniform") {
    for (std::size_t k = 0; k < n; ++k)
      push(unit(rng) * static_cast<double>(side),
           unit(rng) * static_cast<double>(side));
  } else if (dist == "clustered") {
    // Dense gaussian clusters separated by large empty voids.
    const std::size_t clusters = 64;
    std::vector<double> centres;
    for (std::size_t c = 0; c < clusters; ++c) {
      centres.push_back(unit(rng) * static_cast<double>(side) * 4.0);
      centres.push_back(unit(rng) * static_cast<double>(side) * 4.0);
    }
    std::normal_distribution<double> gauss(0.0, static_cast<double>(side) * 0.05);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t c = k % clusters;
      push(centres[2 * c] + gauss(rng), centres[2 * c + 1] + gauss(rng));
    }
  } else {
    std::fprintf(stderr, "unknown distribution '%s'\n", dist.c_str());
    std::exit(1);
  }
  return xyz;
}

/// FNV-1a over 64-bit words of byte arrays, each array's length counted too.
class Fnv1a64 {
 public:
  void add(const void* data, std::size_t bytes)
  {
    const auto* b = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t word;
      std::memcpy(&word, b + i, 8);
      h_ = (h_ ^ word) * 1099511628211ull;
    }
    for (; i < bytes; ++i)
      h_ = (h_ ^ b[i]) * 1099511628211ull;
    h_ = (h_ ^ bytes) * 1099511628211ull; // array boundaries count
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

/// Hash of a mesh's arrays (triangles, halfedges, xy, z): equal meshes give equal
/// hashes; any changed index, order or coordinate changes it in practice.
inline std::uint64_t meshHash(const TriangleMesh& mesh)
{
  Fnv1a64 h;
  h.add(mesh.triangles.data(), mesh.triangles.size() * sizeof(VertexId));
  h.add(mesh.halfedges.data(), mesh.halfedges.size() * sizeof(HalfedgeId));
  h.add(mesh.xy.data(), mesh.xy.size() * sizeof(Point2));
  h.add(mesh.z.data(), mesh.z.size() * sizeof(double));
  return h.value();
}

/// Hash of the mesh as a set: each triangle rotated to start at its smallest vertex
/// (orientation kept), the triangles sorted, then xy and z. Equal for two
/// triangulations of the same vertices that list the same triangles in another order,
/// so a change of insertion order can be checked against the build before it.
inline std::uint64_t meshSetHash(const TriangleMesh& mesh)
{
  std::vector<std::array<VertexId, 3>> set(mesh.triangles.size() / 3);
  for (std::size_t t = 0; t < set.size(); ++t) {
    const VertexId* v = &mesh.triangles[3 * t];
    const int first = v[0] <= v[1] && v[0] <= v[2] ? 0 : (v[1] <= v[2] ? 1 : 2);
    set[t] = {v[first], v[(first + 1) % 3], v[(first + 2) % 3]};
  }
  std::sort(set.begin(), set.end());
  Fnv1a64 h;
  h.add(set.data(), set.size() * sizeof(set[0]));
  h.add(mesh.xy.data(), mesh.xy.size() * sizeof(Point2));
  h.add(mesh.z.data(), mesh.z.size() * sizeof(double));
  return h.value();
}

} // namespace pcl_vts::bench
