// The library's mesh pictures (mesh_picture.h): the PNG writer decoded back by zlib
// pixel for pixel, and renderMesh checked on invariants, never golden pixels: a mesh
// filling its frame leaves no background inside it, one frame is one camera, edges,
// marks and flips get their colours, bad input gives a picture instead of a crash.
#include "support/png_decode.h"
#include "support/temp_folder_test.h"

#include <pcl_vts/picture/mesh_picture.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

namespace fs = std::filesystem;

constexpr double X0 = 512345.25, Y0 = 5412345.75; // UTM-sized origin

/// nx x ny grid of cells over [X0, X0 + nx] x [Y0, Y0 + ny], two CCW triangles per
/// cell, z a smooth hill plus noise.
PictureMesh gridMesh(int nx, int ny, double cell = 1.0, unsigned seed = 1)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  PictureMesh mesh;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      mesh.xyz.insert(mesh.xyz.end(),
                      {X0 + i * cell, Y0 + j * cell,
                       100 + 3 * std::sin(0.3 * i) * std::cos(0.2 * j) + noise(rng)});
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j),
                             id(i + 1, j + 1), id(i, j + 1)});
  return mesh;
}

/// Pairs of the grid's outer edges.
std::vector<std::uint32_t> outline(int nx, int ny)
{
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  std::vector<std::uint32_t> edges;
  for (int i = 0; i < nx; ++i)
    edges.insert(edges.end(), {id(i, 0), id(i + 1, 0), id(i, ny), id(i + 1, ny)});
  for (int j = 0; j < ny; ++j)
    edges.insert(edges.end(), {id(0, j), id(0, j + 1), id(nx, j), id(nx, j + 1)});
  return edges;
}

PictureColour pixel(const Picture& p, int column, int row)
{
  const std::uint8_t* c =
      p.rgb.data() + 3 * (static_cast<std::size_t>(row) * p.width + column);
  return {c[0], c[1], c[2]};
}

bool same(PictureColour a, PictureColour b)
{
  return a.r == b.r && a.g == b.g && a.b == b.b;
}

std::size_t countPixels(const Picture& p, bool (*test)(PictureColour))
{
  std::size_t n = 0;
  for (int r = 0; r < p.height; ++r)
    for (int c = 0; c < p.width; ++c)
      n += test(pixel(p, c, r));
  return n;
}

bool isBoundary(PictureColour c)
{
  return same(c, PICTURE_BOUNDARY);
}
bool isNonManifold(PictureColour c)
{
  return same(c, PICTURE_NON_MANIFOLD);
}
bool isMark(PictureColour c)
{
  return same(c, PICTURE_MARK);
}
/// The back-face orange at any shade: blue 0, green/red as in PICTURE_BACK_FACE.
bool isBackFace(PictureColour c)
{
  return c.b == 0 && c.r >= 100 && std::abs(c.g * 255.0 - c.r * 140.0) <= 2.0 * 255.0;
}

void expectWellFormed(const Picture& p)
{
  EXPECT_GT(p.width, 0);
  EXPECT_GT(p.height, 0);
  EXPECT_EQ(p.rgb.size(), 3 * static_cast<std::size_t>(p.width) * p.height);
}

const PictureView VIEWS[] = {PictureView::TOP, PictureView::OBLIQUE};

// ---- PNG writer ------------------------------------------------------------------

class MeshPicturePng : public test::TempFolderTest {};

TEST_F(MeshPicturePng, RoundTripsThroughZlibPixelForPixel)
{
  std::mt19937 rng(7);
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{1, 1}, {3, 2}, {257, 131}}) {
    // Flat areas (long matches), gradients (filters) and noise (literals).
    Picture p;
    p.width = w;
    p.height = h;
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c) {
        const bool noisy = (c / 16 + r / 16) % 3 == 0;
        p.rgb.push_back(static_cast<std::uint8_t>(noisy ? rng() : c));
        p.rgb.push_back(static_cast<std::uint8_t>(noisy ? rng() : r * 2));
        p.rgb.push_back(static_cast<std::uint8_t>(noisy ? rng() : 200));
      }
    const std::string path = (root_ / "round.png").string();
    ASSERT_TRUE(writePng(path, p).ok());
    Picture back;
    std::string error;
    ASSERT_TRUE(test::decodePng(path, back, error)) << error;
    EXPECT_EQ(back.width, w);
    EXPECT_EQ(back.height, h);
    EXPECT_TRUE(back.rgb == p.rgb) << w << " x " << h;
  }
}

TEST_F(MeshPicturePng, RenderedPictureRoundTripsAndCompresses)
{
  const PictureMesh mesh = gridMesh(40, 30);
  PictureOptions options;
  options.width = 400;
  options.caption = "grid 40 x 30";
  const Picture p = renderMesh(mesh, pictureFrameOf(mesh), options);
  const std::string path = (root_ / "mesh.png").string();
  ASSERT_TRUE(writePng(path, p).ok());
  Picture back;
  std::string error;
  ASSERT_TRUE(test::decodePng(path, back, error)) << error;
  EXPECT_TRUE(back.rgb == p.rgb);
  EXPECT_LT(fs::file_size(path), p.rgb.size() / 2) << "deflate should find matches";
}

TEST_F(MeshPicturePng, UnwritablePathIsAnIoErrorAndLeavesNoTempFile)
{
  Picture p;
  p.width = 2;
  p.height = 2;
  p.rgb.assign(12, 128);
  const Status missing = writePng((root_ / "no" / "such.png").string(), p);
  EXPECT_EQ(missing.code, StatusCode::IO_ERROR);
  EXPECT_NE(missing.message.find("such.png"), std::string::npos) << missing.message;
  // A folder in the way: the temp file is written, the rename fails, it must go.
  fs::create_directories(root_ / "taken.png" / "inside");
  const Status taken = writePng((root_ / "taken.png").string(), p);
  EXPECT_EQ(taken.code, StatusCode::IO_ERROR);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(root_))
    names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"taken.png"});
  // An inconsistent picture is refused before any file is made.
  p.rgb.pop_back();
  EXPECT_EQ(writePng((root_ / "bad.png").string(), p).code,
            StatusCode::INVALID_PARAMETER);
  EXPECT_FALSE(fs::exists(root_ / "bad.png"));
}

// ---- renderMesh ------------------------------------------------------------------

TEST(MeshPicture, MeshFillingItsFrameLeavesNoBackgroundInsideTopView)
{
  for (const double cell : {1.0, 0.37}) {
    const PictureMesh mesh = gridMesh(37, 23, cell);
    const PictureFrame frame = pictureFrameOf(mesh);
    for (const int width : {200, 611}) {
      PictureOptions options;
      options.width = width;
      const Picture p = renderMesh(mesh, frame, options);
      expectWellFormed(p);
      double c0, r0, c1, r1;
      ASSERT_TRUE(
          picturePixelOf(frame, options, frame.min[0], frame.max[1], 0, c0, r0));
      ASSERT_TRUE(
          picturePixelOf(frame, options, frame.max[0], frame.min[1], 0, c1, r1));
      EXPECT_NEAR(c1 - c0, width * 0.95, width * 0.05); // fills the width, small margin
      std::size_t inside = 0, background = 0;
      for (int r = static_cast<int>(std::ceil(r0)); r + 1 <= r1; ++r)
        for (int c = static_cast<int>(std::ceil(c0)); c + 1 <= c1; ++c) {
          ++inside;
          background += same(pixel(p, c, r), PICTURE_BACKGROUND);
        }
      EXPECT_GT(inside, 0u);
      EXPECT_EQ(background, 0u) << "cell " << cell << ", width " << width;
      // Outside the frame, only background.
      EXPECT_TRUE(same(pixel(p, 0, 0), PICTURE_BACKGROUND));
      EXPECT_TRUE(same(pixel(p, p.width - 1, p.height - 1), PICTURE_BACKGROUND));
    }
  }
}

TEST(MeshPicture, SameFrameMapsAWorldPointToTheSamePixel)
{
  // Two different meshes, one marked vertex each at the same world point.
  PictureMesh big = gridMesh(30, 20);
  PictureMesh small = gridMesh(3, 2, 1.0, 9);
  for (std::size_t k = 0; k + 2 < small.xyz.size(); k += 3) { // move it inside big
    small.xyz[k] += 11;
    small.xyz[k + 1] += 7;
  }
  const std::uint32_t big_v = 7 * 31 + 12; // grid point (12, 7) of big
  const std::uint32_t small_v = 0 * 4 + 1; // grid point (1, 0) of small: same x, y
  small.xyz[3 * small_v + 2] = big.xyz[3 * big_v + 2];
  big.vertex_marks.assign(big.xyz.size() / 3, 0);
  big.vertex_marks[big_v] = 1;
  small.vertex_marks.assign(small.xyz.size() / 3, 0);
  small.vertex_marks[small_v] = 1;
  ASSERT_EQ(big.xyz[3 * big_v], small.xyz[3 * small_v]);
  ASSERT_EQ(big.xyz[3 * big_v + 1], small.xyz[3 * small_v + 1]);
  const PictureFrame frame = unionOf(pictureFrameOf(big), pictureFrameOf(small));
  for (const PictureView view : VIEWS) {
    PictureOptions options;
    options.view = view;
    options.width = 300;
    const Picture a = renderMesh(big, frame, options);
    const Picture b = renderMesh(small, frame, options);
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    auto markCentre = [](const Picture& p, double& mc, double& mr) {
      double sc = 0, sr = 0, n = 0;
      for (int r = 0; r < p.height; ++r)
        for (int c = 0; c < p.width; ++c)
          if (isMark(pixel(p, c, r)))
            sc += c + 0.5, sr += r + 0.5, ++n;
      mc = sc / n;
      mr = sr / n;
      return n;
    };
    double ac, ar, bc, br, wc, wr;
    EXPECT_GT(markCentre(a, ac, ar), 0);
    EXPECT_GT(markCentre(b, bc, br), 0);
    ASSERT_TRUE(picturePixelOf(frame, options, big.xyz[3 * big_v],
                               big.xyz[3 * big_v + 1], big.xyz[3 * big_v + 2], wc, wr));
    EXPECT_NEAR(ac, bc, 0.5);
    EXPECT_NEAR(ar, br, 0.5);
    EXPECT_NEAR(ac, wc, 1.0);
    EXPECT_NEAR(ar, wr, 1.0);
  }
}

TEST(MeshPicture, BoundaryAndNonManifoldEdgesShowInTheirColours)
{
  PictureMesh mesh = gridMesh(20, 12);
  for (const PictureView view : VIEWS) {
    PictureOptions options;
    options.view = view;
    options.width = 320;
    const Picture plain = renderMesh(mesh, pictureFrameOf(mesh), options);
    EXPECT_EQ(countPixels(plain, isBoundary), 0u);
    EXPECT_EQ(countPixels(plain, isNonManifold), 0u);
    PictureMesh edged = mesh;
    edged.boundary_edges = outline(20, 12);
    edged.non_manifold_edges = {0, 22}; // the diagonal of the first cell
    const Picture p = renderMesh(edged, pictureFrameOf(edged), options);
    // The outline is ~2 x (300 + 180) pixels long: most of it solid red.
    EXPECT_GT(countPixels(p, isBoundary), 600u);
    EXPECT_GT(countPixels(p, isNonManifold), 5u);
  }
}

TEST(MeshPicture, FlippedTrianglesShowTheBackFaceColour)
{
  const PictureMesh mesh = gridMesh(20, 12);
  PictureMesh flipped = mesh;
  for (std::size_t t = 0; t < flipped.triangles.size() / 3; t += 5)
    std::swap(flipped.triangles[3 * t + 1], flipped.triangles[3 * t + 2]);
  for (const PictureView view : VIEWS) {
    PictureOptions options;
    options.view = view;
    options.width = 320;
    EXPECT_EQ(countPixels(renderMesh(mesh, pictureFrameOf(mesh), options), isBackFace),
              0u);
    EXPECT_GT(
        countPixels(renderMesh(flipped, pictureFrameOf(flipped), options), isBackFace),
        1000u);
  }
}

TEST(MeshPicture, NearerSurfaceWinsWhateverTheDrawingOrder)
{
  // Two flat squares at z 0 and z 10: from above and from the side the upper one is
  // seen at the centre, drawn first or last.
  PictureMesh two;
  two.xyz = {0, 0, 0,  10, 0, 0,  10, 10, 0,  0, 10, 0,
             0, 0, 10, 10, 0, 10, 10, 10, 10, 0, 10, 10};
  two.triangles = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  PictureMesh upper = two;
  upper.triangles = {4, 5, 6, 4, 6, 7};
  PictureMesh reversed = two;
  std::reverse(reversed.triangles.begin(), reversed.triangles.end());
  for (std::size_t t = 0; t < reversed.triangles.size(); t += 3) // keep CCW
    std::swap(reversed.triangles[t + 1], reversed.triangles[t + 2]);
  const PictureFrame frame = pictureFrameOf(two);
  for (const PictureView view : VIEWS) {
    PictureOptions options;
    options.view = view;
    options.width = 200;
    double c, r;
    ASSERT_TRUE(picturePixelOf(frame, options, 5, 5, 10, c, r));
    const Picture expected = renderMesh(upper, frame, options);
    const PictureColour want =
        pixel(expected, static_cast<int>(c), static_cast<int>(r));
    EXPECT_FALSE(same(want, PICTURE_BACKGROUND));
    for (const PictureMesh* m : {&two, &reversed}) {
      const Picture p = renderMesh(*m, frame, options);
      EXPECT_TRUE(same(pixel(p, static_cast<int>(c), static_cast<int>(r)), want));
    }
  }
}

TEST(MeshPicture, ClassesAndMarksChangeTheColours)
{
  PictureMesh mesh = gridMesh(10, 10);
  PictureOptions options;
  options.width = 200;
  const PictureFrame frame = pictureFrameOf(mesh);
  const Picture surface = renderMesh(mesh, frame, options);
  for (const std::uint8_t cls : {1, 2}) {
    PictureMesh classed = mesh;
    classed.triangle_class.assign(mesh.triangles.size() / 3, cls);
    const Picture p = renderMesh(classed, frame, options);
    double c, r;
    ASSERT_TRUE(picturePixelOf(frame, options, X0 + 5.3, Y0 + 5.6, 0, c, r));
    const PictureColour got = pixel(p, static_cast<int>(c), static_cast<int>(r));
    if (cls == 1) // removed: grey
      EXPECT_TRUE(got.r == got.g && got.g == got.b) << int(got.r) << " " << int(got.g);
    else // filled: blue dominates
      EXPECT_GT(got.b, std::max(got.r, got.g));
  }
  EXPECT_EQ(countPixels(surface, isMark), 0u);
  mesh.vertex_marks.assign(mesh.xyz.size() / 3, 0);
  mesh.vertex_marks[60] = 1;
  EXPECT_GT(countPixels(renderMesh(mesh, frame, options), isMark), 0u);
}

TEST(MeshPicture, DegenerateInputGivesAPictureNotACrash)
{
  PictureOptions options;
  options.width = 240;
  options.caption = "degenerate";
  auto hasText = [](const Picture& p) {
    return countPixels(p, [](PictureColour c) { return c.r < 100 && c.g < 100; }) > 20;
  };
  // Empty mesh, empty frame.
  const Picture empty =
      renderMesh(PictureMesh{}, pictureFrameOf(PictureMesh{}), options);
  expectWellFormed(empty);
  EXPECT_TRUE(hasText(empty));
  EXPECT_TRUE(isEmpty(pictureFrameOf(PictureMesh{})));
  // Every vertex at one point: a frame without extent.
  PictureMesh point;
  point.xyz = {1, 2, 3, 1, 2, 3, 1, 2, 3};
  point.triangles = {0, 1, 2};
  const Picture dot = renderMesh(point, pictureFrameOf(point), options);
  expectWellFormed(dot);
  EXPECT_TRUE(hasText(dot));
  // NaN and infinite coordinates, ids out of range, a far-away vertex, odd-sized
  // arrays: skipped, the rest drawn, the frame stays finite.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  PictureMesh bad = gridMesh(8, 8);
  bad.xyz[3 * 10] = nan;
  bad.xyz[3 * 20 + 2] = std::numeric_limits<double>::infinity();
  bad.xyz[3 * 30] = 1e300;
  bad.triangles.insert(bad.triangles.end(), {0, 1, 99999});
  bad.triangle_class = {2, 2};              // wrong size: ignored
  bad.vertex_marks = {1, 1, 1, 1, 1, 1, 1}; // shorter than the vertices
  bad.boundary_edges = {10, 11, 30, 31, 5}; // NaN end, far end, odd count
  bad.non_manifold_edges = {99999, 0};
  PictureFrame frame = pictureFrameOf(gridMesh(8, 8));
  for (const PictureView view : VIEWS) {
    options.view = view;
    const Picture p = renderMesh(bad, frame, options);
    expectWellFormed(p);
    EXPECT_GT(
        countPixels(p, [](PictureColour c) { return !same(c, PICTURE_BACKGROUND); }),
        1000u);
    const Picture q = renderMesh(bad, pictureFrameOf(bad), options);
    expectWellFormed(q);
  }
  PictureMesh nan_only;
  nan_only.xyz = {nan, 0, 0, 1, nan, 0, 1, 1, nan};
  nan_only.triangles = {0, 1, 2};
  EXPECT_TRUE(isEmpty(pictureFrameOf(nan_only)));
  expectWellFormed(renderMesh(nan_only, pictureFrameOf(nan_only), options));
  // Widths out of range are clamped.
  for (const int width : {-5, 0, 1}) {
    options.width = width;
    expectWellFormed(
        renderMesh(gridMesh(4, 4), pictureFrameOf(gridMesh(4, 4)), options));
  }
  options.width = 100000;
  const Picture wide = renderMesh(PictureMesh{}, frame, options);
  expectWellFormed(wide);
  EXPECT_EQ(wide.width, 8192);
}

TEST(MeshPicture, ThinStripIsScaledToAtMostTwiceAsTallAsWide)
{
  const PictureMesh strip = gridMesh(1, 200);
  PictureOptions options;
  options.width = 100;
  const Picture p = renderMesh(strip, pictureFrameOf(strip), options);
  expectWellFormed(p);
  EXPECT_LE(p.height, 2 * p.width + 1);
}

TEST(MeshPicture, BesideEachOtherTilesWithWhiteGaps)
{
  Picture a, b;
  a.width = 3, a.height = 2, a.rgb.assign(18, 10);
  b.width = 2, b.height = 4, b.rgb.assign(24, 20);
  const Picture t = besideEachOther({a, b}, 5);
  ASSERT_EQ(t.width, 10);
  ASSERT_EQ(t.height, 4);
  EXPECT_EQ(pixel(t, 0, 0).r, 10);
  EXPECT_EQ(pixel(t, 2, 1).g, 10);
  EXPECT_TRUE(same(pixel(t, 0, 3), PICTURE_BACKGROUND)); // below the shorter one
  EXPECT_TRUE(same(pixel(t, 5, 0), PICTURE_BACKGROUND)); // the gap
  EXPECT_EQ(pixel(t, 8, 3).b, 20);
  EXPECT_EQ(besideEachOther({}, 4).width, 0);
}

} // namespace
} // namespace pcl_vts
