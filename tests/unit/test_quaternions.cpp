// Quaternions at any finite, non-zero scale are normalised (annotations,
// imported poses) without underflow or overflow.
#include <gtest/gtest.h>

#include <cmath>

#include "lom/annotations.hpp"
#include "lom/geometry.hpp"
#include "test_input_helpers.hpp"

namespace {

using lom::test::errorOf;
using lom::test::writeText;

TEST(QuaternionTest, TinyAndHugeComponentsAreNormalisedNotRefused) {
  const auto tiny = lom::unitQuaternion({1e-200, 0, 0, 1e-200});
  ASSERT_TRUE(tiny.has_value());
  EXPECT_NEAR(tiny->x(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(tiny->w(), std::sqrt(0.5), 1e-15);
  const auto huge = lom::unitQuaternion({1e300, 1e300, 0, 0});
  ASSERT_TRUE(huge.has_value());
  EXPECT_NEAR(huge->x(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(huge->y(), std::sqrt(0.5), 1e-15);
  const auto subnormal = lom::unitQuaternion({0, 0, 4e-320, 0});
  ASSERT_TRUE(subnormal.has_value());
  EXPECT_EQ(subnormal->z(), 1.0);
  EXPECT_FALSE(lom::unitQuaternion({0, 0, 0, 0}).has_value());
  EXPECT_FALSE(lom::unitQuaternion({0, NAN, 0, 1}).has_value());
  EXPECT_FALSE(lom::unitQuaternion({0, 0, INFINITY, 1}).has_value());
}

TEST(QuaternionTest, AnnotationsAcceptAnyFiniteNonZeroScale) {
  lom::test::TempDir dir;
  writeText(
      dir / "boxes.json",
      R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
      R"({"label": 1, "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [1e-200, 0, 0, 1e-200]},)"
      R"({"label": 2, "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [1e300, 1e300, 0, 0]}]})");
  const lom::Annotations annotations = lom::loadAnnotations(dir / "boxes.json");
  ASSERT_EQ(annotations.boxes.size(), 2u);
  EXPECT_NEAR(annotations.boxes[0].box.rotation.norm(), 1.0, 1e-15);
  EXPECT_NEAR(annotations.boxes[0].box.rotation.x(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(annotations.boxes[1].box.rotation.y(), std::sqrt(0.5), 1e-15);

  writeText(dir / "zero.json",
            R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
            R"({"label": 1, "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [0, 0, 0, 0]}]})");
  const lom::Problem problem = errorOf([&] { (void)lom::loadAnnotations(dir / "zero.json"); });
  EXPECT_EQ(problem.field, "boxes[0].rotation");
}

}  // namespace
