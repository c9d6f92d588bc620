// Scenes of the Princeton Shelf & Tote benchmark (APC 2016) written by the test:
// cam.info.txt, bit-rotated depth, segm ground truth and per-object masks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>

#include "lom/import.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 16;
constexpr int kH = 12;
constexpr int kCrayola = 7;   // crayola_24_ct
constexpr int kExpo = 14;     // expo_dry_erase_board_eraser

// Stored depth: the value in 0.1 mm units rotated left by 3 bits.
std::uint16_t rotateForStorage(std::uint16_t tenths_of_mm) {
  return static_cast<std::uint16_t>(((tenths_of_mm << 3) | (tenths_of_mm >> 13)) & 0xFFFF);
}

std::uint16_t depthTenths(int u, int v) { return static_cast<std::uint16_t>(8000 + 10 * u + 3 * v); }

Eigen::Matrix4d framePose(int frame) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.2 * frame, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.topRightCorner<3, 1>() = Eigen::Vector3d(0.05 * frame, 0.0, -0.3);
  return pose;
}

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string rows(const Eigen::MatrixXd& m) {
  std::ostringstream out;
  out << std::scientific << std::setprecision(8);
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = 0; c < m.cols(); ++c) out << m(r, c) << "\t ";
    out << "\n";
  }
  return out.str();
}

std::string camInfo(int frames, const std::string& objects_line) {
  Eigen::Matrix3d k;
  k << 20, 0, 7.5, 0, 21, 5.5, 0, 0, 1;
  std::ostringstream out;
  out << "# Environment: shelf\n# Bin ID: A\n" << objects_line << "\n\n";
  out << "# Color camera intrinsic matrix\n" << rows(k) << "\n";
  out << "# Depth camera intrinsic matrix\n" << rows(k * 0.9) << "\n";
  out << "# Depth-to-color camera extrinsic matrix\n" << rows(Eigen::Matrix4d::Identity()) << "\n";
  out << "# Bin-to-world extrinsic matrix\n" << rows(Eigen::Matrix4d::Identity()) << "\n";
  for (int f = 0; f < frames; ++f)
    out << "# Camera-to-world extrinsic matrix (frame " << f << ")\n" << rows(framePose(f)) << "\n";
  return out.str();
}

// Two frames; frame 1 has no mask for expo (only crayola).
void writeScene(const fs::path& dir) {
  writeText(dir / "cam.info.txt",
            camInfo(2, "# Objects: [\"crayola_24_ct\",\"expo_dry_erase_board_eraser\"]"));
  fs::create_directories(dir / "segm");
  fs::create_directories(dir / "masks");
  for (int f = 0; f < 2; ++f) {
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06d", f);
    DepthImage stored;
    stored.width = kW;
    stored.height = kH;
    stored.metres.resize(kW * kH);
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) stored.metres[v * kW + u] = rotateForStorage(depthTenths(u, v));
    writeDepthPng(dir / (std::string(base) + ".depth.png"), stored, 1.0);
    ColorImage color;
    color.width = kW;
    color.height = kH;
    color.rgb.assign(kW * kH * 3, static_cast<std::uint8_t>(50 + f));
    writeColorPng(dir / (std::string(base) + ".color.png"), color);
    // Ground truth: left columns crayola, right columns expo, top row background.
    LabelImage segm;
    segm.width = kW;
    segm.height = kH;
    segm.ids.assign(kW * kH, 0);
    for (int v = 1; v < kH; ++v)
      for (int u = 0; u < kW; ++u) segm.ids[v * kW + u] = static_cast<std::uint16_t>(6 * (u < kW / 2 ? kCrayola : kExpo));
    writeLabelPng(dir / "segm" / (std::string(base) + ".segm.png"), segm);
    // Masks: crayola 0.7 / expo 0.5 on the left (sum > 1), 0.2 / 0.1 on the right.
    DepthImage crayola, expo;
    for (DepthImage* m : {&crayola, &expo}) {
      m->width = kW;
      m->height = kH;
      m->metres.resize(kW * kH);
    }
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) {
        crayola.metres[v * kW + u] = u < kW / 2 ? 0.7f : 0.2f;
        expo.metres[v * kW + u] = u < kW / 2 ? 0.5f : 0.1f;
      }
    writeDepthPng(dir / "masks" / (std::string(base) + ".crayola_24_ct.mask.png"), crayola, 1.0 / 65535.0);
    if (f == 0)
      writeDepthPng(dir / "masks" / (std::string(base) + ".expo_dry_erase_board_eraser.mask.png"), expo,
                    1.0 / 65535.0);
  }
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ImportApcShelf, RoundTrip) {
  test::TempDir dir;
  writeScene(dir / "scene-0000");
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report = importSource(std::nullopt, dir / "scene-0000", dir / "seq", options);
  EXPECT_EQ(report.kind, SourceKind::ApcShelf);
  ASSERT_EQ(report.frames_written, 2u) << report.text();

  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.labels, apc2016Labels());
  EXPECT_EQ(sequence.camera.fx, 20.0) << "the colour camera: depth is registered to it";
  EXPECT_EQ(sequence.camera.fy, 21.0);
  EXPECT_DOUBLE_EQ(sequence.camera.depth_scale, 1e-4);
  EXPECT_TRUE(sequence.frames[1].T_world_camera.matrix().isApprox(framePose(1), 1e-7));

  const FrameData frame = loadFrame(sequence, 0);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u)
      ASSERT_NEAR(frame.depth.at(u, v), depthTenths(u, v) / 10000.0, 1e-6) << u << "," << v;
  EXPECT_EQ(sequence.frames[0].proba_labels, (std::vector<int>{0, kCrayola, kExpo}));
  ASSERT_TRUE(frame.proba.has_value());
  const float* left = frame.proba->pixel(2, 5);
  EXPECT_NEAR(left[0], 0.0f, 1e-3) << "masks sum above 1: no background left";
  EXPECT_NEAR(left[1], 0.7f / 1.2f, 1e-3) << "renormalised";
  EXPECT_NEAR(left[2], 0.5f / 1.2f, 1e-3);
  const float* right = frame.proba->pixel(kW - 2, 5);
  EXPECT_NEAR(right[0], 0.7f, 1e-3) << "background is what is left";
  EXPECT_NEAR(right[1], 0.2f, 1e-3);
  EXPECT_NEAR(right[2], 0.1f, 1e-3);
  ASSERT_TRUE(frame.label.has_value()) << "segm is the 2D ground truth";
  EXPECT_EQ(frame.label->at(0, 0), 0);
  EXPECT_EQ(frame.label->at(1, 3), kCrayola);
  EXPECT_EQ(frame.label->at(kW - 1, 3), kExpo);

  // Frame 1 has no expo mask: probability 0 there, noted.
  const FrameData second = loadFrame(sequence, 1);
  EXPECT_NEAR(second.proba->pixel(kW - 2, 5)[2], 0.0f, 1e-6);
  EXPECT_NEAR(second.proba->pixel(kW - 2, 5)[0], 0.8f, 1e-3);
  // The note names the object and the frame.
  bool noted = false;
  for (const auto& n : report.notes)
    noted |= n ==
             "no mask of expo_dry_erase_board_eraser in frame-000001: it gets probability 0 "
             "there";
  EXPECT_TRUE(noted) << report.text();
}

TEST(ImportApcShelf, FramesWithoutMasksUseSegmOneHot) {
  test::TempDir dir;
  writeScene(dir / "scene");
  fs::remove_all(dir / "scene" / "masks");
  const ImportReport report = importSource(SourceKind::ApcShelf, dir / "scene", dir / "seq");
  ASSERT_EQ(report.frames_written, 2u);
  const Sequence sequence = loadSequence(dir / "seq");
  const FrameData frame = loadFrame(sequence, 0);
  ASSERT_TRUE(frame.proba.has_value());
  EXPECT_EQ(sequence.frames[0].proba_labels, (std::vector<int>{0, kCrayola, kExpo}));
  EXPECT_NEAR(frame.proba->pixel(1, 3)[1], 0.9f, 1e-3);
}

TEST(ImportApcShelf, OnlyFramesWithoutMasksAreMarkedProbaFromLabel) {
  test::TempDir dir;
  writeScene(dir / "scene");
  fs::remove(dir / "scene" / "masks" / "frame-000001.crayola_24_ct.mask.png");
  const ImportReport report = importSource(SourceKind::ApcShelf, dir / "scene", dir / "seq");
  ASSERT_EQ(report.frames_written, 2u) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_FALSE(sequence.frames[0].proba_from_label) << "the segmenter's masks";
  EXPECT_TRUE(sequence.frames[1].proba_from_label) << "one-hot from segm";
  bool noted = false;
  for (const auto& n : report.notes)
    noted |= n == "no masks at all in frame-000001: their segm labels became one-hot probabilities";
  EXPECT_TRUE(noted) << report.text();
  for (const auto& n : report.notes)
    EXPECT_EQ(n.find("no mask of"), std::string::npos) << "frame 1 has no masks at all: " << n;
  for (const auto& frame : sequence.frames)
    EXPECT_FALSE(frame.stamp.has_value()) << "frame numbers are not times";
}

TEST(ImportApcShelf, MalformedInputs) {
  test::TempDir dir;
  writeScene(dir / "scene");
  auto run = [&] { (void)importSource(SourceKind::ApcShelf, dir / "scene", dir / "seq"); };

  writeText(dir / "scene" / "cam.info.txt", camInfo(2, "# Objects: [\"crayola_24_ct\",\"teddy\"]"));
  std::string error = errorOf(run);
  EXPECT_NE(error.find("names of the 39 APC 2016 objects, found 'teddy'"), std::string::npos) << error;

  writeText(dir / "scene" / "cam.info.txt", camInfo(2, "# Bin ID: A"));
  error = errorOf(run);
  EXPECT_NE(error.find("# Objects"), std::string::npos) << error;

  std::string text = camInfo(2, "# Objects: ['crayola_24_ct']");
  text += "1 2 3\n";  // a stray row
  writeText(dir / "scene" / "cam.info.txt", text);
  error = errorOf(run);
  EXPECT_NE(error.find("50 + 16 N numbers"), std::string::npos) << error;
  EXPECT_NE(error.find("found 85 numbers"), std::string::npos) << error;

  // One pose for two frames: the second is skipped.
  writeText(dir / "scene" / "cam.info.txt", camInfo(1, "# Objects: ['crayola_24_ct']"));
  const ImportReport report = importSource(SourceKind::ApcShelf, dir / "scene", dir / "seq");
  EXPECT_EQ(report.frames_written, 1u);
  ASSERT_EQ(report.skipped.size(), 1u);
  EXPECT_NE(report.skipped[0].reason.find("no camera pose"), std::string::npos);
  EXPECT_EQ(loadSequence(dir / "seq").frames[0].proba_labels, (std::vector<int>{0, kCrayola}));
}

}  // namespace
}  // namespace lom
