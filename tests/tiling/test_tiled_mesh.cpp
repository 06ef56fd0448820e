// The tiled path against the in-memory run: the same triangle set and the same file
// bytes (both in canonical order), for every generator and for tilings from one tile
// to tiny tiles; temporary files gone afterwards; bad conditions fail cleanly.
#include "support/cgal_oracle.h"
#include "support/generators.h"
#include "support/synthetic_terrain.h"
#include "support/temp_folder_test.h"

#include <pcl_vts/tiling/tiled_mesh.h>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace pcl_vts {
namespace test {
namespace {

std::string slurp(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Feeds xyz in chunks of `chunk` points, as a reader of several files would.
PointFeed feedOf(const std::vector<double>& xyz, std::size_t chunk = 997)
{
  return [&xyz, chunk](const PointSink& sink) {
    for (std::size_t at = 0; at < xyz.size() / 3; at += chunk) {
      const std::size_t n = std::min(chunk, xyz.size() / 3 - at);
      if (Status s = sink(&xyz[3 * at], n); !s.ok())
        return s;
    }
    return Status::success();
  };
}

/// K ranks as K threads of one process: collectives over shared slots, so the
/// rank logic of the tiled job (parts, ordering, index sharing, agreement) runs in
/// ctest without mpirun.
class InProcessRanks {
 public:
  explicit InProcessRanks(int size)
      : size_(size)
  {}
  class Comm : public JobComm {
   public:
    Comm(InProcessRanks& all, int rank)
        : all_(all)
        , rank_(rank)
    {}
    int rank() const override { return rank_; }
    int size() const override { return all_.size_; }
    void sum(std::vector<std::uint64_t>& v) override
    {
      reduce(v, [](std::uint64_t a, std::uint64_t b) { return a + b; });
    }
    void min(std::vector<double>& v) override
    {
      reduce(v, [](double a, double b) { return std::min(a, b); });
    }
    void max(std::vector<double>& v) override
    {
      reduce(v, [](double a, double b) { return std::max(a, b); });
    }
    void broadcast(std::string& bytes, int root) override
    {
      if (rank_ == root)
        all_.text_ = bytes;
      barrier();
      bytes = all_.text_;
      barrier();
    }
    void barrier() override { all_.wait(); }
    void startTasks() override
    {
      barrier();
      if (rank_ == 0)
        all_.next_ = 0;
      barrier();
    }
    std::uint64_t nextTask() override { return all_.next_.fetch_add(1); }

   private:
    template <typename T, typename Op>
    void reduce(std::vector<T>& v, Op op)
    {
      std::vector<std::vector<T>>& slots = all_.slots<T>();
      {
        const std::lock_guard<std::mutex> lock(all_.mutex_);
        slots.resize(static_cast<std::size_t>(all_.size_));
        slots[static_cast<std::size_t>(rank_)] = v;
      }
      barrier();
      for (int r = 0; r < all_.size_; ++r)
        if (r != rank_)
          for (std::size_t k = 0; k < v.size(); ++k)
            v[k] = op(v[k], slots[static_cast<std::size_t>(r)][k]);
      barrier();
    }
    InProcessRanks& all_;
    int rank_;
  };

 private:
  void wait()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const std::uint64_t generation = generation_;
    if (++arrived_ == size_) {
      arrived_ = 0;
      ++generation_;
      cv_.notify_all();
      return;
    }
    cv_.wait(lock, [&] { return generation_ != generation; });
  }
  template <typename T>
  std::vector<std::vector<T>>& slots();

  int size_;
  std::mutex mutex_;
  std::condition_variable cv_;
  int arrived_ = 0;
  std::uint64_t generation_ = 0;
  std::string text_;
  std::atomic<std::uint64_t> next_{0};
  std::vector<std::vector<std::uint64_t>> u64_;
  std::vector<std::vector<double>> f64_;
};
template <>
std::vector<std::vector<std::uint64_t>>& InProcessRanks::slots<std::uint64_t>()
{
  return u64_;
}
template <>
std::vector<std::vector<double>>& InProcessRanks::slots<double>()
{
  return f64_;
}

class TiledMeshTest : public TempFolderTest {
 protected:
  /// Writes the in-memory run in canonical order; false (with a message) if it fails.
  Status writeInMemory(const std::vector<double>& xyz, const std::string& path,
                       TriangleMesh* canonical = nullptr, const VtsOptions& vts = {},
                       ReconstructionDiagnostics* post = nullptr)
  {
    VtsResult result;
    Status s = runVtsPipeline(xyz.data(), xyz.size() / 3, vts, result);
    if (!s.ok())
      return s;
    // As pcd_to_mesh writes it: filled meshes mark their inserted points.
    std::vector<std::uint8_t>& inserted = result.reconstruction.fill.inserted;
    const bool filled = vts.reconstruction.fill;
    if (Status c = canonicalMesh(result.mesh, filled ? &inserted : nullptr); !c.ok())
      return c;
    // The twins it carries along are the ones a rebuild from its triangles finds.
    TriangleMesh rebuilt = result.mesh;
    EXPECT_TRUE(rebuilt.rebuildHalfedges());
    EXPECT_EQ(result.mesh.halfedges, rebuilt.halfedges);
    if (canonical != nullptr)
      *canonical = result.mesh;
    if (post != nullptr)
      *post = result.reconstruction;
    MeshWriteOptions options;
    options.inserted = filled ? &inserted : nullptr;
    return writeMesh(path, result.mesh, options);
  }

  Status writeTiled(const std::vector<double>& xyz, const std::string& path,
                    int tile_level, int block_level, TiledMeshReport& report,
                    const VtsOptions& vts = {})
  {
    TiledMeshOptions options;
    options.vts = vts;
    options.temp_parent = root_.string();
    options.tile_level = tile_level;
    options.block_level = block_level;
    return runTiledMesh(feedOf(xyz), options, path, MeshWriteOptions{}, report);
  }

  /// Runs the job on `ranks` in-process ranks (rank r gets options(r)); their statuses.
  static std::vector<Status> runRanks(int ranks, const PointInputs& inputs,
                                      const TiledMeshOptions& options,
                                      const std::string& path)
  {
    InProcessRanks all(ranks);
    std::vector<Status> status(static_cast<std::size_t>(ranks));
    std::vector<std::thread> team;
    for (int r = 0; r < ranks; ++r)
      team.emplace_back([&, r] {
        InProcessRanks::Comm comm(all, r);
        TiledMeshReport report;
        status[static_cast<std::size_t>(r)] =
            runTiledMesh(inputs, options, path, MeshWriteOptions{}, report, comm);
      });
    for (std::thread& t : team)
      t.join();
    return status;
  }

  /// xyz as five sources, so that ranks read different inputs.
  static PointInputs fiveSources(const std::vector<double>& xyz)
  {
    PointInputs inputs;
    inputs.count = 5;
    inputs.read = [&xyz](std::size_t k, const PointSink& sink) {
      const std::size_t points = xyz.size() / 3;
      const std::size_t a = points * k / 5, b = points * (k + 1) / 5;
      return b > a ? sink(&xyz[3 * a], b - a) : Status::success();
    };
    return inputs;
  }

  /// Runs xyz tiled with --tile-output (and the post-passes when `post`), and checks
  /// that the tile meshes hold every triangle of the whole mesh exactly once, and its
  /// vertices.
  void expectTileMeshesCover(const std::vector<double>& xyz, bool post);

  std::size_t entriesIn(const std::filesystem::path& folder) const
  {
    return static_cast<std::size_t>(
        std::distance(std::filesystem::directory_iterator(folder),
                      std::filesystem::directory_iterator{}));
  }
};

class TiledEqualsInMemory : public TiledMeshTest,
                            public ::testing::WithParamInterface<Distribution> {};

TEST_P(TiledEqualsInMemory, SameBytesForEveryTiling)
{
  // Every tile of an all-cocircular set needs every point: keep that one small.
  const std::size_t n = GetParam() == Distribution::CIRCLE ? 800 : 6000;
  const std::vector<double> xyz = generatePoints(GetParam(), n, 11);
  const std::string reference = (root_ / "memory.ply").string();
  TriangleMesh canonical;
  const Status memory = writeInMemory(xyz, reference, &canonical);
  const std::string expected = memory.ok() ? slurp(reference) : std::string();
  for (const auto& [tile_level, block_level] :
       std::vector<std::pair<int, int>>{{0, 2}, {1, 3}, {2, 4}, {3, 5}, {3, 7}}) {
    SCOPED_TRACE("tile level " + std::to_string(tile_level) + ", block level " +
                 std::to_string(block_level));
    const std::string path = (root_ / "tiled.ply").string();
    TiledMeshReport report;
    const Status tiled = writeTiled(xyz, path, tile_level, block_level, report);
    ASSERT_EQ(tiled.ok(), memory.ok())
        << tiled.toString() << " / " << memory.toString();
    if (!memory.ok()) {
      EXPECT_EQ(tiled.code, memory.code);
      continue;
    }
    EXPECT_EQ(report.triangles, canonical.triangleCount());
    EXPECT_EQ(report.vertices, canonical.vertexCount());
    EXPECT_TRUE(slurp(path) == expected)
        << "tiled file differs from the in-memory file";
    EXPECT_EQ(entriesIn(root_), 2u) << "temporary files left behind";
  }
}

TEST_P(TiledEqualsInMemory, SameBytesForEveryThreadAndRankCount)
{
  const std::size_t n = GetParam() == Distribution::CIRCLE ? 500 : 4000;
  const std::vector<double> xyz = generatePoints(GetParam(), n, 12);
  const std::string reference = (root_ / "memory.ply").string();
  const Status memory = writeInMemory(xyz, reference);
  const std::string expected = memory.ok() ? slurp(reference) : std::string();
  // Five sources, so that ranks read different inputs (the parts must join in order).
  const PointInputs inputs = fiveSources(xyz);
  std::string first_index; // --tile-output's index: the same for every rank count
  for (const auto& [ranks, threads] :
       std::vector<std::pair<int, unsigned>>{{1, 3}, {2, 1}, {3, 2}}) {
    const std::filesystem::path tiles = root_ / "tiles";
    std::filesystem::remove_all(tiles);
    std::filesystem::create_directory(tiles);
    SCOPED_TRACE(std::to_string(ranks) + " ranks, " + std::to_string(threads) +
                 " threads");
    const std::string path = (root_ / "tiled.ply").string();
    TiledMeshOptions options;
    options.temp_parent = root_.string();
    options.tile_level = 2;
    options.block_level = 5;
    options.threads = threads;
    options.tile_output = tiles.string();
    const std::vector<Status> status = runRanks(ranks, inputs, options, path);
    for (const Status& s : status) {
      ASSERT_EQ(s.ok(), memory.ok()) << s.toString();
      if (!s.ok()) {
        EXPECT_EQ(s.code, memory.code);
      }
    }
    if (memory.ok()) {
      EXPECT_TRUE(slurp(path) == expected) << "differs from the in-memory file";
      const std::string index = slurp((tiles / "index.csv").string());
      if (first_index.empty())
        first_index = index;
      EXPECT_EQ(index, first_index) << "the tile index depends on the ranks";
    }
    std::filesystem::remove_all(tiles);
    EXPECT_EQ(entriesIn(root_), memory.ok() ? 2u : 0u) << "temporary files left behind";
  }
}

// The post-passes across tiles: the same bytes and counts as in memory, for trimming
// alone at the default factor and at an aggressive one (many pinches to repair), and
// for trimming and filling (the default pipeline; a small largest-hole limit too), for
// tilings down to tiny tiles and for ranks and threads.
TEST_P(TiledEqualsInMemory, PostPassesSameBytesForEveryTilingRankAndThreadCount)
{
  const std::size_t n = GetParam() == Distribution::CIRCLE ? 300 : 3000;
  const std::vector<double> xyz = generatePoints(GetParam(), n, 13);
  const PointInputs inputs = fiveSources(xyz);
  struct Post {
    double trim_factor;
    bool fill;
    double max_hole_area;
  };
  for (const Post& post :
       {Post{3.0, false, 0.0}, Post{1.4, false, 0.0}, Post{3.0, true, 0.0},
        Post{1.6, true, 0.0}, Post{1.6, true, 40.0}}) {
    SCOPED_TRACE(
        "trim factor " + std::to_string(post.trim_factor) +
        (post.fill ? ", fill up to " + std::to_string(post.max_hole_area) : ""));
    VtsOptions vts;
    vts.reconstruction.trim = true;
    vts.reconstruction.fill = post.fill;
    vts.reconstruction.trim_options.trim_factor = post.trim_factor;
    vts.reconstruction.fill_options.max_hole_area = post.max_hole_area;
    const std::string reference = (root_ / "memory.ply").string();
    TriangleMesh canonical;
    ReconstructionDiagnostics done;
    const Status memory = writeInMemory(xyz, reference, &canonical, vts, &done);
    ASSERT_EQ(memory.ok(), GetParam() != Distribution::COLLINEAR) << memory.toString();
    if (!memory.ok())
      continue;
    const std::string expected = slurp(reference);
    for (const auto& [tile_level, block_level] :
         std::vector<std::pair<int, int>>{{0, 2}, {2, 4}, {3, 6}}) {
      SCOPED_TRACE("tile level " + std::to_string(tile_level));
      const std::string path = (root_ / "tiled.ply").string();
      TiledMeshReport report;
      const Status tiled = writeTiled(xyz, path, tile_level, block_level, report, vts);
      ASSERT_TRUE(tiled.ok()) << tiled.toString();
      EXPECT_EQ(report.triangles, canonical.triangleCount());
      EXPECT_EQ(report.trim.triangles_removed, done.trim.triangles_removed);
      EXPECT_EQ(report.trim.vertices_lost, done.trim.vertices_lost);
      EXPECT_EQ(report.trim.kept_to_stay_manifold, done.trim.kept_to_stay_manifold);
      EXPECT_EQ(report.fill.holes_found, done.fill.holes_found);
      EXPECT_EQ(report.fill.holes_filled, done.fill.holes_filled);
      EXPECT_EQ(report.fill.points_inserted, done.fill.points_inserted);
      EXPECT_EQ(report.fill.max_hole_area, done.fill.max_hole_area);
      EXPECT_TRUE(slurp(path) == expected)
          << "tiled file differs from the in-memory file";
      EXPECT_EQ(entriesIn(root_), 2u) << "temporary files left behind";
    }
    std::string first_index; // --tile-output's index: the same for every rank count
    for (const auto& [ranks, threads] :
         std::vector<std::pair<int, unsigned>>{{1, 3}, {3, 1}}) {
      SCOPED_TRACE(std::to_string(ranks) + " ranks, " + std::to_string(threads) +
                   " threads");
      const std::filesystem::path tiles = root_ / "tiles";
      std::filesystem::create_directory(tiles);
      TiledMeshOptions options;
      options.vts = vts;
      options.temp_parent = root_.string();
      options.tile_level = 3;
      options.block_level = 5;
      options.threads = threads;
      options.tile_output = tiles.string();
      const std::string path = (root_ / "ranks.ply").string();
      for (const Status& s : runRanks(ranks, inputs, options, path))
        ASSERT_TRUE(s.ok()) << s.toString();
      EXPECT_TRUE(slurp(path) == expected) << "differs from the in-memory file";
      const std::string index = slurp((tiles / "index.csv").string());
      if (first_index.empty())
        first_index = index;
      EXPECT_EQ(index, first_index) << "the tile index depends on the ranks";
      std::filesystem::remove(path);
      std::filesystem::remove_all(tiles);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllGenerators, TiledEqualsInMemory,
                         ::testing::ValuesIn(allDistributions()),
                         [](const auto& param_info) {
                           return distributionName(param_info.param);
                         });

/// A binary little-endian PLY as written by writeMesh: float or double x y z, faces.
bool readBinaryPly(const std::string& path, TriangleMesh& mesh)
{
  const std::string bytes = slurp(path);
  const std::size_t end = bytes.find("end_header\n");
  if (end == std::string::npos)
    return false;
  std::istringstream header(bytes.substr(0, end));
  std::size_t nv = 0, nf = 0;
  bool dbl = false, flags = false;
  for (std::string line; std::getline(header, line);) {
    std::sscanf(line.c_str(), "element vertex %zu", &nv);
    std::sscanf(line.c_str(), "element face %zu", &nf);
    if (line == "property double x")
      dbl = true;
    if (line == "property uchar inserted")
      flags = true; // hole filling's mark, one byte after z
  }
  const char* p = bytes.data() + end + 11;
  const std::size_t item = dbl ? 8 : 4;
  if (bytes.size() != end + 11 + nv * (3 * item + (flags ? 1 : 0)) + nf * 13)
    return false;
  mesh = TriangleMesh{};
  for (std::size_t v = 0; v < nv; ++v) {
    double c[3];
    for (double& value : c) {
      if (dbl) {
        std::memcpy(&value, p, 8);
      } else {
        float f;
        std::memcpy(&f, p, 4);
        value = f;
      }
      p += item;
    }
    p += flags ? 1 : 0;
    mesh.xy.push_back({c[0], c[1]});
    mesh.z.push_back(c[2]);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    std::int32_t t[3];
    std::memcpy(t, p + 1, 12);
    p += 13;
    for (std::int32_t v : t)
      mesh.triangles.push_back(static_cast<VertexId>(v));
  }
  return true;
}

TEST_F(TiledMeshTest, TileMeshesAndIndexCoverTheMeshOnceWithSharedSeams)
{
  // The triangulation, and the surface mesh (trimmed, holes filled: the tile meshes
  // then share the final mesh's inserted points and patches).
  const std::vector<double> xyz = generatePoints(Distribution::BIG_VOIDS, 5000, 17);
  for (const bool post : {false, true}) {
    SCOPED_TRACE(post ? "trim and fill" : "triangulation");
    expectTileMeshesCover(xyz, post);
  }
}

void TiledMeshTest::expectTileMeshesCover(const std::vector<double>& xyz, bool post)
{
  const std::filesystem::path tiles = root_ / "tiles";
  std::filesystem::remove_all(tiles);
  std::filesystem::create_directory(tiles);
  TiledMeshOptions options;
  if (post) {
    options.vts.reconstruction = ReconstructionOptions{};
    options.vts.reconstruction.trim_options.trim_factor = 1.6;
  }
  options.temp_parent = root_.string();
  options.tile_level = 2;
  options.block_level = 5;
  options.tile_output = tiles.string();
  TiledMeshReport report;
  const std::string path = (root_ / "all.ply").string();
  ASSERT_TRUE(
      runTiledMesh(feedOf(xyz), options, path, MeshWriteOptions{}, report).ok());
  TriangleMesh all;
  ASSERT_TRUE(readBinaryPly(path, all));
  // Each triangle of the whole mesh, by its corners' coordinates, exactly once.
  using Corner = std::pair<double, double>;
  std::map<std::array<Corner, 3>, int> seen;
  const auto key = [](const TriangleMesh& m, std::size_t t) {
    std::array<Corner, 3> k;
    for (int c = 0; c < 3; ++c)
      k[static_cast<std::size_t>(c)] = {
          m.xy[m.triangles[3 * t + static_cast<std::size_t>(c)]].x,
          m.xy[m.triangles[3 * t + static_cast<std::size_t>(c)]].y};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (std::size_t t = 0; t < all.triangleCount(); ++t)
    seen[key(all, t)] = 0;
  std::map<Corner, double> height; // each vertex's z, inserted ones included
  for (std::size_t v = 0; v < all.vertexCount(); ++v)
    height[{all.xy[v].x, all.xy[v].y}] = all.z[v];
  if (post) {
    ASSERT_GT(report.fill.points_inserted, 0u);
    ASSERT_GT(report.trim.triangles_removed, 0u);
  }
  std::ifstream index((tiles / "index.csv").string());
  std::string line;
  ASSERT_TRUE(std::getline(index, line));
  EXPECT_EQ(line, "tile,column,row,x0,y0,x1,y1,vertices,triangles,file");
  std::size_t files = 0, triangles = 0;
  while (std::getline(index, line)) {
    ++files;
    const std::string name = line.substr(line.rfind(',') + 1);
    std::size_t nt = 0;
    const std::size_t comma = line.rfind(',', line.rfind(',') - 1);
    nt = std::stoul(line.substr(comma + 1));
    TriangleMesh tile;
    ASSERT_TRUE(readBinaryPly((tiles / name).string(), tile)) << name;
    ASSERT_EQ(tile.triangleCount(), nt) << name;
    triangles += nt;
    for (std::size_t v = 0; v < tile.vertexCount(); ++v) {
      const auto it = height.find({tile.xy[v].x, tile.xy[v].y});
      ASSERT_NE(it, height.end()) << name << ": a vertex the whole mesh does not have";
      EXPECT_EQ(it->second, tile.z[v]) << name;
    }
    for (std::size_t t = 0; t < tile.triangleCount(); ++t) {
      auto it = seen.find(key(tile, t));
      ASSERT_NE(it, seen.end()) << name << ": a triangle the whole mesh does not have";
      ++it->second;
    }
  }
  EXPECT_EQ(files, report.tiles);
  EXPECT_EQ(triangles, all.triangleCount());
  for (const auto& entry : seen)
    ASSERT_EQ(entry.second, 1) << "a triangle in " << entry.second << " tile meshes";
}

TEST_F(TiledMeshTest, MatchesTheCgalOracle)
{
  // Independent of the in-memory code path: the tiled triangle set is CGAL's.
  const std::vector<double> xyz = generatePoints(Distribution::BIG_VOIDS, 4000, 5);
  const std::string path = (root_ / "tiled.obj").string();
  TiledMeshReport report;
  ASSERT_TRUE(writeTiled(xyz, path, 3, 6, report).ok());
  std::vector<Point2> points;
  std::vector<std::uint32_t> flat;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) {
      double x, y, z;
      ASSERT_EQ(std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z), 3);
      points.push_back({x, y});
    } else if (line.rfind("f ", 0) == 0) {
      unsigned a, b, c;
      ASSERT_EQ(std::sscanf(line.c_str(), "f %u %u %u", &a, &b, &c), 3);
      flat.insert(flat.end(), {a - 1, b - 1, c - 1});
    }
  }
  EXPECT_GT(report.tiles, 8u);
  std::vector<std::uint32_t> identity(points.size());
  std::iota(identity.begin(), identity.end(), 0u);
  EXPECT_EQ(canonicalTriangles(flat, identity),
            canonicalTriangles(cgalDelaunay(points)));
}

TEST_F(TiledMeshTest, DuplicatesAcrossChunksKeepTheRuleOfTheInMemoryRun)
{
  std::vector<double> xyz = generatePoints(Distribution::DUPLICATES, 5000, 3);
  const std::vector<double> again = generatePoints(Distribution::UNIFORM, 2000, 3);
  xyz.insert(xyz.end(), again.begin(), again.end()); // same XY positions, other z
  xyz.insert(xyz.end(), xyz.begin(), xyz.begin() + 3000);
  const std::string reference = (root_ / "memory.ply").string();
  ASSERT_TRUE(writeInMemory(xyz, reference).ok());
  const std::string path = (root_ / "tiled.ply").string();
  TiledMeshReport report;
  ASSERT_TRUE(writeTiled(xyz, path, 2, 4, report).ok());
  EXPECT_TRUE(slurp(path) == slurp(reference));
}

TEST_F(TiledMeshTest, NonFinitePointsAreDroppedAndCounted)
{
  std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 3000, 9);
  xyz[3 * 10] = std::nan("");
  xyz[3 * 20 + 2] = HUGE_VAL;
  const std::string path = (root_ / "tiled.ply").string();
  TiledMeshReport report;
  ASSERT_TRUE(writeTiled(xyz, path, 2, 4, report).ok());
  EXPECT_EQ(report.non_finite_dropped, 2u);
  EXPECT_EQ(report.vertices, 2998u);
}

// The default pipeline on the synthetic terrain of docs/reconstruction.md (a notch,
// voids filled and one left open): holes cross tile borders and corners at 16 and
// 256 tiles, and the tiled run still writes the in-memory bytes.
TEST_F(TiledMeshTest, DefaultPipelineFillsHolesAcrossTilesAsInMemory)
{
  const SyntheticTerrain terrain = makeSyntheticTerrain(5);
  VtsOptions vts;
  vts.reconstruction = ReconstructionOptions{};
  const std::string reference = (root_ / "memory.ply").string();
  ReconstructionDiagnostics done;
  ASSERT_TRUE(writeInMemory(terrain.xyz, reference, nullptr, vts, &done).ok());
  ASSERT_GE(done.fill.holes_filled, 3u);
  ASSERT_GE(done.fill.holes_left_open, 1u);
  for (const auto& [tile_level, block_level] :
       std::vector<std::pair<int, int>>{{2, 5}, {4, 7}}) {
    SCOPED_TRACE("tile level " + std::to_string(tile_level));
    const std::string path = (root_ / "tiled.ply").string();
    TiledMeshReport report;
    ASSERT_TRUE(
        writeTiled(terrain.xyz, path, tile_level, block_level, report, vts).ok());
    EXPECT_EQ(report.fill.holes_filled, done.fill.holes_filled);
    EXPECT_EQ(report.fill.points_inserted, done.fill.points_inserted);
    EXPECT_TRUE(slurp(path) == slurp(reference)) << "differs from the in-memory file";
  }
}

// The bucketed points are read only while tiles are meshed: they are gone from the
// temporary folder before the post-passes and the writer add their files; the
// post-passes' files are gone before the writer starts; the report's peak covers the
// points and the tile results together.
// The points are stored once: the tile results hold the triangles alone (a 32-byte
// header, then 12 bytes a triangle), the writer rebuilds the vertices from the point
// files, which stay until then; the post-passes' files are gone before the write.
TEST_F(TiledMeshTest, TileResultsHoldTrianglesAndThePointsStayUntilTheWrite)
{
  const SyntheticTerrain terrain = makeSyntheticTerrain(5);
  TiledMeshOptions options;
  options.vts.reconstruction = ReconstructionOptions{};
  options.temp_parent = root_.string();
  options.tile_level = 2;
  options.block_level = 5;
  std::map<std::string, std::pair<int, int>> seen; // phase: point files, result files
  int others_at_writing = -1;                      // files neither points nor results
  int malformed_results = -1; // result files not of header + triangles
  options.progress = [&](const TiledProgress& p) {
    int points = 0, results = 0, others = 0, malformed = 0;
    for (const auto& folder : std::filesystem::directory_iterator(root_))
      if (folder.path().filename().string().rfind(".pcl_vts-", 0) == 0)
        for (const auto& file : std::filesystem::directory_iterator(folder.path())) {
          const std::string name = file.path().filename().string();
          points += name.rfind("tile_", 0) == 0;
          const bool result = name.rfind("result_", 0) == 0;
          results += result;
          others += name.rfind("tile_", 0) != 0 && !result;
          if (result) {
            std::uint64_t header[2] = {0, 0};
            std::ifstream in(file.path(), std::ios::binary);
            in.read(reinterpret_cast<char*>(header), sizeof(header));
            malformed += std::filesystem::file_size(file.path()) != 32 + 12 * header[1];
          }
        }
    seen[p.phase] = {points, results};
    if (std::string(p.phase) == "writing") {
      others_at_writing = others;
      malformed_results = malformed;
    }
  };
  TiledMeshReport report;
  ASSERT_TRUE(runTiledMesh(feedOf(terrain.xyz), options, (root_ / "t.ply").string(),
                           MeshWriteOptions{}, report)
                  .ok());
  for (const char* phase : {"meshing", "trimming", "filling", "writing"}) {
    ASSERT_EQ(seen.count(phase), 1u) << phase;
    EXPECT_GT(seen[phase].first, 0) << "no point files at " << phase;
  }
  for (const char* phase : {"trimming", "filling", "writing"})
    EXPECT_GT(seen[phase].second, 0) << "no tile results at " << phase;
  EXPECT_EQ(others_at_writing, 0) << "the post-passes' files outlived them";
  EXPECT_EQ(malformed_results, 0) << "a result file holds more than its triangles";
  EXPECT_EQ(report.temp_bytes_after_write, 0u);
}

// The writer rebuilds each tile's vertices from its points: every duplicate rule
// folds runs of equal XY as the in-memory run does (ties of z, the mean's summing
// order, -0.0 beside +0.0), with the duplicates spread over the input.
TEST_F(TiledMeshTest, EveryDuplicateRuleGivesTheInMemoryBytes)
{
  // Jittered, then an exact raster (the lattice fast path, in memory and in every
  // tile): -0.0 and +0.0 at the same XY keep the first input's sign on both paths.
  for (const bool raster : {false, true}) {
    SCOPED_TRACE(raster ? "raster" : "jittered");
    std::vector<double> xyz;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3), height(-2.0, 2.0);
    for (int y = -12; y <= 12; ++y)
      for (int x = -12; x <= 12; ++x) {
        const double jx = raster ? 0.0 : jitter(rng), jy = raster ? 0.0 : jitter(rng);
        const double px = x == 0 ? (y % 2 == 0 ? 0.0 : -0.0) : x + jx;
        xyz.insert(xyz.end(), {px, y + jy, height(rng)});
      }
    const std::size_t n = xyz.size() / 3;
    for (std::size_t k = 0; k < n; k += 3) { // 1 to 3 more points at the same XY
      for (std::size_t d = 0; d <= k % 3; ++d) {
        const double z = d == 1 ? xyz[3 * k + 2] : height(rng);        // some equal z
        const double x = xyz[3 * k] == 0.0 ? -xyz[3 * k] : xyz[3 * k]; // the other zero
        xyz.insert(xyz.end(), {x, xyz[3 * k + 1], d == 2 ? -0.0 : z});
      }
    }
    for (DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                               DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
      SCOPED_TRACE(duplicateRuleName(rule));
      VtsOptions vts;
      vts.duplicate_rule = rule;
      const std::string reference = (root_ / "m.ply").string();
      ASSERT_TRUE(writeInMemory(xyz, reference, nullptr, vts).ok());
      for (int block_level : {3, 5}) {
        TiledMeshReport report;
        const std::string path = (root_ / "t.ply").string();
        const Status s = writeTiled(xyz, path, 2, block_level, report, vts);
        ASSERT_TRUE(s.ok()) << s.toString();
        EXPECT_TRUE(slurp(path) == slurp(reference))
            << "block level " << block_level << ": differs from the in-memory file";
      }
    }
  }
}

// A PLY writer is the last reader of the tile results and points: each goes back once
// read, and nothing of them is left after the write. OBJ reads the vertices twice when
// points were inserted: its results stay, and it still writes the in-memory bytes.
TEST_F(TiledMeshTest, TileResultsGoBackAsThePlyIsWritten)
{
  const SyntheticTerrain terrain = makeSyntheticTerrain(5);
  VtsOptions vts;
  vts.reconstruction = ReconstructionOptions{};
  for (const char* name : {"t.ply", "t.obj"}) {
    SCOPED_TRACE(name);
    const std::string reference = (root_ / (std::string("m") + name)).string();
    ASSERT_TRUE(writeInMemory(terrain.xyz, reference, nullptr, vts).ok());
    const std::string path = (root_ / name).string();
    TiledMeshReport report;
    ASSERT_TRUE(writeTiled(terrain.xyz, path, 2, 5, report, vts).ok());
    EXPECT_TRUE(slurp(path) == slurp(reference)) << "differs from the in-memory file";
    if (std::string(name) == "t.ply")
      EXPECT_EQ(report.temp_bytes_after_write, 0u);
    else
      EXPECT_GE(report.temp_bytes_after_write, 24 * report.vertices);
  }
}

TEST_F(TiledMeshTest, AnInputThatChangesBetweenPassesIsAnError)
{
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 3000, 2);
  int pass = 0;
  const PointFeed shrinking = [&](const PointSink& sink) {
    const std::size_t n = xyz.size() / 3 - (pass++ == 0 ? 0 : 100);
    return sink(xyz.data(), n);
  };
  TiledMeshOptions options;
  options.temp_parent = root_.string();
  options.tile_level = 1;
  TiledMeshReport report;
  const Status s = runTiledMesh(shrinking, options, (root_ / "t.ply").string(),
                                MeshWriteOptions{}, report);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("changed"), std::string::npos) << s.message;
  EXPECT_EQ(report.failure, TiledFailure::OTHER) << "the input's, not the folder's";
  EXPECT_EQ(entriesIn(root_), 0u) << "temporary files or a partial output left behind";
}

TEST_F(TiledMeshTest, AFullTemporaryDiskIsAClearErrorWithNothingLeft)
{
  // A child process with a 64 KiB file-size limit stands for a full disk.
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 20000, 4);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    signal(SIGXFSZ, SIG_IGN);
    rlimit limit{64 * 1024, 64 * 1024};
    setrlimit(RLIMIT_FSIZE, &limit);
    TiledMeshOptions options;
    options.temp_parent = root_.string();
    options.tile_level = 0;
    TiledMeshReport report;
    const Status s = runTiledMesh(feedOf(xyz), options, (root_ / "t.ply").string(),
                                  MeshWriteOptions{}, report);
    // In the library's words (a tool adds its flag: TiledFailure).
    const bool clear = s.code == StatusCode::IO_ERROR &&
                       report.failure == TiledFailure::TEMP_FOLDER &&
                       s.message.find("temporary folder") != std::string::npos &&
                       s.message.find("is full") != std::string::npos &&
                       s.message.find("--") == std::string::npos;
    _exit(clear ? 0 : 1);
  }
  int wstatus = 0;
  ASSERT_EQ(waitpid(child, &wstatus, 0), child);
  ASSERT_TRUE(WIFEXITED(wstatus));
  EXPECT_EQ(WEXITSTATUS(wstatus), 0) << "no clear 'full' error";
  EXPECT_EQ(entriesIn(root_), 0u) << "temporary files or a partial output left behind";
}

TEST_F(TiledMeshTest, ATemporaryFolderThatCannotBeCreatedIsAClearError)
{
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 100, 2);
  TiledMeshOptions options;
  options.temp_parent = (root_ / "missing" / "deeper").string();
  TiledMeshReport report;
  const Status s = runTiledMesh(feedOf(xyz), options, (root_ / "t.ply").string(),
                                MeshWriteOptions{}, report);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("temporary folder"), std::string::npos) << s.message;
  EXPECT_EQ(report.failure, TiledFailure::TEMP_FOLDER);
}

TEST_F(TiledMeshTest, AMemoryLimitBelowTheMinimumNamesItInTheLibrarysWords)
{
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 20000, 3);
  TiledMeshOptions options;
  options.temp_parent = root_.string();
  options.memory_limit = std::uint64_t{1} << 20;
  TiledMeshReport report;
  const Status s = runTiledMesh(feedOf(xyz), options, (root_ / "t.ply").string(),
                                MeshWriteOptions{}, report);
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER);
  EXPECT_EQ(report.failure, TiledFailure::MEMORY_LIMIT);
  EXPECT_NE(s.message.find("the memory limit of 1 MiB is below"), std::string::npos)
      << s.message;
  EXPECT_EQ(s.message.find("--"), std::string::npos) << s.message;
  EXPECT_EQ(entriesIn(root_), 0u) << "temporary files or a partial output left behind";
}

TEST_F(TiledMeshTest, TilesOnAStraightDataBoundaryLoadAStripOfItNotEverything)
{
  // LiDAR quantised to 1 cm inside a square: along the hull's straight sides the
  // Delaunay triangles are long slivers whose circumdisks are huge; deciding them
  // needs the points in a thin strip along the side (inherent), but no more: the
  // global hull makes everything beyond the side known empty.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz;
  for (int i = 0; i < 200000; ++i)
    xyz.insert(xyz.end(), {500000.0 + std::round(100000.0 * u(rng)) / 100.0,
                           4100000.0 + std::round(100000.0 * u(rng)) / 100.0, u(rng)});
  TiledMeshReport report;
  ASSERT_TRUE(writeTiled(xyz, (root_ / "t.ply").string(), 3, 7, report).ok());
  EXPECT_EQ(report.tiles, 64u);
  EXPECT_LT(report.max_tile_points, 200000u / 8) << "a tile loaded 8 tiles' worth";
  EXPECT_LT(report.points_loaded, 5 * 200000u / 2);
}

TEST_F(TiledMeshTest, HalosStaySmallOnUniformData)
{
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 40000, 8);
  TiledMeshReport report;
  ASSERT_TRUE(writeTiled(xyz, (root_ / "t.ply").string(), 2, 6, report).ok());
  EXPECT_EQ(report.tiles, 16u);
  // Each tile loads its own quarter of a quarter plus a ring of blocks.
  EXPECT_LT(report.points_loaded, 2 * xyz.size() / 3);
  EXPECT_LE(report.max_rounds,
            6u); // hull edges are settled by the nearest blocks first
}

// The pre-pass's files (the tiled ground filter's) are the job's inputs: read by the
// scan and the bucketing, then removed before the tiles are meshed; the mesh is the
// one of the same points fed directly.
TEST_F(TiledMeshTest, PreparedFilesAreRemovedOnceBucketed)
{
  const SyntheticTerrain terrain = makeSyntheticTerrain(5);
  const std::size_t half = terrain.xyz.size() / 6 * 3;
  TiledMeshOptions options;
  options.temp_parent = root_.string();
  options.tile_level = 1;
  std::vector<std::string> written;
  options.prepare = [&](const PointInputs&, const std::string& folder, JobComm&,
                        std::vector<std::string>& files) {
    for (int k = 0; k < 2; ++k) {
      const std::string path = folder + "/prepared_" + std::to_string(k) + ".xyz";
      std::ofstream out(path, std::ios::binary);
      const double* first = terrain.xyz.data() + (k == 0 ? 0 : half);
      const std::size_t count = k == 0 ? half : terrain.xyz.size() - half;
      out.write(reinterpret_cast<const char*>(first),
                static_cast<std::streamsize>(count * sizeof(double)));
      files.push_back(path);
    }
    written = files;
    return Status::success();
  };
  options.read_prepared = [](const std::string& file, const PointSink& sink) {
    const std::string bytes = slurp(file);
    std::vector<double> xyz(bytes.size() / sizeof(double));
    std::memcpy(xyz.data(), bytes.data(), xyz.size() * sizeof(double));
    if (xyz.empty())
      return Status::error(StatusCode::IO_ERROR, "cannot read " + file);
    return sink(xyz.data(), xyz.size() / 3);
  };
  std::map<std::string, int> present; // phase: prepared files present
  options.progress = [&](const TiledProgress& p) {
    int count = 0;
    for (const std::string& file : written)
      count += std::filesystem::exists(file);
    present[p.phase] = count;
  };
  TiledMeshReport report;
  const std::string tiled = (root_ / "tiled.ply").string();
  ASSERT_TRUE(runTiledMesh([](const PointSink&) { return Status::success(); }, options,
                           tiled, MeshWriteOptions{}, report)
                  .ok());
  ASSERT_EQ(written.size(), 2u);
  ASSERT_EQ(present.count("bucketing"), 1u);
  EXPECT_EQ(present["bucketing"], 2) << "the files were gone while being read";
  for (const char* phase : {"meshing", "writing"}) {
    ASSERT_EQ(present.count(phase), 1u) << phase;
    EXPECT_EQ(present[phase], 0) << "prepared files left at " << phase;
  }
  TiledMeshOptions direct;
  direct.temp_parent = root_.string();
  direct.tile_level = 1;
  const std::string reference = (root_ / "direct.ply").string();
  ASSERT_TRUE(
      runTiledMesh(feedOf(terrain.xyz), direct, reference, MeshWriteOptions{}, report)
          .ok());
  EXPECT_EQ(slurp(tiled), slurp(reference));
}

// Renumbering the vertices cannot break a manifold, so rebuilding the twins fails
// only on a mesh that was not one: three triangles on one edge are reported, and
// the mesh and its flags are left as they were.
TEST(CanonicalMesh, ANonManifoldMeshIsAnInternalErrorAndLeftAsItWas)
{
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {0.5, 1}, {0.5, -1}, {0.5, 2}};
  mesh.z.assign(5, 0.0);
  mesh.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4}; // edge 0-1 in three triangles
  const TriangleMesh before = mesh;
  std::vector<std::uint8_t> inserted = {0, 1, 0, 1, 1};
  const Status s = canonicalMesh(mesh, &inserted);
  EXPECT_EQ(s.code, StatusCode::INTERNAL_ERROR);
  EXPECT_NE(s.message.find("not an oriented 2-manifold"), std::string::npos)
      << s.message;
  EXPECT_EQ(mesh.triangles, before.triangles);
  EXPECT_EQ(mesh.z, before.z);
  EXPECT_EQ(inserted, (std::vector<std::uint8_t>{0, 1, 0, 1, 1}));

  mesh.triangles = {0, 1, 2, 1, 0, 3}; // a manifold: reordered, twins paired
  ASSERT_TRUE(canonicalMesh(mesh, &inserted).ok());
  EXPECT_EQ(mesh.halfedges.size(), 6u);
  EXPECT_EQ(std::count(mesh.halfedges.begin(), mesh.halfedges.end(), INVALID_ID), 4);
}

// The twins are carried along only when every one is in range, not its own halfedge,
// names it back and joins the same two vertices the other way (each halfedge tests
// its twin's start; the twin's own test gives the other end). Each kind of damage
// makes canonicalMesh rebuild them instead: the result equals the one from the
// undamaged mesh, and would not if a damaged twin were carried.
TEST(CanonicalMesh, DamagedTwinsAreRebuiltNotCarried)
{
  const std::vector<double> xyz = generatePoints(Distribution::JITTERED_GRID, 3000, 9);
  VtsResult result;
  ASSERT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, VtsOptions{}, result).ok());
  const TriangleMesh original = result.mesh;
  TriangleMesh expected = original;
  ASSERT_TRUE(canonicalMesh(expected, nullptr).ok());
  TriangleMesh cleared = original; // no twins given: rebuilt
  cleared.halfedges.clear();
  ASSERT_TRUE(canonicalMesh(cleared, nullptr).ok());
  EXPECT_EQ(cleared.triangles, expected.triangles);
  EXPECT_EQ(cleared.halfedges, expected.halfedges);
  // An interior pair (e, t) and another interior halfedge f starting where e ends
  // (f != t): f ends elsewhere than e starts.
  HalfedgeId e = 0;
  while (original.halfedges[e] == INVALID_ID)
    ++e;
  const HalfedgeId t = original.halfedges[e];
  HalfedgeId f = 0;
  while (f == t || original.halfedges[f] == INVALID_ID ||
         original.triangles[f] != original.triangles[nextHalfedge(e)] ||
         original.triangles[nextHalfedge(f)] == original.triangles[e])
    ++f;
  for (int kind = 0; kind < 6; ++kind) {
    SCOPED_TRACE(kind);
    TriangleMesh mesh = original;
    std::vector<HalfedgeId>& twin = mesh.halfedges;
    switch (kind) {
    case 0: // e's twin is f: starts where e ends, ends elsewhere (mutual)
      twin[twin[f]] = INVALID_ID;
      twin[t] = INVALID_ID;
      twin[e] = f;
      twin[f] = e;
      break;
    case 1: // e names t, t names another
      twin[t] = f;
      break;
    case 2: // out of range
      twin[e] = static_cast<HalfedgeId>(twin.size());
      break;
    case 3: // its own twin
      twin[e] = e;
      break;
    case 4: // e and the halfedge after t, mutual: runs the same way
      twin[t] = INVALID_ID;
      twin[twin[nextHalfedge(t)]] = INVALID_ID;
      twin[e] = nextHalfedge(t);
      twin[nextHalfedge(t)] = e;
      break;
    default: // one twin missing on one side only
      twin[t] = INVALID_ID;
      break;
    }
    ASSERT_TRUE(canonicalMesh(mesh, nullptr).ok());
    EXPECT_EQ(mesh.triangles, expected.triangles);
    EXPECT_EQ(mesh.halfedges, expected.halfedges);
  }
}

// A corner that names no vertex is a clear error before anything moves (the
// renaming would index past the vertices), twins given or not, on any threads.
TEST(CanonicalMesh, ACornerThatIsNoVertexIsAnErrorAndTheMeshLeftAsItWas)
{
  const std::vector<double> xyz = generatePoints(Distribution::UNIFORM, 200000, 3);
  VtsResult result;
  ASSERT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, VtsOptions{}, result).ok());
  for (const bool twins : {true, false})
    for (const unsigned threads : {1u, 3u}) {
      TriangleMesh mesh = result.mesh;
      if (!twins)
        mesh.halfedges.clear();
      mesh.triangles[3 * (mesh.triangleCount() - 1) + 1] =
          static_cast<VertexId>(mesh.vertexCount());
      const TriangleMesh before = mesh;
      std::vector<std::uint8_t> inserted(mesh.vertexCount(), 0);
      inserted[5] = 1;
      const std::vector<std::uint8_t> inserted_before = inserted;
      const Status s = canonicalMesh(mesh, &inserted, threads);
      EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER) << twins << " " << threads;
      EXPECT_EQ(mesh.triangles, before.triangles);
      EXPECT_EQ(mesh.halfedges, before.halfedges);
      EXPECT_EQ(mesh.xy, before.xy);
      EXPECT_EQ(inserted, inserted_before);
    }
}

// The passes split over threads (counting sorts with a histogram per chunk, the
// renaming, the rows' sorts, the gathers) give the arrays of one thread, with twins
// carried and with twins rebuilt, on a mesh large enough for several chunks.
TEST(CanonicalMesh, SameArraysForEveryThreadCount)
{
  // No post-passes (the default): the hull's fans make rows of many triangles.
  const std::vector<double> xyz = generatePoints(Distribution::CLUSTERED, 300000, 9);
  VtsResult result;
  ASSERT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, VtsOptions{}, result).ok());
  std::vector<std::uint8_t> flags(result.mesh.vertexCount());
  for (std::size_t v = 0; v < flags.size(); ++v)
    flags[v] = static_cast<std::uint8_t>(v % 7 == 0);
  for (const bool carry : {true, false}) {
    SCOPED_TRACE(carry ? "twins carried" : "twins rebuilt");
    TriangleMesh given = result.mesh;
    if (!carry)
      given.halfedges.clear();
    TriangleMesh one = given;
    std::vector<std::uint8_t> one_flags = flags;
    ASSERT_TRUE(canonicalMesh(one, &one_flags, 1).ok());
    ASSERT_NE(one.triangles, result.mesh.triangles); // the order did change
    for (const unsigned threads : {2u, 3u, 8u}) {
      SCOPED_TRACE(threads);
      TriangleMesh many = given;
      std::vector<std::uint8_t> many_flags = flags;
      ASSERT_TRUE(canonicalMesh(many, &many_flags, threads).ok());
      EXPECT_EQ(many.xy, one.xy);
      EXPECT_EQ(many.z, one.z);
      EXPECT_EQ(many.triangles, one.triangles);
      EXPECT_EQ(many.halfedges, one.halfedges);
      EXPECT_EQ(many_flags, one_flags);
    }
  }
}

} // namespace
} // namespace test
} // namespace pcl_vts
