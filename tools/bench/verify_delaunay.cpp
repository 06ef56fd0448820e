// Independent exact check of a triangle mesh written by pcd_to_mesh (binary or ASCII
// PLY, float or double vertices): uses CGAL's exact predicates only, none of pcl_vts.
//   verify_delaunay MESH.ply
// Checks: every triangle counter-clockwise; every directed edge used once and every
// undirected edge at most twice; every vertex used; no vertex strictly inside the
// circumcircle of a triangle across an interior edge (locally Delaunay => Delaunay);
// the triangle count equals that of CGAL's Delaunay triangulation of the same vertices
// and the boundary edges are exactly CGAL's convex hull edges.
// Exit 0 and "OK ..." when every check passes, 1 otherwise.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

struct Mesh {
  std::vector<Point> points;
  std::vector<std::uint32_t> triangles;
};

bool fail(const std::string& why)
{
  std::cerr << "verify_delaunay: FAIL: " << why << "\n";
  return false;
}

template <typename T>
T readScalar(std::istream& in, bool binary)
{
  if (!binary) {
    double v;
    in >> v;
    return static_cast<T>(v);
  }
  T v;
  in.read(reinterpret_cast<char*>(&v), sizeof(T));
  return v;
}

double readTyped(std::istream& in, const std::string& type, bool binary)
{
  if (type == "double" || type == "float64")
    return readScalar<double>(in, binary);
  if (type == "float" || type == "float32")
    return readScalar<float>(in, binary);
  if (type == "int" || type == "int32")
    return readScalar<std::int32_t>(in, binary);
  if (type == "uint" || type == "uint32")
    return readScalar<std::uint32_t>(in, binary);
  if (type == "uchar" || type == "uint8")
    return binary ? readScalar<std::uint8_t>(in, binary) : readScalar<int>(in, binary);
  throw std::runtime_error("unsupported PLY type " + type);
}

bool readPly(const char* path, Mesh& mesh)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return fail(std::string("cannot open ") + path);
  std::string line, format;
  std::size_t vertices = 0, faces = 0;
  std::vector<std::string> vertex_types, vertex_names;
  std::string list_count_type, list_index_type, element;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "format")
      s >> format;
    else if (word == "element") {
      s >> element;
      (element == "vertex" ? vertices : faces) = 0;
      s >> (element == "vertex" ? vertices : faces);
    } else if (word == "property" && element == "vertex") {
      std::string type, name;
      s >> type >> name;
      vertex_types.push_back(type);
      vertex_names.push_back(name);
    } else if (word == "property" && element == "face")
      s >> word >> list_count_type >> list_index_type;
    else if (word == "end_header")
      break;
  }
  const bool binary = format == "binary_little_endian";
  if (!binary && format != "ascii")
    return fail("unsupported PLY format " + format);
  mesh.points.reserve(vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    double x = 0, y = 0;
    for (std::size_t p = 0; p < vertex_types.size(); ++p) {
      const double value = readTyped(in, vertex_types[p], binary);
      if (vertex_names[p] == "x")
        x = value;
      else if (vertex_names[p] == "y")
        y = value;
    }
    mesh.points.emplace_back(x, y);
  }
  mesh.triangles.reserve(3 * faces);
  for (std::size_t f = 0; f < faces; ++f) {
    const auto count = static_cast<int>(readTyped(in, list_count_type, binary));
    if (count != 3)
      return fail("face " + std::to_string(f) + " has " + std::to_string(count) +
                  " vertices");
    for (int k = 0; k < 3; ++k) {
      const double id = readTyped(in, list_index_type, binary);
      if (id < 0 || id >= static_cast<double>(vertices))
        return fail("face " + std::to_string(f) + " has vertex id out of range");
      mesh.triangles.push_back(static_cast<std::uint32_t>(id));
    }
  }
  if (!in)
    return fail("PLY file truncated");
  return true;
}

bool verify(const Mesh& mesh)
{
  const std::size_t t_count = mesh.triangles.size() / 3;
  const auto& p = mesh.points;
  // Orientation, and the directed-edge map for twins.
  std::unordered_map<std::uint64_t, std::uint32_t> directed; // edge -> opposite vertex
  directed.reserve(3 * t_count);
  std::vector<char> used(p.size(), 0);
  for (std::size_t t = 0; t < t_count; ++t) {
    const std::uint32_t* v = &mesh.triangles[3 * t];
    if (CGAL::orientation(p[v[0]], p[v[1]], p[v[2]]) != CGAL::LEFT_TURN)
      return fail("triangle " + std::to_string(t) + " is not counter-clockwise");
    for (int k = 0; k < 3; ++k) {
      used[v[k]] = 1;
      const std::uint64_t key = (std::uint64_t(v[k]) << 32) | v[(k + 1) % 3];
      if (!directed.emplace(key, v[(k + 2) % 3]).second)
        return fail("directed edge " + std::to_string(v[k]) + "->" +
                    std::to_string(v[(k + 1) % 3]) + " used twice (overlap)");
    }
  }
  for (std::size_t v = 0; v < p.size(); ++v)
    if (!used[v])
      return fail("vertex " + std::to_string(v) + " is not used");
  // Locally Delaunay across every interior edge.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
  for (const auto& [key, opposite] : directed) {
    const auto a = static_cast<std::uint32_t>(key >> 32);
    const auto b = static_cast<std::uint32_t>(key & 0xffffffffu);
    const auto twin = directed.find((std::uint64_t(b) << 32) | a);
    if (twin == directed.end()) {
      boundary.emplace_back(a, b);
      continue;
    }
    if (CGAL::side_of_oriented_circle(p[a], p[b], p[opposite], p[twin->second]) ==
        CGAL::ON_POSITIVE_SIDE)
      return fail("edge " + std::to_string(a) + "-" + std::to_string(b) +
                  " is not Delaunay: vertex " + std::to_string(twin->second) +
                  " is inside the circle of its neighbour");
  }
  // Same triangle count and the same hull as CGAL's Delaunay triangulation.
  CGAL::Delaunay_triangulation_2<Kernel> dt(p.begin(), p.end());
  if (dt.number_of_vertices() != p.size())
    return fail("CGAL found duplicate vertices");
  if (dt.number_of_faces() != t_count)
    return fail("CGAL has " + std::to_string(dt.number_of_faces()) +
                " triangles, the mesh " + std::to_string(t_count));
  std::map<std::pair<double, double>, std::uint32_t> id_of;
  for (std::uint32_t v = 0; v < p.size(); ++v)
    id_of[{p[v].x(), p[v].y()}] = v;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hull;
  for (auto f = dt.incident_faces(dt.infinite_vertex()), done = f;;) {
    const int i = f->index(dt.infinite_vertex());
    const auto a = f->vertex(dt.ccw(i))->point(), b = f->vertex(dt.cw(i))->point();
    hull.emplace_back(id_of[{b.x(), b.y()}], id_of[{a.x(), a.y()}]);
    if (++f == done)
      break;
  }
  std::sort(hull.begin(), hull.end());
  std::sort(boundary.begin(), boundary.end());
  if (hull != boundary)
    return fail("boundary edges (" + std::to_string(boundary.size()) +
                ") differ from CGAL's convex hull edges (" +
                std::to_string(hull.size()) + ")");
  std::cout
      << "OK " << p.size() << " vertices, " << t_count << " triangles, "
      << boundary.size() << " hull edges: counter-clockwise, manifold, every "
      << "vertex used, locally Delaunay everywhere, same count and hull as CGAL\n";
  return true;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 2) {
    std::cerr << "usage: verify_delaunay MESH.ply\n";
    return 2;
  }
  Mesh mesh;
  try {
    if (!readPly(argv[1], mesh) || !verify(mesh))
      return 1;
  } catch (const std::exception& e) {
    return fail(e.what()) ? 0 : 1;
  }
  return 0;
}
