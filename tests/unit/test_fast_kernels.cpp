// The kernels of the fast integration path: row back-projection, row logit
// and ray marking, against the straightforward computations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "brick_set.hpp"
#include "fusion_internal.hpp"
#include "test_mesh_checks.hpp"

namespace {

float floatOfBits(std::uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}
std::uint32_t bitsOf(float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  return bits;
}
std::uint64_t bitsOf64(double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, sizeof(bits));
  return bits;
}

TEST(FastLogitTest, WithinAMillionthOfClampedLogitOverTheProbabilities) {
  // Every 61st float in [0, 1] (17 million values, all exponents), the clamp
  // edges, 0 and 1, and values just outside [0, 1].
  std::vector<float> p;
  for (std::uint32_t bits = 0; bits <= bitsOf(1.0f); bits += 61) p.push_back(floatOfBits(bits));
  for (float extra : {0.f, 1.f, 1e-6f, 1.0f - 1e-6f, 0.5f, 0.3f, 0.7f, 0.97f, 0.12f,
                      std::nextafter(1.f, 0.f), std::numeric_limits<float>::denorm_min(), 1.5f, -0.25f})
    p.push_back(extra);
  std::vector<float> out(p.size()), baseline(p.size());
  lom::logitRow(p.data(), p.size(), out.data());
  lom::logitRow(p.data(), p.size(), baseline.data(), false);
  double worst = 0.0;
  float worst_p = 0.f;
  size_t differing_bits = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const double error = std::fabs(static_cast<double>(out[i]) - lom::clampedLogit(p[i]));
    if (error > worst) {
      worst = error;
      worst_p = p[i];
    }
    differing_bits += bitsOf(out[i]) != bitsOf(baseline[i]) ? 1 : 0;
  }
  EXPECT_LT(worst, 1e-6) << "at p = " << worst_p;
  EXPECT_EQ(differing_bits, 0u) << "the AVX2 and the baseline builds must agree to the bit";
  // The clamp: 0 and below, 1 and above give the clamped extremes exactly as the reference.
  const float extremes[] = {0.f, -0.25f, 1.f, 1.5f};
  float logits[4];
  lom::logitRow(extremes, 4, logits);
  EXPECT_NEAR(logits[0], lom::clampedLogit(0.f), 1e-6);
  EXPECT_EQ(logits[0], logits[1]);
  EXPECT_NEAR(logits[2], lom::clampedLogit(1.f), 1e-6);
  EXPECT_EQ(logits[2], logits[3]);
  EXPECT_GT(logits[2], 13.8f);
}

TEST(PixelProjectorTest, RowMatchesThePerPixelBackProjection) {
  const lom::grid::Grid grid(0.01);
  lom::CameraIntrinsics camera;
  camera.width = 97;  // not a multiple of any vector width
  camera.height = 5;
  camera.fx = 520.0;
  camera.fy = 525.0;
  camera.cx = 48.3;
  camera.cy = 2.1;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), position(-3.0, 3.0), depth(0.05, 1.6);
  const double max_range = 1.0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
    const lom::PixelProjector projector(grid, camera, pose, max_range);
    std::vector<float> row(static_cast<size_t>(camera.width));
    for (auto& d : row) d = static_cast<float>(depth(rng));
    // No measurement, and a point outside the 16-bit key range (655 m at 1 cm).
    row[3] = 0.f;
    row[4] = std::numeric_limits<float>::quiet_NaN();
    row[5] = std::numeric_limits<float>::infinity();
    row[6] = -1.f;
    row[7] = 1e4f;
    for (int v = 0; v < camera.height; ++v) {
      std::vector<std::uint64_t> packed(row.size()), avx2(row.size()), baseline(row.size());
      projector.projectRow(v, row.data(), camera.width, packed.data());
      projector.projectRow(v, row.data(), camera.width, avx2.data(), lom::VectorKernels::UpToAvx2);
      projector.projectRow(v, row.data(), camera.width, baseline.data(), lom::VectorKernels::Baseline);
      EXPECT_EQ(packed, baseline) << "the AVX-512 and the baseline builds must agree";
      EXPECT_EQ(avx2, baseline) << "the AVX2 and the baseline builds must agree";
      for (int u = 0; u < camera.width; ++u) {
        const double z = row[static_cast<size_t>(u)];
        const double x = (u - camera.cx) / camera.fx, y = (v - camera.cy) / camera.fy;
        std::uint64_t expected = lom::kNoVoxel;
        if (z > 0.0 && std::isfinite(z)) {
          // The documented rule, computed per pixel.
          const Eigen::Vector3d point =
              pose.translation() +
              z * (pose.linear().col(0) * x + pose.linear().col(1) * y + pose.linear().col(2));
          lom::grid::Key key;
          if (grid.keyOf(point, key))
            expected = lom::packVoxel(key, (point - pose.translation()).norm() > max_range);
        }
        ASSERT_EQ(packed[static_cast<size_t>(u)], expected) << "pixel (" << u << ", " << v << ")";
      }
    }
    if (!lom::cpuHasAvx2()) GTEST_LOG_(INFO) << "no AVX2 here: both calls ran the baseline build";
  }
}

// The Morton codes of the voxels a walk visits, in the order it visits them.
std::vector<std::uint64_t> visitedCodes(const lom::grid::RayWalk& walk) {
  std::vector<std::uint64_t> visited;
  lom::grid::walkRay(walk, [&](unsigned x, unsigned y, unsigned z) {
    visited.push_back(lom::grid::mortonCode(static_cast<std::uint16_t>(x),
                                            static_cast<std::uint16_t>(y),
                                            static_cast<std::uint16_t>(z)));
  });
  return visited;
}

// The Morton codes of the voxels BrickSet marks for some walks, ascending:
// markWalk on each, or markWalks eight at a time (where the processor can).
std::vector<std::uint64_t> markedCodes(const std::vector<lom::grid::RayWalk>& walks,
                                       bool eight_at_once) {
  lom::BrickSet marks;
  if (eight_at_once)
    marks.markWalks(walks.data(), walks.size(), true);
  else
    for (const auto& walk : walks) marks.markWalk(walk);
  std::vector<lom::VoxelUpdate> misses;
  marks.appendMisses(misses);
  std::vector<std::uint64_t> marked;
  for (const auto& miss : misses) {
    marked.push_back(miss.morton);
    EXPECT_EQ(miss.morton, lom::grid::mortonCode(miss.key[0], miss.key[1], miss.key[2]));
  }
  return marked;
}
std::vector<std::uint64_t> markedCodes(const lom::grid::RayWalk& walk) {
  return markedCodes({walk}, false);
}

// The voxels some walks visit, ascending, each once.
std::vector<std::uint64_t> visitedSet(const std::vector<lom::grid::RayWalk>& walks) {
  std::vector<std::uint64_t> all;
  for (const auto& walk : walks) {
    const std::vector<std::uint64_t> visited = visitedCodes(walk);
    all.insert(all.end(), visited.begin(), visited.end());
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

// Checks the eight-lane marking against the walks: each walk alone (one lane)
// and all together (lanes taking the next walk as theirs end).
void expectEightLanesMarkWhatTheWalksVisit(const std::vector<lom::grid::RayWalk>& walks) {
  if (!lom::cpuHasAvx512()) return;
  for (size_t i = 0; i < walks.size(); ++i)
    ASSERT_EQ(markedCodes({walks[i]}, true), visitedSet({walks[i]})) << "walk " << i << " alone";
  ASSERT_EQ(markedCodes(walks, true), visitedSet(walks)) << walks.size() << " walks at once";
}

// The fast path marks each ray's voxels in bricks, in slices along the
// axis with the closest borders, a step at a time where a slice could hold
// two steps on one axis; the marked set must be exactly what traverseRay
// visits, in every direction, across brick borders, along axes, for short
// rays, on and next to diagonals (where slices give way to single steps),
// and just far enough from one for slices.
TEST(BrickSetTest, MarksExactlyTheVoxelsTraverseRayVisits) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-0.6, 0.6);
  std::uniform_int_distribution<int> kind(0, 9);
  for (const double resolution : {0.01, 0.005, 0.05}) {
    const lom::grid::Grid grid(resolution);
    std::vector<lom::grid::RayWalk> walks;
    for (int ray = 0; ray < 4000; ++ray) {
      Eigen::Vector3d origin(coordinate(random), coordinate(random), coordinate(random));
      Eigen::Vector3d end(coordinate(random), coordinate(random), coordinate(random));
      const int k = kind(random);
      if (k == 0) end[1] = origin[1];                     // in a plane
      if (k == 1) end.tail<2>() = origin.tail<2>();       // along x
      if (k == 2) end = origin + 0.3 * resolution * (end - origin).normalized();  // short
      if (k == 3) origin = grid.centerOf(lom::grid::Key{32768, 32768, 32768});  // from a voxel centre
      const double run = 0.5 * (end - origin).norm();
      const double sx = end[0] < origin[0] ? -run : run, sy = end[1] < origin[1] ? -run : run;
      if (k == 4) end = origin + Eigen::Vector3d(sx, sy, 0.3 * run);  // on a diagonal of x and y
      if (k == 5) end = origin + Eigen::Vector3d(sx, sy * (1 + 1e-13), -0.2 * run);  // next to one
      if (k == 6) end = origin + Eigen::Vector3d(sx, sy, sy);  // on the diagonal of the cube
      if (k == 7) end = origin + Eigen::Vector3d(sx, sy * (1 + 1e-9), 0.1 * run);  // just sliced
      // traverseRay's walk
      lom::grid::RayWalk walk;
      ASSERT_TRUE(lom::grid::setUpRay(grid, origin, end, walk));
      std::vector<std::uint64_t> visited = visitedCodes(walk);
      const std::vector<std::uint64_t> marked = markedCodes(walk);
      std::sort(visited.begin(), visited.end());
      visited.erase(std::unique(visited.begin(), visited.end()), visited.end());
      ASSERT_EQ(marked, visited) << "resolution " << resolution << ", ray " << ray;
      walks.push_back(walk);
      if (walks.size() == 37) {  // not a multiple of eight: lanes run dry at the end
        expectEightLanesMarkWhatTheWalksVisit(walks);
        walks.clear();
      }
    }
    expectEightLanesMarkWhatTheWalksVisit(walks);
  }
  if (!lom::cpuHasAvx512()) GTEST_LOG_(INFO) << "no AVX-512 here: eight-lane marking not checked";
}

// Walks whose border distances tie (binary fractions, so the sums stay
// exact), for every order of the axes by distance between borders and in
// every direction: the slices must take tied steps in nextAxis's order (the
// lower axis first), as the step-at-a-time walk does, also across bricks.
TEST(BrickSetTest, BreaksTiesBetweenAxesAsTheWalkDoes) {
  const double deltas[3] = {0.5, 0.75, 1.0};  // the slicing axis's, then the others'
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::mt19937 random(5);
  std::uniform_int_distribution<int> quarter(1, 4), offset(0, 31);
  size_t tied_walks = 0;
  std::vector<lom::grid::RayWalk> walks;
  for (const auto& order : orders) {
    for (int signs = 0; signs < 8; ++signs) {
      for (int start = 0; start < 6; ++start) {
        lom::grid::RayWalk walk;
        walk.length = 100.1;  // no border at this distance: the end voxel is well defined
        for (int i = 0; i < 3; ++i) {
          const int a = order[i];
          walk.step[a] = (signs >> a) & 1 ? -1 : 1;
          walk.t_delta[a] = deltas[i];
          walk.t_max[a] = start == 0 ? deltas[i] : deltas[i] * quarter(random) / 4.0;
          walk.key[a] = 32768 + offset(random);
          // The end voxel: one step per border before `length`.
          const int borders =
              static_cast<int>(std::floor((walk.length - walk.t_max[a]) / walk.t_delta[a])) + 1;
          walk.end_key[a] = walk.key[a] + walk.step[a] * borders;
        }
        walk.max_steps = 3 * 400 + 3;
        std::vector<std::uint64_t> visited = visitedCodes(walk);
        bool tied = false;
        for (double t = 0; t < walk.length && !tied; t += 1.0 / 16) {
          int at_t = 0;  // axes with a border at t
          for (int a = 0; a < 3; ++a) {
            const double k = (t - walk.t_max[a]) / walk.t_delta[a];
            at_t += k >= 0 && k == std::floor(k);
          }
          tied = at_t > 1;
        }
        tied_walks += tied;
        const std::vector<std::uint64_t> marked = markedCodes(walk);
        std::sort(visited.begin(), visited.end());
        ASSERT_EQ(visited.size(), std::set<std::uint64_t>(visited.begin(), visited.end()).size());
        ASSERT_EQ(marked, visited) << "order " << order[0] << order[1] << order[2] << ", signs "
                                   << signs << ", start " << start;
        walks.push_back(walk);
      }
    }
  }
  EXPECT_GT(tied_walks, 150u) << "most walks should have ties to break";
  expectEightLanesMarkWhatTheWalksVisit(walks);
}

// Walks the lanes leave to markWalk: a batch reaching over too many bricks
// (rays of a metre at 1 mm), and a walk whose step budget could end it early.
TEST(BrickSetTest, EightLanesLeaveFarReachingAndBudgetedWalksToOneAtATime) {
  if (!lom::cpuHasAvx512()) GTEST_SKIP() << "no AVX-512 here: eight-lane marking not used";
  const lom::grid::Grid fine(0.001);
  std::vector<lom::grid::RayWalk> far(3);
  ASSERT_TRUE(lom::grid::setUpRay(fine, {0.01, 0.02, 0.03}, {0.61, -0.52, 0.43}, far[0]));
  ASSERT_TRUE(lom::grid::setUpRay(fine, {0.01, 0.02, 0.03}, {-0.6, 0.4, -0.5}, far[1]));
  ASSERT_TRUE(lom::grid::setUpRay(fine, {0.01, 0.02, 0.03}, {0.3, 0.5, -0.6}, far[2]));
  EXPECT_EQ(markedCodes(far, true), visitedSet(far));

  const lom::grid::Grid grid(0.01);
  lom::grid::RayWalk budgeted;
  ASSERT_TRUE(lom::grid::setUpRay(grid, {0.001, 0.002, 0.003}, {0.31, 0.22, -0.13}, budgeted));
  budgeted.max_steps = 20;  // the walk stops after 20 steps, before its end voxel
  const std::vector<std::uint64_t> visited = visitedSet({budgeted});
  EXPECT_EQ(visited.size(), 21u);
  EXPECT_EQ(markedCodes({budgeted}, true), visited);
}

// The rays' set-up eight at a time gives setUpRay's walks to the last bit:
// ends at voxel centres and at max range, along axes (zero steps), in the
// origin's voxel, and outside the key range (left out, as setUpRay refuses
// them).
TEST(FastRaySetUpTest, EightAtATimeGivesSetUpRaysWalks) {
  if (!lom::cpuHasAvx512()) GTEST_SKIP() << "no AVX-512 here: the rays are set up one at a time";
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(-0.8, 0.8);
  std::uniform_int_distribution<int> kind(0, 7), offset(-90, 90);
  for (const double resolution : {0.01, 0.005, 0.037}) {
    const lom::grid::Grid grid(resolution);
    for (int frame = 0; frame < 40; ++frame) {
      Eigen::Vector3d origin(coordinate(random), coordinate(random), coordinate(random));
      // Every tenth frame from 3 voxels below the top of the key range on x:
      // rays beyond max range towards +x end outside it.
      const bool at_edge = frame % 10 == 9;
      if (at_edge) origin[0] = (lom::grid::kKeyOffset - 3) * resolution;
      lom::grid::Key origin_key;
      ASSERT_TRUE(grid.keyOf(origin, origin_key));
      const double max_range = 0.2 + 0.01 * frame;
      std::vector<std::uint64_t> voxels;
      for (int i = 0; i < 203; ++i) {  // not a multiple of eight
        lom::grid::Key key = origin_key;
        const int k = kind(random);
        for (int a = 0; a < 3; ++a)
          if (!(k == 1 && a > 0) && !(k == 2 && a == 1))  // along x; in a plane
            key[static_cast<size_t>(a)] =
                static_cast<std::uint16_t>(key[static_cast<size_t>(a)] + offset(random));
        if (k == 3) key = origin_key;  // the origin's own voxel
        if (k == 4)
          key[0] = static_cast<std::uint16_t>(65535 - (i % 3));  // the far end of the key range
        if (at_edge) {  // towards +x, ends inside the range
          key = origin_key;
          key[0] = static_cast<std::uint16_t>(origin_key[0] + 1 + i % 2);
          key[1] = static_cast<std::uint16_t>(origin_key[1] + i % 3);
        }
        voxels.push_back(lom::packVoxel(key, k >= 4 || i % 5 == 0));
      }
      std::vector<lom::grid::RayWalk> expected;
      for (const std::uint64_t voxel : voxels) {
        const lom::PixelRay ray = lom::unpackVoxel(voxel);
        lom::grid::RayWalk walk;
        if (lom::grid::setUpRay(grid, origin,
                                lom::rayEnd(grid, origin, ray.end_key, ray.beyond_range, max_range),
                                walk))
          expected.push_back(walk);
      }
      if (at_edge) {
        EXPECT_LT(expected.size(), voxels.size()) << "some ends outside the key range";
      }
      std::vector<lom::grid::RayWalk> walks(voxels.size());
      walks.resize(lom::setUpRaysAvx512(grid, origin, max_range, voxels.data(), voxels.size(),
                                        walks.data()));
      ASSERT_EQ(walks.size(), expected.size());
      for (size_t i = 0; i < walks.size(); ++i) {
        const lom::grid::RayWalk &a = walks[i], &b = expected[i];
        for (int axis = 0; axis < 3; ++axis) {
          ASSERT_EQ(a.key[axis], b.key[axis]) << "walk " << i;
          ASSERT_EQ(a.end_key[axis], b.end_key[axis]) << "walk " << i;
        }
        if (std::equal(a.key, a.key + 3, a.end_key)) continue;  // nothing else is set
        for (int axis = 0; axis < 3; ++axis) {
          ASSERT_EQ(a.step[axis], b.step[axis]) << "walk " << i;
          ASSERT_EQ(bitsOf64(a.t_max[axis]), bitsOf64(b.t_max[axis]))
              << "walk " << i << " axis " << axis;
          ASSERT_EQ(bitsOf64(a.t_delta[axis]), bitsOf64(b.t_delta[axis]))
              << "walk " << i << " axis " << axis;
        }
        ASSERT_EQ(bitsOf64(a.length), bitsOf64(b.length)) << "walk " << i;
        ASSERT_EQ(a.max_steps, b.max_steps) << "walk " << i;
      }
    }
  }
}

// Misses on saturated free space change nothing: the 4^3 blocks of a brick
// that the tree holds as saturated free space are left out of the miss
// stream, and nothing else is.
TEST(BrickSetTest, LeavesOutTheMissesOfSaturatedFreeBlocks) {
  lom::LabelMap map{lom::test::numberedLabels(3)};
  lom::LabelOcTree& tree = map.tree();
  const unsigned corner = 32768;  // a brick's first key on every axis
  auto miss = [&](unsigned x0, unsigned y0, unsigned z0, unsigned size, int times) {
    std::vector<octomap::OcTreeKey> keys;
    for (unsigned x = x0; x < x0 + size; ++x)
      for (unsigned y = y0; y < y0 + size; ++y)
        for (unsigned z = z0; z < z0 + size; ++z)
          keys.emplace_back(static_cast<std::uint16_t>(corner + x), static_cast<std::uint16_t>(corner + y),
                            static_cast<std::uint16_t>(corner + z));
    for (int t = 0; t < times; ++t) {
      for (const auto& key : keys) tree.applyMiss(key);
      tree.refreshAncestors(keys);
    }
  };
  miss(0, 0, 0, 4, 3);    // block 0: saturated
  miss(8, 4, 0, 4, 3);    // block 10 (child 1, grandchild 2): saturated
  miss(8, 8, 8, 8, 3);    // child 7, blocks 56-63: saturated
  miss(0, 4, 0, 4, 3);    // block 2: saturated but for one voxel,
  const octomap::OcTreeKey hit(static_cast<std::uint16_t>(corner + 1), static_cast<std::uint16_t>(corner + 5),
                               static_cast<std::uint16_t>(corner + 2));
  tree.applyHit(hit, std::vector<float>{0.5f, -0.5f, 0.f}.data());
  tree.refreshAncestors({hit});
  miss(4, 0, 0, 4, 2);    // block 1: missed twice, not saturated
  const octomap::OcTreeKey first(corner, corner, corner);
  EXPECT_EQ(tree.saturatedFreeBlocks(first), std::uint64_t{1} | std::uint64_t{1} << 10 | std::uint64_t{0xff} << 56);
  EXPECT_EQ(tree.saturatedFreeBlocks(octomap::OcTreeKey(corner + 16, corner, corner)), 0u) << "unknown space";

  // Rays through the brick along its edges and through the saturated blocks.
  const lom::grid::Grid grid(tree.getResolution());
  lom::BrickSet marks;
  auto key = [&](unsigned x, unsigned y, unsigned z) {
    return lom::grid::Key{static_cast<std::uint16_t>(corner + x), static_cast<std::uint16_t>(corner + y),
                          static_cast<std::uint16_t>(corner + z)};
  };
  const std::pair<lom::grid::Key, lom::grid::Key> rays[] = {
      {key(0, 0, 0), key(16, 0, 0)}, {key(0, 0, 0), key(0, 16, 0)},
      {key(0, 4, 0), key(16, 4, 0)}, {key(8, 8, 0), key(8, 8, 16)}};
  for (const auto& [from, to] : rays) {
    lom::grid::RayWalk walk;
    ASSERT_TRUE(lom::grid::setUpRay(grid, grid.centerOf(from), grid.centerOf(to), walk));
    marks.markWalk(walk);
  }
  std::vector<lom::VoxelUpdate> misses;
  EXPECT_EQ(marks.appendMisses(misses, &tree), 62u) << "every marked voxel is counted";
  std::vector<std::array<unsigned, 3>> kept;
  for (const auto& m : misses) kept.push_back({m.key[0] - corner, m.key[1] - corner, m.key[2] - corner});
  std::vector<std::array<unsigned, 3>> expected;
  for (unsigned x = 4; x < 16; ++x) expected.push_back({x, 0, 0});  // blocks 1, 8 and 9
  for (unsigned y = 4; y < 16; ++y) expected.push_back({0, y, 0});  // blocks 2, 16 and 18
  for (unsigned x = 1; x < 16; ++x)                                 // blocks 2, 3 and 11, not 10
    if (x < 8 || x >= 12) expected.push_back({x, 4, 0});
  for (unsigned z = 0; z < 8; ++z) expected.push_back({8, 8, z});   // blocks 24 and 28, not child 7
  std::sort(kept.begin(), kept.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(kept, expected);
}

}  // namespace
