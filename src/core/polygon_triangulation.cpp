// Polygon CDT by ear clipping + constrained Lawson flips + incremental insertion.
// Local halfedge arrays as in mesh_arrays.h; a twin-less halfedge is a polygon edge
// (a constraint).
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/polygon_triangulation.h>
#include <pcl_vts/core/predicates.h>

#include <string>

namespace pcl_vts {

namespace {

class PatchBuilder {
 public:
  explicit PatchBuilder(const std::vector<Point2>& points)
      : pts_(points)
  {}

  bool earClip(std::size_t n)
  {
    std::vector<std::uint32_t> prev(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
      prev[i] = static_cast<std::uint32_t>((i + n - 1) % n);
      next[i] = static_cast<std::uint32_t>((i + 1) % n);
    }
    std::size_t remaining = n;
    std::uint32_t i = 0;
    std::size_t since_last_ear = 0;
    while (remaining > 3) {
      if (isEar(prev[i], i, next[i], next)) {
        addTriangle(prev[i], i, next[i]);
        next[prev[i]] = next[i];
        prev[next[i]] = prev[i];
        --remaining;
        since_last_ear = 0;
        i = prev[i];
      } else {
        if (++since_last_ear > remaining)
          return false; // a full turn without an ear: not simple or not CCW
        i = next[i];
      }
    }
    if (orient2d(pts_[prev[i]], pts_[i], pts_[next[i]]) != Sign::POSITIVE)
      return false;
    addTriangle(prev[i], i, next[i]);
    mesh_.halfedges.clear();
    mesh_.xy.clear();
    return mesh_.rebuildHalfedges();
  }

  void flipAll()
  {
    for (HalfedgeId e = 0; e < mesh_.triangles.size(); ++e)
      stack_.push_back(e);
    legalize();
  }

  /// Inserts pts_[v]; false when it is skipped (on a vertex, a polygon edge, or
  /// outside).
  bool insert(std::uint32_t v)
  {
    const Point2& p = pts_[v];
    TriangleId t = locate(p);
    if (t == INVALID_ID)
      return false;
    Sign s[3];
    for (int k = 0; k < 3; ++k) {
      const HalfedgeId e = 3 * t + static_cast<HalfedgeId>(k);
      s[k] = orient2d(pts_[tri(e)], pts_[tri(nextHalfedge(e))], p);
    }
    int zeros = 0;
    HalfedgeId on_edge = INVALID_ID;
    for (int k = 0; k < 3; ++k)
      if (s[k] == Sign::ZERO) {
        ++zeros;
        on_edge = 3 * t + static_cast<HalfedgeId>(k);
      }
    if (zeros >= 2)
      return false; // on a vertex
    if (zeros == 1) {
      if (mesh_.halfedges[on_edge] == INVALID_ID)
        return false; // on the polygon: keep the rim exactly as it is
      splitEdge(on_edge, v);
    } else {
      splitTriangle(t, v);
    }
    legalize();
    last_ = t;
    return true;
  }

  std::vector<VertexId>& triangles() { return mesh_.triangles; }

 private:
  VertexId tri(HalfedgeId e) const { return mesh_.triangles[e]; }

  bool isEar(std::uint32_t a, std::uint32_t b, std::uint32_t c,
             const std::vector<std::uint32_t>& next) const
  {
    if (orient2d(pts_[a], pts_[b], pts_[c]) != Sign::POSITIVE)
      return false;
    for (std::uint32_t v = next[c]; v != a; v = next[v]) {
      const Point2& p = pts_[v];
      if (p == pts_[a] || p == pts_[b] || p == pts_[c])
        return false;
      if (orient2d(pts_[a], pts_[b], p) != Sign::NEGATIVE &&
          orient2d(pts_[b], pts_[c], p) != Sign::NEGATIVE &&
          orient2d(pts_[c], pts_[a], p) != Sign::NEGATIVE)
        return false; // a vertex in the closed ear: the diagonal is blocked
    }
    return true;
  }

  void addTriangle(VertexId a, VertexId b, VertexId c)
  {
    mesh_.triangles.push_back(a);
    mesh_.triangles.push_back(b);
    mesh_.triangles.push_back(c);
  }

  void link(HalfedgeId a, HalfedgeId b)
  {
    if (a != INVALID_ID)
      mesh_.halfedges[a] = b;
    if (b != INVALID_ID)
      mesh_.halfedges[b] = a;
  }

  TriangleId newTriangle(VertexId a, VertexId b, VertexId c)
  {
    const auto t = static_cast<TriangleId>(mesh_.triangles.size() / 3);
    addTriangle(a, b, c);
    mesh_.halfedges.insert(mesh_.halfedges.end(), 3, INVALID_ID);
    return t;
  }

  /// Visibility walk from the last triangle; linear scan when the walk meets the
  /// polygon (it cannot cross a constraint) or runs too long.
  TriangleId locate(const Point2& p) const
  {
    const std::size_t count = mesh_.triangles.size() / 3;
    TriangleId t = last_ < count ? last_ : 0;
    for (std::size_t steps = 0; steps < count; ++steps) {
      HalfedgeId cross = INVALID_ID;
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        if (orient2d(pts_[tri(e)], pts_[tri(nextHalfedge(e))], p) == Sign::NEGATIVE) {
          cross = e;
          break;
        }
      if (cross == INVALID_ID)
        return t;
      if (mesh_.halfedges[cross] == INVALID_ID)
        break;
      t = triangleOf(mesh_.halfedges[cross]);
    }
    for (TriangleId u = 0; u < count; ++u) {
      bool inside = true;
      for (HalfedgeId e = 3 * u; e < 3 * u + 3 && inside; ++e)
        inside =
            orient2d(pts_[tri(e)], pts_[tri(nextHalfedge(e))], p) != Sign::NEGATIVE;
      if (inside)
        return u;
    }
    return INVALID_ID;
  }

  //        c                     t = (a, b, p), n1 = (b, c, p), n2 = (c, a, p)
  //       / \    .
  //      / p \   .
  //     a-----b
  void splitTriangle(TriangleId t, VertexId p)
  {
    const VertexId a = tri(3 * t), b = tri(3 * t + 1), c = tri(3 * t + 2);
    const HalfedgeId x_bc = mesh_.halfedges[3 * t + 1];
    const HalfedgeId x_ca = mesh_.halfedges[3 * t + 2];
    mesh_.triangles[3 * t + 2] = p;
    const TriangleId n1 = newTriangle(b, c, p);
    const TriangleId n2 = newTriangle(c, a, p);
    link(3 * n1, x_bc);
    link(3 * n2, x_ca);
    link(3 * t + 1, 3 * n1 + 2);
    link(3 * n1 + 1, 3 * n2 + 2);
    link(3 * n2 + 1, 3 * t + 2);
    stack_.push_back(3 * t);
    stack_.push_back(3 * n1);
    stack_.push_back(3 * n2);
  }

  // e = a->b in t = (a, b, c), twin b->a in u = (b, a, d), p on ab:
  // t = (a, p, c), n1 = (p, b, c), u = (b, p, d), n2 = (p, a, d).
  void splitEdge(HalfedgeId e, VertexId p)
  {
    const HalfedgeId f = mesh_.halfedges[e];
    const TriangleId t = triangleOf(e), u = triangleOf(f);
    const VertexId a = tri(e), b = tri(nextHalfedge(e)), c = tri(prevHalfedge(e));
    const VertexId d = tri(prevHalfedge(f));
    const HalfedgeId x_bc = mesh_.halfedges[nextHalfedge(e)];
    const HalfedgeId x_ca = mesh_.halfedges[prevHalfedge(e)];
    const HalfedgeId x_ad = mesh_.halfedges[nextHalfedge(f)];
    const HalfedgeId x_db = mesh_.halfedges[prevHalfedge(f)];
    setTriangle(t, a, p, c);
    setTriangle(u, b, p, d);
    const TriangleId n1 = newTriangle(p, b, c);
    const TriangleId n2 = newTriangle(p, a, d);
    link(3 * t + 2, x_ca);
    link(3 * n1 + 1, x_bc);
    link(3 * u + 2, x_db);
    link(3 * n2 + 1, x_ad);
    link(3 * t, 3 * n2);
    link(3 * t + 1, 3 * n1 + 2);
    link(3 * n1, 3 * u);
    link(3 * u + 1, 3 * n2 + 2);
    stack_.push_back(3 * t + 2);
    stack_.push_back(3 * n1 + 1);
    stack_.push_back(3 * u + 2);
    stack_.push_back(3 * n2 + 1);
  }

  void setTriangle(TriangleId t, VertexId a, VertexId b, VertexId c)
  {
    mesh_.triangles[3 * t] = a;
    mesh_.triangles[3 * t + 1] = b;
    mesh_.triangles[3 * t + 2] = c;
  }

  // e = a->b in t = (a, b, c), twin in u = (b, a, d); after the flip
  // t = (c, a, d), u = (d, b, c), diagonal c-d.
  void legalize()
  {
    while (!stack_.empty()) {
      const HalfedgeId e = stack_.back();
      stack_.pop_back();
      const HalfedgeId f = mesh_.halfedges[e];
      if (f == INVALID_ID)
        continue; // polygon edge: constrained
      const VertexId a = tri(e), b = tri(nextHalfedge(e)), c = tri(prevHalfedge(e));
      const VertexId d = tri(prevHalfedge(f));
      if (incircle(pts_[a], pts_[b], pts_[c], pts_[d]) != Sign::POSITIVE)
        continue;
      const TriangleId t = triangleOf(e), u = triangleOf(f);
      const HalfedgeId x_bc = mesh_.halfedges[nextHalfedge(e)];
      const HalfedgeId x_ca = mesh_.halfedges[prevHalfedge(e)];
      const HalfedgeId x_ad = mesh_.halfedges[nextHalfedge(f)];
      const HalfedgeId x_db = mesh_.halfedges[prevHalfedge(f)];
      setTriangle(t, c, a, d);
      setTriangle(u, d, b, c);
      link(3 * t, x_ca);
      link(3 * t + 1, x_ad);
      link(3 * u, x_db);
      link(3 * u + 1, x_bc);
      link(3 * t + 2, 3 * u + 2);
      stack_.push_back(3 * t);
      stack_.push_back(3 * t + 1);
      stack_.push_back(3 * u);
      stack_.push_back(3 * u + 1);
    }
  }

  const std::vector<Point2>& pts_;
  TriangleMesh mesh_; ///< triangles and halfedges only
  std::vector<HalfedgeId> stack_;
  TriangleId last_ = 0;
};

} // namespace

Status triangulatePolygon(const std::vector<Point2>& points, std::size_t polygon_size,
                          PolygonTriangulation& output)
{
  output = PolygonTriangulation{};
  if (polygon_size < 3 || polygon_size > points.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "polygon_size = " + std::to_string(polygon_size) +
                             " must be >= 3 and <= the point count (" +
                             std::to_string(points.size()) + ")");
  PatchBuilder builder(points);
  if (!builder.earClip(polygon_size))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "the polygon of " + std::to_string(polygon_size) +
                             " vertices is not simple and counter-clockwise");
  builder.flipAll();
  output.steiner_used.assign(points.size() - polygon_size, 0);
  for (std::size_t k = polygon_size; k < points.size(); ++k)
    output.steiner_used[k - polygon_size] =
        builder.insert(static_cast<std::uint32_t>(k)) ? 1 : 0;
  output.triangles = std::move(builder.triangles());
  return Status::success();
}

} // namespace pcl_vts
