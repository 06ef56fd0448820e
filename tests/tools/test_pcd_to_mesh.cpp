// End-to-end tests of the pcd_to_mesh CLI: the built binary runs in a fresh temp
// folder; each failure class is checked on exit status, the one stderr line and the
// absence of any output (or temp) file; each success reads the mesh file back with a
// reader written here and checks invariants against the input read independently:
// 2n - h - 2 triangles (h from an exact hull), CCW, all vertices used, vertices equal
// to input points bit for bit, Delaunay with --no-trim --no-fill.
#include "support/png_decode.h"

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <tuple>
#include <unistd.h>
#include <vector>

#ifndef PCL_VTS_PCD_TO_MESH
#error "PCL_VTS_PCD_TO_MESH must name the built pcd_to_mesh binary"
#endif

namespace {

namespace fs = std::filesystem;
using pcl_vts::Point2;
using pcl_vts::Sign;
using pcl_vts::TriangleMesh;
using Xyz = std::array<double, 3>;

const std::string TEST_DATA = PCL_VTS_TEST_DATA_DIR;
const std::string SHARED_DATA = PCL_VTS_SHARED_DATA_DIR;

// ---- running the CLI
// -----------------------------------------------------------------

struct CliResult {
  int exit_code = -1; ///< -1 when the process did not exit normally (signal)
  std::string out;
  std::string err;
};

std::string readText(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeBytes(const fs::path& path, const std::string& bytes)
{
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string shellQuote(const std::string& s)
{
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// A fresh folder per test: work/ is where the CLI runs (and must stay clean of
/// stray files), logs/ holds its captured stdout and stderr.
class PcdToMesh : public ::testing::Test {
 protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/pcd_to_mesh_test.XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    root_ = pattern;
    work_ = root_ / "work";
    fs::create_directory(work_);
    fs::create_directory(root_ / "logs");
  }

  void TearDown() override
  {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  /// Runs the CLI in work/; shell_prefix runs first in the same shell (e.g. ulimit).
  /// The pure triangulation: the post-passes (trim, fill) switched off.
  /// Each {option, value} on input is a usage error (exit 1) naming the option, and
  /// leaves no file behind.
  void
  expectUsageErrors(const std::string& input,
                    const std::vector<std::vector<std::string>>& option_values) const
  {
    for (const std::vector<std::string>& bad : option_values) {
      std::vector<std::string> args = {input, "out.ply"};
      args.insert(args.end(), bad.begin(), bad.end());
      const CliResult r = run(args);
      SCOPED_TRACE(bad[0] + " " + bad[1]);
      EXPECT_EQ(r.exit_code, 1) << r.err;
      EXPECT_NE(r.err.find(bad[0]), std::string::npos) << r.err;
      EXPECT_TRUE(workFiles().empty());
    }
  }

  CliResult runDelaunay(std::vector<std::string> args) const
  {
    args.push_back("--no-trim");
    args.push_back("--no-fill");
    return run(args);
  }

  CliResult run(const std::vector<std::string>& args,
                const std::string& shell_prefix = "") const
  {
    // timeout: a hang becomes a failure (exit 124) instead of a stuck ctest.
    std::string cmd = "cd " + shellQuote(work_.string()) + " && " + shell_prefix +
                      " timeout 300 " + shellQuote(PCL_VTS_PCD_TO_MESH);
    for (const std::string& a : args)
      cmd += " " + shellQuote(a);
    cmd += " > " + shellQuote((root_ / "logs" / "out").string()) + " 2> " +
           shellQuote((root_ / "logs" / "err").string());
    const int status = std::system(cmd.c_str());
    CliResult r;
    if (status != -1 && WIFEXITED(status))
      r.exit_code = WEXITSTATUS(status);
    r.out = readText(root_ / "logs" / "out");
    r.err = readText(root_ / "logs" / "err");
    return r;
  }

  /// Names of the files in work/, sorted.
  std::vector<std::string> workFiles() const
  {
    std::vector<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(work_))
      names.push_back(fs::relative(entry.path(), work_).string());
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path work(const std::string& name) const { return work_ / name; }

  /// Checks a failed run: its exit code, exactly one stderr line with the prefix and
  /// the expected words, and that work/ holds exactly the files it held before.
  void expectFailure(const CliResult& r, int exit_code, const std::string& words,
                     const std::vector<std::string>& files_before) const
  {
    EXPECT_EQ(r.exit_code, exit_code) << "stderr: " << r.err;
    EXPECT_EQ(r.err.rfind("pcd_to_mesh: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos)
        << "expected '" << words << "' in: " << r.err;
    EXPECT_EQ(workFiles(), files_before) << "a failed run must leave no file behind";
  }

  fs::path root_;
  fs::path work_;
};

// ---- PCD files written by the tests
// ---------------------------------------------------

std::string pcdHeader(const std::string& fields, const std::string& sizes,
                      const std::string& types, std::size_t points,
                      const std::string& data)
{
  std::size_t n_fields =
      1 + static_cast<std::size_t>(std::count(fields.begin(), fields.end(), ' '));
  std::string counts;
  for (std::size_t i = 0; i < n_fields; ++i)
    counts += i ? " 1" : "1";
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields +
         "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " +
         std::to_string(points) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
         std::to_string(points) + "\nDATA " + data + "\n";
}

/// ASCII PCD with float32 x y z, values printed exactly.
std::string asciiPcd(const std::vector<Xyz>& points)
{
  std::string s = pcdHeader("x y z", "4 4 4", "F F F", points.size(), "ascii");
  char line[128];
  for (const Xyz& p : points) {
    std::snprintf(line, sizeof(line), "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
    s += line;
  }
  return s;
}

/// Binary PCD with float64 fields named as given ("x y z" or "X Y Z").
std::string binaryPcd64(const std::vector<Xyz>& points,
                        const std::string& names = "x y z")
{
  std::string s = pcdHeader(names, "8 8 8", "F F F", points.size(), "binary");
  for (const Xyz& p : points)
    s.append(reinterpret_cast<const char*>(p.data()), sizeof(double) * 3);
  return s;
}

/// Points on a millimetre lattice around UTM easting 5e5, northing 5e6: none of
/// them is a float, so a float anywhere on the way would show.
std::vector<Xyz> utmCloud(std::size_t n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::set<std::pair<std::int64_t, std::int64_t>> used;
  std::vector<Xyz> points;
  while (points.size() < n) {
    const auto e = static_cast<std::int64_t>(rng() % 80000); // 80 m in mm
    const auto nn = static_cast<std::int64_t>(rng() % 60000);
    if (!used.insert({e, nn}).second)
      continue;
    const auto h = static_cast<std::int64_t>(rng() % 20000);
    points.push_back({(500000000.0 + static_cast<double>(e)) / 1000.0,
                      (5000000000.0 + static_cast<double>(nn)) / 1000.0,
                      (120000.0 + static_cast<double>(h)) / 1000.0});
  }
  return points;
}

// ---- reading inputs independently of the CLI's reader
// --------------------------------

/// Float32 x y z PCDs (any DATA kind) through PCL's own PointXYZ path: exact for
/// float32 fields.
std::vector<Xyz> loadFloat32Pcd(const std::string& path)
{
  pcl::PointCloud<pcl::PointXYZ> cloud;
  EXPECT_EQ(pcl::io::loadPCDFile(path, cloud), 0) << path;
  std::vector<Xyz> points;
  for (const auto& p : cloud.points)
    points.push_back({p.x, p.y, p.z});
  return points;
}

/// Uncompressed binary PCD with float64 coordinates, parsed here by hand.
std::vector<Xyz> loadBinaryFloat64Pcd(const std::string& path,
                                      const std::array<std::string, 3>& names)
{
  const std::string bytes = readText(path);
  std::istringstream header(bytes);
  std::string line;
  std::vector<std::string> fields;
  std::vector<int> sizes;
  std::size_t points = 0;
  std::size_t body = 0;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "FIELDS")
      for (std::string f; words >> f;)
        fields.push_back(f);
    else if (key == "SIZE")
      for (int sz; words >> sz;)
        sizes.push_back(sz);
    else if (key == "POINTS")
      words >> points;
    else if (key == "DATA") {
      body = static_cast<std::size_t>(header.tellg());
      break;
    }
  }
  std::size_t step = 0;
  std::array<std::size_t, 3> offset{};
  for (std::size_t f = 0; f < fields.size(); ++f) {
    for (int a = 0; a < 3; ++a)
      if (fields[f] == names[a])
        offset[a] = step;
    step += static_cast<std::size_t>(sizes.at(f));
  }
  EXPECT_GE(bytes.size(), body + points * step);
  std::vector<Xyz> out(points);
  for (std::size_t i = 0; i < points; ++i)
    for (int a = 0; a < 3; ++a)
      std::memcpy(&out[i][a], bytes.data() + body + i * step + offset[a], 8);
  return out;
}

// ---- reading the CLI's mesh files
// -----------------------------------------------------

struct MeshFile {
  TriangleMesh mesh;
  std::vector<std::uint8_t> inserted; ///< the optional "uchar inserted" property
  bool binary = false;
  std::string vertex_type; ///< "float" or "double" (PLY, VTK); "" for OBJ
};

::testing::AssertionResult readPly(const std::string& path, MeshFile& m)
{
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != "ply")
    return ::testing::AssertionFailure() << path << ": no 'ply' magic";
  std::size_t nv = 0, nf = 0;
  std::vector<std::string> vprops;
  bool in_vertex = false, face_ok = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream w(line);
    std::string a, b, c;
    w >> a >> b >> c;
    if (a == "format")
      m.binary = b == "binary_little_endian";
    else if (a == "element") {
      in_vertex = b == "vertex";
      (in_vertex ? nv : nf) = std::stoul(c);
    } else if (a == "property" && in_vertex && b == "uchar" && c == "inserted") {
      vprops.push_back(c);
    } else if (a == "property" && in_vertex) {
      vprops.push_back(c);
      if (m.vertex_type.empty())
        m.vertex_type = b;
      else if (m.vertex_type != b)
        return ::testing::AssertionFailure() << "mixed vertex property types";
    } else if (a == "property")
      face_ok = line == "property list uchar int vertex_indices";
  }
  const bool flags = vprops == std::vector<std::string>{"x", "y", "z", "inserted"};
  if (line != "end_header" ||
      (vprops != std::vector<std::string>{"x", "y", "z"} && !flags) || !face_ok)
    return ::testing::AssertionFailure() << path << ": unexpected PLY header";
  const bool dbl = m.vertex_type == "double";
  m.mesh.xy.resize(nv);
  m.mesh.z.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    double c[3];
    for (double& value : c) {
      if (!m.binary)
        in >> value;
      else if (dbl)
        in.read(reinterpret_cast<char*>(&value), 8);
      else {
        float f;
        in.read(reinterpret_cast<char*>(&f), 4);
        value = f;
      }
    }
    m.mesh.xy[v] = {c[0], c[1]};
    m.mesh.z[v] = c[2];
    if (flags) {
      unsigned flag = 0;
      if (m.binary) {
        unsigned char f8 = 0;
        in.read(reinterpret_cast<char*>(&f8), 1);
        flag = f8;
      } else
        in >> flag;
      m.inserted.push_back(static_cast<std::uint8_t>(flag));
    }
  }
  for (std::size_t t = 0; t < nf; ++t) {
    unsigned count = 0;
    std::int32_t idx[3] = {0, 0, 0};
    if (m.binary) {
      unsigned char c8 = 0;
      in.read(reinterpret_cast<char*>(&c8), 1);
      count = c8;
      in.read(reinterpret_cast<char*>(idx), 12);
    } else
      in >> count >> idx[0] >> idx[1] >> idx[2];
    if (count != 3)
      return ::testing::AssertionFailure() << "face " << t << " is not a triangle";
    for (std::int32_t i : idx)
      m.mesh.triangles.push_back(static_cast<pcl_vts::VertexId>(i));
  }
  if (!in)
    return ::testing::AssertionFailure() << path << ": body shorter than its header";
  if (m.binary && in.peek() != EOF)
    return ::testing::AssertionFailure() << path << ": bytes after the last face";
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult readObj(const std::string& path, MeshFile& m)
{
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream w(line);
    std::string key;
    w >> key;
    if (key == "v") {
      double x, y, z;
      w >> x >> y >> z;
      m.mesh.xy.push_back({x, y});
      m.mesh.z.push_back(z);
    } else if (key == "f") {
      for (int k = 0; k < 3; ++k) {
        long i = 0;
        w >> i;
        m.mesh.triangles.push_back(static_cast<pcl_vts::VertexId>(i - 1));
      }
    } else
      return ::testing::AssertionFailure() << "unexpected OBJ line: " << line;
    if (!w)
      return ::testing::AssertionFailure() << "bad OBJ line: " << line;
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult readVtk(const std::string& path, MeshFile& m)
{
  std::ifstream in(path);
  std::string line, title, kind, dataset;
  std::getline(in, line);
  std::getline(in, title);
  std::getline(in, kind);
  std::getline(in, dataset);
  if (line.rfind("# vtk DataFile", 0) != 0 || kind != "ASCII" ||
      dataset != "DATASET POLYDATA")
    return ::testing::AssertionFailure() << path << ": unexpected VTK header";
  std::string key;
  std::size_t nv = 0, nf = 0, total = 0;
  in >> key >> nv >> m.vertex_type;
  if (key != "POINTS")
    return ::testing::AssertionFailure() << "no POINTS";
  for (std::size_t v = 0; v < nv; ++v) {
    double x, y, z;
    in >> x >> y >> z;
    m.mesh.xy.push_back({x, y});
    m.mesh.z.push_back(z);
  }
  in >> key >> nf >> total;
  if (key != "POLYGONS" || total != 4 * nf)
    return ::testing::AssertionFailure() << "bad POLYGONS line";
  for (std::size_t t = 0; t < nf; ++t) {
    unsigned count;
    in >> count;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t i;
      in >> i;
      m.mesh.triangles.push_back(i);
    }
    if (count != 3)
      return ::testing::AssertionFailure() << "polygon " << t << " is not a triangle";
  }
  if (!in)
    return ::testing::AssertionFailure() << path << ": truncated";
  return ::testing::AssertionSuccess();
}

// ---- invariants
// -------------------------------------------------------------------------

/// Bitwise identity of a point: equal doubles with equal bits (0.0 vs -0.0 differ).
using PointBits = std::array<std::uint64_t, 3>;

PointBits bitsOf(double x, double y, double z)
{
  PointBits b;
  std::memcpy(&b[0], &x, 8);
  std::memcpy(&b[1], &y, 8);
  std::memcpy(&b[2], &z, 8);
  return b;
}

std::vector<Point2> distinctXy(const std::vector<Xyz>& points)
{
  std::vector<Point2> xy;
  for (const Xyz& p : points)
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
      xy.push_back({p[0], p[1]});
  std::sort(xy.begin(), xy.end(), pcl_vts::lexLess);
  xy.erase(std::unique(xy.begin(), xy.end()), xy.end());
  return xy;
}

/// Points on the boundary of the convex hull, collinear ones included: a strict
/// monotone-chain hull (exact orient2d), then every point on one of its edges.
std::size_t hullBoundaryCount(const std::vector<Point2>& sorted_distinct)
{
  const auto& p = sorted_distinct;
  std::vector<Point2> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 &&
           pcl_vts::orient2d(hull[k - 2], hull[k - 1], p[i]) != Sign::POSITIVE)
      --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower &&
           pcl_vts::orient2d(hull[k - 2], hull[k - 1], p[i]) != Sign::POSITIVE)
      --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  std::size_t count = 0;
  for (const Point2& q : p)
    for (std::size_t e = 0; e < hull.size(); ++e) {
      const Point2& a = hull[e];
      const Point2& b = hull[(e + 1) % hull.size()];
      if (pcl_vts::orient2d(a, b, q) == Sign::ZERO && std::min(a.x, b.x) <= q.x &&
          q.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= q.y &&
          q.y <= std::max(a.y, b.y)) {
        ++count;
        break;
      }
    }
  return count;
}

/// The summary line "  <label>   <number>" of a successful run.
std::size_t summaryValue(const std::string& out, const std::string& label)
{
  const std::string key = "\n  " + label + " ";
  const std::size_t at = out.find(key);
  EXPECT_NE(at, std::string::npos) << "no '" << label << "' in the summary:\n" << out;
  if (at == std::string::npos)
    return 0;
  return std::stoul(out.substr(at + key.size()));
}

/// The checks every output mesh must pass, whatever the input: a triangulation of
/// the hull of the distinct input XY, CCW, every vertex used, each vertex one of the
/// input points (bit for bit; z may be any input z at that XY).
void expectTriangulationOfInput(const TriangleMesh& mesh, const std::vector<Xyz>& input)
{
  const std::vector<Point2> distinct = distinctXy(input);
  const std::size_t n = distinct.size();
  const std::size_t h = hullBoundaryCount(distinct);
  ASSERT_EQ(mesh.vertexCount(), n);
  EXPECT_EQ(mesh.triangleCount(), 2 * n - h - 2) << "n = " << n << ", h = " << h;
  std::vector<bool> used(n, false);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const pcl_vts::VertexId* v = &mesh.triangles[3 * t];
    ASSERT_TRUE(v[0] < n && v[1] < n && v[2] < n) << "triangle " << t;
    EXPECT_EQ(pcl_vts::orient2d(mesh.xy[v[0]], mesh.xy[v[1]], mesh.xy[v[2]]),
              Sign::POSITIVE)
        << "triangle " << t << " is not CCW";
    used[v[0]] = used[v[1]] = used[v[2]] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unused vertices";
  std::set<PointBits> inputs;
  for (const Xyz& p : input)
    inputs.insert(bitsOf(p[0], p[1], p[2]));
  std::size_t foreign = 0;
  for (std::size_t v = 0; v < n; ++v)
    foreign += inputs.count(bitsOf(mesh.xy[v].x, mesh.xy[v].y, mesh.z[v])) == 0;
  EXPECT_EQ(foreign, 0u) << "vertices that are not input points, bit for bit";
}

void expectDelaunay(TriangleMesh& mesh)
{
  ASSERT_TRUE(mesh.rebuildHalfedges()) << "not an edge-manifold triangulation";
  std::string why;
  EXPECT_TRUE(pcl_vts::isDelaunay(mesh, &why)) << why;
  EXPECT_TRUE(pcl_vts::isEdgeManifold(mesh, &why)) << why;
}

// ---- failures: exit status, one stderr line, no file
// ----------------------------------

TEST_F(PcdToMesh, MissingInputFileIsAnInputError)
{
  const auto before = workFiles();
  expectFailure(run({"absent.pcd", "out.ply"}), 2, "absent.pcd", before);
}

TEST_F(PcdToMesh, EmptyFileIsAnInputErrorNotACrash)
{
  writeBytes(work("empty.pcd"), "");
  const auto before = workFiles();
  expectFailure(run({"empty.pcd", "out.ply"}), 2, "empty (0 bytes)", before);
}

TEST_F(PcdToMesh, HeaderOnlyFileIsTruncated)
{
  writeBytes(work("h.pcd"), pcdHeader("x y z", "4 4 4", "F F F", 10, "binary"));
  const auto before = workFiles();
  expectFailure(run({"h.pcd", "out.ply"}), 2, "truncated", before);
}

TEST_F(PcdToMesh, HeaderWithZeroPointsIsEmptyInput)
{
  writeBytes(work("h.pcd"), pcdHeader("x y z", "4 4 4", "F F F", 0, "binary"));
  const auto before = workFiles();
  expectFailure(run({"h.pcd", "out.ply"}), 3, "0 points", before);
}

TEST_F(PcdToMesh, TruncatedBinaryBodyIsAnInputError)
{
  std::string bytes = binaryPcd64(utmCloud(100, 1));
  bytes.resize(bytes.size() - 50);
  writeBytes(work("t.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"t.pcd", "out.ply"}), 2, "truncated", before);
}

TEST_F(PcdToMesh, WrongMagicIsNotAPcdFile)
{
  writeBytes(work("m.pcd"), "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n");
  const auto before = workFiles();
  expectFailure(run({"m.pcd", "out.ply"}), 2, "not a PCD file", before);
}

TEST_F(PcdToMesh, HeaderClaimingTwoBillionPointsFailsWithoutAllocating)
{
  std::string bytes = pcdHeader("x y z", "4 4 4", "F F F", 2000000000, "binary");
  bytes += std::string(1200, '\0');
  writeBytes(work("huge.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"huge.pcd", "out.ply"}), 2, "2000000000", before);
}

TEST_F(PcdToMesh, CompressedBodyThatLiesAboutItsSizeIsAnInputError)
{
  std::string bytes = pcdHeader("x y z", "4 4 4", "F F F", 1000, "binary_compressed");
  const std::uint32_t sizes[2] = {16, 12000}; // 16 LZF bytes cannot unpack to 12000
  bytes.append(reinterpret_cast<const char*>(sizes), 8);
  bytes += std::string(16, '\x01');
  writeBytes(work("c.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"c.pcd", "out.ply"}), 2, "corrupt", before);
}

TEST_F(PcdToMesh, FileWithoutXyzFieldsIsAnInputError)
{
  std::string bytes = pcdHeader("a b c", "4 4 4", "F F F", 3, "ascii");
  bytes += "1 2 3\n4 5 6\n7 8 10\n";
  writeBytes(work("abc.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"abc.pcd", "out.ply"}), 2, "no 'x' field", before);
}

TEST_F(PcdToMesh, AsciiValueThatIsNotANumberIsAnErrorNotAZero)
{
  // PCL's own ASCII reader would store 0 here and carry on.
  std::string bytes = pcdHeader("x y z", "4 4 4", "F F F", 4, "ascii");
  bytes += "0 0 1\n10 0 2\n0 1O 3\n10 10 4\n";
  writeBytes(work("a.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"a.pcd", "out.ply"}), 2, "'1O' is not a number", before);
}

TEST_F(PcdToMesh, AsciiLineWithMissingValueIsAnError)
{
  std::string bytes = pcdHeader("x y z", "4 4 4", "F F F", 4, "ascii");
  bytes += "100.25 200.5 1.125\n110.25 200.5 2.125\n100.25 210.5\n110.25 210.5 4.125\n";
  writeBytes(work("a.pcd"), bytes);
  const auto before = workFiles();
  expectFailure(run({"a.pcd", "out.ply"}), 2, "has 2 values, expected 3", before);
}

TEST_F(PcdToMesh, AllPointsIdenticalIsUnusableData)
{
  writeBytes(work("same.pcd"), asciiPcd(std::vector<Xyz>(10, Xyz{3.5, 4.5, 1.0})));
  const auto before = workFiles();
  expectFailure(run({"same.pcd", "out.ply"}), 3, "TOO_FEW_POINTS", before);
}

TEST_F(PcdToMesh, AllCollinearIsUnusableData)
{
  std::vector<Xyz> line;
  for (int i = 0; i < 20; ++i)
    line.push_back({1.0 + 2.0 * i, 5.0 - i, 0.5 * i});
  writeBytes(work("line.pcd"), asciiPcd(line));
  const auto before = workFiles();
  expectFailure(run({"line.pcd", "out.ply"}), 3, "ALL_COLLINEAR", before);
}

TEST_F(PcdToMesh, TwoPointsAreTooFew)
{
  writeBytes(work("two.pcd"), asciiPcd({{0, 0, 0}, {1, 1, 1}}));
  const auto before = workFiles();
  expectFailure(run({"two.pcd", "out.ply"}), 3, "TOO_FEW_POINTS", before);
}

TEST_F(PcdToMesh, MissingOutputFolderIsAnOutputError)
{
  writeBytes(work("in.pcd"), binaryPcd64(utmCloud(50, 2)));
  const auto before = workFiles();
  expectFailure(run({"in.pcd", "no/such/folder/out.ply"}), 4, "does not exist", before);
}

TEST_F(PcdToMesh, OutputPathThatIsAFolderIsAnOutputError)
{
  writeBytes(work("in.pcd"), binaryPcd64(utmCloud(50, 2)));
  fs::create_directory(work("mesh.ply"));
  const auto before = workFiles();
  expectFailure(run({"in.pcd", "mesh.ply"}), 4, "mesh.ply", before);
}

TEST_F(PcdToMesh, UnknownOutputExtensionIsAUsageError)
{
  writeBytes(work("in.pcd"), binaryPcd64(utmCloud(50, 2)));
  const auto before = workFiles();
  expectFailure(run({"in.pcd", "out.stl"}), 1, "unknown output extension", before);
  expectFailure(run({"in.pcd", "out"}), 1, "unknown output extension", before);
}

TEST_F(PcdToMesh, BadOptionValuesAndUnknownOptionsAreUsageErrors)
{
  writeBytes(work("in.pcd"), binaryPcd64(utmCloud(50, 2)));
  const auto before = workFiles();
  expectFailure(run({"in.pcd", "out.ply", "--cell-size", "-1"}), 1, "'-1' must be >= 0",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--cell-size", "abc"}), 1, "not a number",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--cell-size", "2m"}), 1, "not a number",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--cell-size", "inf"}), 1, "out of range",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--cell-size"}), 1, "needs a value", before);
  // Well-formed but absurd for this cloud: the core's own limit, still a usage error.
  expectFailure(run({"in.pcd", "out.ply", "--cell-size", "1e-12"}), 1,
                "options rejected", before);
  expectFailure(run({"in.pcd", "out.ply", "--frobnicate"}), 1, "--frobnicate", before);
  expectFailure(run({"in.pcd", "out.ply", "--duplicates", "median"}), 1, "median",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--no-trim=yes"}), 1, "takes no value",
                before);
  expectFailure(run({"in.pcd"}), 1, "expected INPUT... and OUTPUT", before);
  expectFailure(run({"in.pcd", "out.ply", "--memory-limit", "lots"}), 1, "512M",
                before);
  expectFailure(run({"in.pcd", "out.ply", "--tile-level", "11"}), 1, "0..10", before);
}

TEST_F(PcdToMesh, WriteFailureMidFileIsAnOutputErrorAndLeavesNoFile)
{
  // A 4 KiB file size limit: the mesh (~760 KB) fails part-way with EFBIG.
  const auto before = workFiles();
  expectFailure(
      run({TEST_DATA + "/samp11-utm-ground.pcd", "big.ply"}, "ulimit -f 8 &&"), 4,
      "File too large", before);
}

TEST_F(PcdToMesh, FailedRunLeavesAnExistingOutputUntouched)
{
  std::vector<Xyz> line;
  for (int i = 0; i < 5; ++i)
    line.push_back({double(i), double(i), 0.0});
  writeBytes(work("line.pcd"), asciiPcd(line));
  writeBytes(work("out.ply"), "previous mesh");
  const auto before = workFiles();
  expectFailure(run({"line.pcd", "out.ply"}), 3, "ALL_COLLINEAR", before);
  EXPECT_EQ(readText(work("out.ply")), "previous mesh");
}

TEST_F(PcdToMesh, HelpListsEveryOptionWithItsDefaultAndExitsZero)
{
  for (const char* flag : {"--help", "-h"}) {
    const CliResult r = run({flag});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(r.err.empty()) << r.err;
    for (const char* option :
         {"--cell-size", "--duplicates", "--classes", "--returns", "--no-trim",
          "--no-fill", "--ascii", "--double", "--quiet", "--help"})
      EXPECT_NE(r.out.find(option), std::string::npos) << option;
    std::size_t defaults = 0;
    for (std::size_t at = r.out.find("(default"); at != std::string::npos;
         at = r.out.find("(default", at + 1))
      ++defaults;
    EXPECT_GE(defaults, 7u) << "each option states its default";
    for (const char* code : {"  0  ", "  1  ", "  2  ", "  3  ", "  4  ", "  5  "})
      EXPECT_NE(r.out.find(code), std::string::npos) << "exit code" << code;
  }
}

// ---- successes: the mesh read back
// -----------------------------------------------------

TEST_F(PcdToMesh, Samp11GroundToBinaryPlyIsTheHullTriangulation)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  const CliResult r = runDelaunay({input, "samp11.ply"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_EQ(workFiles(), std::vector<std::string>{"samp11.ply"}) << "temp file left";

  MeshFile m;
  ASSERT_TRUE(readPly(work("samp11.ply").string(), m));
  EXPECT_TRUE(m.binary);
  EXPECT_EQ(m.vertex_type, "float") << "float32 input: float vertices are exact";
  const std::vector<Xyz> points = loadFloat32Pcd(input);
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, points));

  const std::vector<Point2> distinct = distinctXy(points);
  EXPECT_EQ(summaryValue(r.out, "points read"), points.size());
  EXPECT_EQ(summaryValue(r.out, "distinct points"), distinct.size());
  EXPECT_EQ(summaryValue(r.out, "hull vertices"), hullBoundaryCount(distinct));
  EXPECT_EQ(summaryValue(r.out, "triangles"), m.mesh.triangleCount());
  EXPECT_EQ(summaryValue(r.out, "duplicates merged"), points.size() - distinct.size());
  EXPECT_NE(r.out.find("trim         [off : --no-trim]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fill         [off : --no-fill]"), std::string::npos) << r.out;

  // Default duplicate rule: the lowest z at each XY.
  std::map<std::pair<double, double>, double> lowest;
  for (const Xyz& p : points) {
    auto [it, fresh] = lowest.insert({{p[0], p[1]}, p[2]});
    if (!fresh)
      it->second = std::min(it->second, p[2]);
  }
  std::size_t wrong_z = 0;
  for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
    wrong_z += lowest.at({m.mesh.xy[v].x, m.mesh.xy[v].y}) != m.mesh.z[v];
  EXPECT_EQ(wrong_z, 0u);
}

TEST_F(PcdToMesh, AutzenFloat64UpperCaseXyzKeepsEveryBit)
{
  const std::string input = TEST_DATA + "/autzen-utm.pcd";
  const CliResult r = runDelaunay({input, "autzen.ply", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "--quiet prints nothing:\n" << r.out;
  MeshFile m;
  ASSERT_TRUE(readPly(work("autzen.ply").string(), m));
  EXPECT_EQ(m.vertex_type, "double");
  const std::vector<Xyz> points = loadBinaryFloat64Pcd(input, {"X", "Y", "Z"});
  ASSERT_EQ(points.size(), 1065u);
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, points));
  // No duplicates in this file, so every input point must come back, bit for bit.
  std::set<PointBits> in, out;
  for (const Xyz& p : points)
    in.insert(bitsOf(p[0], p[1], p[2]));
  for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
    out.insert(bitsOf(m.mesh.xy[v].x, m.mesh.xy[v].y, m.mesh.z[v]));
  EXPECT_EQ(in, out);
}

TEST_F(PcdToMesh, UtmMillimetreCloudRoundTripsExactlyThroughEveryFormat)
{
  const std::vector<Xyz> points = utmCloud(3000, 42);
  writeBytes(work("utm.pcd"), binaryPcd64(points));
  std::set<PointBits> in;
  for (const Xyz& p : points)
    in.insert(bitsOf(p[0], p[1], p[2]));

  struct Case {
    std::string output;
    std::vector<std::string> options;
    bool binary;
  };
  const std::vector<Case> cases = {{"utm.ply", {}, true},
                                   {"utm_ascii.PLY", {"--ascii"}, false},
                                   {"utm.obj", {}, false},
                                   {"utm.VTK", {}, false}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.output);
    std::vector<std::string> args = {"utm.pcd", c.output};
    args.insert(args.end(), c.options.begin(), c.options.end());
    const CliResult r = runDelaunay(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    MeshFile m;
    const std::string path = work(c.output).string();
    const std::string ext = c.output.substr(c.output.size() - 3);
    if (ext == "ply" || ext == "PLY")
      ASSERT_TRUE(readPly(path, m));
    else if (ext == "obj")
      ASSERT_TRUE(readObj(path, m));
    else
      ASSERT_TRUE(readVtk(path, m));
    if (ext != "obj") {
      EXPECT_EQ(m.vertex_type, "double");
    }
    EXPECT_EQ(m.binary, c.binary);
    ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, points));
    std::set<PointBits> out;
    for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
      out.insert(bitsOf(m.mesh.xy[v].x, m.mesh.xy[v].y, m.mesh.z[v]));
    EXPECT_EQ(in, out) << "every coordinate must survive the file, bit for bit";
  }
  std::vector<std::string> expected = {"utm.VTK", "utm.obj", "utm.pcd", "utm.ply",
                                       "utm_ascii.PLY"};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(workFiles(), expected) << "temp files left behind";
}

TEST_F(PcdToMesh, PclWrittenFloat64FilesOfEveryDataKindRoundTrip)
{
  // x y z float64 between two other fields, written by PCL itself.
  const std::vector<Xyz> points = utmCloud(2000, 7);
  pcl::PCLPointCloud2 cloud;
  cloud.width = static_cast<std::uint32_t>(points.size());
  cloud.height = 1;
  const auto field = [](const char* name, std::uint32_t offset, std::uint8_t type) {
    pcl::PCLPointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    return f;
  };
  cloud.fields = {field("intensity", 0, pcl::PCLPointField::FLOAT32),
                  field("x", 4, pcl::PCLPointField::FLOAT64),
                  field("y", 12, pcl::PCLPointField::FLOAT64),
                  field("z", 20, pcl::PCLPointField::FLOAT64),
                  field("classification", 28, pcl::PCLPointField::UINT8)};
  cloud.point_step = 29;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.assign(cloud.row_step, 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    std::memcpy(&cloud.data[i * cloud.point_step + 4], points[i].data(), 24);

  pcl::PCDWriter writer;
  const Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  const Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  ASSERT_EQ(writer.writeASCII(work("a.pcd").string(), cloud, origin, orientation, 17),
            0);
  ASSERT_EQ(writer.writeBinary(work("b.pcd").string(), cloud), 0);
  ASSERT_EQ(writer.writeBinaryCompressed(work("c.pcd").string(), cloud), 0);
  std::set<PointBits> in;
  for (const Xyz& p : points)
    in.insert(bitsOf(p[0], p[1], p[2]));
  for (const char* name : {"a", "b", "c"}) {
    SCOPED_TRACE(name);
    const CliResult r =
        runDelaunay({std::string(name) + ".pcd", std::string(name) + ".ply"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("x y z float64"), std::string::npos) << r.out;
    MeshFile m;
    ASSERT_TRUE(readPly(work(std::string(name) + ".ply").string(), m));
    EXPECT_EQ(m.vertex_type, "double");
    ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, points));
    std::set<PointBits> out;
    for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
      out.insert(bitsOf(m.mesh.xy[v].x, m.mesh.xy[v].y, m.mesh.z[v]));
    EXPECT_EQ(in, out);
  }
}

TEST_F(PcdToMesh, DoubleOptionForcesDoubleVerticesForFloatInput)
{
  const CliResult r = run({TEST_DATA + "/samp11-utm-ground.pcd", "d.ply", "--double"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  MeshFile m;
  ASSERT_TRUE(readPly(work("d.ply").string(), m));
  EXPECT_EQ(m.vertex_type, "double");
}

TEST_F(PcdToMesh, NonFinitePointsAreDroppedAndCounted)
{
  std::vector<Xyz> points = {{0, 0, 1}, {10, 0, 2}, {0, 10, 3}, {10, 10, 4}, {5, 5, 5}};
  std::string bytes = asciiPcd(points);
  bytes.replace(bytes.find("POINTS 5"), 8, "POINTS 7");
  bytes.replace(bytes.find("WIDTH 5"), 7, "WIDTH 7");
  bytes += "nan 3 3\n4 4 inf\n";
  writeBytes(work("nan.pcd"), bytes);
  const CliResult r = runDelaunay({"nan.pcd", "out.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 7u);
  EXPECT_EQ(summaryValue(r.out, "non-finite dropped"), 2u);
  EXPECT_EQ(summaryValue(r.out, "triangles"), 4u);
  MeshFile m;
  ASSERT_TRUE(readObj(work("out.obj").string(), m));
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, points));
}

TEST_F(PcdToMesh, NoTrimNoFillOutputIsDelaunay)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  const CliResult r = runDelaunay({input, "dt.ply", "--no-trim", "--no-fill"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  MeshFile m;
  ASSERT_TRUE(readPly(work("dt.ply").string(), m));
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, loadFloat32Pcd(input)));
  expectDelaunay(m.mesh);
}

TEST_F(PcdToMesh, NoTrimNoFillOnSharedTerrainIsDelaunay)
{
  const std::string dir = SHARED_DATA + "/pcd/isprs_filtertest";
  if (!fs::exists(dir))
    GTEST_SKIP() << "shared data not found at " << dir;
  for (const char* name :
       {"FSite8_red2-utm.pcd", "samp53-utm.pcd", "samp71-utm-ground.pcd"}) {
    SCOPED_TRACE(name);
    const std::string input = dir + "/" + name;
    const CliResult r =
        runDelaunay({input, "dt.ply", "--no-trim", "--no-fill", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    MeshFile m;
    ASSERT_TRUE(readPly(work("dt.ply").string(), m));
    ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, loadFloat32Pcd(input)));
    expectDelaunay(m.mesh);
  }
}

// ---- the checkers above are shown to fail
// -----------------------------------------------

TEST(PcdToMeshCheckers, HullCountIncludesCollinearBoundaryPoints)
{
  // 3 x 3 lattice: 8 boundary points (4 corners + 4 edge midpoints), 1 interior.
  std::vector<Xyz> grid;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      grid.push_back({double(i), double(j), 0.0});
  EXPECT_EQ(hullBoundaryCount(distinctXy(grid)), 8u);
}

TEST(PcdToMeshCheckers, TriangulationCheckCatchesFlippedAndForeignVertices)
{
  const std::vector<Xyz> input = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  TriangleMesh good;
  good.xy = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  good.z = {0, 0, 0, 0};
  good.triangles = {0, 1, 3, 0, 3, 2};
  expectTriangulationOfInput(good, input);

  TriangleMesh cw = good;
  std::swap(cw.triangles[1], cw.triangles[2]);
  EXPECT_NONFATAL_FAILURE(expectTriangulationOfInput(cw, input), "is not CCW");

  TriangleMesh moved = good;
  moved.z[3] = std::nextafter(0.0, 1.0);
  EXPECT_NONFATAL_FAILURE(expectTriangulationOfInput(moved, input), "bit for bit");
}

// ---- other input formats (LAS, ASCII grid, XYZ text, PLY) through the same CLI
// ------------------------------------------------------------------------------

/// LAS 1.2, point format 0, written byte by byte: X Y Z int32 = round(v / scale),
/// classification in the low 5 bits of byte 15.
std::string lasFile(const std::vector<Xyz>& points, const std::vector<int>& classes,
                    double scale, const Xyz& offset)
{
  std::string b(227, '\0');
  const auto put = [&b](std::size_t at, const void* v, std::size_t n) {
    std::memcpy(&b[at], v, n); // the test host is little-endian, as LAS is
  };
  std::memcpy(&b[0], "LASF", 4);
  b[24] = 1;
  b[25] = 2;
  const std::uint16_t header_size = 227, record = 20;
  const std::uint32_t offset_to_points = 227;
  const auto count = static_cast<std::uint32_t>(points.size());
  put(94, &header_size, 2);
  put(96, &offset_to_points, 4);
  put(105, &record, 2);
  put(107, &count, 4);
  for (int a = 0; a < 3; ++a) {
    put(131 + 8 * a, &scale, 8);
    put(155 + 8 * a, &offset[a], 8);
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::string r(record, '\0');
    for (int a = 0; a < 3; ++a) {
      const auto v =
          static_cast<std::int32_t>(std::llround((points[i][a] - offset[a]) / scale));
      std::memcpy(&r[4 * a], &v, 4);
    }
    r[14] = 0x09; // return 1 of 1
    r[15] = static_cast<char>(classes.empty() ? 2 : classes[i]);
    b += r;
  }
  return b;
}

/// What a LAS reader must return for lasFile's points: int32 * scale + offset.
std::vector<Xyz> lasRoundTrip(const std::vector<Xyz>& points, double scale,
                              const Xyz& offset)
{
  std::vector<Xyz> out;
  for (const Xyz& p : points) {
    Xyz q;
    for (int a = 0; a < 3; ++a)
      q[a] = static_cast<double>(
                 static_cast<std::int32_t>(std::llround((p[a] - offset[a]) / scale))) *
                 scale +
             offset[a];
    out.push_back(q);
  }
  return out;
}

std::string xyzText(const std::vector<Xyz>& points, const char* header, char sep)
{
  std::string s = header;
  char line[160];
  for (const Xyz& p : points) {
    std::snprintf(line, sizeof(line), "%.17g%c%.17g%c%.17g\n", p[0], sep, p[1], sep,
                  p[2]);
    s += line;
  }
  return s;
}

std::string plyDouble(const std::vector<Xyz>& points)
{
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                  std::to_string(points.size()) +
                  "\nproperty double x\nproperty double y\nproperty double z\n"
                  "end_header\n";
  for (const Xyz& p : points)
    s.append(reinterpret_cast<const char*>(p.data()), 24);
  return s;
}

TEST_F(PcdToMesh, UtmMillimetreCloudRoundTripsThroughEveryInputFormat)
{
  const std::vector<Xyz> points = utmCloud(2000, 11);
  const Xyz offset = {500000.0, 5000000.0, 0.0};
  const std::vector<Xyz> las_points = lasRoundTrip(points, 0.001, offset);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(std::abs(las_points[i][a] - points[i][a]), 1e-6) << "LAS scale 1 mm";
  struct Case {
    std::string input, bytes;
    std::vector<Xyz> expected; ///< what the reader must give, bit for bit
  };
  const std::vector<Case> cases = {
      {"utm.xyz", xyzText(points, "", ' '), points},
      {"utm.CSV", xyzText(points, "X,Y,Z\n", ','), points},
      {"utm.ply", plyDouble(points), points},
      {"utm.las", lasFile(points, {}, 0.001, offset), las_points},
      {"utm.pcd", binaryPcd64(points), points},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.input);
    writeBytes(work(c.input), c.bytes);
    const CliResult r = runDelaunay({c.input, "out.ply"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(summaryValue(r.out, "points read"), points.size());
    EXPECT_EQ(summaryValue(r.out, "points kept"), points.size());
    MeshFile m;
    ASSERT_TRUE(readPly(work("out.ply").string(), m));
    EXPECT_EQ(m.vertex_type, "double");
    ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, c.expected));
    double worst = 0.0;
    for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v) {
      // The input point nearest to this vertex (same XY within 1 mm).
      double best = 1e300;
      for (const Xyz& p : points)
        if (std::abs(p[0] - m.mesh.xy[v].x) < 1e-3 &&
            std::abs(p[1] - m.mesh.xy[v].y) < 1e-3)
          best = std::min(best, std::max({std::abs(p[0] - m.mesh.xy[v].x),
                                          std::abs(p[1] - m.mesh.xy[v].y),
                                          std::abs(p[2] - m.mesh.z[v])}));
      worst = std::max(worst, best);
    }
    EXPECT_LE(worst, 0.5e-3) << "every vertex within the 1 mm input resolution";
  }
}

TEST_F(PcdToMesh, LasClassesOptionKeepsOnlyThoseClasses)
{
  std::vector<Xyz> points = utmCloud(600, 5);
  std::vector<int> classes;
  std::vector<Xyz> ground;
  const Xyz offset = {500000.0, 5000000.0, 0.0};
  const std::vector<Xyz> exact = lasRoundTrip(points, 0.001, offset);
  for (std::size_t i = 0; i < points.size(); ++i) {
    classes.push_back(i % 3 == 0 ? 2 : (i % 3 == 1 ? 1 : 9));
    if (classes.back() != 1)
      ground.push_back(exact[i]);
  }
  writeBytes(work("c.las"), lasFile(points, classes, 0.001, offset));
  const CliResult r = runDelaunay({"c.las", "g.ply", "--classes", "2,9"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 600u);
  EXPECT_EQ(summaryValue(r.out, "points kept"), ground.size());
  MeshFile m;
  ASSERT_TRUE(readPly(work("g.ply").string(), m));
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, ground));

  const auto before = workFiles();
  expectFailure(runDelaunay({"c.las", "g2.ply", "--classes=6"}), 3,
                "classes present: 1 (200)", before);
  expectFailure(runDelaunay({"c.las", "g2.ply", "--classes", "2,300"}), 1, "'300'",
                before);
  expectFailure(runDelaunay({"c.las", "g2.ply", "--returns", "second"}), 1, "second",
                before);
  writeBytes(work("t.xyz"), xyzText(points, "", ' '));
  const auto before2 = workFiles();
  expectFailure(runDelaunay({"t.xyz", "g2.ply", "--classes", "2"}), 1, "LAS input only",
                before2);
}

TEST_F(PcdToMesh, AscGridCellCentresWithNodataSkipped)
{
  writeBytes(work("g.asc"), "ncols 3\nnrows 3\nxllcorner 500000\nyllcorner 5000000\n"
                            "cellsize 0.5\nnodata_value -9999\n"
                            "1 2 3\n4 -9999 6\n7 8 9\n");
  const CliResult r = runDelaunay({"g.asc", "g.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 9u);
  EXPECT_EQ(summaryValue(r.out, "points kept"), 8u);
  MeshFile m;
  ASSERT_TRUE(readObj(work("g.obj").string(), m));
  std::vector<Xyz> expected;
  const double z[3][3] = {{1, 2, 3}, {4, -9999, 6}, {7, 8, 9}};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      if (z[row][col] != -9999)
        expected.push_back(
            {500000 + 0.5 * (col + 0.5), 5000000 + 0.5 * (3 - row - 0.5), z[row][col]});
  ASSERT_NO_FATAL_FAILURE(expectTriangulationOfInput(m.mesh, expected));
}

TEST_F(PcdToMesh, BadInputOfEveryFormatIsOneLineAndNoFile)
{
  const std::vector<Xyz> points = utmCloud(50, 3);
  const Xyz offset = {500000.0, 5000000.0, 0.0};
  const std::string las = lasFile(points, {}, 0.001, offset);
  std::string las_huge = las;
  const std::uint32_t billions = 3000000000u;
  std::memcpy(&las_huge[107], &billions, 4);
  std::string laz = las;
  laz[104] = static_cast<char>(0x80);
  const std::string ply = plyDouble(points);
  std::string ply_huge = ply;
  ply_huge.replace(ply_huge.find("vertex 50"), 9, "vertex 3000000000");
  const std::string asc_head =
      "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  struct Case {
    std::string name, bytes;
    int exit_code;
    std::string words;
  };
  const std::vector<Case> cases = {
      {"e.las", "", 2, "empty (0 bytes)"},
      {"e.asc", "", 2, "empty (0 bytes)"},
      {"e.xyz", "", 2, "empty (0 bytes)"},
      {"e.ply", "", 2, "empty (0 bytes)"},
      {"h.las", las.substr(0, 227), 2, "truncated"},
      {"h.ply", ply.substr(0, ply.find("end_header") + 11), 2, "truncated"},
      {"h.asc", asc_head, 2, "truncated"},
      {"h.csv", "x,y,z\n", 3, "header line only"},
      {"t.las", las.substr(0, las.size() - 7), 2, "truncated"},
      {"t.ply", ply.substr(0, ply.size() - 7), 2, "truncated"},
      {"t.asc", asc_head + "1 2 3\n4 5\n", 2, "truncated"},
      {"m.las", "LASX" + las.substr(4), 2, "no 'LASF' signature"},
      {"m.ply", "ply2\n" + ply.substr(4), 2, "no 'ply' magic"},
      {"m.asc", "ply\nformat ascii 1.0\n", 2, "not an ESRI ASCII grid"},
      {"m.xyz", las, 2, "not a text file"},
      {"b.las", las_huge, 2, "3000000000"},
      {"b.ply", ply_huge, 2, "3000000000"},
      {"b.asc", "ncols 90000\nnrows 90000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n",
       2, "90000 x 90000"},
      {"z.laz", laz, 2, "no 'laszip encoded' VLR"},
      {"n.xyz", "1 2 3\n4 5 x\n", 2, "'x' is not a number"},
      {"u.foo", "some text\n", 2, "unknown input format"},
      {"same.xyz", "1 1 1\n1 1 2\n1 1 3\n1 1 4\n", 3, "TOO_FEW_POINTS"},
      {"line.asc",
       "ncols 5\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4 5\n", 3,
       "ALL_COLLINEAR"},
      {"nodata.asc", asc_head + "nodata_value 0\n0 0 0\n0 0 0\n", 3, "NODATA"},
      {"nan.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
       "property float y\nproperty float z\nend_header\nnan 0 0\n0 nan 0\n"
       "0 0 inf\n",
       3, "EMPTY_INPUT"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    writeBytes(work(c.name), c.bytes);
    const auto before = workFiles();
    expectFailure(run({c.name, "out.ply"}), c.exit_code, c.words, before);
  }
}

TEST_F(PcdToMesh, NonFinitePointsOfTextInputAreDroppedAndCounted)
{
  writeBytes(work("n.xyz"),
             "0 0 1\n10 0 2\nnan 3 3\n0 10 3\n4 4 inf\n10 10 4\n5 5 5\n");
  const CliResult r = run({"n.xyz", "out.ply"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 7u);
  EXPECT_EQ(summaryValue(r.out, "non-finite dropped"), 2u);
  EXPECT_EQ(summaryValue(r.out, "triangles"), 4u);
}

TEST_F(PcdToMesh, SharedLasAndDemFilesMeshDirectly)
{
  const std::string las = SHARED_DATA + "/las/pdal/simple.las";
  const std::string asc = SHARED_DATA + "/dem/landlab/hugo_site.asc";
  if (!fs::exists(las) || !fs::exists(asc))
    GTEST_SKIP() << "shared data not found at " << SHARED_DATA;
  CliResult r = run({las, "s.ply", "--classes", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 1065u);
  EXPECT_EQ(summaryValue(r.out, "points kept"), 276u);
  EXPECT_EQ(summaryValue(r.out, "distinct points"), 276u);
  r = run({asc, "h.ply"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points read"), 76u * 55u);
  EXPECT_EQ(summaryValue(r.out, "points kept"), 2152u);
  EXPECT_EQ(summaryValue(r.out, "distinct points"), 2152u);
}

TEST_F(PcdToMesh, InputThatIsAFolderIsAnInputError)
{
  for (const char* name : {"d.las", "d.xyz", "d.asc", "d.ply", "d.pcd"}) {
    fs::create_directory(work(name));
    const auto before = workFiles();
    expectFailure(run({name, "out.ply"}), 2, "", before);
    const CliResult r = run({name, "out.ply"});
    // A folder is a list of inputs: an empty one names itself.
    EXPECT_NE(r.err.find("holds no file with a supported extension"), std::string::npos)
        << r.err;
  }
}

TEST_F(PcdToMesh, UnreadableInputAndUnwritableFolderAreErrors)
{
  if (::geteuid() == 0)
    GTEST_SKIP() << "running as root: file permissions do not apply";
  writeBytes(work("in.xyz"), "0 0 0\n1 0 0\n0 1 0\n");
  fs::permissions(work("in.xyz"), fs::perms::none);
  fs::create_directory(work("ro"));
  fs::permissions(work("ro"), fs::perms::owner_read | fs::perms::owner_exec);
  const auto before = workFiles();
  expectFailure(run({"in.xyz", "out.ply"}), 2, "Permission denied", before);
  fs::permissions(work("in.xyz"), fs::perms::owner_all);
  expectFailure(run({"in.xyz", "ro/out.ply"}), 4, "not writable", before);
  fs::permissions(work("ro"), fs::perms::owner_all);
}

TEST_F(PcdToMesh, UtmMillimetreAscGridKeepsEveryCellCentre)
{
  // 30 x 20 cells of 1 mm at easting 5e5, northing 5e6: every centre must come out
  // within far less than the 1 mm resolution of its exact decimal position.
  const int ncols = 30, nrows = 20;
  std::string grid = "ncols 30\nnrows 20\nxllcorner 500000.000\nyllcorner 5000000.000\n"
                     "cellsize 0.001\nnodata_value -9999\n";
  std::map<std::pair<int, int>, double> z;
  for (int r = 0; r < nrows; ++r) {
    for (int c = 0; c < ncols; ++c) {
      const double v = 120.0 + 0.001 * ((r * 7919 + c * 104729) % 20000);
      char text[32];
      std::snprintf(text, sizeof(text), "%.3f ", v);
      grid += text;
      z[{c, nrows - 1 - r}] = std::strtod(text, nullptr);
    }
    grid += "\n";
  }
  writeBytes(work("utm.asc"), grid);
  const CliResult r = run({"utm.asc", "utm.ply"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summaryValue(r.out, "points kept"), std::size_t(ncols * nrows));
  MeshFile m;
  ASSERT_TRUE(readPly(work("utm.ply").string(), m));
  ASSERT_EQ(m.mesh.vertexCount(), std::size_t(ncols * nrows));
  EXPECT_EQ(m.vertex_type, "double");
  std::set<std::pair<int, int>> seen;
  for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v) {
    // Exact centre of cell (c, row from the bottom): 5e5 + (c + 0.5) mm.
    const long double fx =
        (static_cast<long double>(m.mesh.xy[v].x) - 500000.0L) * 1000;
    const long double fy =
        (static_cast<long double>(m.mesh.xy[v].y) - 5000000.0L) * 1000;
    const auto c = static_cast<int>(std::floor(fx));
    const auto row = static_cast<int>(std::floor(fy));
    ASSERT_TRUE(c >= 0 && c < ncols && row >= 0 && row < nrows) << v;
    EXPECT_LE(std::abs(fx - (c + 0.5L)), 1e-6L) << "x off its centre by > 1 nm";
    EXPECT_LE(std::abs(fy - (row + 0.5L)), 1e-6L) << "y off its centre by > 1 nm";
    EXPECT_EQ(m.mesh.z[v], z.at({c, row}));
    seen.insert({c, row});
  }
  EXPECT_EQ(seen.size(), std::size_t(ncols * nrows));
}

TEST_F(PcdToMesh, EverySharedLasAscAndPcdFileMeshesDirectly)
{
  if (!fs::exists(SHARED_DATA + "/las"))
    GTEST_SKIP() << "shared data not found at " << SHARED_DATA;
  // Points in each file (records, or valid cells of a grid) from
  // ../shared/data/README.md; PCD files are checked against PCL's own reader.
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected = {
      {"las/pdal/autzen_trim.las", {110000, 110000}},
      {"las/from_laz/lidR_Topography.las", {73403, 73403}},
      {"las/from_laz/pdal_las_with_several_extra_byte_bloc.las", {697721, 697721}},
      {"las/pdal/hexbin-crop.las", {38367, 38367}},
      {"las/pdal/4_6_crop.las", {23875, 23875}},
      {"las/laspy/file_with_both_wkt_and_geotiff_vlrs.las", {25408, 25408}},
      {"las/pdal/sample_c.las", {14408, 14408}},
      {"las/liblas/certainty3d-color-utm-feet-navd88.las", {10126, 10126}},
      {"las/pdal/mvk-thin.las", {6280, 6280}},
      {"las/pdal/epsg_4326.las", {5380, 5380}},
      {"las/pdal/warsaw_small.las", {3000, 3000}},
      {"las/pdal/simple.las", {1065, 1065}},
      {"las/pdal/test1_4.las", {1000, 1000}},
      {"dem/landlab/west_bijou_gully.asc", {43 * 89, 1088}},
      {"dem/landlab/hugo_site.asc", {76 * 55, 2152}},
      {"dem/landlab/zSW3.asc", {300 * 452, 100448}},
      {"dem/landlab/pre_runout_DEM.asc", {80 * 122, 9638}},
      {"dem/landlab/SRTMGL3_boulder_40.09_-105.55.asc", {240 * 144, 34560}},
      {"dem/topotoolbox/exampleDEM_orkhon.asc", {98 * 180, 17640}},
      {"dem/pysheds/dem.derived.asc", {367 * 359, 131753}},
      {"dem/topotoolbox/srtm_bigtujunga30m_utm11.derived.asc", {1197 * 643, 769671}}};
  std::size_t files = 0;
  // laz/ holds the LAZ files' uncompressed twins (some with 0 or 1 point): the LAZ
  // reader's tests compare them; this test covers the meshable collections.
  std::vector<fs::path> paths;
  for (const char* folder : {"las", "dem", "pcd"})
    for (const auto& entry :
         fs::recursive_directory_iterator(SHARED_DATA + "/" + folder))
      paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  for (const fs::path& path : paths) {
    const fs::directory_entry entry(path);
    const std::string ext = entry.path().extension().string();
    if (ext != ".las" && ext != ".asc" && ext != ".pcd")
      continue;
    const std::string rel = fs::relative(entry.path(), SHARED_DATA).string();
    SCOPED_TRACE(rel);
    ++files;
    const CliResult r = run({entry.path().string(), "m.ply"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::size_t read = 0, kept = 0;
    if (ext == ".pcd") {
      // autzen-utm.pcd has float64 upper-case X Y Z, which PointXYZ cannot map.
      read = kept = rel.find("autzen") != std::string::npos
                        ? 1065
                        : loadFloat32Pcd(entry.path().string()).size();
    } else {
      ASSERT_EQ(expected.count(rel), 1u) << "a new file: add its counts here";
      std::tie(read, kept) = expected.at(rel);
    }
    EXPECT_EQ(summaryValue(r.out, "points read"), read);
    EXPECT_EQ(summaryValue(r.out, "points kept"), kept);
    EXPECT_GT(summaryValue(r.out, "triangles"), kept / 2);
  }
  EXPECT_EQ(files, 13u + 8u + 33u);
}

} // namespace

namespace pcl_vts {
namespace {

TEST_F(PcdToMesh, DefaultPipelineTrimsAndFillsIntoAManifoldMesh)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  const CliResult full = run({input, "surface.ply", "--threads", "2"});
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const CliResult raw = runDelaunay({input, "raw.ply"});
  ASSERT_EQ(raw.exit_code, 0) << raw.err;
  EXPECT_NE(full.out.find("  trim         [done"), std::string::npos) << full.out;
  EXPECT_NE(full.out.find("  fill         [done"), std::string::npos) << full.out;

  MeshFile surface, delaunay;
  ASSERT_TRUE(readPly(work("surface.ply").string(), surface));
  ASSERT_TRUE(readPly(work("raw.ply").string(), delaunay));
  TriangleMesh& mesh = surface.mesh;
  ASSERT_TRUE(mesh.rebuildHalfedges()) << "an edge is used by more than two triangles";
  std::string why;
  EXPECT_TRUE(isEdgeManifold(mesh, &why)) << why;
  EXPECT_TRUE(allTrianglesCcw(mesh, &why)) << why;
  // Both files are in canonical order (Morton code, x, y): without the inserted
  // points, the surface's vertices are the triangulation's, in the same order; the
  // summary counts agree with the file.
  const std::size_t inserted = summaryValue(full.out, "points inserted");
  EXPECT_GT(inserted, 0u) << "samp11 ground has building holes to fill";
  ASSERT_EQ(mesh.vertexCount(), delaunay.mesh.vertexCount() + inserted);
  ASSERT_EQ(surface.inserted.size(), mesh.vertexCount());
  std::size_t marked = 0, next = 0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (surface.inserted[v] != 0) {
      ++marked;
      continue;
    }
    ASSERT_LT(next, delaunay.mesh.vertexCount());
    ASSERT_TRUE(mesh.xy[v] == delaunay.mesh.xy[next++]) << "vertex " << v << " moved";
  }
  EXPECT_EQ(marked, inserted);
  EXPECT_TRUE(delaunay.inserted.empty());
  EXPECT_EQ(summaryValue(full.out, "triangles"), mesh.triangleCount());
  EXPECT_GT(summaryValue(full.out, "trimmed triangles"), 0u);
  // Trimming removed boundary triangles: the outline is no longer the hull's.
  EXPECT_NE(boundaryEdgeCount(mesh), boundaryEdgeCount(delaunay.mesh));
}

TEST_F(PcdToMesh, PostPassOptionsAreValidated)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  expectUsageErrors(input, {{"--trim-factor", "0"},
                            {"--trim-factor", "-1"},
                            {"--max-edge", "-2"},
                            {"--max-hole-area", "nan"},
                            {"--threads", "1.5"},
                            {"--threads", "-1"}});
}

} // namespace
} // namespace pcl_vts

namespace pcl_vts {
namespace {

/// Output vertices as bit patterns, and a check that each is an input point.
std::set<PointBits> vertexBits(const MeshFile& m)
{
  std::set<PointBits> out;
  for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
    out.insert(bitsOf(m.mesh.xy[v].x, m.mesh.xy[v].y, m.mesh.z[v]));
  return out;
}

TEST_F(PcdToMesh, PreprocessingKeepsOriginalPointsBitForBit)
{
  std::vector<Xyz> points = utmCloud(4000, 7);
  // A spike far above the surface for the outlier filter.
  points.push_back({points[100][0] + 0.0005, points[100][1] + 0.0005, 1e4});
  writeBytes(work("in.pcd"), binaryPcd64(points));
  std::set<PointBits> input;
  double xmin = points[0][0], xmax = xmin, ymin = points[0][1], ymax = ymin;
  for (const Xyz& p : points) {
    input.insert(bitsOf(p[0], p[1], p[2]));
    xmin = std::min(xmin, p[0]);
    xmax = std::max(xmax, p[0]);
    ymin = std::min(ymin, p[1]);
    ymax = std::max(ymax, p[1]);
  }
  const double xmid = 0.5 * (xmin + xmax), ymid = 0.5 * (ymin + ymax);
  char crop[256];
  std::snprintf(crop, sizeof(crop), "%.17g,%.17g,%.17g,%.17g", xmin, ymin, xmid, ymid);

  const CliResult r = runDelaunay({"in.pcd", "crop.ply", "--crop", crop});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  MeshFile m;
  ASSERT_TRUE(readPly(work("crop.ply").string(), m));
  std::size_t inside = 0;
  for (const Xyz& p : points)
    inside += p[0] <= xmid && p[1] <= ymid;
  EXPECT_EQ(m.mesh.vertexCount(), inside);
  for (const PointBits& b : vertexBits(m))
    EXPECT_TRUE(input.count(b)) << "a vertex is not an input point";
  for (std::size_t v = 0; v < m.mesh.vertexCount(); ++v)
    EXPECT_TRUE(m.mesh.xy[v].x <= xmid && m.mesh.xy[v].y <= ymid) << v;

  const CliResult f = runDelaunay({"in.pcd", "filtered.ply", "--voxel", "1.5",
                                   "--grid-min", "2", "--outliers", "8,3"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  MeshFile g;
  ASSERT_TRUE(readPly(work("filtered.ply").string(), g));
  // 80 m x 60 m: a 2 m grid keeps at most one point per cell.
  EXPECT_LE(g.mesh.vertexCount(), 41u * 31u);
  EXPECT_GT(g.mesh.vertexCount(), 500u);
  for (const PointBits& b : vertexBits(g))
    EXPECT_TRUE(input.count(b)) << "a vertex is not an input point";
  for (std::size_t v = 0; v < g.mesh.vertexCount(); ++v)
    EXPECT_LT(g.mesh.z[v], 1e3) << "the spike survived the outlier filter";
  EXPECT_NE(f.out.find("  outliers     [done"), std::string::npos) << f.out;
}

TEST_F(PcdToMesh, PreprocessingOptionsAreValidated)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  expectUsageErrors(input, {{"--voxel", "-1"},
                            {"--grid-min", "abc"},
                            {"--outliers", "8"},
                            {"--outliers", "0,2"},
                            {"--outliers", "8,-1"},
                            {"--crop", "1,2,3"},
                            {"--crop", "1,2,3,x"},
                            {"--crop", "5,0,1,1"}});
  // A crop that keeps nothing: unusable data, exit 3.
  const CliResult r = run({input, "out.ply", "--crop", "0,0,1,1"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("crop"), std::string::npos) << r.err;
  EXPECT_TRUE(workFiles().empty());
}

// ---- --png: a picture of the final mesh
// ------------------------------------------------------

TEST_F(PcdToMesh, PngOptionDrawsTheFinalMeshAsADecodablePicture)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  const CliResult r =
      run({input, "out.ply", "--png", "view.PNG", "--png-width", "300"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(workFiles(), (std::vector<std::string>{"out.ply", "view.PNG"}));
  Picture picture;
  std::string error;
  ASSERT_TRUE(test::decodePng(work("view.PNG").string(), picture, error)) << error;
  EXPECT_EQ(picture.width, 2 * 300 + 300 / 50); // top and oblique, a gap between
  std::size_t red = 0, marks = 0;
  for (std::size_t i = 0; i + 2 < picture.rgb.size(); i += 3) {
    const PictureColour c{picture.rgb[i], picture.rgb[i + 1], picture.rgb[i + 2]};
    red += c.r == PICTURE_BOUNDARY.r && c.g == PICTURE_BOUNDARY.g &&
           c.b == PICTURE_BOUNDARY.b;
    marks += c.r == PICTURE_MARK.r && c.g == PICTURE_MARK.g && c.b == PICTURE_MARK.b;
  }
  EXPECT_GT(red, 100u) << "the outline is drawn in red";
  EXPECT_GT(marks, 10u) << "inserted points are drawn as dots";
  EXPECT_NE(r.out.find("Drawing 'view.PNG' [done"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("picture written to"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(", picture "), std::string::npos) << "time of the picture step";
}

TEST_F(PcdToMesh, PngOptionsAreValidated)
{
  const std::string input = TEST_DATA + "/samp11-utm-ground.pcd";
  expectUsageErrors(input, {{"--png", "view.jpg"},
                            {"--png", ".png/"},
                            {"--png-width", "10"},
                            {"--png-width", "1.5"},
                            {"--png-width", "9000"},
                            {"--png-width", "abc"}});
  const auto before = workFiles();
  expectFailure(run({input, "out.ply", "--png-width", "500"}), 1, "needs --png",
                before);
  expectFailure(run({input, "out.ply", "--png"}), 1, "needs a value", before);
}

TEST_F(PcdToMesh, UnwritablePngPathIsAnOutputErrorAndLeavesNoFile)
{
  writeBytes(work("in.pcd"), binaryPcd64(utmCloud(60, 3)));
  const auto before = workFiles();
  // Checked before any work: no mesh either.
  expectFailure(run({"in.pcd", "out.ply", "--png", "no/such/view.png"}), 4,
                "does not exist", before);
  fs::create_directory(work("taken.png"));
  const auto with_folder = workFiles();
  expectFailure(run({"in.pcd", "out.ply", "--png", "taken.png"}), 4, "it is a folder",
                with_folder);
  fs::remove(work("taken.png"));
  // The picture fails after the mesh is written (an 8 KiB file size limit: the small
  // mesh fits, the picture does not): exit 4, the complete mesh stays, no partial PNG.
  const CliResult r = run({"in.pcd", "out.ply", "--png", "view.png"}, "ulimit -f 8 &&");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("view.png"), std::string::npos) << r.err;
  EXPECT_EQ(workFiles(), (std::vector<std::string>{"in.pcd", "out.ply"}));
}

TEST_F(PcdToMesh, HelpListsThePngOptions)
{
  const CliResult r = run({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--png FILE"), std::string::npos);
  EXPECT_NE(r.out.find("--png-width N"), std::string::npos);
}

// ---- Many inputs and the tiled path (issue 12) -------------------------------------

/// Splits a cloud into `parts` XYZ files in work/; returns their names.
std::vector<std::string> splitIntoXyzFiles(const std::vector<Xyz>& cloud,
                                           std::size_t parts, const fs::path& folder)
{
  std::vector<std::string> names;
  for (std::size_t k = 0; k < parts; ++k) {
    const std::vector<Xyz> part(
        cloud.begin() + static_cast<long>(k * cloud.size() / parts),
        cloud.begin() + static_cast<long>((k + 1) * cloud.size() / parts));
    names.push_back("part" + std::to_string(k) + ".xyz");
    writeBytes(folder / names.back(), xyzText(part, "", ' '));
  }
  return names;
}

/// A PLY file without its comment line (which names the inputs).
std::string withoutComment(const std::string& ply)
{
  const std::size_t at = ply.find("\ncomment ");
  return at == std::string::npos
             ? ply
             : ply.substr(0, at) + ply.substr(ply.find('\n', at + 1));
}

TEST_F(PcdToMesh, SeveralFilesFoldersAndListsMeshAsOnePointSet)
{
  std::vector<Xyz> cloud = utmCloud(4000, 21);
  cloud.insert(cloud.end(), cloud.begin(),
               cloud.begin() + 500); // duplicates across files
  writeBytes(work("all.xyz"), xyzText(cloud, "", ' '));
  fs::create_directory(work("parts"));
  const std::vector<std::string> names = splitIntoXyzFiles(cloud, 3, work("parts"));
  writeBytes(work("list.txt"), "# the parts\nparts/" + names[0] + "\n\nparts/" +
                                   names[1] + "\n" +
                                   work("parts/" + names[2]).string() + "\n");
  ASSERT_EQ(run({"all.xyz", "one.ply"}).exit_code, 0);
  const std::string expected = withoutComment(readText(work("one.ply")));
  const CliResult files =
      run({"parts/" + names[0], "parts/" + names[1], "parts/" + names[2], "files.ply"});
  ASSERT_EQ(files.exit_code, 0) << files.err;
  EXPECT_EQ(summaryValue(files.out, "points read"), cloud.size());
  EXPECT_EQ(summaryValue(files.out, "duplicates merged"), 500u);
  EXPECT_TRUE(withoutComment(readText(work("files.ply"))) == expected);
  ASSERT_EQ(run({"parts", "folder.ply"}).exit_code, 0);
  EXPECT_TRUE(withoutComment(readText(work("folder.ply"))) == expected);
  // Run twice with the output inside the input folder: the first output is not read.
  for (int k = 0; k < 2; ++k)
    ASSERT_EQ(run({"parts", "parts/inside.ply"}).exit_code, 0);
  EXPECT_TRUE(withoutComment(readText(work("parts/inside.ply"))) == expected);
  ASSERT_EQ(run({"@list.txt", "list.ply"}).exit_code, 0);
  EXPECT_TRUE(withoutComment(readText(work("list.ply"))) == expected);
}

TEST_F(PcdToMesh, ACorruptFileAmongManyIsAnInputErrorNamingIt)
{
  const std::vector<std::string> names = splitIntoXyzFiles(utmCloud(900, 4), 3, work_);
  writeBytes(work("bad.xyz"), "1 2 3\n4 five 6\n");
  const auto before = workFiles();
  expectFailure(run({names[0], "bad.xyz", names[1], "out.ply"}), 2, "bad.xyz", before);
  expectFailure(run({names[0], "bad.xyz", names[1], "out.ply", "--tile-level", "1",
                     "--no-trim", "--no-fill"}),
                2, "bad.xyz", before);
  expectFailure(run({"@missing.txt", "out.ply"}), 2, "missing.txt", before);
}

TEST_F(PcdToMesh, TiledRunWritesTheInMemoryBytesAndLeavesNoTemporaryFile)
{
  const std::vector<std::string> names =
      splitIntoXyzFiles(utmCloud(20000, 8), 4, work_);
  std::vector<std::string> args = names;
  args.push_back("memory.ply");
  const CliResult memory = runDelaunay(args);
  ASSERT_EQ(memory.exit_code, 0) << memory.err;
  for (const std::string level : {"0", "2", "4"}) {
    args.back() = "tiled" + level + ".ply";
    std::vector<std::string> tiled_args = args;
    tiled_args.insert(tiled_args.end(), {"--tile-level", level, "--temp-dir", "."});
    const CliResult tiled = runDelaunay(tiled_args);
    ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
    EXPECT_NE(tiled.out.find("Meshing tiled"), std::string::npos) << tiled.out;
    EXPECT_EQ(summaryValue(tiled.out, "triangles"),
              summaryValue(memory.out, "triangles"));
    EXPECT_EQ(summaryValue(tiled.out, "distinct points"),
              summaryValue(memory.out, "distinct points"));
    EXPECT_TRUE(readText(work(args.back())) == readText(work("memory.ply")))
        << "tiled output differs at tile level " << level;
  }
  // Only the inputs and the meshes: the temporary folder is gone.
  EXPECT_EQ(workFiles().size(), names.size() + 4);
}

TEST_F(PcdToMesh, TiledGroundPmfWritesTheInMemoryBytes)
{
  // --ground pmf (with --crop) on a tiled run: the pre-pass over pre-tiles with the
  // filter's halo keeps the in-memory points, so the mesh has the in-memory bytes,
  // whatever --memory-limit or --tile-level cut it into.
  const std::string input = SHARED_DATA + "/pcd/isprs_filtertest/samp53-utm.pcd";
  if (!fs::exists(input))
    GTEST_SKIP() << "shared data not found at " << input;
  const std::vector<std::string> ground = {"--ground", "pmf", "--pmf-window", "9"};
  const auto with = [&](std::vector<std::string> args,
                        const std::vector<std::string>& more) {
    args.insert(args.end(), ground.begin(), ground.end());
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  const CliResult memory = run(with({input, "memory.ply"}, {}));
  ASSERT_EQ(memory.exit_code, 0) << memory.err;
  // 34378 points need about 11 MB in memory: 10M sends the job to the tiles.
  for (const std::vector<std::string>& tiling :
       {std::vector<std::string>{"--memory-limit", "10M"},
        std::vector<std::string>{"--tile-level", "2"}}) {
    SCOPED_TRACE(tiling[0]);
    const CliResult tiled =
        run(with({input, "tiled.ply"},
                 {tiling[0], tiling[1], "--threads", "1", "--temp-dir", "."}));
    ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
    EXPECT_NE(tiled.out.find("Meshing tiled"), std::string::npos) << tiled.out;
    EXPECT_NE(tiled.out.find("pre-tiles of side"), std::string::npos) << tiled.out;
    EXPECT_TRUE(readText(work("tiled.ply")) == readText(work("memory.ply")));
  }
  const std::vector<std::string> crop = {"--crop", "494750,5420400,495050,5420700"};
  ASSERT_EQ(run(with({input, "memory_crop.ply"}, crop)).exit_code, 0);
  const CliResult tiled_crop =
      run(with({input, "tiled_crop.ply"}, {crop[0], crop[1], "--tile-level", "1"}));
  ASSERT_EQ(tiled_crop.exit_code, 0) << tiled_crop.err;
  EXPECT_TRUE(readText(work("tiled_crop.ply")) == readText(work("memory_crop.ply")));
  EXPECT_TRUE(readText(work("tiled_crop.ply")) != readText(work("memory.ply")));
  // samp24 has 559 duplicates among its ground points: every rule sees the in-memory
  // order (equal XY share a pre-tile file, in input order).
  const std::string samp24 = SHARED_DATA + "/pcd/isprs_filtertest/samp24-utm.pcd";
  for (const std::string rule : {"first", "mean"}) {
    SCOPED_TRACE(rule);
    const std::vector<std::string> dup = {"--duplicates", rule};
    const CliResult m = run(with({samp24, "dup_memory.ply"}, dup));
    ASSERT_EQ(m.exit_code, 0) << m.err;
    EXPECT_GT(summaryValue(m.out, "duplicates merged"), 500u);
    ASSERT_EQ(run(with({samp24, "dup_tiled.ply"},
                       {dup[0], dup[1], "--tile-level", "2", "--temp-dir", "."}))
                  .exit_code,
              0);
    EXPECT_TRUE(readText(work("dup_tiled.ply")) == readText(work("dup_memory.ply")));
  }
  // The other steps are not tiled: a clear refusal, nothing left behind.
  const auto before = workFiles();
  expectFailure(run(with({input, "out.ply"}, {"--voxel", "0.5", "--tile-level", "1"})),
                1, "--voxel, --grid-min, --outliers and --png run in memory only",
                before);
}

TEST_F(PcdToMesh, AJobAboveTheMemoryLimitRunsTiledWithTheInMemoryBytes)
{
  const std::vector<std::string> names =
      splitIntoXyzFiles(utmCloud(120000, 3), 2, work_);
  // 120000 points need about 38 MB in memory: a 24M limit sends the job to the tiles.
  const CliResult tiled =
      runDelaunay({names[0], names[1], "tiled.ply", "--memory-limit", "24M"});
  ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
  EXPECT_NE(tiled.out.find("Meshing tiled"), std::string::npos) << tiled.out;
  ASSERT_EQ(runDelaunay({names[0], names[1], "memory.ply"}).exit_code, 0);
  EXPECT_TRUE(readText(work("tiled.ply")) == readText(work("memory.ply")));
  // The default pipeline (trim, fill): tiled too, the bytes of the in-memory run.
  const CliResult surface =
      run({names[0], names[1], "tiled_surface.ply", "--memory-limit", "24M"});
  ASSERT_EQ(surface.exit_code, 0) << surface.err;
  EXPECT_NE(surface.out.find("Meshing tiled"), std::string::npos) << surface.out;
  EXPECT_NE(surface.out.find("outward triangles removed"), std::string::npos)
      << surface.out;
  EXPECT_NE(surface.out.find("holes found"), std::string::npos) << surface.out;
  const CliResult memory_surface = run({names[0], names[1], "memory_surface.ply"});
  ASSERT_EQ(memory_surface.exit_code, 0);
  EXPECT_TRUE(readText(work("tiled_surface.ply")) ==
              readText(work("memory_surface.ply")));
  // The same counts in both summaries: the triangulation's, then the post-passes'.
  const auto counted = [](const std::string& out, const std::string& phase) {
    const std::size_t at = out.find("  " + phase + " ");
    const std::size_t colon = out.find(" : ", at);
    return at == std::string::npos || colon == std::string::npos
               ? std::string("none")
               : out.substr(colon + 3, out.find_first_of(",]", colon) - colon - 3);
  };
  for (const std::string phase : {"triangulate", "trim", "fill"})
    EXPECT_EQ(counted(surface.out, phase), counted(memory_surface.out, phase)) << phase;
  EXPECT_FALSE(readText(work("tiled_surface.ply")) == readText(work("tiled.ply")));
}

TEST_F(PcdToMesh, TileOutputWritesOneMeshPerTileAndAnIndex)
{
  const std::vector<std::string> names = splitIntoXyzFiles(utmCloud(8000, 6), 2, work_);
  fs::create_directory(work("tiles"));
  const CliResult r = runDelaunay(
      {names[0], names[1], "all.ply", "--tile-output", "tiles", "--tile-level", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string index = readText(work("tiles/index.csv"));
  const std::size_t lines =
      static_cast<std::size_t>(std::count(index.begin(), index.end(), '\n'));
  EXPECT_EQ(lines, summaryValue(r.out, "tiles") + 1) << index; // + the header
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(work("tiles")))
    files += entry.path().extension() == ".ply";
  EXPECT_EQ(files + 1, lines);
  const auto before = workFiles();
  expectFailure(runDelaunay({names[0], "x.ply", "--tile-output", "missing"}), 4,
                "missing", before);
  // The default pipeline too: the tiles of the surface mesh, inserted points marked.
  fs::create_directory(work("surface_tiles"));
  const CliResult surface = run({names[0], names[1], "surface.ply", "--tile-output",
                                 "surface_tiles", "--tile-level", "2"});
  ASSERT_EQ(surface.exit_code, 0) << surface.err;
  const std::string surface_index = readText(work("surface_tiles/index.csv"));
  EXPECT_EQ(static_cast<std::size_t>(
                std::count(surface_index.begin(), surface_index.end(), '\n')),
            lines);
  EXPECT_NE(readText(work("surface_tiles/tile_0_0.ply")).find("global surface mesh"),
            std::string::npos);
}

TEST_F(PcdToMesh, TiledRunsOfTheSharedRealFilesWriteTheInMemoryBytes)
{
  if (!fs::exists(SHARED_DATA + "/las"))
    GTEST_SKIP() << "shared data not found at " << SHARED_DATA;
  // Real LiDAR (UTM and feet, a collinear scan pattern, classes) and DEMs (exact
  // grids with NODATA holes): the tiled triangulation at 16 and 256 tiles equals the
  // in-memory one byte for byte: the triangulation, trimmed, trimmed and filled.
  for (const char* rel :
       {"las/pdal/autzen_trim.las", "las/from_laz/lidR_Topography.las",
        "las/pdal/4_6_crop.las", "las/liblas/certainty3d-color-utm-feet-navd88.las",
        "las/pdal/mvk-thin.las", "dem/landlab/hugo_site.asc",
        "dem/topotoolbox/exampleDEM_orkhon.asc", "dem/landlab/west_bijou_gully.asc"}) {
    SCOPED_TRACE(rel);
    const std::string path = SHARED_DATA + "/" + rel;
    for (const int passes : {0, 1, 2}) { // none, trim, trim and fill
      const auto post = [&](std::vector<std::string> args) {
        if (passes < 2)
          args.push_back("--no-fill");
        if (passes < 1)
          args.push_back("--no-trim");
        return run(args);
      };
      const CliResult memory = post({path, "memory.ply"});
      ASSERT_EQ(memory.exit_code, 0) << memory.err;
      for (const std::string level : {"2", "4"}) {
        const CliResult tiled =
            post({path, "tiled.ply", "--tile-level", level, "--temp-dir", "."});
        ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
        EXPECT_TRUE(readText(work("tiled.ply")) == readText(work("memory.ply")))
            << "tile level " << level << ", post-passes " << passes;
      }
    }
  }
}

TEST_F(PcdToMesh, SigtermDuringATiledRunLeavesNoTemporaryFileAndNoOutput)
{
  const std::vector<std::string> names =
      splitIntoXyzFiles(utmCloud(400000, 9), 4, work_);
  const auto before = workFiles();
  // SIGTERM half a second in: bucketing or meshing, both hold temporary files. (Ctrl-C
  // is SIGINT, handled the same way; a shell starts background jobs with SIGINT
  // ignored, and the tool respects an ignored signal, so the test sends SIGTERM.)
  std::string command =
      "cd " + shellQuote(work_.string()) + " && (" + shellQuote(PCL_VTS_PCD_TO_MESH);
  for (const std::string& name : names)
    command += " " + name;
  command +=
      " out.ply --no-trim --no-fill --tile-level 4 --threads 1 --temp-dir . "
      "> /dev/null 2>&1 & pid=$!; sleep 0.5; kill -TERM $pid; wait $pid; echo $? > " +
      shellQuote((root_ / "logs" / "rc").string()) + ")";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const int rc = std::atoi(readText(root_ / "logs" / "rc").c_str());
  EXPECT_EQ(rc, 128 + SIGTERM) << "the run should end by the signal";
  EXPECT_EQ(workFiles(), before) << "temporary files or a partial output left behind";
}

TEST_F(PcdToMesh, AMemoryLimitBelowWhatATileNeedsNamesTheMinimum)
{
  // 20000 points need ~6 MB in memory: above 1M, so tiled, and below its minimum.
  const std::vector<std::string> names =
      splitIntoXyzFiles(utmCloud(20000, 2), 1, work_);
  const auto before = workFiles();
  expectFailure(runDelaunay({names[0], "out.ply", "--memory-limit", "1M"}), 1,
                "--memory-limit: the memory limit of 1 MiB is below the", before);
}

TEST_F(PcdToMesh, ATemporaryFolderThatIsFullFailsCleanly)
{
  const std::vector<std::string> names =
      splitIntoXyzFiles(utmCloud(30000, 5), 1, work_);
  const auto before = workFiles();
  // A 200 KiB file-size limit: the bucket files cannot be written.
  const CliResult r = run({names[0], "out.ply", "--tile-level", "0", "--no-trim",
                           "--no-fill", "--temp-dir", "."},
                          "ulimit -f 200 &&");
  expectFailure(r, 4, "--temp-dir: cannot ", before);
}

/// Memory tests: each run under GNU time, its peak measured over the process alone
/// (`--help`: PCL's, VTK's and GDAL's libraries mapped, not the job's memory).
class PcdToMeshMemory : public PcdToMesh {
 protected:
  void SetUp() override
  {
    PcdToMesh::SetUp();
    if (std::system("test -x /usr/bin/time") != 0)
      GTEST_SKIP() << "GNU time (Debian package time) is not installed";
    ASSERT_EQ(run({"--help"}, timed()).exit_code, 0);
    process_kib_ = peakKiB();
  }

  /// Runs args; out: its peak RSS over the process alone, in KiB.
  CliResult runMeasured(const std::vector<std::string>& args,
                        std::size_t& job_kib) const
  {
    const CliResult r = run(args, timed());
    const std::size_t peak = peakKiB();
    job_kib = peak - std::min(peak, process_kib_);
    return r;
  }

  std::size_t process_kib_ = 0;

 private:
  std::string timed() const
  {
    return "/usr/bin/time -f %M -o " + shellQuote((root_ / "logs" / "rss").string());
  }
  std::size_t peakKiB() const
  {
    return static_cast<std::size_t>(
        std::strtoull(readText(root_ / "logs" / "rss").c_str(), nullptr, 10));
  }
};

/// The "largest tile N points" of a tiled run's summary; 0 when it is absent.
std::size_t largestTile(const std::string& out)
{
  const std::size_t at = out.find("largest tile ");
  return at == std::string::npos ? 0
                                 : static_cast<std::size_t>(std::strtoull(
                                       out.c_str() + at + 13, nullptr, 10));
}

TEST_F(PcdToMeshMemory, TiledRunStaysWithinTheMemoryLimit)
{
  // 2.25e6 points in 8 LAS files of 1 km² (a LiDAR delivery in miniature): 7 of
  // 250000 and one of 500000, twice as dense and larger than the job's share of the
  // limit if it were read whole. (An L-shaped delivery, with a 1 km² void in a
  // concave corner, makes the tiles at the corner load far more: docs/scaling.md.)
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::string> args;
  for (int k = 0; k < 8; ++k) {
    std::vector<Xyz> points(k == 6 ? 500000 : 250000);
    for (Xyz& p : points)
      p = {500000.0 + 1000.0 * (k % 4) + 1000.0 * u(rng),
           4100000.0 + 1000.0 * (k / 4) + 1000.0 * u(rng), 100.0 + 10.0 * u(rng)};
    args.push_back("t" + std::to_string(k) + ".las");
    writeBytes(work(args.back()),
               lasFile(points, {}, 0.01, {500000.0, 4100000.0, 0.0}));
  }
  args.insert(args.end(), {"out.ply", "--no-trim", "--no-fill", "--memory-limit", "64M",
                           "--threads", "2", "--temp-dir", "."});
  std::size_t job_kib = 0;
  const CliResult r = runMeasured(args, job_kib);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Meshing tiled"), std::string::npos) << r.out;
  EXPECT_LT(job_kib, 64u * 1024u)
      << "the process alone takes " << process_kib_ << " KiB";
  EXPECT_EQ(summaryValue(r.out, "points read"), 2250000u);
}

TEST_F(PcdToMeshMemory, OneFileLargerThanTheLimitIsNeverHeldWhole)
{
  // 600000 points in one XYZ file (17 MB of text, 14 MB as doubles), and the same in
  // one binary PCD of doubles (14 MB): deciding between memory and tiles once read the
  // file whole, and the tiles read it whole again. Both now stream it: the job stays
  // far below a 24M limit.
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::string text;
  text.reserve(600000 * 29);
  std::string pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\n"
                    "COUNT 1 1 1\nWIDTH 600000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
                    "POINTS 600000\nDATA binary\n";
  char line[64];
  for (int i = 0; i < 600000; ++i) {
    const double p[3] = {500000 + 800 * u(rng), 4100000 + 800 * u(rng), 100 + u(rng)};
    std::snprintf(line, sizeof line, "%.2f %.2f %.2f\n", p[0], p[1], p[2]);
    text += line;
    pcd.append(reinterpret_cast<const char*>(p), sizeof p);
  }
  writeBytes(work("big.xyz"), text);
  writeBytes(work("big.pcd"), pcd);
  for (const std::string input : {"big.xyz", "big.pcd"}) {
    SCOPED_TRACE(input);
    std::size_t job_kib = 0;
    const CliResult r =
        runMeasured({input, "out.ply", "--no-trim", "--no-fill", "--memory-limit",
                     "24M", "--threads", "2", "--temp-dir", "."},
                    job_kib);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Meshing tiled"), std::string::npos) << r.out;
    EXPECT_EQ(summaryValue(r.out, "points read"), 600000u);
    EXPECT_LT(job_kib, 24u * 1024u)
        << "the process alone takes " << process_kib_ << " KiB";
  }
}

TEST_F(PcdToMeshMemory, AnLShapedDeliveryStaysWithinTheMemoryLimit)
{
  // 1.2e6 points on 2 km x 2 km less its upper-right quarter (a delivery shaped like
  // an L), 1 cm coordinates. The triangles across the void reach the other arm, and
  // the local hulls of the first rounds had disks over the whole arm: the corner
  // tiles once loaded 665 thousand points (157 MiB over a 64 MiB limit). Halos now
  // take, per triangle or hull edge and round, the blocks a circle grown from the
  // edge reaches first.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 2000.0);
  std::vector<Xyz> points;
  while (points.size() < 1200000) {
    const double x = u(rng), y = u(rng);
    if (x > 1000.0 && y > 1000.0)
      continue;
    points.push_back({500000.0 + x, 4100000.0 + y, 100.0 + x / 1000.0});
  }
  writeBytes(work("l.las"), lasFile(points, {}, 0.01, {500000.0, 4100000.0, 0.0}));
  std::size_t job_kib = 0;
  const CliResult r =
      runMeasured({"l.las", "out.ply", "--no-trim", "--no-fill", "--memory-limit",
                   "64M", "--threads", "2", "--temp-dir", "."},
                  job_kib);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Meshing tiled"), std::string::npos) << r.out;
  EXPECT_LT(job_kib, 64u * 1024u)
      << "the process alone takes " << process_kib_ << " KiB";
  EXPECT_GT(largestTile(r.out), 0u) << r.out;
  EXPECT_LT(largestTile(r.out), 200000u) << r.out;
}

TEST_F(PcdToMeshMemory, CurvedQuantisedBoundaryTilesStayWithinTheMemoryLimit)
{
  const std::string laz = SHARED_DATA + "/laz/las_with_several_extra_byte_bloc.laz";
  if (!fs::exists(laz))
    GTEST_SKIP() << "shared data not found at " << laz;
  // IGN LiDAR HD ground, read from LAZ: a curved data edge made of straight runs of
  // points quantised to 1 cm, so nearly collinear triples along it form triangles too
  // flat for a floating-point circumdisk. Each once made its tile load every block
  // (683023 points in one tile, 160 MiB over a 64 MiB limit); now their disks are
  // bounded by the half-plane beyond the long edge and the disk on it.
  const CliResult memory = runDelaunay({laz, "memory.ply", "--classes", "2"});
  ASSERT_EQ(memory.exit_code, 0) << memory.err;
  for (const std::string threads : {"1", "2"}) {
    SCOPED_TRACE("threads " + threads);
    std::size_t job_kib = 0;
    const CliResult tiled =
        runMeasured({laz, "tiled.ply", "--classes", "2", "--no-trim", "--no-fill",
                     "--memory-limit", "64M", "--threads", threads, "--temp-dir", "."},
                    job_kib);
    ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
    EXPECT_NE(tiled.out.find("Meshing tiled"), std::string::npos) << tiled.out;
    EXPECT_TRUE(readText(work("tiled.ply")) == readText(work("memory.ply")));
    EXPECT_LT(job_kib, 64u * 1024u)
        << "the process alone takes " << process_kib_ << " KiB";
    EXPECT_GT(largestTile(tiled.out), 0u) << tiled.out;
    EXPECT_LT(largestTile(tiled.out), 200000u) << tiled.out;
  }
}

} // namespace
} // namespace pcl_vts
