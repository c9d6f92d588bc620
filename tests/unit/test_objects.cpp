// Objects of a labelled map: clusters, boxes, centroids, counts, probabilities.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "lom/error.hpp"
#include "lom/objects.hpp"

namespace {

using lom::LabelMap;
using lom::ObjectInstance;
using lom::OrientedBox;

// An axis-aligned box from its lower and upper corners (metres).
OrientedBox aabb(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  OrientedBox box;
  box.center = 0.5 * (low + high);
  box.size = high - low;
  return box;
}

LabelMap emptyMap() { return LabelMap(lom::apc2016Labels()); }  // resolution 1 cm

constexpr int kOrigin = 32768;
lom::VoxelKey key(int i, int j, int k) {
  return {static_cast<std::uint16_t>(kOrigin + i), static_cast<std::uint16_t>(kOrigin + j),
          static_cast<std::uint16_t>(kOrigin + k)};
}

TEST(Objects, EachLabelGivesItsBoxCentroidCountAndProbability) {
  LabelMap map = emptyMap();
  const OrientedBox book = aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.03});   // 10 x 10 x 3 voxels
  const OrientedBox glue = aabb({0.10, -0.02, 0.0}, {0.14, 0.02, 0.12});   // 4 x 4 x 12 voxels
  EXPECT_EQ(lom::rasterizeBox(map, book, 19, 0.9), 300u);
  EXPECT_EQ(lom::rasterizeBox(map, glue, 13, 0.8), 192u);

  const auto objects = lom::extractObjects(map);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].label, 13);  // by ascending label
  EXPECT_EQ(objects[1].label, 19);
  const ObjectInstance& b = objects[1];
  EXPECT_EQ(b.name, "i_am_a_bunny_book");
  EXPECT_EQ(b.instance, 0);
  EXPECT_EQ(b.id(), "19");
  EXPECT_EQ(b.voxelCount(), 300u);
  EXPECT_EQ(b.label_voxels, 300u);
  EXPECT_EQ(b.label_clusters, 1u);
  EXPECT_TRUE(b.centroid.isApprox(book.center, 1e-9)) << b.centroid.transpose();
  EXPECT_TRUE(b.box.center.isApprox(book.center, 1e-9)) << b.box.center.transpose();
  EXPECT_NEAR(b.box.size.maxCoeff(), 0.10, 1e-9);
  EXPECT_NEAR(b.box.size.minCoeff(), 0.03, 1e-9);
  EXPECT_NEAR(b.box.volume(), book.volume(), 1e-9);
  EXPECT_NEAR(b.mean_probability, 0.9, 1e-5);
  EXPECT_NEAR(objects[0].mean_probability, 0.8, 1e-5);
  EXPECT_EQ(objects[0].voxelCount(), 192u);
}

TEST(Objects, StraySpeckOfTheLabelDoesNotMoveTheBox) {
  LabelMap map = emptyMap();
  const OrientedBox book = aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.03});
  lom::rasterizeBox(map, book, 19);
  const ObjectInstance clean = lom::extractObjects(map).at(0);
  lom::rasterizeBox(map, aabb({-0.40, 0.30, 0.20}, {-0.38, 0.31, 0.21}), 19);  // 2 voxels far away

  const auto objects = lom::extractObjects(map);
  ASSERT_EQ(objects.size(), 1u);
  const ObjectInstance& o = objects[0];
  EXPECT_EQ(o.voxelCount(), 300u);
  EXPECT_EQ(o.label_voxels, 302u);
  EXPECT_EQ(o.label_clusters, 1u) << "the speck is smaller than the default minimum of 8";
  lom::ObjectOptions every_cluster;
  every_cluster.min_cluster_voxels = 1;
  EXPECT_EQ(lom::extractObjects(map, every_cluster).at(0).label_clusters, 2u);
  EXPECT_TRUE(o.box.center.isApprox(clean.box.center, 1e-12));
  EXPECT_TRUE(o.box.size.isApprox(clean.box.size, 1e-12));
  EXPECT_TRUE(o.centroid.isApprox(book.center, 1e-9));
}

// A map that records no camera (an older map, or one built without) stands
// its boxes on the up it is given, the mean up of the cameras it was fused
// from: here a world whose up is +y, with a tall object turned 25 degrees
// about it.
TEST(Objects, BoxesOfAMapWithoutCamerasStandOnTheUpTheyAreGiven) {
  LabelMap map = emptyMap();
  OrientedBox tall;
  tall.center = Eigen::Vector3d(0.2, 0.15, 0.1);
  tall.size = Eigen::Vector3d(0.08, 0.04, 0.16);  // 16 cm along its z ...
  // ... which stands along the world's +y, turned 25 degrees about it.
  tall.rotation = Eigen::AngleAxisd(25.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX());
  ASSERT_GT(lom::rasterizeBox(map, tall, 19), 400u);
  ASSERT_FALSE(map.camerasUp());

  lom::ObjectOptions options;
  options.cameras_up = Eigen::Vector3d::UnitY();
  const ObjectInstance standing = lom::extractObjects(map, options).at(0);
  const Eigen::Matrix3d axes = standing.box.rotation.toRotationMatrix();
  EXPECT_GT(std::abs(axes.col(2).dot(Eigen::Vector3d::UnitY())), 0.999) << axes;
  EXPECT_NEAR(standing.box.size.z(), 0.16, 0.021);  // its height, along that up
  EXPECT_LT(standing.box.volume(), 1.3 * tall.volume());

  // Without it the box stands on +z, the world's up of a map that says nothing.
  const ObjectInstance on_z = lom::extractObjects(map).at(0);
  const Eigen::Matrix3d z_axes = on_z.box.rotation.toRotationMatrix();
  EXPECT_LT(std::abs(z_axes.col(2).dot(Eigen::Vector3d::UnitY())), 0.9) << z_axes;
}

TEST(Objects, LeftOutVoxelsAreNotedAboveAShare) {
  LabelMap map = emptyMap();
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.10, 0.10, 0.05}), 19);   // 500 voxels
  lom::rasterizeBox(map, aabb({0.30, 0.0, 0.0}, {0.32, 0.02, 0.02}), 19);  // 8, 1.6%
  EXPECT_EQ(lom::leftOutNote(lom::extractObjects(map).at(0)), "");
  lom::rasterizeBox(map, aabb({-0.30, 0.0, 0.0}, {-0.25, 0.05, 0.02}), 19);  // 50 more
  const ObjectInstance object = lom::extractObjects(map).at(0);
  EXPECT_EQ(lom::leftOutNote(object),
            "the box of label 19 (i_am_a_bunny_book) holds the 500 voxels of its largest "
            "cluster; 58 more of its 558 lie in 2 other clusters, left out");
}

TEST(Objects, AllClustersReportsEveryClusterAsAnInstance) {
  LabelMap map = emptyMap();
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.03, 0.03, 0.03}), 19);    // 27 voxels
  lom::rasterizeBox(map, aabb({0.20, 0.0, 0.0}, {0.22, 0.02, 0.02}), 19);   // 8 voxels
  lom::rasterizeBox(map, aabb({0.0, 0.20, 0.0}, {0.01, 0.21, 0.01}), 19);   // 1 voxel

  lom::ObjectOptions options;
  options.all_clusters = true;
  // By default a cluster of fewer than 8 voxels is no object.
  EXPECT_EQ(options.min_cluster_voxels, lom::kDefaultMinObjectVoxels);
  auto objects = lom::extractObjects(map, options);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[1].voxelCount(), 8u);

  options.min_cluster_voxels = 1;
  objects = lom::extractObjects(map, options);
  ASSERT_EQ(objects.size(), 3u);
  EXPECT_EQ(objects[0].instance, 0);
  EXPECT_EQ(objects[0].voxelCount(), 27u);
  EXPECT_EQ(objects[1].instance, 1);
  EXPECT_EQ(objects[1].voxelCount(), 8u);
  EXPECT_EQ(objects[1].id(), "19#1");
  EXPECT_EQ(objects[2].voxelCount(), 1u);
  for (const auto& o : objects) EXPECT_EQ(o.label_voxels, 36u);
  for (const auto& o : objects) EXPECT_EQ(o.label_clusters, 3u);
  EXPECT_TRUE(objects[1].box.center.isApprox(Eigen::Vector3d(0.21, 0.01, 0.01), 1e-9));

  options.min_cluster_voxels = 5;
  objects = lom::extractObjects(map, options);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[1].voxelCount(), 8u);
  EXPECT_EQ(objects[0].label_clusters, 2u);

  options.all_clusters = false;  // only the largest, whatever the minimum
  objects = lom::extractObjects(map, options);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].voxelCount(), 27u);

  options.min_cluster_voxels = 30;  // no cluster is large enough: no object
  EXPECT_TRUE(lom::extractObjects(map, options).empty());
}

TEST(Objects, ToleranceIsInVoxelEdges) {
  LabelMap map = emptyMap();
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.03, 0.03, 0.03}), 19);
  lom::rasterizeBox(map, aabb({0.05, 0.0, 0.0}, {0.07, 0.03, 0.03}), 19);  // centres 3 voxel edges apart
  lom::ObjectOptions options;
  EXPECT_EQ(lom::extractObjects(map, options).at(0).voxelCount(), 27u);
  options.cluster_tolerance_voxels = 3.0;
  EXPECT_EQ(lom::extractObjects(map, options).at(0).voxelCount(), 45u);
}

TEST(Objects, CandidatesRestrictTheLabelsAndBackgroundIsNoObject) {
  LabelMap map = emptyMap();
  lom::rasterizeBox(map, aabb({0.0, 0.0, -0.02}, {0.5, 0.5, 0.0}), 0);  // the bin floor
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.03, 0.03, 0.03}), 8);
  lom::rasterizeBox(map, aabb({0.2, 0.0, 0.0}, {0.23, 0.03, 0.03}), 19);
  auto objects = lom::extractObjects(map);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].label, 8);
  EXPECT_EQ(objects[1].label, 19);

  lom::ObjectOptions options;
  options.labels = std::vector<int>{19, 30};
  objects = lom::extractObjects(map, options);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].label, 19);

  options.labels = std::vector<int>{19, 40};
  options.map_file = "/data/bin.ot";
  try {
    (void)lom::extractObjects(map, options);
    FAIL() << "an unknown candidate label must be an error";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, "/data/bin.ot");
    EXPECT_EQ(e.problem().field, "candidates");
    EXPECT_NE(std::string(e.what()).find("40"), std::string::npos) << e.what();
  }
  options.labels.reset();
  options.cluster_tolerance_voxels = 0.0;
  EXPECT_THROW((void)lom::extractObjects(map, options), lom::Error);
}

TEST(Objects, PrunedLeavesCountAsTheirFinestVoxels) {
  LabelMap map = emptyMap();
  // 8 x 8 x 8 voxels aligned to the octree: pruned into one leaf of 8 cm.
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.08, 0.08, 0.08}), 19);
  map.prune();
  EXPECT_LT(map.numLeaves(), 10u);
  const auto objects = lom::extractObjects(map);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].voxelCount(), 512u);
  EXPECT_TRUE(objects[0].centroid.isApprox(Eigen::Vector3d(0.04, 0.04, 0.04), 1e-9));
  EXPECT_NEAR(objects[0].box.volume(), 0.08 * 0.08 * 0.08, 1e-12);
}

TEST(Objects, EuclideanClustersComeLargestFirstWithTiesToTheSmallestKey) {
  std::vector<lom::VoxelKey> keys = {key(50, 0, 0), key(51, 0, 0),                 // 2, larger key
                                     key(0, 0, 0),  key(1, 0, 0),                  // 2, smallest key
                                     key(20, 0, 0), key(21, 0, 0), key(22, 0, 0),  // 3
                                     key(90, 0, 0)};                               // 1
  const auto clusters = lom::euclideanClusters(keys, 2.0);
  ASSERT_EQ(clusters.size(), 4u);
  EXPECT_EQ(clusters[0].size(), 3u);
  EXPECT_EQ(clusters[1], (std::vector<lom::VoxelKey>{key(0, 0, 0), key(1, 0, 0)}));
  EXPECT_EQ(clusters[2], (std::vector<lom::VoxelKey>{key(50, 0, 0), key(51, 0, 0)}));
  EXPECT_EQ(clusters[3], (std::vector<lom::VoxelKey>{key(90, 0, 0)}));
  EXPECT_EQ(lom::euclideanClusters(keys, 2.0, 2).size(), 3u);
  EXPECT_TRUE(lom::euclideanClusters({}, 2.0).empty());
}

TEST(Objects, RasterizedBoxesAreOccupiedAndFreeBoxesAreKnownFree) {
  LabelMap map = emptyMap();
  lom::rasterizeBox(map, aabb({0.0, 0.0, 0.0}, {0.02, 0.02, 0.02}), 19, 0.9);
  EXPECT_EQ(lom::rasterizeFreeBox(map, aabb({-0.1, 0.0, 0.0}, {-0.05, 0.02, 0.02})), 20u);
  const lom::VoxelState occupied = map.voxelAt(Eigen::Vector3d(0.005, 0.005, 0.005));
  EXPECT_TRUE(occupied.occupied);
  EXPECT_EQ(occupied.label, 19);
  const lom::VoxelState free = map.voxelAt(Eigen::Vector3d(-0.075, 0.005, 0.005));
  EXPECT_TRUE(free.known);
  EXPECT_FALSE(free.occupied);
  EXPECT_THROW(lom::rasterizeBox(map, aabb({0, 0, 0}, {0.01, 0.01, 0.01}), 40), lom::Error);
  EXPECT_THROW(lom::rasterizeBox(map, aabb({0, 0, 0}, {0.01, 0.01, 0.01}), 19, 1.0), lom::Error);
}

}  // namespace
