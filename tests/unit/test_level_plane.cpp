// The map's up levelled by its largest plane near the cameras' up: a floor
// seen by cameras pitched towards it gives the floor's normal, whatever the
// clutter on it; walls, scattered voxels or too few voxels give no level.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "lom/level_plane.hpp"

namespace {

constexpr double kResolution = 0.02;

double degreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// Voxel centres (snapped to the grid) of a square of `side` metres through
// `origin`, spanned by the unit vectors `a` and `b`.
void addSquare(std::vector<Eigen::Vector3d>& centres, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& a, const Eigen::Vector3d& b, double side) {
  const int steps = static_cast<int>(side / (0.5 * kResolution));
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < steps; ++j) {
      const Eigen::Vector3d p = origin + (i * a + j * b) * 0.5 * kResolution;
      centres.push_back(((p / kResolution).array().floor() + 0.5).matrix() * kResolution);
    }
}

// A room whose floor has normal `floor_up`: the floor, two walls and clutter.
std::vector<Eigen::Vector3d> room(const Eigen::Vector3d& floor_up) {
  const Eigen::Vector3d up = floor_up.normalized();
  const Eigen::Vector3d across = up.unitOrthogonal();
  const Eigen::Vector3d along = up.cross(across);
  std::vector<Eigen::Vector3d> centres;
  addSquare(centres, Eigen::Vector3d::Zero(), across, along, 3.0);  // floor
  addSquare(centres, Eigen::Vector3d::Zero(), across, up, 2.5);     // walls
  addSquare(centres, Eigen::Vector3d::Zero(), along, up, 2.5);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(0.0, 2.5);
  for (int i = 0; i < 20000; ++i)  // furniture, noise
    centres.push_back(coordinate(random) * across + coordinate(random) * along +
                      coordinate(random) * up);
  std::shuffle(centres.begin(), centres.end(), random);
  return centres;
}

TEST(LevelPlaneTest, AFloorLevelsTheCamerasTiltedUp) {
  // The floor's normal, and the cameras' mean up tilted 20 degrees from it
  // (handheld cameras pitched down towards the room).
  const Eigen::Vector3d floor_up = Eigen::Vector3d(0.1, -0.95, -0.3).normalized();
  const Eigen::Vector3d cameras_up =
      Eigen::AngleAxisd(20.0 * M_PI / 180.0, floor_up.unitOrthogonal()) * floor_up;
  const std::vector<Eigen::Vector3d> centres = room(floor_up);
  const auto plane = lom::findLevelPlane(centres, cameras_up, kResolution);
  ASSERT_TRUE(plane);
  EXPECT_LT(degreesBetween(plane->normal, floor_up), 0.5) << plane->normal.transpose();
  EXPECT_NEAR(plane->normal.norm(), 1.0, 1e-12);
  EXPECT_EQ(plane->sampled, 4096u);
  EXPECT_GT(plane->voxels, plane->sampled / 10);
  // The normal is on the side of the cameras' up, and the search repeats exactly.
  const auto flipped = lom::findLevelPlane(centres, -cameras_up, kResolution);
  ASSERT_TRUE(flipped);
  EXPECT_LT(degreesBetween(flipped->normal, -floor_up), 0.5);
  const auto again = lom::findLevelPlane(centres, cameras_up, kResolution);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->normal, plane->normal);
  EXPECT_EQ(again->voxels, plane->voxels);
}

TEST(LevelPlaneTest, NoLevelWithoutAPlaneNearTheCamerasUp) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // Only walls (their normals are 90 degrees from up).
  std::vector<Eigen::Vector3d> walls;
  addSquare(walls, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), up, 2.0);
  addSquare(walls, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), up, 2.0);
  EXPECT_FALSE(lom::findLevelPlane(walls, up, kResolution));
  // A floor tilted more than kMaxLevelTiltDegrees from the cameras' up.
  const Eigen::Vector3d steep = Eigen::AngleAxisd((lom::kMaxLevelTiltDegrees + 10.0) * M_PI / 180.0,
                                                  Eigen::Vector3d::UnitX()) *
                                up;
  EXPECT_FALSE(lom::findLevelPlane(room(steep), up, kResolution));
  // Scattered voxels.
  std::vector<Eigen::Vector3d> scattered;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(0.0, 3.0);
  for (int i = 0; i < 5000; ++i)
    scattered.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  EXPECT_FALSE(lom::findLevelPlane(scattered, up, kResolution));
  // Too few voxels, no direction, no resolution.
  std::vector<Eigen::Vector3d> patch;
  addSquare(patch, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
            0.1);
  EXPECT_FALSE(lom::findLevelPlane(patch, up, kResolution));
  const std::vector<Eigen::Vector3d> floor = room(up);
  EXPECT_FALSE(lom::findLevelPlane(floor, Eigen::Vector3d::Zero(), kResolution));
  EXPECT_FALSE(lom::findLevelPlane(floor, up, 0.0));
  EXPECT_TRUE(lom::findLevelPlane(floor, up, kResolution));
}

}  // namespace
