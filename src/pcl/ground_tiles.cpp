#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/ground_tiles.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>

namespace pcl_vts {
namespace {

/// Peak bytes per point of the in-memory ground filter (the doubles, PCL's float
/// copies of each round, its octree): at most about 230 measured on 3.6e5 points.
constexpr std::uint64_t PMF_BYTES_PER_POINT = 320;

/// At most this many pre-tiles per side (a million pre-tiles).
constexpr int MAX_PRE_TILES_PER_SIDE = 1024;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

Status ioError(const std::string& what, const std::string& path)
{
  return Status::error(StatusCode::IO_ERROR, what + " '" + path + "'");
}

Status appendDoubles(const std::string& path, const std::vector<double>& values)
{
  if (values.empty())
    return Status::success();
  File f(std::fopen(path.c_str(), "ab"));
  if (!f || std::fwrite(values.data(), sizeof(double), values.size(), f.get()) !=
                values.size())
    return ioError("cannot write temporary file", path);
  if (std::fclose(f.release()) != 0)
    return ioError("cannot write temporary file", path);
  return Status::success();
}

Status readDoubles(const std::string& path, std::vector<double>& values)
{
  values.clear();
  File f(std::fopen(path.c_str(), "rb"));
  if (!f)
    return ioError("cannot read temporary file", path);
  if (std::fseek(f.get(), 0, SEEK_END) != 0)
    return ioError("cannot read temporary file", path);
  const long bytes = std::ftell(f.get());
  if (bytes < 0 || bytes % static_cast<long>(3 * sizeof(double)) != 0 ||
      std::fseek(f.get(), 0, SEEK_SET) != 0)
    return ioError("cannot read temporary file", path);
  values.resize(static_cast<std::size_t>(bytes) / sizeof(double));
  if (std::fread(values.data(), sizeof(double), values.size(), f.get()) !=
      values.size())
    return ioError("cannot read temporary file", path);
  return Status::success();
}

bool finite(const double* p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

bool insideCrop(const PreprocessOptions& o, const double* p)
{
  return !o.crop || (p[0] >= o.crop_min_x && p[0] <= o.crop_max_x &&
                     p[1] >= o.crop_min_y && p[1] <= o.crop_max_y);
}

Status emptyAfter(const char* step)
{
  return Status::error(StatusCode::EMPTY_INPUT,
                       std::string("no point left after preprocessing step '") + step +
                           "'");
}

/// The square pre-tiles over the cloud's box: column and row of an XY position.
struct PreTiles {
  double x0 = 0.0, y0 = 0.0, side = 1.0;
  int per_side = 1; ///< pre-tiles per side (per_side x per_side)

  int index(double v, double origin) const
  {
    const double t = std::floor((v - origin) / side);
    return t < 0.0 ? 0 : t >= per_side ? per_side - 1 : static_cast<int>(t);
  }
  int column(double x) const { return index(x, x0); }
  int row(double y) const { return index(y, y0); }
};

/// Pre-tiles per side: the fewest whose core and halo hold about the points the
/// memory allows, at the cloud's mean density.
int choosePreTiles(std::uint64_t n, double width, double height, double halo,
                   std::uint64_t memory_limit)
{
  const double budget =
      std::max(1.0, static_cast<double>(memory_limit / PMF_BYTES_PER_POINT));
  const double extent = std::max(width, height);
  if (!(extent > 0.0))
    return 1;
  for (int k = 1; k < MAX_PRE_TILES_PER_SIDE; k *= 2) {
    const double reach = extent / k + 2.0 * halo;
    const double share = std::min(1.0, reach / std::max(width, extent * 1e-9)) *
                         std::min(1.0, reach / std::max(height, extent * 1e-9));
    // Past a side of the halo, smaller pre-tiles load mostly halo.
    if (static_cast<double>(n) * share <= budget || extent / k < halo)
      return k;
  }
  return MAX_PRE_TILES_PER_SIDE;
}

/// What every process needs for the filter phase (from the one that read).
struct Plan {
  PreTiles tiles;
  double shift[3] = {0.0, 0.0, 0.0};
  std::vector<std::uint64_t> loaded; ///< points per pre-tile file, halo included

  std::size_t count() const
  {
    return static_cast<std::size_t>(tiles.per_side) *
           static_cast<std::size_t>(tiles.per_side);
  }
};

/// Pre-tile t's points with its halo, as bucketed (removed once filtered).
std::string loadFile(const std::string& folder, std::size_t t)
{
  return folder + "/pmf_" + std::to_string(t) + ".xyz";
}

/// Pre-tile t's ground points in its core: one of the files the pre-pass hands over.
std::string groundFile(const std::string& folder, std::size_t t)
{
  return folder + "/ground_" + std::to_string(t) + ".xyz";
}

/// The crop's points when there is no ground filter: the one file handed over.
std::string croppedFile(const std::string& folder)
{
  return folder + "/cropped.xyz";
}

/// A status, or the plan and the reading's report, as text (doubles in hex: exact).
std::string encodePlan(const Status& status, const Plan& plan,
                       const GroundTilesReport& report)
{
  if (!status.ok())
    return "error " + std::to_string(static_cast<int>(status.code)) + " " +
           status.message;
  char text[512];
  std::snprintf(text, sizeof(text), "ok %d %a %a %a %a %a %a %a %llu %llu %llu %llu",
                plan.tiles.per_side, plan.tiles.x0, plan.tiles.y0, plan.tiles.side,
                plan.shift[0], plan.shift[1], plan.shift[2], report.halo,
                static_cast<unsigned long long>(report.points),
                static_cast<unsigned long long>(report.non_finite),
                static_cast<unsigned long long>(report.cropped),
                static_cast<unsigned long long>(report.kept));
  return text;
}

Status decodePlan(const std::string& bytes, Plan& plan, GroundTilesReport& report)
{
  if (bytes.rfind("error ", 0) == 0) {
    char* end = nullptr;
    const long code = std::strtol(bytes.c_str() + 6, &end, 10);
    return Status::error(static_cast<StatusCode>(code),
                         *end == ' ' ? std::string(end + 1) : std::string());
  }
  unsigned long long points = 0, non_finite = 0, cropped = 0, kept = 0;
  if (std::sscanf(bytes.c_str(),
                  "ok %d %la %la %la %la %la %la %la %llu %llu %llu %llu",
                  &plan.tiles.per_side, &plan.tiles.x0, &plan.tiles.y0,
                  &plan.tiles.side, &plan.shift[0], &plan.shift[1], &plan.shift[2],
                  &report.halo, &points, &non_finite, &cropped, &kept) != 12)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "ground pre-pass: a rank received no plan");
  report.points = points;
  report.non_finite = non_finite;
  report.cropped = cropped;
  report.kept = kept;
  report.tiles_per_side = plan.tiles.per_side;
  report.tile_side = plan.tiles.side;
  return Status::success();
}

} // namespace

Status readGroundFile(const std::string& path, std::size_t chunk_points,
                      const GroundSink& sink)
{
  File f(std::fopen(path.c_str(), "rb"));
  if (!f)
    return ioError("cannot read temporary file", path);
  std::vector<double> chunk(3 * std::max<std::size_t>(chunk_points, 1));
  const std::size_t chunk_bytes = chunk.size() * sizeof(double);
  constexpr std::size_t POINT_BYTES = 3 * sizeof(double);
  for (;;) {
    // Counted in bytes: a file cut inside a double is not whole triples either.
    const std::size_t got = std::fread(chunk.data(), 1, chunk_bytes, f.get());
    if (got < chunk_bytes && std::ferror(f.get()))
      return ioError("cannot read temporary file", path);
    if (got % POINT_BYTES != 0)
      return ioError("temporary file cut short (not whole xyz triples)", path);
    if (got > 0)
      if (Status s = sink(chunk.data(), got / POINT_BYTES); !s.ok())
        return s;
    if (got < chunk_bytes)
      return Status::success();
  }
}

namespace {

/// Worker threads of the pre-pass (options.threads; 0 = every hardware thread).
unsigned workerCount(const GroundTilesOptions& options)
{
  return options.threads != 0 ? options.threads : allCores();
}

void reportProgress(const GroundTilesOptions& options, const char* phase,
                    std::uint64_t done, std::uint64_t total)
{
  if (options.progress)
    options.progress(phase, done, total);
}

/// Phase 1, the scan: report's points, non_finite and cropped counted, the box of
/// the points the crop keeps (the in-memory shift); with the crop alone (no ground
/// filter) those points go to the cropped file, the only pass. EMPTY_INPUT as in
/// memory when none is left.
Status scanPoints(const GroundFeed& feed, const GroundTilesOptions& options,
                  const std::string& folder, std::array<double, 3>& lo,
                  std::array<double, 3>& hi, GroundTilesReport& report)
{
  const PreprocessOptions& pre = options.preprocess;
  Stopwatch watch;
  std::uint64_t n = 0;
  const std::string cropped_path = croppedFile(folder);
  std::vector<double> buffer;
  const std::size_t buffer_values = 3 * 65536;
  Status s = feed([&](const double* xyz, std::size_t count) {
    reportProgress(options, "ground scan", report.points, 0);
    for (std::size_t i = 0; i < count; ++i) {
      const double* p = xyz + 3 * i;
      ++report.points;
      if (!finite(p)) {
        ++report.non_finite;
        continue;
      }
      if (!insideCrop(pre, p))
        continue;
      for (std::size_t c = 0; c < 3; ++c) {
        lo[c] = n == 0 ? p[c] : std::min(lo[c], p[c]);
        hi[c] = n == 0 ? p[c] : std::max(hi[c], p[c]);
      }
      ++n;
      if (!pre.ground_pmf) { // the crop alone: one pass, one file
        buffer.insert(buffer.end(), p, p + 3);
        if (buffer.size() >= buffer_values) {
          if (Status w = appendDoubles(cropped_path, buffer); !w.ok())
            return w;
          buffer.clear();
        }
      }
    }
    return Status::success();
  });
  if (!s.ok())
    return s;
  report.cropped = n;
  report.seconds_scan = watch.seconds();
  if (report.points == report.non_finite)
    return emptyAfter("non-finite");
  if (n == 0)
    return emptyAfter("crop");
  if (!pre.ground_pmf) {
    report.kept = n;
    report.tiles = report.tiles_per_side = 1;
    return appendDoubles(cropped_path, buffer);
  }
  return Status::success();
}

/// Phases 1 and 2 (the process that reads the inputs): the plan, the pre-tile files.
Status readAndBucket(const GroundFeed& feed, const GroundTilesOptions& options,
                     const std::string& folder, Plan& plan, GroundTilesReport& report)
{
  const PreprocessOptions& pre = options.preprocess;
  std::array<double, 3> lo{}, hi{};
  if (Status s = scanPoints(feed, options, folder, lo, hi, report);
      !s.ok() || !pre.ground_pmf)
    return s;
  const std::uint64_t n = report.cropped;

  // 2. Bucket: each point into the file of every pre-tile whose core or halo holds
  //    it, in input order.
  Stopwatch watch;
  const double width = hi[0] - lo[0], height = hi[1] - lo[1];
  const double extent = std::max(width, height);
  // The reach of the filter, one cell and a millionth of the extent for the float
  // rounding of the shifted coordinates and of PCL's box bounds.
  const double halo = pmfReach(pre) + 1e-6 * extent;
  const unsigned workers = workerCount(options);
  PreTiles& tiles = plan.tiles;
  tiles.x0 = lo[0];
  tiles.y0 = lo[1];
  tiles.per_side =
      options.tiles_per_side > 0
          ? std::min(options.tiles_per_side, MAX_PRE_TILES_PER_SIDE)
          : choosePreTiles(n, width, height, halo, options.memory_limit / workers);
  tiles.side = extent > 0.0 ? extent / tiles.per_side : 1.0;
  report.tiles_per_side = tiles.per_side;
  report.tile_side = tiles.side;
  report.halo = halo;
  const std::size_t count = plan.count();
  for (std::size_t c = 0; c < 3; ++c)
    plan.shift[c] = 0.5 * (lo[c] + hi[c]);
  // The points wait in one buffer per pre-tile; all of them go to the files once
  // they hold an eighth of the limit (the buffers released: their total stays
  // bounded whatever the number of pre-tiles).
  std::vector<std::vector<double>> buffers(count);
  std::vector<std::size_t> dirty; // pre-tiles with buffered points
  std::vector<std::uint64_t>& loaded = plan.loaded;
  loaded.assign(count, 0);
  const std::size_t max_buffered =
      3 * static_cast<std::size_t>(std::clamp<std::uint64_t>(
              options.memory_limit / 8 / 24, 4096, std::uint64_t{1} << 22));
  std::size_t buffered = 0;
  const auto flush = [&]() {
    for (const std::size_t t : dirty) {
      if (Status w = appendDoubles(loadFile(folder, t), buffers[t]); !w.ok())
        return w;
      std::vector<double>().swap(buffers[t]);
    }
    dirty.clear();
    buffered = 0;
    return Status::success();
  };
  std::uint64_t seen = 0;
  Status s = feed([&](const double* xyz, std::size_t points) {
    reportProgress(options, "ground bucket", seen, n);
    for (std::size_t i = 0; i < points; ++i) {
      const double* p = xyz + 3 * i;
      if (!finite(p) || !insideCrop(pre, p))
        continue;
      ++seen;
      const int c0 = tiles.column(p[0] - halo), c1 = tiles.column(p[0] + halo);
      const int r0 = tiles.row(p[1] - halo), r1 = tiles.row(p[1] + halo);
      for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
          const std::size_t t = static_cast<std::size_t>(r * tiles.per_side + c);
          std::vector<double>& b = buffers[t];
          if (b.empty())
            dirty.push_back(t);
          b.insert(b.end(), p, p + 3);
          ++loaded[t];
          if ((buffered += 3) >= max_buffered)
            if (Status w = flush(); !w.ok())
              return w;
        }
    }
    return Status::success();
  });
  if (!s.ok())
    return s;
  if (seen != n)
    return Status::error(StatusCode::IO_ERROR,
                         "the inputs changed while they were read (" +
                             std::to_string(n) + " points kept by the crop, then " +
                             std::to_string(seen) + ")");
  if (Status w = flush(); !w.ok())
    return w;
  std::vector<std::vector<double>>().swap(buffers);
  report.seconds_bucket = watch.seconds();
  return Status::success();
}

/// What one pre-tile gave.
struct PreTileResult {
  Status status;
  std::uint64_t loaded = 0, kept = 0; ///< loaded = 0: no core point
};

/// Phase 3 for pre-tile t: its file read (and removed), the in-memory filter run on
/// the points with their halo, the ground of its core appended to its ground file.
/// xyz is scratch.
Status filterPreTile(const std::string& folder, const PreTiles& tiles,
                     const PreprocessOptions& ground, std::size_t t,
                     std::vector<double>& xyz, PreTileResult& result)
{
  const int row = static_cast<int>(t / static_cast<std::size_t>(tiles.per_side));
  const int column = static_cast<int>(t % static_cast<std::size_t>(tiles.per_side));
  if (Status r = readDoubles(loadFile(folder, t), xyz); !r.ok())
    return r;
  std::remove(loadFile(folder, t).c_str());
  const auto core = [&](const double* p) {
    return tiles.column(p[0]) == column && tiles.row(p[1]) == row;
  };
  bool any_core = false;
  for (std::size_t i = 0; i < xyz.size() && !any_core; i += 3)
    any_core = core(&xyz[i]);
  if (!any_core)
    return Status::success();
  result.loaded = xyz.size() / 3;
  std::vector<PreprocessStep> steps;
  const Status f = preprocessCloud(xyz, ground, steps);
  if (f.code == StatusCode::EMPTY_INPUT)
    return Status::success(); // no ground in this pre-tile
  if (!f.ok())
    return f;
  std::size_t out = 0;
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    if (core(&xyz[i])) {
      std::copy(xyz.begin() + static_cast<std::ptrdiff_t>(i),
                xyz.begin() + static_cast<std::ptrdiff_t>(i + 3),
                xyz.begin() + static_cast<std::ptrdiff_t>(out));
      out += 3;
    }
  xyz.resize(out);
  result.kept = out / 3;
  return appendDoubles(groundFile(folder, t), xyz);
}

/// Runs task(t, scratch) for each t that next_task() hands out below count, on
/// `threads` threads (the calling thread alone when 1), until the counter runs out or
/// a task returns false. report(pre-tiles taken so far) is called from the calling
/// thread only: between tasks, or every half second while a pool works.
void takeTasks(std::size_t count, std::size_t threads,
               const std::function<std::size_t()>& next_task,
               const std::function<bool(std::size_t, std::vector<double>&)>& task,
               const std::function<void(std::uint64_t)>& report)
{
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t running = 0; // workers still taking tasks (under mutex)
  std::size_t taken = 0;   // the highest task taken here (progress)
  // inline: the calling thread takes the tasks itself and reports between them.
  const auto work = [&](bool inline_run) {
    std::vector<double> scratch;
    for (std::size_t t; !failed && (t = next_task()) < count;) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        taken = std::max(taken, t + 1);
      }
      if (!task(t, scratch))
        failed = true;
      if (inline_run)
        report(taken);
    }
    const std::lock_guard<std::mutex> lock(mutex);
    --running;
    changed.notify_all();
  };
  std::vector<std::thread> pool;
  if (threads > 1) {
    running = threads;
    try {
      for (std::size_t w = 0; w < threads; ++w)
        pool.emplace_back(work, false);
    } catch (const std::system_error&) {
      // A thread limit: the threads that started take every task (none: see below).
      const std::lock_guard<std::mutex> lock(mutex);
      running -= threads - pool.size();
    }
  }
  if (pool.empty()) {
    running = 1;
    work(true);
    return;
  }
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (running > 0) {
      const std::size_t done = taken;
      lock.unlock();
      report(done);
      lock.lock();
      changed.wait_for(lock, std::chrono::milliseconds(500));
    }
  }
  for (std::thread& thread : pool)
    thread.join();
}

} // namespace

Status groundTiles(const GroundFeed& feed, const GroundTilesOptions& options,
                   const std::string& folder, std::vector<std::string>& files,
                   GroundTilesReport& report)
{
  report = GroundTilesReport{};
  files.clear();
  const PreprocessOptions& pre = options.preprocess;
  if (pre.voxel > 0.0 || pre.grid_min > 0.0 || pre.outlier_k > 0)
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "voxel, grid_min and outlier_k run in memory only, not over pre-tiles");
  if (Status s = validatePreprocessOptions(pre); !s.ok())
    return s;
  const GroundShare& share = options.share;
  const bool shared = share.ranks > 1;
  Plan plan;
  Status status;
  if (share.rank == 0)
    status = readAndBucket(feed, options, folder, plan, report);
  if (shared) { // rank 0's plan (or error) to every rank
    std::string bytes = share.rank == 0 ? encodePlan(status, plan, report) : "";
    share.broadcast(bytes, 0);
    if (share.rank != 0)
      status = decodePlan(bytes, plan, report);
    if (status.ok() && pre.ground_pmf) {
      plan.loaded.resize(plan.count());
      share.sum(plan.loaded);
    }
  }
  if (!status.ok())
    return status;
  if (!pre.ground_pmf) {
    files.push_back(croppedFile(folder));
    return Status::success();
  }
  const PreTiles& tiles = plan.tiles;
  const std::size_t count = plan.count();
  const std::vector<std::uint64_t>& loaded = plan.loaded;
  const unsigned workers = workerCount(options);
  Stopwatch watch;

  // 3. Filter each pre-tile with its halo; keep the ground of its core. The
  //    pre-tiles go to whichever worker asks next; the files are listed in order.
  PreprocessOptions ground = pre;
  ground.crop = false;
  ground.fixed_shift = true;
  for (int c = 0; c < 3; ++c)
    ground.shift[c] = plan.shift[c];
  std::vector<PreTileResult> results(count);
  std::atomic<std::size_t> next{0};
  // The next pre-tile: from the counter shared by every rank and thread.
  if (shared)
    share.start_tasks();
  takeTasks(
      count, std::min<std::size_t>(workers, count),
      [&]() -> std::size_t {
        return shared ? static_cast<std::size_t>(share.next_task()) : next.fetch_add(1);
      },
      [&](std::size_t t, std::vector<double>& xyz) {
        if (loaded[t] != 0)
          results[t].status = filterPreTile(folder, tiles, ground, t, xyz, results[t]);
        return results[t].status.ok();
      },
      [&](std::uint64_t done) {
        reportProgress(options, "ground filter", done, count);
      });

  // Every rank's pre-tiles: the first failure (the lowest rank's), the counts.
  Status failure;
  for (std::size_t t = 0; t < count && failure.ok(); ++t)
    failure = results[t].status;
  if (shared) {
    std::vector<std::uint64_t> failed_on(static_cast<std::size_t>(share.ranks), 0);
    failed_on[static_cast<std::size_t>(share.rank)] = failure.ok() ? 0 : 1;
    share.sum(failed_on);
    const auto first = std::find(failed_on.begin(), failed_on.end(), 1u);
    if (first != failed_on.end()) {
      const int root = static_cast<int>(first - failed_on.begin());
      std::string bytes = share.rank == root ? encodePlan(failure, plan, report) : "";
      share.broadcast(bytes, root);
      return decodePlan(bytes, plan, report);
    }
  }
  if (!failure.ok())
    return failure;
  std::vector<std::uint64_t> counts(2 * count, 0);
  for (std::size_t t = 0; t < count; ++t) {
    counts[2 * t] = results[t].loaded;
    counts[2 * t + 1] = results[t].kept;
  }
  if (shared)
    share.sum(counts);
  for (std::size_t t = 0; t < count; ++t) {
    const std::uint64_t loaded_here = counts[2 * t], kept = counts[2 * t + 1];
    if (loaded_here == 0)
      continue;
    ++report.tiles;
    report.points_loaded += loaded_here;
    report.max_tile_points = std::max(report.max_tile_points, loaded_here);
    if (kept == 0)
      continue;
    report.kept += kept;
    files.push_back(groundFile(folder, t));
  }
  report.seconds_filter = watch.seconds();
  if (report.kept == 0)
    return emptyAfter("ground");
  return Status::success();
}

} // namespace pcl_vts
