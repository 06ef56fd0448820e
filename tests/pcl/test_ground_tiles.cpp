// The tiled --ground pmf (ground_tiles.h): the pre-tiles with their halo keep exactly
// the points the in-memory filter keeps (the same doubles, duplicates in the same
// order), for every pre-tiling and thread count: on terrain with buildings across the
// pre-tile borders, on an exact lattice (PCL's box edges land on points, shifted
// coordinates at 0), on an ISPRS sample, where a point is decided by one a full
// window away (the halo is needed) and where float ties are decided by the shift (the
// whole cloud's is needed); each pre-tile loads its core and halo only.
#include <pcl_vts/ground_tiles.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <pcl/octree/octree_search.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace {

namespace fs = std::filesystem;

/// Points stable-sorted by XY: equal XY keep their order (the duplicate rules see it).
std::vector<double> byXy(const std::vector<double>& xyz)
{
  std::vector<std::size_t> order(xyz.size() / 3);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return xyz[3 * a] != xyz[3 * b] ? xyz[3 * a] < xyz[3 * b]
                                    : xyz[3 * a + 1] < xyz[3 * b + 1];
  });
  std::vector<double> out;
  for (const std::size_t k : order)
    out.insert(out.end(), &xyz[3 * k], &xyz[3 * k] + 3);
  return out;
}

class GroundTiles : public ::testing::Test {
 protected:
  void SetUp() override
  {
    folder_ = fs::temp_directory_path() /
              ("pcl_vts_ground_tiles_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  /// The tiled pre-pass over xyz fed in chunks of 1000 points; its files' points.
  Status tiled(const std::vector<double>& xyz, const GroundTilesOptions& options,
               std::vector<double>& kept, GroundTilesReport& report)
  {
    fs::remove_all(folder_);
    fs::create_directories(folder_);
    const GroundFeed feed = [&](const GroundSink& sink) {
      for (std::size_t at = 0; at < xyz.size(); at += 3000)
        if (Status s =
                sink(&xyz[at], std::min<std::size_t>(1000, (xyz.size() - at) / 3));
            !s.ok())
          return s;
      return Status::success();
    };
    std::vector<std::string> files;
    kept.clear();
    if (Status s = groundTiles(feed, options, folder_.string(), files, report); !s.ok())
      return s;
    for (const std::string& file : files)
      if (Status s = readGroundFile(file, 777,
                                    [&](const double* p, std::size_t n) {
                                      kept.insert(kept.end(), p, p + 3 * n);
                                      return Status::success();
                                    });
          !s.ok())
        return s;
    return Status::success();
  }

  /// In memory and with each pre-tiling: the same points, duplicates in the same order.
  void expectTheInMemoryPoints(const std::vector<double>& xyz,
                               const PreprocessOptions& pre,
                               const std::vector<int>& tilings)
  {
    std::vector<double> memory = xyz;
    std::vector<PreprocessStep> steps;
    ASSERT_TRUE(preprocessCloud(memory, pre, steps).ok());
    ASSERT_LT(memory.size(), xyz.size()); // the filter removed something
    const std::vector<double> expected = byXy(memory);
    for (const int k : tilings) {
      GroundTilesOptions options;
      options.preprocess = pre;
      options.tiles_per_side = k;
      options.threads = 1 + static_cast<unsigned>(k % 3); // the same for any count
      std::vector<double> kept;
      GroundTilesReport report;
      ASSERT_TRUE(tiled(xyz, options, kept, report).ok()) << k;
      EXPECT_EQ(report.tiles_per_side, k);
      EXPECT_EQ(report.kept, memory.size() / 3);
      EXPECT_TRUE(byXy(kept) == expected)
          << k << " pre-tiles per side: " << kept.size() / 3 << " points kept, "
          << memory.size() / 3 << " in memory";
      if (k >= 3) { // one pre-tile and its halo at a time, not the whole cloud
        EXPECT_LT(report.max_tile_points, report.cropped) << k;
      }
      // Only the kept files are left.
      std::size_t left = 0;
      for (const auto& entry : fs::directory_iterator(folder_))
        left += entry.path().filename().string().rfind("ground_", 0) == 0 ? 0 : 1;
      EXPECT_EQ(left, 0u);
    }
  }

  fs::path folder_;
};

/// Sloped, wavy ground at 1 m with cm jitter, 8 m buildings and trees placed across
/// the borders of every pre-tiling tested, and returns sharing the XY of a ground
/// point (duplicates).
std::vector<double> builtTerrain()
{
  std::vector<double> xyz;
  std::uint32_t h = 12345;
  const auto jitter = [&h] {
    h = h * 1664525u + 1013904223u;
    return static_cast<double>(h >> 24) / 256.0 * 0.3 - 0.15;
  };
  for (int j = 0; j < 120; ++j)
    for (int i = 0; i < 160; ++i) {
      const double x = std::round((612000.0 + i + jitter()) * 100.0) / 100.0;
      const double y = std::round((5140000.0 + j + jitter()) * 100.0) / 100.0;
      const double g = 210.0 + 0.08 * i + 1.5 * std::sin(0.07 * j) + 0.02 * jitter();
      // Buildings of 8 x 8 m on a 26 m pitch: every pre-tile border crosses some.
      const bool building = (i % 26) < 8 && (j % 26) < 8 && i > 4 && j > 4;
      const bool tree = std::hypot((i % 37) - 18.0, (j % 29) - 14.0) < 2.5;
      const double z = building ? g + 7.0 + 0.01 * i : tree ? g + 5.0 + jitter() : g;
      xyz.insert(xyz.end(), {x, y, std::round(z * 100.0) / 100.0});
      if ((i * 7 + j * 3) % 11 == 0) // a second return at the same XY
        xyz.insert(xyz.end(), {x, y, std::round((z + 3.0 + jitter()) * 100.0) / 100.0});
    }
  return xyz;
}

PreprocessOptions smallWindows()
{
  PreprocessOptions pre;
  pre.ground_pmf = true;
  pre.pmf_max_window = 9; // windows 3, 5, 9: a reach of 18 m
  return pre;
}

TEST_F(GroundTiles, TheReachIsTheSumOfPclsWindows)
{
  PreprocessOptions pre;
  pre.ground_pmf = true;
  EXPECT_EQ(pmfWindowSizes(pre), (std::vector<float>{3, 5, 9, 17, 33}));
  EXPECT_EQ(pmfReach(pre), 68.0); // 67 and one cell
  pre.pmf_cell = 0.5;
  pre.pmf_max_window = 9;
  EXPECT_EQ(pmfWindowSizes(pre), (std::vector<float>{1.5f, 2.5f, 4.5f, 8.5f, 16.5f}));
  pre.pmf_base = 1.0 + 1e-9; // 1 in float: PCL's window loop would never end
  EXPECT_EQ(validatePreprocessOptions(pre).code, StatusCode::INVALID_PARAMETER);
}

TEST_F(GroundTiles, BuildingsAcrossPreTileBordersKeepTheInMemoryPoints)
{
  const std::vector<double> xyz = builtTerrain();
  expectTheInMemoryPoints(xyz, smallWindows(), {3, 5});
  // With a crop first: the shift is the cropped cloud's, as in memory.
  PreprocessOptions cropped = smallWindows();
  cropped.crop = true;
  cropped.crop_min_x = 612013.3;
  cropped.crop_min_y = 5140007.0;
  cropped.crop_max_x = 612150.0;
  cropped.crop_max_y = 5140111.5;
  expectTheInMemoryPoints(xyz, cropped, {4});
}

TEST_F(GroundTiles, AnExactLatticeKeepsTheInMemoryPoints)
{
  // Points on a 0.25 m lattice symmetric about the centre: the shifted floats are
  // exact and hit 0, and PCL's box edges (x +- 0.75, 1.25) fall exactly on points, in
  // octrees of different bounds per pre-tile.
  std::vector<double> xyz;
  for (int j = -40; j <= 40; ++j)
    for (int i = -40; i <= 40; ++i) {
      const bool block = std::abs(i % 20) < 7 && std::abs(j % 20) < 7;
      xyz.insert(xyz.end(), {400000.0 + 0.25 * i, 6200000.0 + 0.25 * j,
                             50.0 + 0.25 * ((i + 3 * j) % 4) + (block ? 3.0 : 0.0)});
    }
  PreprocessOptions pre = smallWindows();
  pre.pmf_cell = 0.5;
  pre.pmf_max_window = 2;
  ASSERT_EQ(pmfWindowSizes(pre), (std::vector<float>{1.5f, 2.5f}));
  pre.pmf_initial_distance = 0.3;
  expectTheInMemoryPoints(xyz, pre, {3, 7});
}

TEST_F(GroundTiles, AnIsprsSampleKeepsTheInMemoryPoints)
{
  const std::string path =
      std::string(PCL_VTS_SHARED_DATA_DIR) + "/pcd/isprs_filtertest/samp53-utm.pcd";
  if (!fs::exists(path))
    GTEST_SKIP() << path << " not found";
  std::vector<double> xyz;
  CloudDescription description;
  ASSERT_TRUE(loadPointCloud(path, CloudLoadOptions{}, xyz, description).ok());
  expectTheInMemoryPoints(xyz, smallWindows(), {3, 6});
}

TEST_F(GroundTiles, APointAFullWindowAwayDecidesAClass)
{
  // One round (window 3, boxes of +-1.5): plateaus of 12 points 0.25 apart, 1 high,
  // between low points. No box of 3 fits on a plateau, so every plateau point is
  // opened to 0 and dropped; but the last one drops only because the low point 3
  // (a full window) before it is there: a pre-tile whose halo missed it would keep
  // it. The plateaus fall at every phase against the pre-tile borders.
  std::vector<double> xyz;
  for (int m = 0; m <= 29 * 41; ++m)
    xyz.insert(xyz.end(), {300000.0 + 0.25 * m, 4000000.0,
                           m % 29 >= 1 && m % 29 <= 12 ? 101.0 : 100.0});
  PreprocessOptions pre;
  pre.ground_pmf = true;
  pre.pmf_max_window = 3;
  ASSERT_EQ(pmfWindowSizes(pre), std::vector<float>{3.0f});
  std::vector<double> memory = xyz;
  std::vector<PreprocessStep> steps;
  ASSERT_TRUE(preprocessCloud(memory, pre, steps).ok());
  for (std::size_t k = 2; k < memory.size(); k += 3)
    ASSERT_EQ(memory[k], 100.0); // the plateaus are gone
  expectTheInMemoryPoints(xyz, pre, {7, 13, 31});
}

TEST_F(GroundTiles, TheWholeCloudsShiftDecidesTheTies)
{
  // Bumps exactly 0.5 (in decimal) above their opening, the first threshold: whether
  // PCL keeps one depends on how its float copy rounds, so on the shift. The
  // pre-tiles must use the whole cloud's shift to keep the same bumps.
  std::vector<double> xyz;
  for (int m = 0; m < 3000; ++m) {
    const double g = 100.0 + 0.01 * m;
    const double z = m % 3 == 1 ? 100.0 + 0.01 * (m + 1) + 0.5 : g; // g(m+1) + 0.5
    xyz.insert(xyz.end(), {500000.0 + m, 4000000.0, std::round(z * 100.0) / 100.0});
  }
  PreprocessOptions pre;
  pre.ground_pmf = true;
  pre.pmf_max_window = 3; // one round, threshold 0.5
  std::vector<double> memory = xyz;
  std::vector<PreprocessStep> steps;
  ASSERT_TRUE(preprocessCloud(memory, pre, steps).ok());
  const std::size_t dropped = (xyz.size() - memory.size()) / 3;
  EXPECT_GT(dropped, 500u);  // the ties fall both ways: most of the 1000 bumps drop,
  EXPECT_LT(dropped, 1000u); // some stay
  expectTheInMemoryPoints(xyz, pre, {5, 16});
}

/// The premise of the pre-tiles: PCL's octree boxSearch (what the morphological
/// opening calls) returns exactly the points that pass the float box test, whatever
/// the octree's bounds, which follow the cloud it is given (a pre-tile's, not the
/// whole cloud's). Checked against a sweep over x on a real sample and an exact
/// lattice (coordinates at 0, box edges on points), whole and cut into tiles.
TEST_F(GroundTiles, PclsBoxSearchIsTheFloatBoxTestWhateverTheOctreeBounds)
{
  std::vector<double> lattice;
  for (int j = -30; j <= 30; ++j)
    for (int i = -30; i <= 30; ++i)
      lattice.insert(lattice.end(), {0.25 * i, 0.25 * j, 0.1 * ((i * j) % 5)});
  std::vector<std::vector<double>> clouds = {lattice};
  const std::string path =
      std::string(PCL_VTS_SHARED_DATA_DIR) + "/pcd/isprs_filtertest/samp24-utm.pcd";
  if (fs::exists(path)) {
    std::vector<double> xyz;
    CloudDescription description;
    ASSERT_TRUE(loadPointCloud(path, CloudLoadOptions{}, xyz, description).ok());
    clouds.push_back(xyz);
  }
  std::size_t queries = 0;
  for (const std::vector<double>& xyz : clouds) {
    double lo[3] = {xyz[0], xyz[1], xyz[2]}, hi[3] = {xyz[0], xyz[1], xyz[2]};
    for (std::size_t k = 0; k < xyz.size(); ++k) {
      lo[k % 3] = std::min(lo[k % 3], xyz[k]);
      hi[k % 3] = std::max(hi[k % 3], xyz[k]);
    }
    const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    for (const float window : {3.0f, 17.0f})
      for (const int k : {3}) {
        if (window > extent / 4) // a box over the whole cloud tests nothing more
          continue;
        const double side = extent / k, halo = 2.0 * window;
        for (int tile = 0; tile < k * k; ++tile) {
          const double x0 = lo[0] + (tile % k) * side - halo,
                       y0 = lo[1] + (tile / k) * side - halo;
          pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
          for (std::size_t p = 0; p < xyz.size(); p += 3)
            if (xyz[p] >= x0 && xyz[p] <= x0 + side + 2 * halo && xyz[p + 1] >= y0 &&
                xyz[p + 1] <= y0 + side + 2 * halo)
              cloud->push_back(pcl::PointXYZ(
                  static_cast<float>(xyz[p] - 0.5 * (lo[0] + hi[0])),
                  static_cast<float>(xyz[p + 1] - 0.5 * (lo[1] + hi[1])),
                  static_cast<float>(xyz[p + 2] - 0.5 * (lo[2] + hi[2]))));
          pcl::octree::OctreePointCloudSearch<pcl::PointXYZ> tree(window);
          tree.setInputCloud(cloud);
          tree.addPointsFromInputCloud();
          std::vector<float> xs;
          for (const pcl::PointXYZ& p : *cloud)
            xs.push_back(p.x);
          std::vector<std::size_t> by_x(xs.size());
          std::iota(by_x.begin(), by_x.end(), std::size_t{0});
          std::sort(by_x.begin(), by_x.end(),
                    [&](std::size_t a, std::size_t b) { return xs[a] < xs[b]; });
          std::sort(xs.begin(), xs.end());
          const float half = window / 2.0f; // as applyMorphologicalOperator
          for (const pcl::PointXYZ& p : *cloud) {
            const Eigen::Vector3f min(p.x - half, p.y - half,
                                      -std::numeric_limits<float>::max());
            const Eigen::Vector3f max(p.x + half, p.y + half,
                                      std::numeric_limits<float>::max());
            pcl::Indices found;
            tree.boxSearch(min, max, found);
            std::vector<std::size_t> got(found.begin(), found.end()), exact;
            for (auto i = static_cast<std::size_t>(
                     std::lower_bound(xs.begin(), xs.end(), min.x()) - xs.begin());
                 i < xs.size() && xs[i] <= max.x(); ++i) {
              const pcl::PointXYZ& q = (*cloud)[by_x[i]];
              if (q.y >= min.y() && q.y <= max.y())
                exact.push_back(by_x[i]);
            }
            std::sort(got.begin(), got.end());
            std::sort(exact.begin(), exact.end());
            ASSERT_EQ(got, exact) << "window " << window << ", tile " << tile << " of "
                                  << k * k << ", point " << p.x << " " << p.y;
            ++queries;
          }
        }
      }
  }
  EXPECT_GT(queries, 20000u);
}

TEST_F(GroundTiles, TheMemoryLimitSetsThePreTiles)
{
  const std::vector<double> xyz = builtTerrain();
  GroundTilesOptions options;
  options.preprocess = smallWindows();
  options.memory_limit = std::uint64_t{2} << 20; // a few thousand points
  std::vector<double> kept;
  GroundTilesReport report;
  ASSERT_TRUE(tiled(xyz, options, kept, report).ok());
  EXPECT_GE(report.tiles_per_side, 4);
  EXPECT_LT(report.max_tile_points, report.cropped / 3);
  std::vector<double> memory = xyz;
  std::vector<PreprocessStep> steps;
  ASSERT_TRUE(preprocessCloud(memory, options.preprocess, steps).ok());
  EXPECT_TRUE(byXy(kept) == byXy(memory));
}

/// In-process "ranks" (threads) for GroundShare: barrier-based collectives.
class Hub {
 public:
  explicit Hub(int ranks)
      : ranks_(ranks)
  {}
  GroundShare share(int rank)
  {
    GroundShare s;
    s.rank = rank;
    s.ranks = ranks_;
    s.broadcast = [this, rank](std::string& bytes, int root) {
      if (rank == root) {
        const std::lock_guard<std::mutex> lock(mutex_);
        bytes_ = bytes;
      }
      barrier();
      bytes = bytes_;
      barrier();
    };
    s.sum = [this](std::vector<std::uint64_t>& values) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (adding_++ == 0)
          sum_.assign(values.size(), 0);
        for (std::size_t k = 0; k < values.size(); ++k)
          sum_[k] += values[k];
      }
      barrier();
      values = sum_;
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        --adding_;
      }
      barrier();
    };
    s.start_tasks = [this] {
      barrier();
      next_ = 0;
      barrier();
    };
    s.next_task = [this] { return next_.fetch_add(1); };
    return s;
  }

 private:
  void barrier()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const std::uint64_t generation = generation_;
    if (++arrived_ == ranks_) {
      arrived_ = 0;
      ++generation_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return generation != generation_; });
    }
  }

  int ranks_;
  std::mutex mutex_;
  std::condition_variable changed_;
  int arrived_ = 0, adding_ = 0;
  std::uint64_t generation_ = 0;
  std::string bytes_;
  std::vector<std::uint64_t> sum_;
  std::atomic<std::uint64_t> next_{0};
};

TEST_F(GroundTiles, RanksSharingThePreTilesKeepTheInMemoryPoints)
{
  const std::vector<double> xyz = builtTerrain();
  std::vector<double> memory = xyz;
  std::vector<PreprocessStep> steps;
  ASSERT_TRUE(preprocessCloud(memory, smallWindows(), steps).ok());
  const int ranks = 3;
  Hub hub(ranks);
  std::vector<std::vector<std::string>> files(ranks);
  std::vector<GroundTilesReport> reports(ranks);
  std::vector<Status> status(ranks);
  const GroundFeed feed = [&](const GroundSink& sink) {
    return sink(xyz.data(), xyz.size() / 3);
  };
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      GroundTilesOptions options;
      options.preprocess = smallWindows();
      options.tiles_per_side = 4;
      options.share = hub.share(r);
      status[r] = groundTiles(feed, options, folder_.string(), files[r], reports[r]);
    });
  for (std::thread& t : threads)
    t.join();
  for (int r = 0; r < ranks; ++r) {
    ASSERT_TRUE(status[r].ok()) << r << ": " << status[r].toString();
    EXPECT_EQ(files[r], files[0]) << r;
    EXPECT_EQ(reports[r].kept, memory.size() / 3) << r;
    EXPECT_EQ(reports[r].points_loaded, reports[0].points_loaded) << r;
  }
  std::vector<double> kept;
  for (const std::string& file : files[0])
    ASSERT_TRUE(readGroundFile(file, 1000, [&](const double* p, std::size_t n) {
                  kept.insert(kept.end(), p, p + 3 * n);
                  return Status::success();
                }).ok());
  EXPECT_TRUE(byXy(kept) == byXy(memory));
  // A failure on rank 0 (nothing left after the crop) is every rank's error.
  for (int r = 0; r < ranks; ++r)
    threads[r] = std::thread([&, r] {
      GroundTilesOptions options;
      options.preprocess = smallWindows();
      options.preprocess.crop = true;
      options.preprocess.crop_min_x = options.preprocess.crop_min_y = 0.0;
      options.preprocess.crop_max_x = options.preprocess.crop_max_y = 1.0;
      options.share = hub.share(r);
      status[r] = groundTiles(feed, options, folder_.string(), files[r], reports[r]);
    });
  for (std::thread& t : threads)
    t.join();
  for (int r = 0; r < ranks; ++r) {
    EXPECT_EQ(status[r].code, StatusCode::EMPTY_INPUT) << r;
    EXPECT_EQ(status[r].message, status[0].message) << r;
  }
}

TEST_F(GroundTiles, NothingLeftIsTheInMemoryError)
{
  std::vector<double> xyz = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  GroundTilesOptions options;
  options.preprocess.ground_pmf = true;
  options.preprocess.crop = true;
  options.preprocess.crop_min_x = 100;
  options.preprocess.crop_max_x = 200;
  options.preprocess.crop_min_y = 100;
  options.preprocess.crop_max_y = 200;
  std::vector<double> kept;
  GroundTilesReport report;
  const Status s = tiled(xyz, options, kept, report);
  EXPECT_EQ(s.code, StatusCode::EMPTY_INPUT);
  EXPECT_NE(s.message.find("'crop'"), std::string::npos) << s.message;
  options.preprocess.crop = false;
  options.preprocess.voxel = 1.0;
  EXPECT_EQ(tiled(xyz, options, kept, report).code, StatusCode::INVALID_PARAMETER);
}

// A ground file is whole xyz triples: one cut short (a trailing partial double, or
// a partial triple) is an IO_ERROR naming it, not the points before the cut.
TEST_F(GroundTiles, AGroundFileCutShortIsAnIoError)
{
  std::vector<double> xyz(3 * 5000);
  std::iota(xyz.begin(), xyz.end(), 0.0);
  const std::string path = (folder_ / "ground_0.xyz").string();
  const auto writeBytes = [&](std::size_t bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(xyz.data(), 1, bytes, f), bytes);
    std::fclose(f);
  };
  std::size_t points = 0;
  const GroundSink count = [&](const double*, std::size_t n) {
    points += n;
    return Status::success();
  };
  writeBytes(xyz.size() * sizeof(double));
  ASSERT_TRUE(readGroundFile(path, 777, count).ok());
  EXPECT_EQ(points, 5000u);
  for (const std::size_t cut : {std::size_t{4}, std::size_t{8}, std::size_t{20}}) {
    writeBytes(xyz.size() * sizeof(double) - cut);
    const Status s = readGroundFile(path, 777, count);
    EXPECT_EQ(s.code, StatusCode::IO_ERROR) << cut;
    EXPECT_NE(s.message.find(path), std::string::npos) << s.message;
  }
  EXPECT_EQ(readGroundFile((folder_ / "missing.xyz").string(), 777, count).code,
            StatusCode::IO_ERROR);
}

} // namespace
} // namespace pcl_vts
