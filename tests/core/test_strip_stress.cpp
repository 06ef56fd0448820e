// Adversarial inputs for the strip triangulator (docs/algorithm.md, section 4): points
// on strip borders, exact ties straddling strips, long triangles and hull edges that
// cross many strips, strips whose vertices only see other strips, strips with no
// points. Every case runs at strip widths 1, 2, 4 and automatic, each checked against
// the CGAL oracle (expectValidTriangulation, our tie-break included), and with 1 and 3
// threads, whose arrays must be identical; the automatic width with cache blocks on.
#include "support/generators.h"
#include "support/pipeline_checks.h"

#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

using test::PipelineRun;
using test::runPipeline;

constexpr std::uint32_t STRIP_WIDTHS[] = {1u, 2u, 4u, 0u};

/// std::mt19937 with hand-written maps (<random>'s distributions are
/// implementation-defined): a seed names the same points everywhere.
class Rng {
 public:
  explicit Rng(std::uint32_t seed)
      : engine_(seed)
  {}
  /// Uniform in [0, 1).
  double uniform()
  {
    const std::uint64_t hi = engine_() >> 5, lo = engine_() >> 6;
    return static_cast<double>((hi << 26) | lo) * 0x1p-53;
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n).
  std::size_t index(std::size_t n)
  {
    return static_cast<std::size_t>(uniform() * static_cast<double>(n));
  }
  /// Uniform integer in [lo, hi].
  double integer(int lo, int hi)
  {
    return static_cast<double>(lo + static_cast<int>(index(hi - lo + 1)));
  }
  bool coin(double p = 0.5) { return uniform() < p; }

 private:
  std::mt19937 engine_;
};

void push(std::vector<double>& xyz, double x, double y, double z = 0.0)
{
  xyz.push_back(x);
  xyz.push_back(y);
  xyz.push_back(z);
}

/// Fisher-Yates over points: sorted input hides bugs.
void shufflePoints(std::vector<double>& xyz, Rng& rng)
{
  for (std::size_t i = xyz.size() / 3; i > 1; --i) {
    const std::size_t j = rng.index(i);
    for (int k = 0; k < 3; ++k)
      std::swap(xyz[3 * (i - 1) + k], xyz[3 * j + k]);
  }
}

/// One input and the cell size it is meant for (0 = automatic).
struct StressCase {
  std::vector<double> xyz;
  double cell_size = 0.0;
};

std::string describe(const std::string& family, std::uint32_t seed, const StressCase& c)
{
  std::ostringstream s;
  s << family << " seed=" << seed << " n=" << c.xyz.size() / 3
    << " cell_size=" << c.cell_size;
  return s.str();
}

/// Runs c at every strip width, checks each run against CGAL and the 3-thread run
/// against the 1-thread one (same arrays). `exact_cell`: the grid must use
/// c.cell_size as given (the case puts points on known column boundaries).
void expectStripsAgree(const StressCase& c, bool exact_cell = false)
{
  const StatusCode expected = test::expectedStatusCode(c.xyz);
  for (const std::uint32_t columns : STRIP_WIDTHS) {
    // Cache blocks on at the automatic width: their windows then hold the whole of
    // these small inputs, so Bowyer-Watson meets every adversarial tie.
    const bool cache_blocks = columns == 0;
    SCOPED_TRACE("strip_columns=" + std::to_string(columns) +
                 (cache_blocks ? " cache_blocks" : ""));
    VtsOptions options;
    options.lattice = false; // the strips themselves, on lattice inputs too
    options.cell_size = c.cell_size;
    options.strip_columns = columns;
    options.cache_blocks = cache_blocks;
    options.threads = 1;
    const PipelineRun one = runPipeline(c.xyz, options);
    ASSERT_EQ(one.status.code, expected) << one.status.toString();
    if (expected != StatusCode::OK)
      return;
    if (exact_cell) {
      ASSERT_EQ(one.result.diagnostics.cell_size, c.cell_size);
    }
    test::expectValidTriangulation(c.xyz, one, options);
    options.threads = 3;
    const PipelineRun three = runPipeline(c.xyz, options);
    ASSERT_TRUE(three.status.ok()) << three.status.toString();
    EXPECT_EQ(three.result.mesh.triangles, one.result.mesh.triangles);
    EXPECT_EQ(three.result.mesh.halfedges, one.result.mesh.halfedges);
    EXPECT_EQ(three.result.hull, one.result.hull);
    EXPECT_EQ(three.result.source_index, one.result.source_index);
    if (::testing::Test::HasFailure())
      return; // one report per case is enough
  }
}

// ---- Families
// ------------------------------------------------------------------------

/// Every x a multiple of the (dyadic) cell size, so every point lies exactly on a
/// column boundary; many points share an x; y on the same lattice (ties) or random.
StressCase onColumnBoundaries(Rng& rng, std::size_t n)
{
  static const double CELLS[] = {1.0, 0.5, 2.0, 0.25};
  StressCase c;
  c.cell_size = CELLS[rng.index(4)];
  const int columns = 1 + static_cast<int>(rng.index(24));
  const bool lattice_y = rng.coin();
  const int rows = 1 + static_cast<int>(rng.index(24));
  for (std::size_t i = 0; i < n; ++i) {
    const double x = c.cell_size * rng.integer(0, columns);
    const double y = lattice_y ? c.cell_size * rng.integer(0, rows)
                               : rng.uniform(0.0, c.cell_size * rows);
    push(c.xyz, x, y, rng.uniform());
  }
  return c;
}

/// A non-dyadic cell size with x = origin + k * cell rounded: (x - origin) / cell
/// lands a few ulps either side of the integer k, i.e. of the column boundary.
StressCase nearColumnBoundaries(Rng& rng, std::size_t n)
{
  static const double CELLS[] = {0.1, 0.3, 1.0 / 3.0, 0.7, 1e-3};
  static const double ORIGINS[] = {0.0, 12.345, -7.1, 5e5 + 0.1, 1e3 / 3.0};
  StressCase c;
  c.cell_size = CELLS[rng.index(5)];
  const double ox = ORIGINS[rng.index(5)], oy = ORIGINS[rng.index(5)];
  const int columns = 2 + static_cast<int>(rng.index(20));
  const int rows = 2 + static_cast<int>(rng.index(20));
  const bool lattice_y = rng.coin(0.7);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = ox + rng.integer(0, columns) * c.cell_size;
    const double y = lattice_y ? oy + rng.integer(0, rows) * c.cell_size
                               : oy + rng.uniform(0.0, rows * c.cell_size);
    push(c.xyz, x, y);
  }
  return c;
}

/// Vertical lines of points at strip borders (x a multiple of 1, 2, 4 or 8 cells),
/// some dense, some with two or three points, so lines of equal x carry collinear
/// hull runs on the left and right borders and the last column may hold only hull
/// vertices.
StressCase verticalLines(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = 1.0;
  const double step = static_cast<double>(1 << rng.index(4));
  const int lines = 2 + static_cast<int>(rng.index(7));
  std::vector<std::size_t> count(lines);
  for (int l = 0; l < lines; ++l)
    count[l] = rng.coin(0.3) ? 1 + rng.index(3) : 2 + rng.index(2 * n / lines + 1);
  const bool lattice_y = rng.coin();
  const double height = static_cast<double>(4 + rng.index(40));
  for (int l = 0; l < lines; ++l)
    for (std::size_t k = 0; k < count[l]; ++k) {
      const double y = lattice_y ? rng.integer(0, static_cast<int>(height))
                                 : rng.uniform(0.0, height);
      push(c.xyz, step * l, y, rng.uniform());
    }
  // A few points off the lines, sometimes none: strips with no points at all.
  const std::size_t loose = rng.coin() ? rng.index(4) : 0;
  for (std::size_t k = 0; k < loose; ++k)
    push(c.xyz, rng.uniform(0.0, step * (lines - 1)), rng.uniform(0.0, height));
  return c;
}

/// The r2 with many lattice points (r2 = 5^a 13^b 17^c ...).
const std::int64_t RICH_R2[] = {25, 65, 325, 1105, 5525, 15625, 27625};

/// Unions of exactly cocircular lattice circles with integer centres, sometimes with
/// their centres and an integer lattice patch, cut by narrow columns: every tie
/// straddles several strips.
StressCase latticeCircles(Rng& rng, std::size_t n)
{
  static const double CELLS[] = {1.0, 2.0, 5.0, 8.0, 0.5};
  StressCase c;
  c.cell_size = CELLS[rng.index(5)];
  const std::size_t circles = 1 + rng.index(3);
  for (std::size_t k = 0; k < circles; ++k) {
    const std::vector<double> xy = test::latticeCircle(RICH_R2[rng.index(7)]);
    const double cx = rng.integer(-20, 20), cy = rng.integer(-20, 20);
    const double keep = rng.coin() ? 1.0 : 0.6;
    for (std::size_t i = 0; i < xy.size() / 2; ++i)
      if (rng.coin(keep))
        push(c.xyz, cx + xy[2 * i], cy + xy[2 * i + 1], rng.uniform());
    if (rng.coin())
      push(c.xyz, cx, cy);
  }
  if (rng.coin(0.3))
    for (std::size_t k = 0; k < n / 4; ++k)
      push(c.xyz, rng.integer(-10, 10), rng.integer(-10, 10));
  return c;
}

/// A square lattice rotated by 45 degrees ((i - j, i + j), a random subset): every
/// lattice cell is a cocircular square whose diagonals are vertical, on the columns.
StressCase rotatedLattice(Rng& rng, std::size_t n)
{
  StressCase c;
  static const double CELLS[] = {1.0, 0.5, 2.0, 3.0};
  c.cell_size = CELLS[rng.index(4)];
  const int m = 2 + static_cast<int>(std::sqrt(static_cast<double>(n)));
  const double keep = rng.coin() ? 1.0 : rng.uniform(0.3, 0.9);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      if (rng.coin(keep))
        push(c.xyz, i - j, i + j, i * j);
  return c;
}

/// The integer lattice with cell size 1: every point on a column boundary, every
/// lattice square a tie, with one-column strips.
StressCase exactGrid(Rng& rng, std::size_t n)
{
  StressCase c;
  static const double CELLS[] = {1.0, 0.5, 2.0, 0.75};
  c.cell_size = CELLS[rng.index(4)];
  c.xyz = test::generatePoints(test::Distribution::EXACT_GRID, n, rng.index(1000));
  return c;
}

/// Two dense clusters far apart in x joined by a sparse bridge: long skinny triangles
/// and long hull edges cross every strip between them, and the bridge's strips hold
/// one or two vertices whose neighbours are all elsewhere.
StressCase twoClusters(Rng& rng, std::size_t n)
{
  StressCase c;
  const double gap = rng.coin() ? 100.0 : 1000.0;
  c.cell_size = rng.coin() ? 1.0 : 0.0;
  const std::size_t bridge = rng.index(5);
  const bool integer = rng.coin();
  for (std::size_t k = 0; k + bridge < n; ++k) {
    const double base = (k % 2 == 0) ? 0.0 : gap;
    push(c.xyz, base + (integer ? rng.integer(0, 10) : rng.uniform(0.0, 10.0)),
         integer ? rng.integer(0, 10) : rng.uniform(0.0, 10.0));
  }
  for (std::size_t k = 0; k < bridge; ++k)
    push(c.xyz, rng.uniform(10.0, gap), rng.coin() ? 5.0 : rng.uniform(0.0, 10.0));
  return c;
}

/// Points (k, k^2) on a parabola (all on the hull: every triangle is long and thin)
/// with a few points inside, sometimes far outliers.
StressCase parabola(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = rng.coin() ? 0.0 : 4.0;
  const int half = 1 + static_cast<int>(rng.index(n / 2 + 1));
  const bool shifted = rng.coin();
  for (int k = -half; k <= half; ++k)
    if (!shifted || k >= 0)
      push(c.xyz, k, static_cast<double>(k) * k);
  const std::size_t inside = rng.index(n / 4 + 1);
  const double top = static_cast<double>(half) * half;
  for (std::size_t k = 0; k < inside; ++k) {
    const double x = rng.uniform(-half, half);
    push(c.xyz, x, rng.uniform(x * x, top));
  }
  return c;
}

/// A uniform patch plus a few far outliers: the outliers' triangles span hundreds of
/// strips and most strips between are empty.
StressCase farOutliers(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = rng.coin() ? 0.0 : 20.0;
  for (std::size_t k = 0; k < n; ++k)
    push(c.xyz, rng.uniform(0.0, 100.0), rng.uniform(0.0, 100.0));
  const std::size_t outliers = 1 + rng.index(4);
  for (std::size_t k = 0; k < outliers; ++k) {
    const double angle = rng.uniform(0.0, 6.283185307179586);
    const double r = rng.uniform(2e3, 8e3);
    push(c.xyz, 50.0 + r * std::cos(angle), 50.0 + r * std::sin(angle));
  }
  return c;
}

/// Dense vertical lines at x = 0 and x = 2s with a sparse line at x = s between: each
/// sparse point's Delaunay neighbours are all on the dense lines, so with narrow strips
/// its strip's vertices form a disconnected subgraph (one seed per vertex).
StressCase isolatedStripVertices(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = 1.0;
  const double s = static_cast<double>(1 << rng.index(4));
  const int pairs = 1 + static_cast<int>(rng.index(3));
  const int dense = std::max<int>(4, static_cast<int>(n) / (2 * pairs + 1));
  const bool jitter = rng.coin();
  for (int p = 0; p <= pairs; ++p)
    for (int k = 0; k < dense; ++k)
      push(c.xyz, 2 * s * p, k + (jitter ? rng.uniform(-0.2, 0.2) : 0.0));
  const double spacing = 3 * s + static_cast<double>(rng.index(8));
  for (int p = 0; p < pairs; ++p)
    for (double y = rng.uniform(0.0, 2.0); y < dense; y += spacing)
      push(c.xyz, 2 * s * p + s, y);
  return c;
}

/// A dense bottom row (a long collinear hull run), a top edge with two or three points
/// (hull edges across every strip), a few points between, sometimes a collinear right
/// side in the last column (a strip holding only hull vertices).
StressCase hullAcrossStrips(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = rng.coin() ? 1.0 : 0.5;
  const int width = 8 + static_cast<int>(rng.index(n));
  const double height = rng.coin() ? 1000.0 : 7.0 + static_cast<double>(rng.index(30));
  for (int x = 0; x <= width; ++x)
    if (x == 0 || x == width || rng.coin(0.7))
      push(c.xyz, x, 0.0);
  push(c.xyz, 0.0, height);
  push(c.xyz, width, height);
  if (rng.coin())
    push(c.xyz, rng.integer(1, width - 1), height);
  if (rng.coin())
    for (double y = 1.0; y < height && y < 64.0; y += 1.0 + rng.index(3))
      push(c.xyz, width, y);
  const std::size_t inside = rng.index(6);
  for (std::size_t k = 0; k < inside; ++k)
    push(c.xyz, rng.uniform(0.0, width), rng.uniform(0.0, height));
  return c;
}

/// Random subsets of a tiny integer lattice, 3 to 12 points on column boundaries:
/// degenerate small configurations (collinear triples, squares, one strip per point).
StressCase tinyLatticeSubset(Rng& rng, std::size_t n)
{
  StressCase c;
  c.cell_size = rng.coin() ? 1.0 : 0.5;
  const int side = 2 + static_cast<int>(rng.index(4));
  const std::size_t count = 3 + rng.index(std::min<std::size_t>(n, 10));
  for (std::size_t k = 0; k < count; ++k)
    push(c.xyz, rng.integer(0, side), rng.integer(0, side), rng.uniform());
  return c;
}

using Family = StressCase (*)(Rng&, std::size_t);

struct NamedFamily {
  const char* name;
  Family make;
};

const NamedFamily FAMILIES[] = {
    {"onColumnBoundaries", onColumnBoundaries},
    {"nearColumnBoundaries", nearColumnBoundaries},
    {"verticalLines", verticalLines},
    {"latticeCircles", latticeCircles},
    {"rotatedLattice", rotatedLattice},
    {"exactGrid", exactGrid},
    {"twoClusters", twoClusters},
    {"parabola", parabola},
    {"farOutliers", farOutliers},
    {"isolatedStripVertices", isolatedStripVertices},
    {"hullAcrossStrips", hullAcrossStrips},
    {"tinyLatticeSubset", tinyLatticeSubset},
};

// ---- Transforms (exact unless said)
// --------------------------------------------------

/// Each point repeated 1-3 times with other z: duplicates are merged before the grid.
void addDuplicates(std::vector<double>& xyz, Rng& rng)
{
  const std::size_t n = xyz.size() / 3;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t r = rng.index(3); r > 0; --r)
      push(xyz, xyz[3 * i], xyz[3 * i + 1], rng.uniform(-5.0, 5.0));
}

/// Adds a UTM-like offset (5e6 + a multiple of 1024): exact for coordinates that are
/// multiples of 2^-20 below 2^22.
void addOffset(std::vector<double>& xyz, double ox, double oy)
{
  for (std::size_t i = 0; i < xyz.size(); i += 3) {
    xyz[i] += ox;
    xyz[i + 1] += oy;
  }
}

/// Scales by a power of two (exact): the same geometry at a tiny or huge extent.
void scale(StressCase& c, double factor)
{
  for (std::size_t i = 0; i < c.xyz.size(); i += 3) {
    c.xyz[i] *= factor;
    c.xyz[i + 1] *= factor;
  }
  c.cell_size *= factor;
}

/// Every coordinate rounded to float32 (collinear rows, new duplicates).
void roundToFloat(std::vector<double>& xyz)
{
  for (double& v : xyz)
    v = static_cast<double>(static_cast<float>(v));
}

// ---- Tests
// ---------------------------------------------------------------------------

TEST(StripStress, EachFamilyOverSeeds)
{
  // Guards the seeds (several per strip), ownership by leftmost column (points on and
  // a few ulps off column boundaries), the border pairing (long edges seen by many
  // strips) and the thread-count independence, family by family.
  for (const NamedFamily& family : FAMILIES) {
    for (std::uint32_t seed = 1; seed <= 14; ++seed) {
      Rng rng(seed * 7919u + 13u);
      const std::size_t n = 3 + rng.index(seed <= 10 ? 60 : 400);
      StressCase c = family.make(rng, n);
      shufflePoints(c.xyz, rng);
      SCOPED_TRACE(describe(family.name, seed, c));
      expectStripsAgree(c);
      if (::testing::Test::HasFailure())
        return;
    }
  }
}

TEST(StripStress, TransformedFamilies)
{
  // The same shapes with duplicates, at a 5e6 offset, at tiny and huge scales (exact
  // powers of two, so the ties survive) and rounded to float: the column coordinate
  // (x - origin) / cell then loses low bits, but membership and ownership must still
  // agree for every strip.
  const char* const TRANSFORMS[] = {"duplicates", "utm", "tiny", "huge", "float"};
  for (std::uint32_t seed = 1; seed <= 60; ++seed) {
    Rng rng(seed * 104729u + 1u);
    const NamedFamily& family = FAMILIES[seed % std::size(FAMILIES)];
    const std::size_t which = (seed / std::size(FAMILIES)) % std::size(TRANSFORMS);
    StressCase c = family.make(rng, 3 + rng.index(120));
    switch (which) {
    case 0:
      addDuplicates(c.xyz, rng);
      break;
    case 1:
      addOffset(c.xyz, 5e6 + 1024.0 * rng.integer(0, 64), 5e6);
      break;
    case 2:
      scale(c, 0x1p-40);
      break;
    case 3:
      scale(c, 0x1p+40);
      break;
    default:
      addOffset(c.xyz, 5e6 + 0.37, 4e6 + 0.61); // inexact: rounds to 2^-30 grid
      roundToFloat(c.xyz);
      addDuplicates(c.xyz, rng);
      c.cell_size = 0.0; // float rounding moves points off the intended columns
      break;
    }
    shufflePoints(c.xyz, rng);
    SCOPED_TRACE(describe(std::string(family.name) + "+" + TRANSFORMS[which], seed, c));
    expectStripsAgree(c);
    if (::testing::Test::HasFailure())
      return;
  }
}

TEST(StripStress, PointsExactlyOnColumnBoundariesUseTheRequestedCell)
{
  // The border families are only adversarial if the grid keeps the cell size asked
  // for (its columns then start exactly at the points' x): checked, then triangulated.
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    Rng rng(seed);
    StressCase c =
        seed % 2 == 0 ? onColumnBoundaries(rng, 200) : verticalLines(rng, 200);
    // Force the extent to exceed the cell (no clamping), keeping x on boundaries.
    push(c.xyz, 0.0, 0.0);
    push(c.xyz, 16.0 * c.cell_size, 16.0 * c.cell_size);
    shufflePoints(c.xyz, rng);
    SCOPED_TRACE(
        describe(seed % 2 == 0 ? "onColumnBoundaries" : "verticalLines", seed, c));
    expectStripsAgree(c, true);
    if (::testing::Test::HasFailure())
      return;
  }
}

TEST(StripStress, EveryVertexIsolatedInItsStrip)
{
  // Columns alternate between dense lines and single points far apart in y: with
  // one-column strips, every sparse strip is a set of vertices with no Delaunay edge
  // between them, each needing its own seed, whose nearest neighbour is in another
  // strip.
  for (const int spacing : {3, 5, 17}) {
    SCOPED_TRACE("spacing=" + std::to_string(spacing));
    StressCase c;
    c.cell_size = 1.0;
    for (int line = 0; line < 9; ++line)
      for (int y = 0; y < 60; y += (line % 2 == 0 ? 1 : spacing))
        push(c.xyz, 2.0 * line, y + (line % 2 == 0 ? 0.0 : 0.5));
    Rng rng(static_cast<std::uint32_t>(spacing));
    shufflePoints(c.xyz, rng);
    expectStripsAgree(c, true);
  }
}

TEST(StripStress, ConcentricLatticeCirclesStraddlingStrips)
{
  // Several integer multiples of rich lattice circles around a common centre, plus
  // the centre and some circles off-centre: thousands of exactly cocircular quadruples
  // cut by one-column strips (the tie-break must not depend on which strip decides).
  for (const std::int64_t r2 : {1105LL, 5525LL, 27625LL}) {
    SCOPED_TRACE("r2=" + std::to_string(r2));
    const std::vector<double> base = test::latticeCircle(r2);
    const double r = std::sqrt(static_cast<double>(r2));
    StressCase c;
    c.cell_size = std::max(1.0, std::floor(r / 16.0));
    push(c.xyz, 0.0, 0.0);
    for (double k = 1.0; k <= 3.0; k += 1.0)
      for (std::size_t i = 0; i < base.size() / 2; ++i)
        push(c.xyz, k * base[2 * i], k * base[2 * i + 1], k);
    for (std::size_t i = 0; i < base.size() / 2; ++i)
      push(c.xyz, base[2 * i] + std::floor(r), base[2 * i + 1]);
    Rng rng(static_cast<std::uint32_t>(r2));
    shufflePoints(c.xyz, rng);
    expectStripsAgree(c);
  }
}

TEST(StripStress, ThreePointsAndCollinearInputs)
{
  // The smallest inputs: a triangle whose vertices sit in three strips, in one strip,
  // across empty strips; collinear inputs (any strip width) must still be
  // ALL_COLLINEAR, duplicates of a triangle still one triangle.
  const std::vector<std::vector<double>> inputs = {
      {0, 0, 0, 1, 0, 0, 0, 1, 0},
      {0, 0, 0, 1000, 0, 0, 500, 1, 0},
      {0, 0, 0, 1000, 1, 0, 0, 2, 0},
      {0, 0, 0, 0, 5, 0, 1000, 2.5, 0},
      {0, 0, 0, 4, 0, 0, 8, 0, 0, 12, 0, 0},
      {0, 0, 0, 0, 3, 0, 0, 7, 0},
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 5, 1, 0, 2, 0, 0, 1},
      {0, 0, 0, 1, 1, 0, 2, 0, 0, 1, -1, 0}, // a tie: the 45-degree square
  };
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    SCOPED_TRACE("input " + std::to_string(k));
    for (const double cell : {0.0, 1.0, 0.25}) {
      SCOPED_TRACE("cell_size=" + std::to_string(cell));
      expectStripsAgree({inputs[k], cell});
    }
  }
}

TEST(StripStress, SeedingAFarVertexIsNotQuadraticInTheGap)
{
  // A vertex alone in its strip is seeded, and its seed candidates are the rings of
  // cells around it up to its nearest neighbour. That must cost about the cells that
  // exist, not (gap in cells)^2: here the grid is one row of 20001 cells, the far
  // vertex's nearest neighbour is 20000 columns away, and one strip (a plain region
  // growing) takes about a millisecond. A generous bound: 250 ms.
  StressCase c;
  c.cell_size = 1.0;
  push(c.xyz, 0.0, 0.0);
  push(c.xyz, 0.0, 0.5);
  push(c.xyz, 20000.0, 0.25);
  VtsOptions options;
  options.cell_size = c.cell_size; // automatic strip width: 20 strips of 1024 columns
  const PipelineRun run = runPipeline(c.xyz, options);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  test::expectValidTriangulation(c.xyz, run, options);
  EXPECT_LT(run.result.diagnostics.seconds_triangulate, 0.25)
      << "cells=" << run.result.diagnostics.cells;
}

TEST(StripStress, ThousandsOfPoints)
{
  // Larger inputs of the nastiest families, so strips hold many seeds and long
  // frontiers, and the automatic width gives several strips.
  const std::size_t FAMILY_IDS[] = {0, 2, 3, 4, 5, 6, 8, 9};
  std::uint32_t seed = 1;
  for (const std::size_t f : FAMILY_IDS) {
    Rng rng(seed * 31u);
    StressCase c = FAMILIES[f].make(rng, 3000);
    shufflePoints(c.xyz, rng);
    SCOPED_TRACE(describe(FAMILIES[f].name, seed, c));
    expectStripsAgree(c);
    ++seed;
  }
}

} // namespace
} // namespace pcl_vts
