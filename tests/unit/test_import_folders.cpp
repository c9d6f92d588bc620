// Folder layouts written by the tests (frames, TUM RGB-D, quaternion poses,
// ScanNet), imported, read back and compared; malformed inputs of each kind.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "lom/import.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 32;
constexpr int kH = 24;

// A slanted surface with a few holes, in whole millimetres.
DepthImage sceneDepth(int seed) {
  DepthImage depth;
  depth.width = kW;
  depth.height = kH;
  depth.metres.resize(kW * kH);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u)
      depth.metres[v * kW + u] = static_cast<float>((1000 + 2 * u + v + 10 * seed) / 1000.0);
  depth.metres[5] = 0.0f;
  return depth;
}

ColorImage sceneColor(int seed) {
  ColorImage color;
  color.width = kW;
  color.height = kH;
  color.rgb.resize(kW * kH * 3);
  for (size_t i = 0; i < color.rgb.size(); ++i)
    color.rgb[i] = static_cast<std::uint8_t>((i * 7 + seed * 13) % 256);
  return color;
}

Eigen::Matrix4d scenePose(int seed) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.1 * seed, Eigen::Vector3d(0, 1, 0.2).normalized()).toRotationMatrix();
  pose.topRightCorner<3, 1>() = Eigen::Vector3d(0.1 * seed, -0.05 * seed, 0.02);
  return pose;
}

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string matrixText(const Eigen::Matrix4d& m) {
  std::ostringstream out;
  out << std::setprecision(17);
  for (int r = 0; r < 4; ++r) out << m(r, 0) << " " << m(r, 1) << " " << m(r, 2) << " " << m(r, 3) << "\n";
  return out.str();
}

void expectDepthEqual(const DepthImage& a, const DepthImage& b, double tolerance = 1e-6) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (size_t i = 0; i < a.metres.size(); ++i)
    ASSERT_NEAR(a.metres[i], b.metres[i], tolerance) << "pixel " << i;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool anySkipped(const ImportReport& report, const std::string& part) {
  for (const auto& s : report.skipped)
    if (contains(s.reason, part)) return true;
  return false;
}

bool anyNote(const ImportReport& report, const std::string& part) {
  for (const auto& n : report.notes)
    if (contains(n, part)) return true;
  return false;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// ---------------------------------------------------------------------------
// frames layout

void writeFramesFolder(const fs::path& dir) {
  fs::create_directories(dir);
  writeText(dir / "camera-intrinsics.txt", "30 0 15.5\n0 31 11.5\n0 0 1\n");
  int seed = 0;
  for (int number : {15, 17, 20}) {
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06d", number);
    DepthImage depth = sceneDepth(seed);
    if (number == 17) depth.metres[7] = 65.535f;  // 7-Scenes' "no depth"
    writeDepthPng(dir / (std::string(base) + ".depth.png"), depth, 0.001);
    writeColorPng(dir / (std::string(base) + ".color.png"), sceneColor(seed));
    if (number != 20) writeText(dir / (std::string(base) + ".pose.txt"), matrixText(scenePose(seed)));
    ++seed;
  }
}

TEST(ImportFrames, RoundTrip) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  EXPECT_EQ(report.frames_found, 3u);
  EXPECT_EQ(report.frames_written, 2u);
  ASSERT_EQ(report.skipped.size(), 1u);
  EXPECT_EQ(report.skipped[0].frame, "frame-000020");
  EXPECT_TRUE(contains(report.skipped[0].reason, "no pose file")) << report.skipped[0].reason;
  EXPECT_TRUE(anyNote(report, "__background__"));

  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.labels.size(), 1);
  EXPECT_EQ(sequence.camera.width, kW);
  EXPECT_EQ(sequence.camera.height, kH);
  EXPECT_EQ(sequence.camera.fx, 30.0);
  EXPECT_EQ(sequence.camera.fy, 31.0);
  EXPECT_EQ(sequence.camera.cx, 15.5);
  ASSERT_EQ(sequence.frames.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(sequence.frames[i].T_world_camera.matrix().isApprox(scenePose(i), 1e-12));
    const FrameData frame = loadFrame(sequence, i);
    DepthImage expected = sceneDepth(i);
    if (i == 1) expected.metres[7] = 0.0f;
    expectDepthEqual(frame.depth, expected);
    ASSERT_TRUE(frame.color.has_value());
    EXPECT_EQ(frame.color->rgb, sceneColor(i).rgb);
    ASSERT_TRUE(frame.label.has_value());
    EXPECT_FALSE(frame.proba.has_value());
    for (auto id : frame.label->ids) ASSERT_EQ(id, 0);
  }
}

// Numbers need not be padded to six digits: a frame's files are named as its
// depth image is.
TEST(ImportFrames, UnpaddedFrameNumbersFindTheirFiles) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  for (const auto& entry : fs::directory_iterator(dir / "src")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame-0000", 0) == 0)
      fs::rename(entry.path(), dir / "src" / ("frame-" + name.substr(10)));  // frame-15.depth.png
  }
  ASSERT_TRUE(fs::exists(dir / "src" / "frame-15.pose.txt"));
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  EXPECT_EQ(report.frames_written, 2u) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  ASSERT_EQ(sequence.frames.size(), 2u);
  EXPECT_TRUE(sequence.frames[1].T_world_camera.matrix().isApprox(scenePose(1), 1e-12));
  EXPECT_TRUE(loadFrame(sequence, 1).color.has_value());
}

TEST(ImportFrames, FrameNumbersAreNotWrittenAsTimeStamps) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  ASSERT_EQ(importSource(SourceKind::Frames, dir / "src", dir / "seq").frames_written, 2u);
  const Sequence sequence = loadSequence(dir / "seq");
  for (const auto& frame : sequence.frames)
    EXPECT_FALSE(frame.stamp.has_value()) << "frame numbers 15 and 17 are not seconds";
  std::ifstream in(dir / "seq" / "sequence.json");
  const std::string json{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_FALSE(contains(json, "\"stamp\"")) << json;
}

TEST(ImportFrames, GeometryOnlyWritesNoProbaFolder) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  ASSERT_EQ(importSource(SourceKind::Frames, dir / "src", dir / "seq").frames_written, 2u);
  EXPECT_TRUE(fs::is_directory(dir / "seq" / "depth"));
  EXPECT_TRUE(fs::is_directory(dir / "seq" / "label"));
  EXPECT_FALSE(fs::exists(dir / "seq" / "proba")) << "nothing goes into proba/";

  // Nor colour/ when no frame has colour.
  ImportOptions no_color;
  no_color.write_color = false;
  ASSERT_EQ(importSource(SourceKind::Frames, dir / "src", dir / "bare", no_color).frames_written,
            2u);
  EXPECT_FALSE(fs::exists(dir / "bare" / "proba"));
  EXPECT_FALSE(fs::exists(dir / "bare" / "color"));
  EXPECT_TRUE(validateSequence(loadSequence(dir / "bare")).empty());
}

TEST(ImportFrames, OneHotFramesAreMarkedAndTheNotesSaySo) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  for (int number : {15, 17}) {
    LabelImage label;
    label.width = kW;
    label.height = kH;
    label.ids.assign(kW * kH, 0);
    for (int i = 0; i < kW * kH / 2; ++i) label.ids[i] = 19;
    char name[40];
    std::snprintf(name, sizeof name, "frame-%06d.label.png", number);
    writeLabelPng(dir / "src" / name, label);
  }
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  ASSERT_EQ(report.frames_written, 2u) << report.text();
  EXPECT_TRUE(anyNote(report, "label images became one-hot probabilities (confidence 0.9)"))
      << report.text();
  EXPECT_TRUE(anyNote(report, "intrinsics read from " +
                                  (dir / "src" / "camera-intrinsics.txt").string() + ": fx 30"))
      << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  for (const auto& frame : sequence.frames) {
    EXPECT_FALSE(frame.proba.empty());
    EXPECT_FALSE(frame.label.empty());
    EXPECT_TRUE(frame.proba_from_label);
  }

  // An intrinsics option replaces the file: the note says so instead.
  ImportOptions options;
  options.intrinsics = parseIntrinsics("40,41,15.5,11.5");
  const ImportReport given = importSource(SourceKind::Frames, dir / "src", dir / "seq2", options);
  EXPECT_FALSE(anyNote(given, "intrinsics read from")) << given.text();
  EXPECT_TRUE(anyNote(given, "instead of the intrinsics of camera-intrinsics.txt")) << given.text();
}

TEST(ImportFrames, LabelImagesBecomeOneHotProbabilities) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  for (int number : {15, 17, 20}) {
    LabelImage label;
    label.width = kW;
    label.height = kH;
    label.ids.assign(kW * kH, 0);
    for (int i = 0; i < kW * kH / 2; ++i) label.ids[i] = 19;
    label.ids[kW * kH - 1] = 8;
    char name[40];
    std::snprintf(name, sizeof name, "frame-%06d.label.png", number);
    writeLabelPng(dir / "src" / name, label);
  }
  ImportOptions options;
  options.label_confidence = 0.8;
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq", options);
  ASSERT_EQ(report.frames_written, 2u);
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.labels, apc2016Labels());
  EXPECT_EQ(sequence.frames[0].proba_labels, (std::vector<int>{0, 8, 19}));
  const FrameData frame = loadFrame(sequence, 0);
  ASSERT_TRUE(frame.proba.has_value());
  ASSERT_EQ(frame.proba->channels, 3);
  const float* first = frame.proba->pixel(0, 0);  // label 19
  EXPECT_NEAR(first[2], 0.8f, 1e-3);
  EXPECT_NEAR(first[0], 0.1f, 1e-3);
  EXPECT_NEAR(first[1], 0.1f, 1e-3);
  const float* last = frame.proba->pixel(kW - 1, kH - 1);  // label 8
  EXPECT_NEAR(last[1], 0.8f, 1e-3);
  ASSERT_TRUE(frame.label.has_value());
  EXPECT_EQ(frame.label->at(0, 0), 19);
}

TEST(ImportFrames, MalformedInputs) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  fs::remove(dir / "src" / "camera-intrinsics.txt");
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "seq"); }),
                       "--intrinsics fx,fy,cx,cy"));
  EXPECT_FALSE(fs::exists(dir / "seq"));

  writeText(dir / "src" / "camera-intrinsics.txt", "30 0 15.5\n0 31 11.5\n");
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "seq"); }),
                       "6 numbers"));

  writeText(dir / "src" / "camera-intrinsics.txt", "30 0 15.5\n0 31 11.5\n0 0 1\n");
  writeText(dir / "src" / "frame-000015.pose.txt", "1 0 0 0\n0 1 0 0\nzero 0 1 0\n0 0 0 1\n");
  writeText(dir / "src" / "frame-000017.pose.txt",
            "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n0 0 0 1\n");
  writeText(dir / "src" / "frame-000020.pose.txt", "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  const std::string all_bad =
      errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "seq"); });
  EXPECT_TRUE(contains(all_bad, "at least one frame")) << all_bad;
  EXPECT_TRUE(contains(all_bad, "'zero'")) << all_bad;
  EXPECT_FALSE(fs::exists(dir / "seq")) << "nothing left behind";

  writeText(dir / "src" / "frame-000015.pose.txt", matrixText(scenePose(0)));
  // An 8-bit depth image is refused with the file named.
  cv::imwrite((dir / "src" / "frame-000017.depth.png").string(), cv::Mat(kH, kW, CV_8UC1, cv::Scalar(9)));
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  EXPECT_EQ(report.frames_written, 1u);
  EXPECT_TRUE(anySkipped(report, "frame-000017.depth.png")) << report.text();
  EXPECT_TRUE(anySkipped(report, "16-bit")) << report.text();
  EXPECT_TRUE(anySkipped(report, "det R = 2")) << report.text();

  // An existing sequence is not replaced without the overwrite option.
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "seq"); }),
                       "already holds sequence.json"));
  ImportOptions overwrite;
  overwrite.overwrite = true;
  EXPECT_EQ(importSource(SourceKind::Frames, dir / "src", dir / "seq", overwrite).frames_written, 1u);
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "src"); }),
                       "other than the source"));
}

TEST(ImportFrames, SubsetAndCancel) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  ImportOptions options;
  options.first_frame = 1;
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq", options);
  EXPECT_EQ(report.frames_found, 3u);
  EXPECT_EQ(report.frames_written, 1u);  // 17 written, 20 has no pose
  // A first frame past the last says so.
  options.first_frame = 3;
  const std::string past =
      errorOf([&] { importSource(SourceKind::Frames, dir / "src", dir / "past", options); });
  EXPECT_TRUE(contains(past, "--first 3 is past the last of the 3 frames found")) << past;
  EXPECT_FALSE(fs::exists(dir / "past"));
  const ImportReport cancelled = importSource(
      SourceKind::Frames, dir / "src", dir / "cancelled", {},
      [](const ImportProgress& p) { return p.done < 1; });
  EXPECT_TRUE(cancelled.cancelled);
  EXPECT_FALSE(fs::exists(dir / "cancelled"));
}

TEST(ImportFrames, DepthOfAnotherSizeGetsScaledIntrinsics) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  DepthImage big;
  big.width = 2 * kW;
  big.height = 2 * kH;
  big.metres.assign(4 * kW * kH, 1.5f);
  writeDepthPng(dir / "src" / "frame-000017.depth.png", big, 0.001);
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  ASSERT_EQ(report.frames_written, 2u);
  EXPECT_TRUE(anyNote(report, "intrinsics scaled")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  ASSERT_TRUE(sequence.frames[1].camera.has_value());
  EXPECT_EQ(sequence.frames[1].camera->width, 2 * kW);
  EXPECT_DOUBLE_EQ(sequence.frames[1].camera->fx, 60.0);
  EXPECT_DOUBLE_EQ(sequence.frames[1].camera->cx, 31.5);
  EXPECT_FALSE(sequence.frames[0].camera.has_value());
}

TEST(ImportFrames, ASkippedFirstFrameDoesNotSetTheCameraSize) {
  // The first frame in name order has depth of another size and no pose: it
  // is skipped, and the intrinsics file applies to the frames written at
  // their own size, unscaled.
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  DepthImage odd;
  odd.width = kW / 2;
  odd.height = kH / 2;
  odd.metres.assign(static_cast<size_t>(odd.width * odd.height), 1.2f);
  writeDepthPng(dir / "src" / "frame-000010.depth.png", odd, 0.001);
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  ASSERT_EQ(report.frames_written, 2u);
  EXPECT_TRUE(anySkipped(report, "no pose file")) << report.text();
  EXPECT_FALSE(anyNote(report, "intrinsics scaled")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_EQ(sequence.camera.width, kW);
  EXPECT_EQ(sequence.camera.height, kH);
  EXPECT_EQ(sequence.camera.fx, 30.0);
  for (const auto& frame : sequence.frames) EXPECT_FALSE(frame.camera.has_value());
}

TEST(ImportFrames, AnUnreadableColourImageKeepsTheFrameWithoutColour) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  writeText(dir / "src" / "frame-000017.color.png", "");
  const ImportReport report = importSource(SourceKind::Frames, dir / "src", dir / "seq");
  EXPECT_EQ(report.frames_written, 2u) << report.text();
  EXPECT_TRUE(anyNote(report, "frame-000017.color.png")) << report.text();
  EXPECT_TRUE(anyNote(report, "imported without colour")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(loadFrame(sequence, 0).color.has_value());
  EXPECT_FALSE(loadFrame(sequence, 1).color.has_value());
}

TEST(ImportFrames, ASourceInsideTheFoldersTheImportReplacesIsRefused) {
  // --overwrite replaces OUT/depth, color, proba, label and sequence.json: a
  // recording kept there would be deleted with them.
  test::TempDir dir;
  writeFramesFolder(dir / "project" / "color");
  ImportOptions options;
  options.overwrite = true;
  const std::string error = errorOf([&] {
    importSource(SourceKind::Frames, dir / "project" / "color", dir / "project", options);
  });
  EXPECT_TRUE(contains(error, "source: expected a recording outside the files the import writes"))
      << error;
  EXPECT_TRUE(fs::exists(dir / "project" / "color" / "frame-000015.depth.png"));
  EXPECT_TRUE(fs::exists(dir / "project" / "color" / "camera-intrinsics.txt"));
  EXPECT_FALSE(fs::exists(dir / "project" / "sequence.json"));
}

TEST(ImportFrames, AFailedImportLeavesAnExistingFolderAsItWasAndNoNewParents) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  // Empty frame folders made beforehand stay empty when the import is cancelled.
  fs::create_directories(dir / "out" / "depth");
  fs::create_directories(dir / "out" / "color");
  const auto cancel_after_one = [](const ImportProgress& p) { return p.done < 1; };
  const ImportReport cancelled =
      importSource(SourceKind::Frames, dir / "src", dir / "out", {}, cancel_after_one);
  ASSERT_TRUE(cancelled.cancelled);
  std::vector<fs::path> left;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "out"))
    left.push_back(entry.path());
  EXPECT_EQ(left.size(), 2u) << "only the two empty folders, no frame files, no staging folder";
  EXPECT_TRUE(fs::is_empty(dir / "out" / "depth"));
  // Completed, the same folder gets the frames.
  EXPECT_EQ(importSource(SourceKind::Frames, dir / "src", dir / "out").frames_written, 2u);
  EXPECT_TRUE(validateSequence(loadSequence(dir / "out")).empty());
  // A new nested output leaves none of the folders it created.
  const ImportReport nested = importSource(SourceKind::Frames, dir / "src",
                                           dir / "new" / "deeper" / "seq", {}, cancel_after_one);
  ASSERT_TRUE(nested.cancelled);
  EXPECT_FALSE(fs::exists(dir / "new"));
}

// A cancelled import removes only what it made: its output folder as the
// kernel resolved it (not the path with ".." folded away across a symbolic
// link) and the folders above it while they are empty (another import may
// have put its output beside it).
TEST(ImportFrames, ACancelledImportRemovesOnlyTheFoldersItMade) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  const auto cancel_after_one = [](const ImportProgress& p) { return p.done < 1; };
  // work/link -> a/b; work/link/../seq is a/seq, not work/seq (the user's).
  fs::create_directories(dir / "a" / "b");
  fs::create_directories(dir / "work" / "seq");
  writeText(dir / "work" / "seq" / "mywork.txt", "mine");
  fs::create_directory_symlink(dir / "a" / "b", dir / "work" / "link");
  const ImportReport through_link = importSource(
      SourceKind::Frames, dir / "src", dir / "work" / "link" / ".." / "seq", {}, cancel_after_one);
  ASSERT_TRUE(through_link.cancelled);
  EXPECT_TRUE(fs::exists(dir / "work" / "seq" / "mywork.txt"));
  EXPECT_FALSE(fs::exists(dir / "a" / "seq"));
  // A parent made by this import, which another output has joined since.
  const fs::path other = dir / "new" / "other";
  const auto joined_then_cancelled = [&](const ImportProgress& p) {
    if (p.done == 1) {
      fs::create_directories(other);
      writeText(other / "sequence.json", "{}");
    }
    return p.done < 1;
  };
  const ImportReport beside =
      importSource(SourceKind::Frames, dir / "src", dir / "new" / "seq", {}, joined_then_cancelled);
  ASSERT_TRUE(beside.cancelled);
  EXPECT_FALSE(fs::exists(dir / "new" / "seq"));
  EXPECT_TRUE(fs::exists(other / "sequence.json")) << "the other output stays";
}

// A damaged cache entry (a frame file gone, a truncated sequence.json) is
// converted again instead of failing on every open; colour images left out
// are said on every open, fresh or reused.
TEST(ImportOpen, ADamagedCacheEntryIsConvertedAgainAndColourLeftOutIsKept) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  writeText(dir / "src" / "frame-000017.color.png", "");
  const OpenedSource first = openSource(dir / "src", {}, dir / "cache");
  EXPECT_TRUE(contains(first.colour_left_out, "frame-000017.color.png")) << first.colour_left_out;
  fs::remove(first.folder / "depth" / "000001.png");
  const OpenedSource second = openSource(dir / "src", {}, dir / "cache");
  EXPECT_FALSE(second.reused_cache) << "a frame file was missing: converted again";
  EXPECT_EQ(second.folder, first.folder);
  EXPECT_TRUE(fs::exists(second.folder / "depth" / "000001.png"));
  EXPECT_TRUE(contains(second.colour_left_out, "frame-000017.color.png"));
  writeText(second.folder / "sequence.json", "{");
  const OpenedSource third = openSource(dir / "src", {}, dir / "cache");
  EXPECT_FALSE(third.reused_cache);
  EXPECT_EQ(third.sequence.frames.size(), 2u);
  const OpenedSource reused = openSource(dir / "src", {}, dir / "cache");
  EXPECT_TRUE(reused.reused_cache);
  EXPECT_TRUE(contains(reused.colour_left_out, "frame-000017.color.png")) << reused.colour_left_out;
  for (const auto& entry : fs::directory_iterator(dir / "cache"))
    EXPECT_EQ(entry.path().filename().string().rfind(".stale-", 0), std::string::npos)
        << entry.path();
}

// Label lists that differ only where a name holds a comma ("a,b" + "c"
// against "a" + "b,c") are different conversions: one reused the other's entry
// and its names.
TEST(ImportOpen, LabelListsWithCommasInNamesAreDifferentEntries) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  ImportOptions first_options, second_options;
  first_options.labels =
      LabelSet({{0, "__background__", {0, 0, 0}}, {1, "a,b", {128, 0, 0}}, {2, "c", {0, 128, 0}}});
  second_options.labels =
      LabelSet({{0, "__background__", {0, 0, 0}}, {1, "a", {128, 0, 0}}, {2, "b,c", {0, 128, 0}}});
  const OpenedSource first = openSource(dir / "src", first_options, dir / "cache");
  const OpenedSource second = openSource(dir / "src", second_options, dir / "cache");
  EXPECT_FALSE(second.reused_cache);
  EXPECT_NE(second.folder, first.folder);
  EXPECT_EQ(second.sequence.labels.at(1).name, "a");
  EXPECT_TRUE(openSource(dir / "src", first_options, dir / "cache").reused_cache);
}

// A recording opened through a symbolic link is the same cache entry.
TEST(ImportOpen, ALinkToARecordingReusesItsEntry) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  fs::create_directory_symlink(dir / "src", dir / "link");
  const OpenedSource first = openSource(dir / "src", {}, dir / "cache");
  const OpenedSource linked = openSource(dir / "link", {}, dir / "cache");
  EXPECT_TRUE(linked.reused_cache);
  EXPECT_EQ(linked.folder, first.folder);
}

// The cache does not only grow: entries not opened for 30 days go when
// another recording is converted, unless they hold files the conversion did
// not write (boxes earlier versions saved there); interrupted conversions'
// leftovers go after a day. Opening an entry counts as a use.
TEST(ImportOpen, UnusedCacheEntriesArePruned) {
  test::TempDir dir;
  writeFramesFolder(dir / "a");
  writeFramesFolder(dir / "b");
  writeFramesFolder(dir / "c");
  writeFramesFolder(dir / "d");
  const fs::path cache = dir / "cache";
  const OpenedSource a = openSource(dir / "a", {}, cache);
  const OpenedSource b = openSource(dir / "b", {}, cache);
  const OpenedSource c = openSource(dir / "c", {}, cache);
  writeText(c.folder / "annotations.json", "{}");
  const auto now = fs::file_time_type::clock::now();
  const auto days = [&](int n) { return now - std::chrono::hours(24 * n); };
  for (const fs::path& entry : {a.folder, b.folder, c.folder}) fs::last_write_time(entry, days(40));
  fs::create_directories(cache / ".partial-0000000000000000-1-1");
  fs::last_write_time(cache / ".partial-0000000000000000-1-1", days(2));
  fs::create_directories(cache / ".partial-0000000000000000-2-2");  // maybe still converting
  // b opened again: used now.
  EXPECT_TRUE(openSource(dir / "b", {}, cache).reused_cache);
  EXPECT_TRUE(fs::exists(a.folder)) << "reusing an entry removes nothing";
  const OpenedSource d = openSource(dir / "d", {}, cache);
  EXPECT_FALSE(d.reused_cache);
  EXPECT_FALSE(fs::exists(a.folder)) << "unused for 40 days";
  EXPECT_TRUE(fs::exists(b.folder)) << "opened just now";
  EXPECT_TRUE(fs::exists(c.folder / "annotations.json")) << "holds boxes: kept";
  EXPECT_TRUE(fs::exists(d.folder));
  EXPECT_FALSE(fs::exists(cache / ".partial-0000000000000000-1-1"));
  EXPECT_TRUE(fs::exists(cache / ".partial-0000000000000000-2-2"));
  for (const auto& entry : fs::directory_iterator(cache))
    EXPECT_EQ(entry.path().filename().string().rfind(".stale-", 0), std::string::npos)
        << entry.path();
  // A pruned recording opens again (converted afresh).
  const OpenedSource again = openSource(dir / "a", {}, cache);
  EXPECT_FALSE(again.reused_cache);
  EXPECT_EQ(again.sequence.frames.size(), 2u);
}

TEST(ImportOpen, ConvertsIntoACacheAndReusesIt) {
  test::TempDir dir;
  writeFramesFolder(dir / "src");
  const OpenedSource first = openSource(dir / "src", {}, dir / "cache");
  EXPECT_EQ(first.kind, SourceKind::Frames);
  EXPECT_TRUE(first.converted);
  EXPECT_FALSE(first.reused_cache);
  EXPECT_EQ(first.sequence.frames.size(), 2u);
  EXPECT_EQ(first.report.frames_written, 2u);
  EXPECT_EQ(first.folder.parent_path(), dir / "cache");
  const OpenedSource second = openSource(dir / "src", {}, dir / "cache");
  EXPECT_TRUE(second.reused_cache);
  EXPECT_EQ(second.folder, first.folder);
  EXPECT_EQ(second.sequence.frames.size(), 2u);
  // Other options: another conversion.
  ImportOptions subset;
  subset.max_frames = 1;
  const OpenedSource third = openSource(dir / "src", subset, dir / "cache");
  EXPECT_FALSE(third.reused_cache);
  EXPECT_NE(third.folder, first.folder);
  EXPECT_EQ(third.sequence.frames.size(), 1u);
  // Files no import reads (boxes saved beside the recording, an export, a
  // hidden file) leave the conversion as it is.
  writeText(dir / "src" / "boxes.json", "{}");
  writeText(dir / "src" / "map.ply", "ply");
  writeText(dir / "src" / ".notes", "x");
  const OpenedSource with_outputs = openSource(dir / "src", {}, dir / "cache");
  EXPECT_TRUE(with_outputs.reused_cache);
  EXPECT_EQ(with_outputs.folder, first.folder);
  // A changed source: converted again.
  writeText(dir / "src" / "frame-000020.pose.txt", matrixText(scenePose(2)));
  const OpenedSource fourth = openSource(dir / "src", {}, dir / "cache");
  EXPECT_FALSE(fourth.reused_cache);
  EXPECT_EQ(fourth.sequence.frames.size(), 3u);
  // A sequence opens as it is.
  const OpenedSource sequence = openSource(first.folder / "sequence.json", {}, dir / "cache");
  EXPECT_EQ(sequence.kind, SourceKind::Sequence);
  EXPECT_FALSE(sequence.converted);
  EXPECT_EQ(sequence.folder, first.folder);
  // Unknown things are refused with the explanation.
  fs::create_directories(dir / "empty");
  EXPECT_TRUE(contains(errorOf([&] { (void)openSource(dir / "empty", {}, dir / "cache"); }),
                       "an empty folder"));
}

// ---------------------------------------------------------------------------
// TUM RGB-D

struct TumFixture {
  fs::path dir;
  std::vector<double> depth_stamps{100.0, 100.033, 100.066, 100.2};
  std::vector<double> rgb_stamps{100.01, 100.043, 100.5};

  static Eigen::Vector3d position(double t) { return {t - 100.0, 2.0 * (t - 100.0), 1.0}; }
  static Eigen::Quaterniond rotation(double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * (t - 100.0), Eigen::Vector3d::UnitZ()));
  }

  explicit TumFixture(const fs::path& folder) : dir(folder) {
    fs::create_directories(dir / "rgb");
    fs::create_directories(dir / "depth");
    std::ostringstream depth_list, rgb_list, gt;
    depth_list << "# depth maps\n# file: 'test.bag'\n# timestamp filename\n" << std::fixed
               << std::setprecision(6);
    rgb_list << "# color images\n" << std::fixed << std::setprecision(6);
    for (size_t i = 0; i < depth_stamps.size(); ++i) {
      std::ostringstream name;
      name << std::fixed << std::setprecision(6) << "depth/" << depth_stamps[i] << ".png";
      DepthImage depth = sceneDepth(static_cast<int>(i));
      writeDepthPng(dir / name.str(), depth, 1.0 / 5000.0);
      depth_list << depth_stamps[i] << " " << name.str() << "\n";
    }
    for (size_t i = 0; i < rgb_stamps.size(); ++i) {
      std::ostringstream name;
      name << std::fixed << std::setprecision(6) << "rgb/" << rgb_stamps[i] << ".png";
      writeColorPng(dir / name.str(), sceneColor(static_cast<int>(i)));
      rgb_list << rgb_stamps[i] << " " << name.str() << "\n";
    }
    // Groundtruth at 100 Hz from 99.95 to 100.07; the frame at 100.2 has none.
    gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(17);
    for (int k = -5; k <= 7; ++k) {
      const double t = 100.0 + 0.01 * k;
      const auto p = position(t);
      const auto q = rotation(t);
      gt << t << " " << p.x() << " " << p.y() << " " << p.z() << " " << q.x() << " " << q.y()
         << " " << q.z() << " " << q.w() << "\n";
    }
    writeText(dir / "depth.txt", depth_list.str());
    writeText(dir / "rgb.txt", rgb_list.str());
    writeText(dir / "groundtruth.txt", gt.str());
  }
};

TEST(ImportTum, RoundTripWithAssociationAndInterpolation) {
  test::TempDir dir;
  TumFixture tum(dir / "rgbd_dataset_freiburg1_test");
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report = importSource(std::nullopt, tum.dir, dir / "seq", options);
  EXPECT_EQ(report.kind, SourceKind::Tum);
  EXPECT_EQ(report.frames_found, 4u);
  EXPECT_EQ(report.frames_written, 3u);
  EXPECT_TRUE(anySkipped(report, "no groundtruth pose within 0.02 s of 100.200000")) << report.text();
  EXPECT_TRUE(anyNote(report, "freiburg1")) << report.text();
  EXPECT_TRUE(anyNote(report, "without colour")) << report.text();

  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_DOUBLE_EQ(sequence.camera.fx, 517.3);
  EXPECT_DOUBLE_EQ(sequence.camera.cy, 255.3);
  EXPECT_DOUBLE_EQ(sequence.camera.depth_scale, 1.0 / 5000.0);
  ASSERT_EQ(sequence.frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const double t = tum.depth_stamps[i];
    ASSERT_TRUE(sequence.frames[i].stamp.has_value()) << "TUM keeps its time stamps";
    EXPECT_DOUBLE_EQ(*sequence.frames[i].stamp, t);
    EXPECT_TRUE(sequence.frames[i].T_world_camera.translation().isApprox(
        TumFixture::position(t), 1e-9))
        << "interpolated between the 100 Hz samples";
    EXPECT_TRUE(sequence.frames[i].T_world_camera.linear().isApprox(
        TumFixture::rotation(t).toRotationMatrix(), 1e-9));
    const FrameData frame = loadFrame(sequence, i);
    expectDepthEqual(frame.depth, sceneDepth(static_cast<int>(i)), 1e-6);
    EXPECT_EQ(frame.color.has_value(), i < 2) << "rgb at 100.5 is too far from 100.066";
    if (frame.color) {
      EXPECT_EQ(frame.color->rgb, sceneColor(static_cast<int>(i)).rgb);
    }
  }

  // A clock offset: with every image stamp 1000 s late nothing has a pose,
  // unless the offset is given.
  options.time_offset = 1000.0;
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "late", options); }),
                       "no groundtruth pose"));
}

TEST(ImportTum, ClocksThatDoNotOverlapAreMeasured) {
  test::TempDir dir;
  TumFixture tum(dir / "tum");
  std::ifstream in(tum.dir / "groundtruth.txt");
  std::ostringstream shifted;
  shifted << std::setprecision(17);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream numbers(line);
    double t = 0.0;
    numbers >> t;
    std::string rest;
    std::getline(numbers, rest);
    shifted << t + 3600.0 << rest << "\n";
  }
  in.close();
  writeText(tum.dir / "groundtruth.txt", shifted.str());
  const std::string error = errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "seq"); });
  EXPECT_TRUE(contains(error, "do not overlap: the clocks differ by about 36")) << error;
  EXPECT_TRUE(contains(error, "time offset")) << error;
  ImportOptions options;
  options.time_offset = 3600.0;
  EXPECT_EQ(importSource(SourceKind::Tum, tum.dir, dir / "seq", options).frames_written, 3u);
}

TEST(ImportTum, NonFiniteTimeStampsAreRefusedWhereTheyAre) {
  test::TempDir dir;
  TumFixture tum(dir / "tum");
  writeText(tum.dir / "groundtruth.txt", "100.0 1 2 3 0 0 0 1\nnan 1 2 3 0 0 0 1\n");
  const std::string gt = errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "seq"); });
  EXPECT_TRUE(contains(gt, "groundtruth.txt: line 2: expected a finite time stamp")) << gt;
  TumFixture lists(dir / "tum2");
  writeText(lists.dir / "depth.txt", "100.0 depth/a.png\ninf depth/b.png\n");
  const std::string list = errorOf([&] { importSource(SourceKind::Tum, lists.dir, dir / "seq"); });
  EXPECT_TRUE(contains(list, "depth.txt: line 2: expected 'timestamp filename'")) << list;
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

TEST(ImportTum, MalformedInputs) {
  test::TempDir dir;
  TumFixture tum(dir / "tum");
  writeText(tum.dir / "groundtruth.txt", "# header\n100.0 1 2 3 0 0 0\n");
  const std::string gt = errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "seq"); });
  EXPECT_TRUE(contains(gt, "groundtruth.txt: line 2: expected 8 numbers")) << gt;
  fs::remove(tum.dir / "groundtruth.txt");
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "seq"); }),
                       "groundtruth.txt"));
  writeText(tum.dir / "depth.txt", "100.0\n");
  const std::string list = errorOf([&] { importSource(SourceKind::Tum, tum.dir, dir / "seq"); });
  EXPECT_TRUE(contains(list, "depth.txt: line 1: expected 'timestamp filename'")) << list;
  // Without freiburg in the name: default intrinsics, noted.
  TumFixture plain(dir / "plain");
  const ImportReport report = importSource(SourceKind::Tum, plain.dir, dir / "seq2");
  EXPECT_TRUE(anyNote(report, "default intrinsics")) << report.text();
}

// ---------------------------------------------------------------------------
// Quaternion layout (kinect-room-5)

void writeQuaternionFolder(const fs::path& dir) {
  fs::create_directories(dir / "color");
  fs::create_directories(dir / "depth");
  std::ostringstream poses;
  poses << std::setprecision(17);
  for (int n = 1; n <= 3; ++n) {
    const DepthImage depth = sceneDepth(n);
    cv::Mat mm(kH, kW, CV_16UC1);
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u)
        mm.at<std::uint16_t>(v, u) =
            static_cast<std::uint16_t>(std::lround(depth.metres[v * kW + u] * 1000.0));
    cv::imwrite((dir / "depth" / (std::to_string(n) + ".pgm")).string(), mm);
    writeColorPng(dir / "color" / (std::to_string(n) + ".png"), sceneColor(n));
    const Eigen::Matrix4d pose = scenePose(n);
    const Eigen::Quaterniond q(Eigen::Matrix3d(pose.topLeftCorner<3, 3>()));
    poses << pose(0, 3) << " " << pose(1, 3) << " " << pose(2, 3) << " " << q.x() << " " << q.y()
          << " " << q.z() << " " << q.w() << "\n";
  }
  writeText(dir / "pose.txt", poses.str());
}

// The quaternion folder at dir/room with `pose_text` as its pose.txt, imported
// with the test camera into dir/out.
ImportReport importQuaternionPoses(const fs::path& dir, const std::string& pose_text,
                                   const std::string& out) {
  ImportOptions options;
  options.intrinsics = parseIntrinsics("30,31,15.5,11.5");
  writeText(dir / "room" / "pose.txt", pose_text);
  return importSource(SourceKind::Quaternion, dir / "room", dir / out, options);
}

TEST(ImportQuaternion, RoundTripWithIntrinsicsOption) {
  test::TempDir dir;
  writeQuaternionFolder(dir / "room");
  ImportOptions options;
  options.intrinsics = parseIntrinsics("30,31,15.5,11.5");
  const ImportReport report = importSource(std::nullopt, dir / "room", dir / "seq", options);
  EXPECT_EQ(report.kind, SourceKind::Quaternion);
  EXPECT_EQ(report.frames_written, 3u);
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.camera.fy, 31.0);
  EXPECT_EQ(sequence.camera.width, kW);
  for (int n = 1; n <= 3; ++n) {
    EXPECT_TRUE(sequence.frames[n - 1].T_world_camera.matrix().isApprox(scenePose(n), 1e-9));
    const FrameData frame = loadFrame(sequence, n - 1);
    expectDepthEqual(frame.depth, sceneDepth(n));
    EXPECT_EQ(frame.color->rgb, sceneColor(n).rgb);
    EXPECT_FALSE(sequence.frames[n - 1].stamp.has_value()) << "7 columns: no time";
  }
}

TEST(ImportQuaternion, KeepsALeadingTimeStampButNotAFrameNumber) {
  test::TempDir dir;
  writeQuaternionFolder(dir / "room");
  ASSERT_EQ(importQuaternionPoses(dir.path(),
                                  "1305031102.5 0 0 0 0 0 0 1\n1305031102.75 0.1 0 0 0 0 0 1\n"
                                  "1305031103.25 0.2 0 0 0 0 0 1\n",
                                  "timed")
                .frames_written,
            3u);
  const Sequence timed = loadSequence(dir / "timed");
  ASSERT_TRUE(timed.frames[2].stamp.has_value());
  EXPECT_DOUBLE_EQ(*timed.frames[2].stamp, 1305031103.25);

  ASSERT_EQ(importQuaternionPoses(dir.path(), "1 0 0 0 0 0 0 1\n2 0.1 0 0 0 0 0 1\n3 0.2 0 0 0 0 0 1\n",
                                  "numbered")
                .frames_written,
            3u);
  for (const auto& frame : loadSequence(dir / "numbered").frames)
    EXPECT_FALSE(frame.stamp.has_value()) << "a frame number is not a time";
}

TEST(ImportQuaternion, WholeNumbersTooLargeForFrameNumbersAreTimeStamps) {
  test::TempDir dir;
  writeQuaternionFolder(dir / "room");
  // Whole numbers, but beyond any frame number (and beyond a 64-bit integer).
  ASSERT_EQ(importQuaternionPoses(
                dir.path(), "1e19 0 0 0 0 0 0 1\n2e19 0.1 0 0 0 0 0 1\n-3e30 0.2 0 0 0 0 0 1\n", "timed")
                .frames_written,
            3u);
  const Sequence timed = loadSequence(dir / "timed");
  ASSERT_TRUE(timed.frames[0].stamp.has_value());
  EXPECT_DOUBLE_EQ(*timed.frames[0].stamp, 1e19);
  ASSERT_TRUE(timed.frames[2].stamp.has_value());
  EXPECT_DOUBLE_EQ(*timed.frames[2].stamp, -3e30);
  EXPECT_NEAR(timed.frames[1].T_world_camera.translation().x(), 0.1, 1e-12);

  // Among frame numbers, such a line names no depth image: that image has no pose.
  const ImportReport numbered = importQuaternionPoses(
      dir.path(), "1 0 0 0 0 0 0 1\n2 0.1 0 0 0 0 0 1\n1e19 0.2 0 0 0 0 0 1\n", "numbered");
  EXPECT_EQ(numbered.frames_written, 2u) << numbered.text();
  EXPECT_TRUE(anySkipped(numbered, "no pose for it in pose.txt")) << numbered.text();
}

// Lines numbered from 0 for images numbered from 1: matched by number, every
// image would take its neighbour's pose. Refused, naming the shift; a line
// that names no image among good ones is noted.
TEST(ImportQuaternion, LineNumbersShiftedFromTheImagesAreRefused) {
  test::TempDir dir;
  writeQuaternionFolder(dir / "room");  // images 1, 2, 3
  const std::string shifted = errorOf([&] {
    importQuaternionPoses(dir.path(), "0 0 0 0 0 0 0 1\n1 0.1 0 0 0 0 0 1\n2 0.2 0 0 0 0 0 1\n",
                          "shifted");
  });
  EXPECT_TRUE(contains(shifted,
                       "pose.txt: poses: expected lines of 8 numbers starting with the "
                       "number of their depth image"))
      << shifted;
  EXPECT_TRUE(contains(shifted,
                       "lines numbered 0 to 2 for depth images 1 to 3: each line's "
                       "number is its image's minus 1"))
      << shifted;
  EXPECT_FALSE(fs::exists(dir / "shifted"));
  const ImportReport extra = importQuaternionPoses(
      dir.path(), "1 0 0 0 0 0 0 1\n2 0.1 0 0 0 0 0 1\n3 0.2 0 0 0 0 0 1\n7 0.3 0 0 0 0 0 1\n",
      "extra");
  EXPECT_EQ(extra.frames_written, 3u);
  EXPECT_TRUE(anyNote(extra, "pose.txt: 1 line names no depth image (numbers 7), left out"))
      << extra.text();
}

TEST(ImportQuaternion, MalformedInputs) {
  test::TempDir dir;
  writeQuaternionFolder(dir / "room");
  // A leading stamp that is not a number is named where it is, not in the output.
  const std::string nan_stamp = errorOf([&] {
    importQuaternionPoses(dir.path(), "1 0 0 0 0 0 0 1\nnan 0.1 0 0 0 0 0 1\n3 0 0 0 0 0 0 1\n",
                          "nan");
  });
  EXPECT_TRUE(contains(nan_stamp, "pose.txt: line 2: expected a finite frame number or time stamp"))
      << nan_stamp;
  EXPECT_FALSE(fs::exists(dir / "nan"));
  writeQuaternionFolder(dir / "room");
  const std::string none = errorOf([&] { importSource(SourceKind::Quaternion, dir / "room", dir / "seq"); });
  EXPECT_TRUE(contains(none, "--intrinsics fx,fy,cx,cy")) << none;
  // An intrinsics file in the folder is found.
  writeText(dir / "room" / "intrinsics.txt", "30 31 15.5 11.5\n");
  EXPECT_EQ(importSource(SourceKind::Quaternion, dir / "room", dir / "seq").frames_written, 3u);
  // Fewer poses than images: the last frame is skipped, the mismatch noted.
  writeText(dir / "room" / "pose.txt", "0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n");
  const ImportReport report = importSource(SourceKind::Quaternion, dir / "room", dir / "seq2");
  EXPECT_EQ(report.frames_written, 2u);
  EXPECT_TRUE(anySkipped(report, "no pose for it in pose.txt"));
  EXPECT_TRUE(anyNote(report, "2 poses for 3 depth images"));
  // With an image missing from the numbering, line i may be the pose of the
  // missing image: every later image would take the wrong pose. Refused,
  // nothing written.
  writeQuaternionFolder(dir / "gap");
  fs::remove(dir / "gap" / "depth" / "2.pgm");
  const std::string gap =
      errorOf([&] { importSource(SourceKind::Quaternion, dir / "gap", dir / "seq-gap"); });
  EXPECT_TRUE(contains(
      gap, (dir / "gap" / "pose.txt").string() + ": poses: expected one pose per depth image"))
      << gap;
  EXPECT_TRUE(contains(gap, "found 3 poses for 2 depth images numbered 1 to 3, with no image 2"))
      << gap;
  EXPECT_FALSE(fs::exists(dir / "seq-gap"));
  // Numbered from 2: image 1 (or 0) may be the one missing.
  writeQuaternionFolder(dir / "late");
  fs::remove(dir / "late" / "depth" / "1.pgm");
  EXPECT_TRUE(contains(
      errorOf([&] { importSource(SourceKind::Quaternion, dir / "late", dir / "seq-late"); }),
      "with no image 0 or 1"));
  // Lines that name their image match by number, gap or not.
  std::string numbered;
  int number = 1;
  std::istringstream lines(test::slurp(dir / "gap" / "pose.txt"));
  for (std::string line; std::getline(lines, line);)
    numbered += std::to_string(number++) + " " + line + "\n";
  writeText(dir / "gap" / "pose.txt", numbered);
  writeText(dir / "gap" / "intrinsics.txt", "30 31 15.5 11.5\n");
  EXPECT_EQ(importSource(SourceKind::Quaternion, dir / "gap", dir / "seq-gap").frames_written, 2u);
  writeText(dir / "room" / "pose.txt", "0 0 0 0 0 1\n");
  const std::string short_line =
      errorOf([&] { importSource(SourceKind::Quaternion, dir / "room", dir / "seq3"); });
  EXPECT_TRUE(contains(short_line, "pose.txt: line 1: expected 7 numbers")) << short_line;
  writeText(dir / "room" / "pose.txt", "0 0 0 0 0 0 0\n0 0 0 0 0 0 1\n0 0 0 0 0 0 1\n");
  const ImportReport zero = importSource(SourceKind::Quaternion, dir / "room", dir / "seq4");
  EXPECT_TRUE(anySkipped(zero, "zero or non-finite quaternion")) << zero.text();
}

// ---------------------------------------------------------------------------
// ScanNet

void writeScanNetScene(const fs::path& dir, bool with_tsv) {
  for (const char* sub : {"color", "depth", "pose", "intrinsic", "label-filt"})
    fs::create_directories(dir / sub);
  // Depth camera 32 x 24; colour 64 x 48 with the same field of view.
  writeText(dir / "intrinsic" / "intrinsic_depth.txt",
            "30 0 15.5 0\n0 31 11.5 0\n0 0 1 0\n0 0 0 1\n");
  writeText(dir / "intrinsic" / "intrinsic_color.txt",
            "60 0 31.5 0\n0 62 23.5 0\n0 0 1 0\n0 0 0 1\n");
  for (int n = 0; n < 3; ++n) {
    writeDepthPng(dir / "depth" / (std::to_string(n) + ".png"), sceneDepth(n), 0.001);
    cv::Mat color(2 * kH, 2 * kW, CV_8UC3, cv::Scalar(40, 120, 200));  // BGR
    cv::imwrite((dir / "color" / (std::to_string(n) + ".jpg")).string(), color);
    cv::Mat label(2 * kH, 2 * kW, CV_16UC1, cv::Scalar(0));
    label(cv::Rect(0, 8, kW, 2 * kH - 8)).setTo(5);           // left half: ScanNet id 5
    label(cv::Rect(kW, 8, kW, 2 * kH - 8)).setTo(1234);       // right half: id 1234
    cv::imwrite((dir / "label-filt" / (std::to_string(n) + ".png")).string(), label);
    writeText(dir / "pose" / (std::to_string(n) + ".txt"),
              n == 1 ? "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n"
                     : matrixText(scenePose(n)));
  }
  if (with_tsv)
    writeText(dir / "scannetv2-labels.combined.tsv",
              "id\traw_category\tcategory\tcount\n5\tchair\tchair\t10\n1234\tmug\tcup\t3\n");
}

TEST(ImportScanNet, RoundTripWithResampledColourAndLabels) {
  test::TempDir dir;
  writeScanNetScene(dir / "scene0000_00", true);
  const ImportReport report = importSource(std::nullopt, dir / "scene0000_00", dir / "seq");
  EXPECT_EQ(report.kind, SourceKind::ScanNet);
  EXPECT_EQ(report.frames_written, 2u);
  EXPECT_TRUE(anySkipped(report, "inf or NaN")) << report.text();
  // The notes give the size the images had, not the size they were resampled to.
  EXPECT_TRUE(anyNote(report, "colour images of 64 x 48 resampled to the depth camera"))
      << report.text();
  EXPECT_TRUE(anyNote(report, "label images of 64 x 48 resampled to the depth camera"))
      << report.text();

  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  ASSERT_EQ(sequence.labels.size(), 3);
  EXPECT_EQ(sequence.labels.at(1).name, "chair");
  EXPECT_EQ(sequence.labels.at(2).name, "cup");
  EXPECT_EQ(sequence.camera.fx, 30.0);
  EXPECT_EQ(sequence.camera.width, kW);
  EXPECT_TRUE(sequence.frames[1].T_world_camera.matrix().isApprox(scenePose(2), 1e-12));
  const FrameData frame = loadFrame(sequence, 0);
  expectDepthEqual(frame.depth, sceneDepth(0));
  ASSERT_TRUE(frame.color.has_value());
  EXPECT_EQ(frame.color->width, kW);
  EXPECT_NEAR(frame.color->rgb[3 * (10 * kW + 10)], 200, 6);  // R after JPEG
  ASSERT_TRUE(frame.label.has_value());
  ASSERT_EQ(frame.label->width, kW);
  EXPECT_EQ(frame.label->at(0, 0), 0);
  EXPECT_EQ(frame.label->at(kW / 2 - 1, kH / 2), 1) << "left half: chair";
  EXPECT_EQ(frame.label->at(kW / 2, kH / 2), 2) << "right half: cup";
  ASSERT_TRUE(frame.proba.has_value());
  EXPECT_EQ(sequence.frames[0].proba_labels, (std::vector<int>{0, 1, 2}));
  EXPECT_NEAR(frame.proba->pixel(kW / 2, kH / 2)[2], 0.9f, 1e-3);
  EXPECT_NEAR(frame.proba->pixel(kW / 2, kH / 2)[0], 0.05f, 1e-3);
  for (const auto& record : sequence.frames) {
    EXPECT_TRUE(record.proba_from_label) << "the proba is the label image, one-hot";
    EXPECT_FALSE(record.stamp.has_value()) << "ScanNet frame numbers are not times";
  }
}

TEST(ImportScanNet, ALabelListStillNotesTheOneHotProbabilities) {
  test::TempDir dir;
  writeScanNetScene(dir / "scene", false);
  fs::remove_all(dir / "scene" / "label-filt");
  fs::create_directories(dir / "scene" / "label-filt");
  for (int n = 0; n < 3; ++n) {
    cv::Mat label(2 * kH, 2 * kW, CV_16UC1, cv::Scalar(0));
    label(cv::Rect(0, 8, kW, 2 * kH - 8)).setTo(1);
    cv::imwrite((dir / "scene" / "label-filt" / (std::to_string(n) + ".png")).string(), label);
  }
  ImportOptions options;
  options.labels = LabelSet({{0, "__background__", {0, 0, 0}}, {1, "chair", {128, 0, 0}}});
  const ImportReport report =
      importSource(SourceKind::ScanNet, dir / "scene", dir / "seq", options);
  ASSERT_EQ(report.frames_written, 2u) << report.text();
  EXPECT_TRUE(anyNote(report, "label images became one-hot probabilities")) << report.text();
  for (const auto& record : loadSequence(dir / "seq").frames) EXPECT_TRUE(record.proba_from_label);
}

TEST(ImportScanNet, NamesWithoutTheLabelTableAndMalformedInputs) {
  test::TempDir dir;
  writeScanNetScene(dir / "scene", false);
  ImportOptions options;
  options.frame_step = 2;
  const ImportReport report = importSource(SourceKind::ScanNet, dir / "scene", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 2u);
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_EQ(sequence.labels.at(2).name, "scannet_1234");

  fs::remove(dir / "scene" / "intrinsic" / "intrinsic_depth.txt");
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::ScanNet, dir / "scene", dir / "s2"); }),
                       "intrinsic_depth.txt"));
  writeText(dir / "scene" / "intrinsic" / "intrinsic_depth.txt", "30 0 15.5\n");
  EXPECT_TRUE(contains(errorOf([&] { importSource(SourceKind::ScanNet, dir / "scene", dir / "s2"); }),
                       "3 numbers"));
  writeText(dir / "scene" / "intrinsic" / "intrinsic_depth.txt",
            "30 0 15.5 0\n0 31 11.5 0\n0 0 1 0\n0 0 0 1\n");
  fs::remove(dir / "scene" / "label-filt" / "2.png");
  const ImportReport missing = importSource(SourceKind::ScanNet, dir / "scene", dir / "s3");
  EXPECT_TRUE(anySkipped(missing, "a label image for every frame")) << missing.text();
  // A colour image of another aspect ratio without a colour camera is left out.
  fs::remove(dir / "scene" / "intrinsic" / "intrinsic_color.txt");
  cv::imwrite((dir / "scene" / "color" / "0.jpg").string(), cv::Mat(10, 50, CV_8UC3, cv::Scalar(1, 2, 3)));
  fs::remove_all(dir / "scene" / "label-filt");
  const ImportReport odd = importSource(SourceKind::ScanNet, dir / "scene", dir / "s4");
  EXPECT_TRUE(anyNote(odd, "another aspect ratio")) << odd.text();
}

// ---------------------------------------------------------------------------
// The import cache's entries: what makes a conversion, what it keeps

// `file` written again, as a repair would: its size and time change.
void touchWithNewContent(const fs::path& file) {
  std::ofstream(file, std::ios::app) << ' ';
  fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(2));
}

// A screenshot, a render or notes saved in a recording's folder (or in a
// folder of their own there) are no input of the conversion: the entry is
// reused, not converted again beside it. A frame file of the layout changed
// still is.
TEST(ImportOpen, ImagesTheLayoutDoesNotReadLeaveTheConversionAsItIs) {
  test::TempDir dir;
  const fs::path cache = dir / "cache";
  const auto shots = [](const fs::path& folder) {
    writeColorPng(folder / "screenshot.png", sceneColor(7));
    cv::imwrite((folder / "render.jpg").string(), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
    writeColorPng(folder / "figures" / "map.png", sceneColor(8));
    writeText(folder / "notes.txt", "the light was off in the first frames\n");
  };
  const auto expectReusedThenReconverted = [&](const fs::path& folder, const ImportOptions& options,
                                               const fs::path& frame_file) {
    SCOPED_TRACE(folder.filename().string());
    const OpenedSource first = openSource(folder, options, cache);
    ASSERT_FALSE(first.reused_cache);
    fs::create_directories(folder / "figures");
    shots(folder);
    const OpenedSource again = openSource(folder, options, cache);
    EXPECT_TRUE(again.reused_cache) << "screenshots are not frames of " << folder;
    EXPECT_EQ(again.folder, first.folder);
    touchWithNewContent(frame_file);
    const OpenedSource repaired = openSource(folder, options, cache);
    EXPECT_FALSE(repaired.reused_cache) << frame_file << " changed: converted again";
    EXPECT_NE(repaired.folder, first.folder);
  };
  writeFramesFolder(dir / "frames");
  expectReusedThenReconverted(dir / "frames", {}, dir / "frames" / "frame-000017.depth.png");
  TumFixture tum(dir / "tum");
  expectReusedThenReconverted(tum.dir, {}, tum.dir / "depth" / "100.033000.png");
  // An image in a TUM folder that no list names is not read either.
  writeColorPng(tum.dir / "rgb" / "unlisted.png", sceneColor(9));
  EXPECT_TRUE(openSource(tum.dir, {}, cache).reused_cache);
  writeQuaternionFolder(dir / "room");
  ImportOptions room;
  room.intrinsics = parseIntrinsics("30,31,15.5,11.5");
  expectReusedThenReconverted(dir / "room", room, dir / "room" / "color" / "2.png");
}

// What `labeloctomap import` warns about (here a TUM folder's default
// intrinsics) is kept with the cached conversion, with every note, so that
// the studio says it on every open, not only the first.
TEST(ImportOpen, TheConversionsWarningsAndNotesAreKeptWithItsEntry) {
  test::TempDir dir;
  TumFixture plain(dir / "plain");
  const OpenedSource first = openSource(plain.dir, {}, dir / "cache");
  ASSERT_FALSE(first.reused_cache);
  ASSERT_EQ(first.warnings.size(), 1u) << first.report.text();
  EXPECT_TRUE(contains(first.warnings[0], "the benchmark's default intrinsics fx = fy = 525"))
      << first.warnings[0];
  EXPECT_EQ(first.warnings, first.report.warnings());
  EXPECT_EQ(first.notes, first.report.notes);
  EXPECT_TRUE(fs::exists(first.folder / kImportNotesFile));
  const OpenedSource reused = openSource(plain.dir, {}, dir / "cache");
  ASSERT_TRUE(reused.reused_cache);
  EXPECT_EQ(reused.warnings, first.warnings) << test::slurp(first.folder / kImportNotesFile);
  EXPECT_EQ(reused.notes, first.notes);
  // Plain notes are no warnings: the published calibration of a freiburg1 folder.
  TumFixture calibrated(dir / "rgbd_dataset_freiburg1_desk");
  const OpenedSource known = openSource(calibrated.dir, {}, dir / "cache");
  EXPECT_TRUE(known.warnings.empty()) << known.warnings.front();
  EXPECT_FALSE(known.notes.empty());
  EXPECT_TRUE(openSource(calibrated.dir, {}, dir / "cache").warnings.empty());
}

}  // namespace
}  // namespace lom
