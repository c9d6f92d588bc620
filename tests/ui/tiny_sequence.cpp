#include "tiny_sequence.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "lom/sequence.hpp"

namespace lom::test {

namespace {

bool inSquare(int u, int v) { return u >= 60 && u < 100 && v >= 40 && v < 80; }
bool inCup(int u, int v) { return u >= 110 && u < 130 && v >= 85 && v < 105; }

DepthImage planeDepth(int frame) {
  DepthImage depth;
  depth.width = kTinyWidth;
  depth.height = kTinyHeight;
  depth.metres.resize(static_cast<size_t>(kTinyWidth) * kTinyHeight);
  // A different number of missing columns per frame, so point counts differ.
  const int missing_columns = 8 * (frame + 1);
  for (int v = 0; v < kTinyHeight; ++v)
    for (int u = 0; u < kTinyWidth; ++u) {
      float z = 0.6f + 0.002f * v + 0.001f * u;
      if (inSquare(u, v)) z -= 0.05f;
      if (u < missing_columns) z = 0.f;
      depth.metres[static_cast<size_t>(v) * kTinyWidth + u] = z;
    }
  return depth;
}

LabelImage labels() {
  LabelImage label;
  label.width = kTinyWidth;
  label.height = kTinyHeight;
  label.ids.resize(static_cast<size_t>(kTinyWidth) * kTinyHeight, 0);
  for (int v = 0; v < kTinyHeight; ++v)
    for (int u = 0; u < kTinyWidth; ++u)
      label.ids[static_cast<size_t>(v) * kTinyWidth + u] =
          inSquare(u, v) ? kSquareLabel : (inCup(u, v) ? 2 : 0);
  return label;
}

ColorImage shelfColor() {
  ColorImage color;
  color.width = kTinyWidth;
  color.height = kTinyHeight;
  color.rgb.resize(static_cast<size_t>(kTinyWidth) * kTinyHeight * 3);
  for (int v = 0; v < kTinyHeight; ++v)
    for (int u = 0; u < kTinyWidth; ++u) {
      auto* pixel = &color.rgb[(static_cast<size_t>(v) * kTinyWidth + u) * 3];
      pixel[0] = static_cast<std::uint8_t>(120 + u / 2);
      pixel[1] = static_cast<std::uint8_t>(100 + v / 2);
      pixel[2] = 80;
    }
  return color;
}

}  // namespace

TinySequence writeTinySequence(const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  Sequence sequence;
  sequence.root = folder;
  sequence.labels = LabelSet({{0, "__background__", {0, 0, 0}},
                              {kSquareLabel, "square_box", kSquareColor},
                              {2, "blue_cup", {40, 90, 220}}});
  sequence.camera = CameraIntrinsics{kTinyWidth, kTinyHeight, 150.0, 150.0, 80.0, 60.0, 0.001};

  TinySequence tiny{folder, {}};
  for (int i = 0; i < kTinyFrames; ++i) {
    const std::string n = std::to_string(i);
    FrameRecord frame;
    frame.stamp = 0.1 * i;
    frame.T_world_camera = Eigen::Isometry3d::Identity();
    frame.T_world_camera.translate(Eigen::Vector3d(0.05 * i, 0.0, 0.0));
    frame.T_world_camera.rotate(Eigen::AngleAxisd(-0.08 * i, Eigen::Vector3d::UnitY()));
    frame.depth = "depth_" + n + ".png";
    frame.color = "color_" + n + ".png";
    frame.label = "label_" + n + ".png";
    sequence.frames.push_back(frame);

    tiny.depths.push_back(planeDepth(i));
    writeDepthPng(folder / frame.depth, tiny.depths.back(), sequence.camera.depth_scale);
    writeColorPng(folder / frame.color, shelfColor());
    writeLabelPng(folder / frame.label, labels());
  }
  saveSequence(sequence, folder);
  return tiny;
}

void writeFramesLayout(const TinySequence& tiny, const std::filesystem::path& folder) {
  const Sequence sequence = loadSequence(tiny.folder);
  std::filesystem::create_directories(folder);
  const CameraIntrinsics& camera = sequence.camera;
  std::ofstream(folder / "intrinsics.K.txt")
      << camera.fx << " 0 " << camera.cx << "\n0 " << camera.fy << " " << camera.cy << "\n0 0 1\n";
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    char stem[32];
    std::snprintf(stem, sizeof(stem), "frame-%06zu", i);
    const FrameData frame = loadFrame(sequence, i);
    writeDepthPng(folder / (std::string(stem) + ".depth.png"), frame.depth, 0.001);
    if (!frame.color) throw std::runtime_error("the tiny sequence has no colour");
    writeColorPng(folder / (std::string(stem) + ".color.png"), *frame.color);
    std::ofstream pose(folder / (std::string(stem) + ".pose.txt"));
    pose.precision(17);
    const Eigen::Matrix4d m = sequence.frames[i].T_world_camera.matrix();
    for (int r = 0; r < 4; ++r)
      pose << m(r, 0) << " " << m(r, 1) << " " << m(r, 2) << " " << m(r, 3) << "\n";
  }
}

size_t countValidDepth(const DepthImage& depth) {
  size_t valid = 0;
  for (float z : depth.metres)
    if (std::isfinite(z) && z > 0.f) ++valid;
  return valid;
}

}  // namespace lom::test
