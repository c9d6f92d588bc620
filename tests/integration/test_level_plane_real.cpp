// The Kinect room's level plane is its floor, at the room's own range and at
// long range (depths to 10 m, whose floor is a few centimetres thick with
// depth noise): the map's up is the floor's normal as fitted to the floor's
// depth pixels themselves, not the cameras' mean up, 17 degrees off. Skipped
// with a message when the recording is absent.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "lom/fusion.hpp"
#include "lom/import.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

double degreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// An image rectangle [u0, u1) x [v0, v1) of a frame.
struct FloorPixels {
  size_t frame;
  int u0, v0, u1, v1;
};

// Carpet in front of the camera and nothing else, chosen by eye in the colour
// images color/1.png, 3.png and 5.png (between the sideboard and the chairs,
// in front of the armchair, in front of the armchair's legs).
const FloorPixels kFloor[] = {
    {0, 60, 340, 200, 470}, {2, 250, 330, 480, 470}, {4, 200, 370, 620, 470}};

struct FittedPlane {
  Eigen::Vector3d normal;
  size_t points = 0;
  double rms = 0.0;  // metres
};

// The floor's plane in the world: least squares over the depth pixels of
// kFloor, again over the points within 2.5 rms of the fit (at least 1 cm), so
// that stray depths at the rectangles' edges do not tilt it.
FittedPlane fitFloor(const Sequence& sequence) {
  std::vector<Eigen::Vector3d> points_world;
  for (const FloorPixels& pixels : kFloor) {
    const FrameData data = loadFrame(sequence, pixels.frame);
    const CameraIntrinsics& camera = sequence.cameraOf(pixels.frame);
    const Eigen::Isometry3d& T_world_camera = sequence.frames[pixels.frame].T_world_camera;
    for (int v = pixels.v0; v < pixels.v1; ++v)
      for (int u = pixels.u0; u < pixels.u1; ++u)
        if (const float z = data.depth.at(u, v); z > 0.0f)
          points_world.push_back(T_world_camera * camera.backProject(u, v, z));
  }
  FittedPlane plane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double band = std::numeric_limits<double>::infinity();
  for (int round = 0; round < 8; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    size_t n = 0;
    const auto within = [&](const Eigen::Vector3d& p) {
      return round == 0 || std::abs(plane.normal.dot(p - point)) <= band;
    };
    for (const Eigen::Vector3d& p : points_world)
      if (within(p)) {
        mean += p;
        ++n;
      }
    mean /= static_cast<double>(n);
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& p : points_world)
      if (within(p)) scatter += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    plane = {solver.eigenvectors().col(0), n, std::sqrt(solver.eigenvalues()(0) / n)};
    point = mean;
    band = std::max(0.01, 2.5 * plane.rms);
  }
  return plane;
}

TEST(LevelPlaneRealData, KinectRoomIsLevelledByItsFloor) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  test::TempDir dir;
  ImportOptions import;
  import.intrinsics = parseIntrinsics("518,519,325.5,253.5");
  (void)importSource(SourceKind::Quaternion, test::sharedDataDir() / "kinect-room-5", dir / "seq",
                     import);
  const Sequence sequence = loadSequence(dir / "seq");
  FittedPlane floor = fitFloor(sequence);
  ASSERT_GT(floor.points, 10000u);
  EXPECT_LT(floor.rms, 0.02);  // a floor, and the three views agree on it

  for (const double max_range : {4.0, 10.0}) {
    SCOPED_TRACE("max range " + std::to_string(max_range));
    FusionOptions options;
    options.map.resolution = 0.02;
    options.map.max_range = max_range;
    const LabelMap map = fuseSequence(sequence, options);
    const auto cameras_up = map.camerasUp();
    ASSERT_TRUE(cameras_up);
    if (floor.normal.dot(*cameras_up) < 0.0) floor.normal = -floor.normal;
    // The cameras are pitched down: their mean up is far from the floor's.
    EXPECT_GT(degreesBetween(*cameras_up, floor.normal), 15.0);
    const auto plane = map.levelPlane();
    ASSERT_TRUE(plane) << "no level plane: up would be the cameras' mean up, "
                       << degreesBetween(*cameras_up, floor.normal) << " degrees off the floor";
    std::cout << "[ level     ] kinect-room-5 at 2 cm, max range " << max_range
              << " m: level plane " << degreesBetween(plane->normal, floor.normal)
              << " deg from the floor's pixels (" << plane->voxels << " of " << plane->sampled
              << " sampled voxels), cameras' mean up " << degreesBetween(*cameras_up, floor.normal)
              << " deg\n";
    // The three views' own floors are up to 2.7 degrees apart (their poses
    // disagree a little): within 2 degrees of their joint fit is level.
    EXPECT_LT(degreesBetween(plane->normal, floor.normal), 2.0) << plane->normal.transpose();
    EXPECT_EQ(map.upDirection().value_or(Eigen::Vector3d::Zero()), plane->normal);
  }
}

}  // namespace
}  // namespace lom
