// Pick planning on generated scenes with known layouts: occluders, their order,
// grasps, placements, approach directions and the plan.json contract.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "lom/error.hpp"
#include "lom/planning.hpp"

namespace {

using lom::LabelMap;
using lom::OrientedBox;
using lom::PickPlan;
using lom::StepAction;

constexpr int kTarget = 19;  // i_am_a_bunny_book
const Eigen::Vector3d kIntoTheBin = Eigen::Vector3d::UnitX();

OrientedBox aabb(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  OrientedBox box;
  box.center = 0.5 * (low + high);
  box.size = high - low;
  return box;
}

struct Item {
  int label;
  Eigen::Vector3d low, high;
};

// A bin seen along +x: the target at the back (x 0.30..0.40), others as given.
LabelMap scene(const std::vector<Item>& items, bool with_target = true) {
  LabelMap map(lom::apc2016Labels());
  if (with_target) lom::rasterizeBox(map, aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.10}), kTarget);
  for (const auto& item : items) lom::rasterizeBox(map, aabb(item.low, item.high), item.label);
  return map;
}

lom::PlanOptions along(const Eigen::Vector3d& approach) {
  lom::PlanOptions options;
  options.approach = approach;
  options.objects.map_file = "/data/bin.ot";
  return options;
}

std::vector<int> removedLabels(const PickPlan& plan) {
  std::vector<int> labels;
  for (const auto& step : plan.steps)
    if (step.action == StepAction::Remove) labels.push_back(plan.objects[step.object].label);
  return labels;
}

int pickedLabel(const PickPlan& plan) {
  EXPECT_FALSE(plan.steps.empty());
  EXPECT_EQ(plan.steps.back().action, StepAction::Pick);
  return plan.objects[plan.steps.back().object].label;
}

lom::ObjectInstance objectWithBox(const OrientedBox& box, const Eigen::Vector3d& centroid) {
  lom::ObjectInstance object;
  object.label = 8;
  object.box = box;
  object.centroid = centroid;
  return object;
}

TEST(Planning, ObjectInFrontOfTheTargetIsRemovedFirst) {
  const LabelMap map = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}}});
  const PickPlan plan = lom::planPick(map, kTarget, along(kIntoTheBin));
  ASSERT_EQ(plan.steps.size(), 2u);
  EXPECT_EQ(removedLabels(plan), std::vector<int>{8});
  EXPECT_EQ(pickedLabel(plan), kTarget);
  ASSERT_EQ(plan.occluders.size(), 1u);
  EXPECT_EQ(plan.roles[plan.occluders[0]], lom::ObjectRole::Occluder);
  EXPECT_EQ(plan.roles[plan.target], lom::ObjectRole::Target);
  EXPECT_NEAR(plan.depth[plan.occluders[0]], 0.14 - 0.35, 1e-9);
  EXPECT_EQ(plan.target_name, "i_am_a_bunny_book");
  EXPECT_EQ(plan.approach_source, lom::ApproachSource::Given);
}

TEST(Planning, ObjectBehindTheTargetIsNotAnOccluder) {
  const LabelMap map = scene({{8, {0.45, -0.05, 0.0}, {0.55, 0.05, 0.10}}});
  const PickPlan plan = lom::planPick(map, kTarget, along(kIntoTheBin));
  EXPECT_TRUE(plan.occluders.empty());
  ASSERT_EQ(plan.steps.size(), 1u);
  EXPECT_EQ(pickedLabel(plan), kTarget);
  EXPECT_GT(plan.depth[0], 0.0);
  EXPECT_EQ(plan.roles[0], lom::ObjectRole::Other);
}

TEST(Planning, ObjectBesideTheTargetIsNotAnOccluder) {
  const LabelMap map = scene({
      {8, {0.10, 0.10, 0.0}, {0.20, 0.20, 0.10}},    // in front, but to the side: nothing hidden
      {13, {0.25, 0.05, 0.0}, {0.35, 0.15, 0.10}},   // in front and touching the target's side
      {30, {0.30, -0.16, 0.0}, {0.40, -0.06, 0.10}}, // right beside, at the same depth
  });
  const PickPlan plan = lom::planPick(map, kTarget, along(kIntoTheBin));
  EXPECT_EQ(plan.objects.size(), 4u);
  EXPECT_TRUE(plan.occluders.empty()) << plan.objects[plan.occluders.at(0)].label;
  EXPECT_EQ(plan.steps.size(), 1u);

  // Shifted so that it hides 2 cm of the target: now it is in the way.
  const LabelMap overlapping = scene({{13, {0.20, 0.03, 0.0}, {0.28, 0.13, 0.10}}});
  EXPECT_EQ(removedLabels(lom::planPick(overlapping, kTarget, along(kIntoTheBin))), std::vector<int>{13});
}

TEST(Planning, TwoOccludersComeOutFrontMostFirst) {
  // The front-most object has the higher label, so the order cannot come from the labels.
  const LabelMap map = scene({{8, {0.16, -0.05, 0.0}, {0.24, 0.05, 0.09}},
                              {30, {0.02, -0.03, 0.0}, {0.08, 0.03, 0.12}}});
  const PickPlan plan = lom::planPick(map, kTarget, along(kIntoTheBin));
  EXPECT_EQ(removedLabels(plan), (std::vector<int>{30, 8}));
  EXPECT_EQ(pickedLabel(plan), kTarget);
  EXPECT_LT(plan.depth[plan.steps[0].object], plan.depth[plan.steps[1].object]);

  // Seen from the back of the bin, both are behind the target.
  const PickPlan reverse = lom::planPick(map, kTarget, along(-kIntoTheBin));
  EXPECT_TRUE(reverse.occluders.empty());
}

// A tall object beside a flat one reaches nearer the camera, into the flat
// one's path, while its centroid lies further back: it is removed first (the
// centroids put the flat one first, which the robot cannot take yet).
TEST(Planning, AnOccluderInAnotherOccludersPathIsRemovedBeforeIt) {
  const Eigen::Vector3d d = Eigen::Vector3d::UnitX();
  const auto box = [](Eigen::Vector3d centre, Eigen::Vector3d size) {
    OrientedBox b;
    b.center = centre;
    b.size = size;
    return b;
  };
  std::vector<lom::ObjectInstance> objects = {
      objectWithBox(box({0.60, 0.0, 0.0}, {0.10, 0.10, 0.10}), {0.60, 0.0, 0.0}),  // target
      objectWithBox(box({0.30, 0.0, 0.0}, {0.04, 0.10, 0.10}), {0.30, 0.0, 0.0}),  // flat
      objectWithBox(box({0.31, 0.0, 0.2}, {0.20, 0.10, 0.50}), {0.31, 0.0, 0.2}),  // tall
  };
  for (int k = 0; k < 3; ++k) objects[static_cast<size_t>(k)].label = 10 + k;
  ASSERT_TRUE(lom::boxInPathOf(objects[2].box, objects[1].box, d));
  ASSERT_FALSE(lom::boxInPathOf(objects[1].box, objects[2].box, d));
  EXPECT_EQ(lom::findOccluders(objects, 0, d), (std::vector<size_t>{2, 1}));

  // Without a removal in the path, front-most first by centroid as before.
  std::vector<size_t> apart = {2, 1};
  objects[2].box.center.z() = 0.6;  // above the flat one's path now
  objects[2].centroid.z() = 0.6;
  lom::orderForRemoval(apart, objects, d);
  EXPECT_EQ(apart, (std::vector<size_t>{1, 2}));
}

// The paper's rule (section V.C): every object whose centroid is nearer the
// cameras than the target's, beside the path or not; objects behind stay.
TEST(Planning, TheCentroidRuleRemovesEveryObjectInFrontOfTheTarget) {
  const Eigen::Vector3d d = Eigen::Vector3d::UnitX();
  const auto object = [](Eigen::Vector3d centre, int label) {
    OrientedBox b;
    b.center = centre;
    b.size = Eigen::Vector3d(0.06, 0.06, 0.06);
    lom::ObjectInstance o = objectWithBox(b, centre);
    o.label = label;
    return o;
  };
  const std::vector<lom::ObjectInstance> objects = {
      object({0.50, 0.0, 0.0}, 19),   // target
      object({0.30, 0.0, 0.0}, 8),    // in front, in the path
      object({0.40, 0.30, 0.0}, 30),  // in front, 30 cm to the side
      object({0.70, 0.0, 0.0}, 12),   // behind
  };
  EXPECT_EQ(lom::findOccluders(objects, 0, d), (std::vector<size_t>{1}));
  EXPECT_EQ(lom::findOccluders(objects, 0, d, 0.0, lom::OccluderRule::Centroid),
            (std::vector<size_t>{1, 2}));  // front-most first
  EXPECT_TRUE(lom::findOccluders(objects, 0, -d, 0.0, lom::OccluderRule::Centroid) ==
              std::vector<size_t>{3});
  EXPECT_STREQ(lom::occluderRuleName(lom::OccluderRule::Centroid), "centroid");
  EXPECT_STREQ(lom::occluderRuleName(lom::OccluderRule::Path), "path");
}

TEST(Planning, StraySpeckOfTheTargetLabelDoesNotMoveTheTargetBox) {
  const LabelMap clean = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}}});
  const PickPlan expected = lom::planPick(clean, kTarget, along(kIntoTheBin));
  LabelMap map = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}}});
  // Two misread voxels far in front and to the side of the bin.
  lom::rasterizeBox(map, aabb({-0.40, 0.35, 0.20}, {-0.38, 0.36, 0.21}), kTarget);

  const PickPlan plan = lom::planPick(map, kTarget, along(kIntoTheBin));
  const lom::ObjectInstance& target = plan.objects[plan.target];
  const lom::ObjectInstance& clean_target = expected.objects[expected.target];
  EXPECT_TRUE(target.box.center.isApprox(clean_target.box.center, 1e-12)) << target.box.center.transpose();
  EXPECT_TRUE(target.box.size.isApprox(clean_target.box.size, 1e-12)) << target.box.size.transpose();
  EXPECT_TRUE(target.centroid.isApprox(Eigen::Vector3d(0.35, 0.0, 0.05), 1e-9));
  EXPECT_EQ(target.voxelCount(), clean_target.voxelCount());
  EXPECT_EQ(target.label_voxels, clean_target.voxelCount() + 2);
  EXPECT_EQ(removedLabels(plan), std::vector<int>{8});
  EXPECT_TRUE(plan.steps.back().grasp.position.isApprox(expected.steps.back().grasp.position, 1e-12));
}

TEST(Planning, DiagonalApproachUsesTheBoxesAcrossIt) {
  const Eigen::Vector3d diagonal = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  // Target cube at (0.30, 0.30); one cube on the diagonal in front of it, one in front but off it.
  LabelMap map(lom::apc2016Labels());
  lom::rasterizeBox(map, aabb({0.25, 0.25, 0.0}, {0.35, 0.35, 0.10}), kTarget);
  lom::rasterizeBox(map, aabb({0.10, 0.10, 0.0}, {0.20, 0.20, 0.10}), 8);
  lom::rasterizeBox(map, aabb({0.07, 0.37, 0.0}, {0.13, 0.43, 0.06}), 13);
  const PickPlan plan = lom::planPick(map, kTarget, along(diagonal));
  EXPECT_EQ(removedLabels(plan), std::vector<int>{8});
  EXPECT_TRUE(plan.approach.isApprox(diagonal, 1e-12));
  EXPECT_EQ(plan.objects[1].label, 13);
  EXPECT_LT(plan.depth[1], 0.0);  // 13 is in front too, but off to the side
  // Along +x or +y neither hides the target: both are beside it.
  EXPECT_TRUE(lom::planPick(map, kTarget, along(kIntoTheBin)).occluders.empty());
  EXPECT_TRUE(lom::planPick(map, kTarget, along(Eigen::Vector3d::UnitY())).occluders.empty());
}

TEST(Planning, BoxesOverlapAcrossTheApproach) {
  const OrientedBox a = aabb({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1});
  OrientedBox b = aabb({0.5, 0.12, 0.0}, {0.6, 0.22, 0.1});  // 2 cm beside a, far behind it
  EXPECT_FALSE(lom::boxesOverlapAcross(a, b, Eigen::Vector3d::UnitX()));
  // Turned 45 degrees about x, its corners reach 0.0207 m further toward a.
  b.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(lom::boxesOverlapAcross(a, b, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(lom::boxesOverlapAcross(a, b, Eigen::Vector3d::UnitX(), 0.01));
  // Along y they line up.
  EXPECT_TRUE(lom::boxesOverlapAcross(a, aabb({0.02, 0.5, 0.02}, {0.05, 0.6, 0.05}), Eigen::Vector3d::UnitY()));
  // Touching faces do not overlap.
  EXPECT_FALSE(lom::boxesOverlapAcross(a, aabb({0.5, 0.1, 0.0}, {0.6, 0.2, 0.1}), Eigen::Vector3d::UnitX()));
}

TEST(Planning, AnObjectBehindTheTargetIsNotInItsPathHoweverTall) {
  // Seen from above at 46 degrees: a flat book (the target), a cup in front
  // of it and a tall, thin DVD standing 1 cm behind it. The DVD's centroid is
  // nearer the camera than the book's, and their outlines overlap across the
  // approach, yet the gripper's path down to the book never meets the DVD.
  const Eigen::Vector3d down(0.693, 0.0, -0.721);
  const LabelMap map = scene({{12, {0.00, 0.00, 0.00}, {0.06, 0.10, 0.10}},
                              {kTarget, {0.10, 0.00, 0.00}, {0.25, 0.10, 0.03}},
                              {20, {0.26, 0.00, 0.00}, {0.28, 0.10, 0.22}}},
                             /*with_target=*/false);
  const PickPlan plan = lom::planPick(map, kTarget, along(down));
  EXPECT_EQ(removedLabels(plan), std::vector<int>{12});
  const OrientedBox book = aabb({0.10, 0.00, 0.00}, {0.25, 0.10, 0.03});
  const OrientedBox dvd = aabb({0.26, 0.00, 0.00}, {0.28, 0.10, 0.22});
  EXPECT_TRUE(lom::boxesOverlapAcross(dvd, book, down, 0.01))
      << "the old test said it hides the book";
  EXPECT_FALSE(lom::boxInPathOf(dvd, book, down, 0.01));
  // Seen from the other side, the DVD stands in front of the book.
  const Eigen::Vector3d from_behind(-0.693, 0.0, -0.721);
  EXPECT_TRUE(lom::boxInPathOf(dvd, book, from_behind, 0.01));
  EXPECT_EQ(removedLabels(lom::planPick(map, kTarget, along(from_behind))), std::vector<int>{20});
}

TEST(Planning, PathOfTheTargetAlongTheApproach) {
  const OrientedBox target = aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.10});
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // Straight in front, far in front, and in front but 2 cm to the side.
  EXPECT_TRUE(lom::boxInPathOf(aabb({0.1, -0.02, 0.0}, {0.2, 0.02, 0.05}), target, x));
  EXPECT_TRUE(lom::boxInPathOf(aabb({-3.0, -0.02, 0.0}, {-2.9, 0.02, 0.05}), target, x));
  EXPECT_FALSE(lom::boxInPathOf(aabb({0.1, 0.07, 0.0}, {0.2, 0.1, 0.05}), target, x));
  // Grazing the path by half a centimetre: in it without a margin, not with 1 cm.
  const OrientedBox grazing = aabb({0.1, 0.045, 0.0}, {0.2, 0.1, 0.05});
  EXPECT_TRUE(lom::boxInPathOf(grazing, target, x));
  EXPECT_FALSE(lom::boxInPathOf(grazing, target, x, 0.01));
  // A face one voxel deep in front is in the way, whatever the margin and the
  // approach (the margin is for grazing the path, not for an object's depth).
  for (const Eigen::Vector3d& approach : {x, Eigen::Vector3d(1.0, 0.0, -0.58).normalized(),
                                          Eigen::Vector3d(1.0, 0.4, -1.0).normalized()})
    for (const double margin : {0.01, 0.015, 0.02})
      for (double back = 0.08; back < 0.3; back += 0.0037) {
        // On the line from the target's centre back towards the camera.
        const Eigen::Vector3d c = target.center - back * approach;
        const Eigen::Vector3d half(0.005, 0.02, 0.02);
        EXPECT_TRUE(lom::boxInPathOf(aabb(c - half, c + half), target, approach, margin))
            << back << " " << margin << " " << approach.transpose();
      }
  // A slab under the target, overlapping its box by 5 mm (a fit a little too
  // tall), seen from 20 degrees off the vertical: not in the way.
  const OrientedBox slab = aabb({0.0, -0.1, -0.05}, {0.5, 0.1, 0.005});
  const Eigen::Vector3d steep(std::sin(20.0 * M_PI / 180.0), 0.0, -std::cos(20.0 * M_PI / 180.0));
  EXPECT_FALSE(lom::boxInPathOf(slab, target, steep, 0.01));
  // Behind the target, even when its box overlaps the target's by a little.
  EXPECT_FALSE(lom::boxInPathOf(aabb({0.39, -0.05, 0.0}, {0.5, 0.05, 0.1}), target, x));
  EXPECT_FALSE(lom::boxInPathOf(aabb({0.5, -0.05, 0.0}, {0.6, 0.05, 0.1}), target, x));
  // A box turned 45 degrees about z, in front: its corner is in the path.
  OrientedBox turned = aabb({0.1, 0.06, 0.0}, {0.2, 0.16, 0.05});
  turned.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(lom::boxInPathOf(turned, target, x));  // reaches y = 0.11 - 0.0707 = 0.039
  EXPECT_FALSE(lom::boxInPathOf(turned, target, x, 0.02));
}

TEST(Planning, GraspIsOnTheFrontFaceNearTheCentroid) {
  const OrientedBox box = aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.10});
  const lom::ObjectInstance object = objectWithBox(box, {0.33, 0.02, 0.04});

  lom::Grasp grasp = lom::graspFor(object, kIntoTheBin);
  EXPECT_TRUE(grasp.position.isApprox(Eigen::Vector3d(0.30, 0.02, 0.04), 1e-12)) << grasp.position.transpose();
  EXPECT_TRUE(grasp.face_normal.isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_EQ(grasp.face_axis, 0);
  EXPECT_TRUE(grasp.approach.isApprox(kIntoTheBin, 1e-12));
  EXPECT_TRUE((grasp.axes.transpose() * grasp.axes).isIdentity(1e-12));
  EXPECT_TRUE(grasp.size.isApprox(box.size, 1e-12));

  // Looking down into the bin at a slant: still the front face.
  grasp = lom::graspFor(object, Eigen::Vector3d(0.9, 0.0, -0.44));
  EXPECT_TRUE(grasp.face_normal.isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(grasp.approach.isApprox(Eigen::Vector3d(0.9, 0.0, -0.44).normalized(), 1e-12));

  // From above: the top face, right above the centroid.
  grasp = lom::graspFor(object, Eigen::Vector3d(0.2, 0.0, -1.0));
  EXPECT_TRUE(grasp.face_normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_TRUE(grasp.position.isApprox(Eigen::Vector3d(0.33, 0.02, 0.10), 1e-12)) << grasp.position.transpose();

  // A box turned about z: the grasp lies on the face whose normal opposes the approach.
  OrientedBox turned = box;
  turned.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  grasp = lom::graspFor(objectWithBox(turned, turned.center), kIntoTheBin);
  EXPECT_LT(grasp.face_normal.dot(kIntoTheBin), -0.9);
  const Eigen::Vector3d local = grasp.axes.transpose() * (grasp.position - turned.center);
  EXPECT_NEAR(std::abs(local[grasp.face_axis]), 0.5 * turned.size[grasp.face_axis], 1e-12);
  EXPECT_LT((grasp.position - turned.center).dot(kIntoTheBin), 0.0);

  // A flat envelope (17 x 15 x 0.9 cm) seen from 25 degrees above: its broad
  // top shows more area along the approach than its edge, which faces it
  // more squarely but which no gripper takes.
  const OrientedBox flat = aabb({0.30, -0.075, 0.0}, {0.47, 0.075, 0.0086});
  const Eigen::Vector3d slant(std::cos(25 * M_PI / 180), 0.0, -std::sin(25 * M_PI / 180));
  grasp = lom::graspFor(objectWithBox(flat, flat.center), slant);
  EXPECT_EQ(grasp.face_axis, 2);
  EXPECT_TRUE(grasp.face_normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_NEAR(grasp.position.z(), 0.0086, 1e-12);
  // Seen level, the edge is all it shows.
  grasp = lom::graspFor(objectWithBox(flat, flat.center), kIntoTheBin);
  EXPECT_EQ(grasp.face_axis, 0);
}

TEST(Planning, RemovedObjectsArePackedIntoTheEmptyBin) {
  OrientedBox bin;  // 0.5 m along x, 0.3 m across, floor at z = 0
  bin.center = {0.0, 1.0, 0.1};
  bin.size = {0.5, 0.3, 0.2};
  const std::vector<OrientedBox> boxes = {
      aabb({0, 0, 0}, {0.1, 0.1, 0.1}), aabb({0, 0, 0}, {0.2, 0.1, 0.1}),
      aabb({0, 0, 0}, {0.3, 0.3, 0.3}),  // too big for the bin
      aabb({0, 0, 0}, {0.1, 0.1, 0.1}), aabb({0, 0, 0}, {0.1, 0.1, 0.1})};  // the last finds no room
  const auto placements = lom::placeInBin(boxes, bin, 0.01);
  ASSERT_EQ(placements.size(), 5u);
  EXPECT_TRUE(placements[0].in_bin);
  EXPECT_TRUE(placements[0].position.isApprox(Eigen::Vector3d(-0.19, 1.0, 0.05), 1e-12))
      << placements[0].position.transpose();
  EXPECT_TRUE(placements[1].position.isApprox(Eigen::Vector3d(-0.03, 1.0, 0.05), 1e-12))
      << placements[1].position.transpose();
  EXPECT_FALSE(placements[2].in_bin);
  EXPECT_TRUE(placements[3].in_bin);
  EXPECT_TRUE(placements[3].position.isApprox(Eigen::Vector3d(0.13, 1.0, 0.05), 1e-12))
      << placements[3].position.transpose();
  EXPECT_FALSE(placements[4].in_bin);

  // A bin longer along y is filled along y.
  std::swap(bin.size.x(), bin.size.y());
  const auto along_y = lom::placeInBin({boxes[0]}, bin, 0.01);
  EXPECT_TRUE(along_y[0].position.isApprox(Eigen::Vector3d(0.0, 0.81, 0.05), 1e-12)) << along_y[0].position.transpose();
  // No bin: everything goes outside.
  for (const auto& p : lom::placeInBin(boxes, std::nullopt, 0.01)) EXPECT_FALSE(p.in_bin);
}

TEST(Planning, PlanPlacesTheRemovedObjectsAndNotTheTarget) {
  const LabelMap map = scene({{8, {0.16, -0.05, 0.0}, {0.24, 0.05, 0.09}},
                              {30, {0.02, -0.03, 0.0}, {0.08, 0.03, 0.12}}});
  lom::PlanOptions options = along(kIntoTheBin);
  PickPlan plan = lom::planPick(map, kTarget, options);
  ASSERT_EQ(plan.steps.size(), 3u);
  for (size_t k = 0; k < 2; ++k) {
    ASSERT_TRUE(plan.steps[k].placement.has_value());
    EXPECT_FALSE(plan.steps[k].placement->in_bin);
  }
  EXPECT_FALSE(plan.steps[2].placement.has_value());

  options.empty_bin = aabb({0.0, 0.5, 0.0}, {0.4, 0.8, 0.25});
  plan = lom::planPick(map, kTarget, options);
  for (size_t k = 0; k < 2; ++k) {
    ASSERT_TRUE(plan.steps[k].placement && plan.steps[k].placement->in_bin) << k;
    EXPECT_TRUE(options.empty_bin->contains(plan.steps[k].placement->position)) << k;
  }
  // Packed one after the other along x, in the order of removal.
  EXPECT_LT(plan.steps[0].placement->position.x(), plan.steps[1].placement->position.x());
  EXPECT_FALSE(plan.steps[2].placement.has_value());
}

TEST(Planning, TransitiveAlsoRemovesWhatBlocksAnOccluder) {
  // 8 hides the target; 13 hides 8 but not the target.
  const LabelMap map = scene({{8, {0.15, 0.0, 0.0}, {0.22, 0.12, 0.10}},
                              {13, {0.02, 0.08, 0.0}, {0.08, 0.18, 0.10}}});
  lom::PlanOptions options = along(kIntoTheBin);
  EXPECT_EQ(removedLabels(lom::planPick(map, kTarget, options)), std::vector<int>{8});
  options.transitive = true;
  EXPECT_EQ(removedLabels(lom::planPick(map, kTarget, options)), (std::vector<int>{13, 8}));
}

TEST(Planning, AllClustersMakesASecondPieceOfTheTargetLabelAnObject) {
  // A second, smaller piece of the target label right in front of it.
  const LabelMap map = scene({{kTarget, {0.10, -0.03, 0.0}, {0.14, 0.03, 0.06}}});
  lom::PlanOptions options = along(kIntoTheBin);
  PickPlan plan = lom::planPick(map, kTarget, options);
  EXPECT_EQ(plan.objects.size(), 1u);
  EXPECT_TRUE(plan.occluders.empty());
  options.objects.all_clusters = true;
  plan = lom::planPick(map, kTarget, options);
  ASSERT_EQ(plan.objects.size(), 2u);
  EXPECT_EQ(plan.objects[plan.target].instance, 0);
  ASSERT_EQ(plan.occluders.size(), 1u);
  EXPECT_EQ(plan.objects[plan.occluders[0]].id(), "19#1");
}

TEST(Planning, CandidatesLimitTheObjectsAndAlwaysKeepTheTarget) {
  const LabelMap map = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}},
                              {13, {0.45, -0.05, 0.0}, {0.55, 0.05, 0.10}}});
  lom::PlanOptions options = along(kIntoTheBin);
  options.objects.labels = std::vector<int>{13};
  const PickPlan plan = lom::planPick(map, kTarget, options);
  ASSERT_EQ(plan.objects.size(), 2u);
  EXPECT_EQ(plan.objects[0].label, 13);
  EXPECT_EQ(plan.objects[1].label, kTarget);
  EXPECT_TRUE(plan.occluders.empty());
}

TEST(Planning, TargetLabelsAreResolvedByIdOrNameAndCheckedAgainstTheMap) {
  const lom::LabelSet labels = lom::apc2016Labels();
  EXPECT_EQ(lom::resolveObjectLabel(labels, "19", "m.ot", "--target"), 19);
  EXPECT_EQ(lom::resolveObjectLabel(labels, "i_am_a_bunny_book", "m.ot", "--target"), 19);
  for (const std::string bad : {"40", "99999999", "no_such_object", "", "-3", "__background__", "0"}) {
    try {
      (void)lom::resolveObjectLabel(labels, bad, "/data/bin.ot", "--target");
      FAIL() << "'" << bad << "' must be rejected";
    } catch (const lom::Error& e) {
      EXPECT_EQ(e.problem().file, "/data/bin.ot") << bad;
      EXPECT_EQ(e.problem().field, "--target") << bad;
      EXPECT_NE(e.problem().expected.find("1..39"), std::string::npos) << e.what();
    }
  }
}

TEST(Planning, TargetWithoutVoxelsIsAnError) {
  const LabelMap map = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}}}, false);
  try {
    (void)lom::planPick(map, kTarget, along(kIntoTheBin));
    FAIL() << "a target without voxels must be an error";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, "/data/bin.ot");
    EXPECT_EQ(e.problem().field, "target");
    EXPECT_NE(std::string(e.what()).find("i_am_a_bunny_book"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no occupied voxel"), std::string::npos) << e.what();
  }
  // The approach is checked too.
  const LabelMap with_target = scene({});
  EXPECT_THROW((void)lom::planPick(with_target, kTarget, along(Eigen::Vector3d::Zero())), lom::Error);
  EXPECT_THROW((void)lom::planPick(with_target, 0, along(kIntoTheBin)), lom::Error);
  EXPECT_THROW((void)lom::planPick(with_target, 40, along(kIntoTheBin)), lom::Error);
}

TEST(Planning, MeanViewingDirectionAveragesTheCameraZAxes) {
  lom::Sequence sequence;
  sequence.root = "/data/seq";
  lom::FrameRecord frame;
  frame.T_world_camera.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  sequence.frames.push_back(frame);  // looks along +x
  frame.T_world_camera.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  sequence.frames.push_back(frame);  // looks along -y
  EXPECT_TRUE(lom::meanViewingDirection(sequence).isApprox(Eigen::Vector3d(1, -1, 0).normalized(), 1e-12));

  frame.T_world_camera.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  sequence.frames = {sequence.frames[0], frame};  // +x and -x cancel out
  EXPECT_THROW((void)lom::meanViewingDirection(sequence), lom::Error);
  sequence.frames.clear();
  EXPECT_THROW((void)lom::meanViewingDirection(sequence), lom::Error);
}

TEST(Planning, DefaultApproachGoesFromTheFreeSpaceToTheObjects) {
  LabelMap map = scene({{8, {0.10, -0.04, 0.0}, {0.18, 0.04, 0.08}}});
  // What the cameras saw through: the space in front of the bin, a little above it.
  lom::rasterizeFreeBox(map, aabb({-0.50, -0.20, 0.0}, {0.05, 0.20, 0.25}));
  lom::PlanOptions options;
  const PickPlan plan = lom::planPick(map, kTarget, options);
  EXPECT_EQ(plan.approach_source, lom::ApproachSource::FreeSpace);
  EXPECT_GT(plan.approach.dot(kIntoTheBin), 0.95) << plan.approach.transpose();
  EXPECT_EQ(removedLabels(plan), std::vector<int>{8});

  // Without free space there is nothing to take the direction from.
  const LabelMap bare = scene({});
  options.objects.map_file = "/data/bare.ot";
  try {
    (void)lom::planPick(bare, kTarget, options);
    FAIL() << "a map without free space needs an approach";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, "/data/bare.ot");
    EXPECT_EQ(e.problem().field, "approach");
    EXPECT_NE(e.problem().expected.find("--approach"), std::string::npos) << e.what();
  }
}

TEST(Planning, JsonFollowsTheContract) {
  const LabelMap map = scene({{8, {0.16, -0.05, 0.0}, {0.24, 0.05, 0.09}},
                              {30, {0.02, -0.03, 0.0}, {0.08, 0.03, 0.12}},
                              {13, {0.45, -0.05, 0.0}, {0.55, 0.05, 0.10}}});
  lom::PlanOptions options = along(kIntoTheBin);
  options.empty_bin = aabb({0.0, 0.5, 0.0}, {0.09, 0.8, 0.25});  // too narrow for 8
  const PickPlan plan = lom::planPick(map, kTarget, options);
  const auto json = nlohmann::json::parse(lom::planJson(plan, "/data/bin.ot"));
  EXPECT_EQ(json["format"], "labeloctomap-plan");
  EXPECT_EQ(json["version"], 1);
  EXPECT_EQ(json["map"], "/data/bin.ot");
  EXPECT_DOUBLE_EQ(json["resolution"].get<double>(), 0.01);
  EXPECT_EQ(json["target"]["label"], kTarget);
  EXPECT_EQ(json["target"]["object"], "19");
  EXPECT_EQ(json["approach"]["source"], "given");
  EXPECT_EQ(json["approach"]["direction"], nlohmann::json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(json["occluders"], nlohmann::json::array({"30", "8"}));
  ASSERT_EQ(json["objects"].size(), 4u);
  EXPECT_EQ(json["objects"][0]["label"], 8);
  EXPECT_EQ(json["objects"][0]["role"], "occluder");
  EXPECT_EQ(json["objects"][1]["role"], "other");  // 13, behind
  EXPECT_EQ(json["objects"][2]["role"], "target");
  EXPECT_EQ(json["objects"][2]["box"]["rotation"].size(), 4u);
  EXPECT_EQ(json["objects"][2]["box"]["axes"].size(), 3u);
  EXPECT_EQ(json["objects"][2]["voxels"], 1000);
  ASSERT_EQ(json["steps"].size(), 3u);
  EXPECT_EQ(json["steps"][0]["step"], 1);
  EXPECT_EQ(json["steps"][0]["action"], "remove");
  EXPECT_EQ(json["steps"][0]["object"], "30");
  EXPECT_EQ(json["steps"][0]["placement"]["where"], "bin");
  EXPECT_EQ(json["steps"][0]["placement"]["position"].size(), 3u);
  EXPECT_EQ(json["steps"][1]["placement"]["where"], "outside");  // no room left
  EXPECT_FALSE(json["steps"][1]["placement"].contains("position"));
  EXPECT_EQ(json["steps"][2]["action"], "pick");
  EXPECT_TRUE(json["steps"][2]["placement"].is_null());
  const auto& grasp = json["steps"][2]["grasp"];
  EXPECT_DOUBLE_EQ(grasp["position"][0].get<double>(), 0.30);
  EXPECT_DOUBLE_EQ(grasp["face_normal"][0].get<double>(), -1.0);
  EXPECT_EQ(grasp["axes"].size(), 3u);
  EXPECT_EQ(json["empty_bin"]["size"].size(), 3u);
  EXPECT_EQ(json["options"]["all_clusters"], false);

  const std::string table = lom::planTable(plan);
  EXPECT_NE(table.find("remove"), std::string::npos) << table;
  EXPECT_NE(table.find("pick"), std::string::npos) << table;
  EXPECT_NE(table.find("outside"), std::string::npos) << table;
  EXPECT_NE(table.find("   1  remove  30 rolodex_jumbo_pencil_cup"), std::string::npos) << table;
  EXPECT_NE(table.find("   2  remove  8 creativity_chenille_stems"), std::string::npos) << table;
  EXPECT_NE(table.find("   3  pick    19 i_am_a_bunny_book"), std::string::npos) << table;
}

}  // namespace
