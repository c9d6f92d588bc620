// Exact intersection volumes and IoU of oriented boxes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "lom/iou.hpp"

namespace {

using lom::OrientedBox;

// Sums of a few dozen tetrahedra in double precision: far below this.
constexpr double kExact = 1e-12;

OrientedBox box(Eigen::Vector3d center, Eigen::Vector3d size,
                Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity()) {
  OrientedBox b;
  b.center = center;
  b.size = size;
  b.rotation = rotation;
  return b;
}

Eigen::Quaterniond aboutZ(double radians) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitZ()));
}

TEST(IouBoxes, IdenticalBoxesGiveOne) {
  const Eigen::Quaterniond tilted(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const OrientedBox a = box({0.3, -0.2, 1.1}, {0.1, 0.25, 0.05}, tilted);
  EXPECT_NEAR(lom::boxIoU(a, a), 1.0, kExact);
  EXPECT_NEAR(lom::intersectionVolume(a, a), a.volume(), kExact * a.volume());
  const OrientedBox unit = box({0, 0, 0}, {1, 1, 1});
  EXPECT_NEAR(lom::boxIoU(unit, unit), 1.0, kExact);
}

TEST(IouBoxes, DisjointBoxesGiveZero) {
  const OrientedBox a = box({0, 0, 0}, {1, 1, 1});
  EXPECT_EQ(lom::boxIoU(a, box({3, 0, 0}, {1, 1, 1})), 0.0);
  // Bounding spheres overlap, yet a rotated box only nearly touches: separated by 0.01 along x.
  const double reach = 0.5 * std::sqrt(2.0);
  EXPECT_NEAR(lom::boxIoU(a, box({0.5 + reach + 0.01, 0, 0}, {1, 1, 1}, aboutZ(M_PI / 4))), 0.0, kExact);
  // Touching faces share no volume.
  EXPECT_NEAR(lom::boxIoU(a, box({1, 0, 0}, {1, 1, 1})), 0.0, kExact);
}

TEST(IouBoxes, HalfOverlapGivesOneThird) {
  // Intersection 0.5, union 1.5.
  const OrientedBox a = box({0, 0, 0}, {1, 1, 1});
  const OrientedBox b = box({0.5, 0, 0}, {1, 1, 1});
  EXPECT_NEAR(lom::intersectionVolume(a, b), 0.5, kExact);
  EXPECT_NEAR(lom::boxIoU(a, b), 1.0 / 3.0, kExact);
  EXPECT_NEAR(lom::boxIoU(b, a), 1.0 / 3.0, kExact);
}

TEST(IouBoxes, CubeRotated45DegreesAboutZ) {
  // The cross-section is the unit square minus four corner triangles of legs
  // sqrt(2)/2 - 1/2: a regular octagon of area 2 sqrt(2) - 2; IoU = 1 / sqrt(2).
  const OrientedBox a = box({0, 0, 0}, {1, 1, 1});
  const OrientedBox b = box({0, 0, 0}, {1, 1, 1}, aboutZ(M_PI / 4));
  const double octagon = 2.0 * std::sqrt(2.0) - 2.0;
  EXPECT_NEAR(lom::intersectionVolume(a, b), octagon, kExact);
  EXPECT_NEAR(lom::boxIoU(a, b), octagon / (2.0 - octagon), kExact);
  EXPECT_NEAR(lom::boxIoU(a, b), 1.0 / std::sqrt(2.0), kExact);
}

TEST(IouBoxes, ContainedBoxGivesVolumeRatio) {
  const OrientedBox outer = box({1, 2, 3}, {2, 3, 4}, aboutZ(0.3));
  const OrientedBox inner = box({1.1, 2.0, 3.2}, {0.5, 0.4, 0.3}, aboutZ(1.0));
  EXPECT_NEAR(lom::boxIoU(outer, inner), inner.volume() / outer.volume(), kExact);
}

TEST(IouBoxes, GeneralRotationsAgreeWithMonteCarlo) {
  const OrientedBox a =
      box({0.02, 0.01, -0.03}, {0.3, 0.2, 0.15}, Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 1, 0).normalized())));
  const OrientedBox b =
      box({0.07, -0.04, 0.02}, {0.25, 0.3, 0.1}, Eigen::Quaterniond(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0, 1, 2).normalized())));
  const double exact = lom::intersectionVolume(a, b);
  ASSERT_GT(exact, 0.0);
  ASSERT_LT(exact, std::min(a.volume(), b.volume()));
  EXPECT_NEAR(lom::intersectionVolume(b, a), exact, kExact);

  // Uniform samples in a: the fraction inside b estimates exact / volume(a).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  constexpr int kSamples = 1000000;
  int inside = 0;
  for (int i = 0; i < kSamples; ++i) {
    const Eigen::Vector3d local(unit(rng) * a.size.x(), unit(rng) * a.size.y(), unit(rng) * a.size.z());
    inside += b.contains(a.center + a.rotation * local);
  }
  const double fraction = static_cast<double>(inside) / kSamples;
  const double standard_error = std::sqrt(fraction * (1 - fraction) / kSamples) * a.volume();
  // Five standard errors: a correct implementation fails this with probability < 1e-6.
  EXPECT_NEAR(exact, fraction * a.volume(), 5 * standard_error);
}

TEST(IouPolyhedron, DiagonalCutHalvesACube) {
  const lom::ConvexPolyhedron cube = lom::boxPolyhedron(box({0, 0, 0}, {2, 2, 2}));
  EXPECT_NEAR(lom::polyhedronVolume(cube), 8.0, kExact);
  const auto half = lom::clipByHalfSpace(cube, Eigen::Vector3d(1, 1, 1).normalized(), 0.0);
  EXPECT_NEAR(lom::polyhedronVolume(half), 4.0, kExact);
  // Cutting off one corner: a tetrahedron of legs 1 (volume 1/6) goes.
  const auto corner = lom::clipByHalfSpace(cube, Eigen::Vector3d(1, 1, 1).normalized(), 2.0 / std::sqrt(3.0));
  EXPECT_NEAR(lom::polyhedronVolume(corner), 8.0 - 1.0 / 6.0, kExact);
  // A plane through a face keeps the whole cube; one beyond it keeps nothing.
  EXPECT_NEAR(lom::polyhedronVolume(lom::clipByHalfSpace(cube, Eigen::Vector3d::UnitX(), 1.0)), 8.0, kExact);
  EXPECT_NEAR(lom::polyhedronVolume(lom::clipByHalfSpace(cube, -Eigen::Vector3d::UnitX(), -1.0)), 0.0, kExact);
}

}  // namespace
