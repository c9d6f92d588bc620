// Depth filters, kind names and detection, intrinsics parsing, report text.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "lom/import.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

DepthImage constantDepth(int width, int height, float z) {
  DepthImage depth;
  depth.width = width;
  depth.height = height;
  depth.metres.assign(static_cast<size_t>(width) * height, z);
  return depth;
}

float& at(DepthImage& d, int u, int v) { return d.metres[static_cast<size_t>(v) * d.width + u]; }

TEST(ImportFilters, InvalidValuesBecomeHoles) {
  DepthImage depth = constantDepth(4, 1, 1.0f);
  depth.metres = {NAN, INFINITY, -1.0f, 1.0f};
  DepthFilterOptions options;
  options.flying_pixels = false;
  const DepthFilterStats stats = filterDepth(depth, options);
  EXPECT_EQ(stats.invalid, 3u);
  EXPECT_EQ(stats.kept, 1u);
  EXPECT_EQ(depth.metres, (std::vector<float>{0.0f, 0.0f, 0.0f, 1.0f}));
}

TEST(ImportFilters, RangeLimits) {
  DepthImage depth = constantDepth(4, 1, 1.0f);
  depth.metres = {0.05f, 0.5f, 2.0f, 5.0f};
  DepthFilterOptions options;
  options.flying_pixels = false;
  options.min_depth = 0.1;
  options.max_depth = 3.0;
  const DepthFilterStats stats = filterDepth(depth, options);
  EXPECT_EQ(stats.out_of_range, 2u);
  EXPECT_EQ(depth.metres, (std::vector<float>{0.0f, 0.5f, 2.0f, 0.0f}));
}

TEST(ImportFilters, DefaultsKeepEverythingInRangeOnSmoothSurfaces) {
  // A slanted plane: neighbouring depths differ by 0.5%, well below the 5% default.
  DepthImage depth = constantDepth(20, 10, 1.0f);
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 20; ++u) at(depth, u, v) = 1.0f + 0.005f * u;
  const DepthImage before = depth;
  const DepthFilterStats stats = filterDepth(depth, {});
  EXPECT_EQ(stats.flying, 0u);
  EXPECT_EQ(depth.metres, before.metres);
}

TEST(ImportFilters, FlyingPixelsAtADepthEdgeAreRemoved) {
  // Foreground at 1 m on the left, background at 2 m on the right and a mixed
  // pixel at 1.5 m between them.
  DepthImage depth = constantDepth(9, 3, 2.0f);
  for (int v = 0; v < 3; ++v) {
    for (int u = 0; u < 4; ++u) at(depth, u, v) = 1.0f;
    at(depth, 4, v) = 1.5f;
  }
  const DepthFilterStats stats = filterDepth(depth, {});
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(at(depth, 4, v), 0.0f) << "the mixed pixel goes";
    EXPECT_EQ(at(depth, 3, v), 0.0f) << "the foreground edge pixel borders a jump";
    EXPECT_EQ(at(depth, 5, v), 0.0f) << "the background edge pixel borders a jump";
    EXPECT_EQ(at(depth, 2, v), 1.0f);
    EXPECT_EQ(at(depth, 6, v), 2.0f);
  }
  EXPECT_EQ(stats.flying, 9u);
  // A hole next to a pixel is not a jump.
  DepthImage holes = constantDepth(3, 1, 1.0f);
  holes.metres[1] = 0.0f;
  EXPECT_EQ(filterDepth(holes, {}).flying, 0u);
  // Off: nothing removed.
  DepthImage off = constantDepth(9, 3, 2.0f);
  at(off, 4, 1) = 1.0f;
  DepthFilterOptions options;
  options.flying_pixels = false;
  EXPECT_EQ(filterDepth(off, options).flying, 0u);
}

TEST(ImportFilters, BilateralSmoothsNoiseButNotEdgesOrHoles) {
  DepthImage depth = constantDepth(12, 12, 1.0f);
  for (int v = 0; v < 12; ++v)
    for (int u = 6; u < 12; ++u) at(depth, u, v) = 1.2f;  // a step the filter must keep
  at(depth, 2, 5) = 1.004f;                                // noise on the flat part
  at(depth, 3, 8) = 0.0f;                                  // a hole
  DepthFilterOptions options;
  options.flying_pixels = false;
  options.bilateral_radius = 2;
  options.bilateral_sigma_depth = 0.01;
  filterDepth(depth, options);
  EXPECT_LT(std::abs(at(depth, 2, 5) - 1.0f), 0.002f) << "noise is smoothed";
  EXPECT_NEAR(at(depth, 5, 5), 1.0f, 1e-4) << "the near side of the step stays";
  EXPECT_NEAR(at(depth, 6, 5), 1.2f, 1e-4) << "the far side of the step stays";
  EXPECT_EQ(at(depth, 3, 8), 0.0f) << "holes stay holes";
}

TEST(ImportFilters, OptionsOutOfRangeAreNamed) {
  DepthImage depth = constantDepth(2, 2, 1.0f);
  DepthFilterOptions options;
  options.flying_pixel_ratio = -1.0;
  try {
    filterDepth(depth, options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.problem().field, "flying_pixel_ratio");
  }
  options = {};
  options.max_depth = 0.05;  // below min_depth
  EXPECT_THROW(filterDepth(depth, options), Error);
  options = {};
  options.bilateral_radius = 99;
  EXPECT_THROW(filterDepth(depth, options), Error);
  // Values are shown as given, not as 1000000.000000.
  options = {};
  options.flying_pixel_radius = 1000000;
  try {
    filterDepth(depth, options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.problem().found, "1000000");
  }
}

TEST(ImportKinds, NamesRoundTrip) {
  for (SourceKind kind : importableKinds()) {
    const auto parsed = sourceKindFromName(sourceKindName(kind));
    ASSERT_TRUE(parsed.has_value()) << sourceKindName(kind);
    EXPECT_EQ(*parsed, kind);
  }
  EXPECT_EQ(sourceKindName(SourceKind::ApcShelf), "apc-shelf");
  EXPECT_EQ(sourceKindFromName("ROSBAG"), SourceKind::RosBag);
  EXPECT_FALSE(sourceKindFromName("auto").has_value());
  EXPECT_FALSE(sourceKindFromName("kitti").has_value());
}

void touch(const std::filesystem::path& path, const std::string& text = "") {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(ImportDetect, EachLayoutIsRecognised) {
  test::TempDir dir;
  touch(dir / "seq" / "sequence.json", "{}");
  touch(dir / "apc" / "cam.info.txt");
  touch(dir / "tum" / "rgb.txt");
  touch(dir / "tum" / "depth.txt");
  std::filesystem::create_directories(dir / "scannet" / "depth");
  std::filesystem::create_directories(dir / "scannet" / "pose");
  std::filesystem::create_directories(dir / "quat" / "depth");
  touch(dir / "quat" / "pose.txt");
  touch(dir / "frames" / "frame-000000.depth.png");
  touch(dir / "x.bag", "#ROSBAG V2.0\n");
  touch(dir / "no-extension", "#ROSBAG V2.0\n");
  EXPECT_EQ(detectSource(dir / "seq").kind, SourceKind::Sequence);
  EXPECT_EQ(detectSource(dir / "seq" / "sequence.json").kind, SourceKind::Sequence);
  EXPECT_EQ(detectSource(dir / "apc").kind, SourceKind::ApcShelf);
  EXPECT_EQ(detectSource(dir / "tum").kind, SourceKind::Tum);
  EXPECT_EQ(detectSource(dir / "scannet").kind, SourceKind::ScanNet);
  EXPECT_EQ(detectSource(dir / "quat").kind, SourceKind::Quaternion);
  EXPECT_EQ(detectSource(dir / "frames").kind, SourceKind::Frames);
  EXPECT_EQ(detectSource(dir / "x.bag").kind, SourceKind::RosBag);
  EXPECT_EQ(detectSource(dir / "no-extension").kind, SourceKind::RosBag);
}

TEST(ImportDetect, UnknownFoldersSayWhatWasLookedFor) {
  test::TempDir dir;
  touch(dir / "stuff" / "notes.txt");
  const SourceDetection d = detectSource(dir / "stuff");
  EXPECT_FALSE(d.kind.has_value());
  EXPECT_NE(d.explanation.find("rgb.txt"), std::string::npos) << d.explanation;
  EXPECT_NE(d.explanation.find("notes.txt"), std::string::npos) << d.explanation;
  EXPECT_FALSE(detectSource(dir / "missing").kind.has_value());
  touch(dir / "image.png");
  EXPECT_FALSE(detectSource(dir / "image.png").kind.has_value());
  try {
    (void)importSource(std::nullopt, dir / "stuff", dir / "out");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("known dataset layout"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(ImportIntrinsics, TextAndFiles) {
  const CameraIntrinsics a = parseIntrinsics("518,519,325.5,253.5");
  EXPECT_EQ(a.fx, 518.0);
  EXPECT_EQ(a.fy, 519.0);
  EXPECT_EQ(a.cx, 325.5);
  EXPECT_EQ(a.cy, 253.5);
  test::TempDir dir;
  touch(dir / "K.txt", "615.2 0 298.4\n0 615.3 247.5\n0 0 1\n");
  const CameraIntrinsics b = parseIntrinsics((dir / "K.txt").string());
  EXPECT_EQ(b.fy, 615.3);
  EXPECT_EQ(b.cx, 298.4);
  touch(dir / "K4.txt", "577.6 0 318.9 0\n0 578.7 242.6 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(parseIntrinsics((dir / "K4.txt").string()).cy, 242.6);
  EXPECT_THROW((void)parseIntrinsics("518,519"), Error);
  EXPECT_THROW((void)parseIntrinsics("-5,519,1,1"), Error);
  EXPECT_THROW((void)parseIntrinsics("not-a-file"), Error);
  // A folder or a device is named as what it is.
  try {
    (void)parseIntrinsics(dir.path().string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.problem().found, "a folder, not a file");
  }
  try {
    (void)parseIntrinsics("/dev/null");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(e.problem().found.find("a special file"), std::string::npos) << e.what();
  }
  touch(dir / "skew.txt", "600 3 320\n0 600 240\n0 0 1\n");
  try {
    (void)parseIntrinsics((dir / "skew.txt").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no skew"), std::string::npos) << e.what();
  }
}

TEST(ImportReportText, ListsSkippedFramesAndNotes) {
  ImportReport report;
  report.kind = SourceKind::Tum;
  report.source = "/data/tum";
  report.output = "/data/seq";
  report.frames_found = 3;
  report.frames_written = 2;
  report.skipped = {{"100.5", "no groundtruth pose"}};
  report.notes = {"intrinsics: freiburg1"};
  const std::string text = report.text();
  EXPECT_NE(text.find("imported 2 of 3 frames (tum) from /data/tum into /data/seq"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("100.5: no groundtruth pose"), std::string::npos) << text;
  EXPECT_NE(text.find("intrinsics: freiburg1"), std::string::npos) << text;
}

}  // namespace
}  // namespace lom
