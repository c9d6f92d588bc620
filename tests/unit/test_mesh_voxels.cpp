// Voxel surface meshes: exact face counts for known voxel sets, watertightness
// (every edge in exactly two triangles, consistently oriented), enclosed
// volume n x resolution^3, topology where voxels touch only along an edge or
// at a corner; and the smooth (marching cubes) surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "lom/export.hpp"
#include "test_mesh_checks.hpp"

namespace {

using lom::SurfaceMesh;
using lom::VoxelKey;
using lom::test::blockKeys;
using lom::test::gridKey;

constexpr double kRes = 0.05;

struct Counts {
  size_t vertices, triangles;
};

Counts counts(const std::vector<VoxelKey>& keys, bool merge) {
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes, {merge});
  return {mesh.vertices.size(), mesh.triangles.size()};
}

// Closed, oriented, exact volume and area, no zero-area triangle, Euler characteristic.
void expectSound(const SurfaceMesh& mesh, size_t voxels, size_t unit_faces, int euler,
                 const std::string& what) {
  const auto triangles = lom::test::trianglesOf(mesh);
  const auto edges = lom::test::edgeReport(triangles);
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u) << what;
  EXPECT_EQ(edges.directed_edges_repeated, 0u) << what;
  const double cell = kRes * kRes * kRes;
  EXPECT_NEAR(lom::test::enclosedVolume(mesh.vertices, triangles), voxels * cell, 1e-9 * voxels)
      << what;
  EXPECT_NEAR(lom::test::surfaceArea(mesh.vertices, triangles), unit_faces * kRes * kRes,
              1e-9 * unit_faces)
      << what;
  EXPECT_GT(lom::test::smallestTriangleArea(mesh.vertices, triangles), 1e-6 * kRes * kRes) << what;
  const long chi = static_cast<long>(mesh.vertices.size()) - static_cast<long>(edges.edges) +
                   static_cast<long>(triangles.size());
  EXPECT_EQ(chi, euler) << what;
}

size_t unitFaces(const std::vector<VoxelKey>& keys) {
  const std::set<VoxelKey> set(keys.begin(), keys.end());
  size_t faces = 0;
  for (const auto& k : keys)
    for (int axis = 0; axis < 3; ++axis)
      for (int step : {-1, 1}) {
        VoxelKey n = k;
        (axis == 0 ? n.x : axis == 1 ? n.y : n.z) += static_cast<std::uint16_t>(step);
        faces += !set.count(n);
      }
  return faces;
}

TEST(VoxelSurface, OneVoxelIsACubeOfTwelveTriangles) {
  const auto keys = std::vector<VoxelKey>{gridKey(0, 0, 0)};
  for (const bool merge : {true, false}) {
    const Counts c = counts(keys, merge);
    EXPECT_EQ(c.vertices, 8u);
    EXPECT_EQ(c.triangles, 12u);
    expectSound(lom::voxelSurface(keys, kRes, {merge}), 1, 6, 2, "one voxel");
  }
}

TEST(VoxelSurface, VerticesAreVoxelCorners) {
  const SurfaceMesh mesh = lom::voxelSurface({gridKey(2, -1, 5)}, kRes);
  std::set<std::array<long, 3>> corners;
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d grid = v / kRes;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(grid[a], std::round(grid[a]), 1e-9);
    corners.insert({std::lround(grid.x()), std::lround(grid.y()), std::lround(grid.z())});
  }
  const std::set<std::array<long, 3>> expected = {{2, -1, 5}, {3, -1, 5}, {2, 0, 5}, {3, 0, 5},
                                                  {2, -1, 6}, {3, -1, 6}, {2, 0, 6}, {3, 0, 6}};
  EXPECT_EQ(corners, expected);
}

TEST(VoxelSurface, CoplanarFacesOfABoxMergeIntoTwelveTriangles) {
  // A 4 x 3 x 2 box: 52 unit faces, 104 triangles unmerged; 6 rectangles merged.
  const auto keys = blockKeys(0, 4, 0, 3, 0, 2);
  const Counts merged = counts(keys, true);
  EXPECT_EQ(merged.vertices, 8u);
  EXPECT_EQ(merged.triangles, 12u);
  const Counts unit = counts(keys, false);
  EXPECT_EQ(unit.triangles, 2 * 52u);
  EXPECT_EQ(unit.vertices, 5u * 4 * 3 - 3u * 2 * 1);  // lattice points on the surface
  for (const bool merge : {true, false})
    expectSound(lom::voxelSurface(keys, kRes, {merge}), keys.size(), 52, 2, "box");
}

TEST(VoxelSurface, StepKeepsTheVertexItsNeighbourNeeds) {
  // Two stacked bars of different length: the top of the long bar is a 1x1
  // rectangle beside the short bar's side; the long bar's side has the step
  // corner on it, which must stay a vertex of that side (no T-junction).
  std::vector<VoxelKey> keys = {gridKey(0, 0, 0), gridKey(1, 0, 0), gridKey(0, 0, 1)};
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes);
  expectSound(mesh, 3, unitFaces(keys), 2, "step");
  // Per y side 7 vertices are kept: the L's six corners and the step's foot
  // (1, 0), a corner of both y-side rectangles that the bottom rectangle must
  // keep on its side. (0, 1) is no rectangle's corner and is dropped.
  EXPECT_EQ(mesh.vertices.size(), 14u);
  EXPECT_EQ(mesh.triangles.size(), 24u);  // Euler: 2 (V - 2)
}

TEST(VoxelSurface, VoxelsTouchingAlongAnEdgeStayTwoClosedCubes) {
  const std::vector<VoxelKey> keys = {gridKey(0, 0, 0), gridKey(1, 1, 0)};
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes);
  EXPECT_EQ(mesh.vertices.size(), 16u);  // the shared edge's two corners exist twice
  EXPECT_EQ(mesh.triangles.size(), 24u);
  expectSound(mesh, 2, 12, 4, "edge contact");  // two spheres: chi = 4
}

TEST(VoxelSurface, VoxelsTouchingAtACornerStayTwoClosedCubes) {
  const std::vector<VoxelKey> keys = {gridKey(0, 0, 0), gridKey(1, 1, 1)};
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes);
  EXPECT_EQ(mesh.vertices.size(), 16u);
  expectSound(mesh, 2, 12, 4, "corner contact");
}

std::vector<VoxelKey> keysAt(const std::vector<std::array<int, 3>>& cells) {
  std::vector<VoxelKey> keys;
  for (const auto& c : cells) keys.push_back(gridKey(c[0], c[1], c[2]));
  return keys;
}

size_t halfLatticeVertices(const SurfaceMesh& mesh) {
  size_t n = 0;
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d grid = v / kRes;
    bool half = false;
    for (int a = 0; a < 3; ++a) half = half || std::abs(grid[a] - std::round(grid[a])) > 0.25;
    n += half;
  }
  return n;
}

TEST(VoxelSurface, EdgeContactOfConnectedVoxelsGetsAMidpointPerSide) {
  // Voxels (1,1,0) and (1,0,1) touch along the edge x in [1, 2] at y = z = 1,
  // with (1,0,0) a closed cavity below it, and are connected through the rest
  // around both ends of the edge. Each side of the edge gets its own midpoint.
  const auto keys = keysAt(
      {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {0, 0, 1}, {1, 0, 1}, {2, 0, 1}});
  for (const bool merge : {true, false}) {
    const SurfaceMesh mesh = lom::voxelSurface(keys, kRes, {merge});
    EXPECT_EQ(halfLatticeVertices(mesh), 2u);
    const auto triangles = lom::test::trianglesOf(mesh);
    const auto edges = lom::test::edgeReport(triangles);
    EXPECT_EQ(edges.edges_not_shared_by_two, 0u);
    EXPECT_EQ(edges.directed_edges_repeated, 0u);
    EXPECT_NEAR(lom::test::enclosedVolume(mesh.vertices, triangles), 8 * kRes * kRes * kRes, 1e-12);
  }
}

TEST(VoxelSurface, LongEdgeContactKeepsItsVerticesWhenSidesMerge) {
  // As above with a two voxel long cavity: the merged sides along the contact
  // keep the middle vertex, which tells the two sides apart.
  const auto keys = keysAt({{0, 0, 0},
                            {3, 0, 0},
                            {0, 1, 0},
                            {1, 1, 0},
                            {2, 1, 0},
                            {3, 1, 0},
                            {0, 0, 1},
                            {1, 0, 1},
                            {2, 0, 1},
                            {3, 0, 1}});
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes);
  const auto triangles = lom::test::trianglesOf(mesh);
  const auto edges = lom::test::edgeReport(triangles);
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u);
  EXPECT_EQ(edges.directed_edges_repeated, 0u);
  EXPECT_NEAR(lom::test::enclosedVolume(mesh.vertices, triangles), 10 * kRes * kRes * kRes, 1e-12);
}

TEST(VoxelSurface, RingHasGenusOne) {
  auto keys = blockKeys(0, 3, 0, 3, 0, 1);
  keys.erase(std::find(keys.begin(), keys.end(), gridKey(1, 1, 0)));
  for (const bool merge : {true, false})
    expectSound(lom::voxelSurface(keys, kRes, {merge}), 8, unitFaces(keys), 0, "ring");
}

TEST(VoxelSurface, HollowBoxHasAnInnerSurface) {
  // A 5x5x5 box with a 3x3x3 cavity: two closed surfaces, the inner one facing in.
  auto keys = blockKeys(0, 5, 0, 5, 0, 5);
  const auto cavity = blockKeys(1, 4, 1, 4, 1, 4);
  std::vector<VoxelKey> shell;
  std::set<VoxelKey> hole(cavity.begin(), cavity.end());
  for (const auto& k : keys)
    if (!hole.count(k)) shell.push_back(k);
  const SurfaceMesh mesh = lom::voxelSurface(shell, kRes);
  EXPECT_EQ(mesh.triangles.size(), 24u);
  expectSound(mesh, shell.size(), 6 * 25 + 6 * 9, 4, "hollow box");
}

// The surface of `keys` (possibly with repeats) is closed and oriented and
// encloses the volume and area of the distinct voxels `unique`, with no
// zero-area triangle; unmerged, two triangles per face and one more per face
// side with a midpoint.
void expectClosedSurface(const std::vector<VoxelKey>& keys, const std::vector<VoxelKey>& unique,
                         bool merge, const std::string& set, double tolerance) {
  const SurfaceMesh mesh = lom::voxelSurface(keys, kRes, {merge});
  const auto triangles = lom::test::trianglesOf(mesh);
  const auto edges = lom::test::edgeReport(triangles);
  const std::string what = set + (merge ? " merged" : " unit faces");
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u) << what;
  EXPECT_EQ(edges.directed_edges_repeated, 0u) << what;
  EXPECT_NEAR(lom::test::enclosedVolume(mesh.vertices, triangles),
              unique.size() * kRes * kRes * kRes, tolerance)
      << what;
  EXPECT_NEAR(lom::test::surfaceArea(mesh.vertices, triangles), unitFaces(unique) * kRes * kRes,
              tolerance)
      << what;
  EXPECT_GT(lom::test::smallestTriangleArea(mesh.vertices, triangles), 1e-6 * kRes * kRes) << what;
  if (!merge) {
    EXPECT_EQ(triangles.size(), 2 * unitFaces(unique) + 2 * halfLatticeVertices(mesh)) << what;
  }
}

TEST(VoxelSurface, RandomVoxelSetsAreClosedAndEncloseTheirVolume) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    std::bernoulli_distribution occupied(trial % 2 ? 0.3 : 0.6);
    std::vector<VoxelKey> keys;
    for (int i = -3; i < 4; ++i)
      for (int j = -3; j < 3; ++j)
        for (int k = 0; k < 5; ++k)
          if (occupied(rng)) keys.push_back(gridKey(i, j, k));
    for (const bool merge : {true, false})
      expectClosedSurface(keys, keys, merge, "trial " + std::to_string(trial), 1e-9);
    EXPECT_LT(counts(keys, true).triangles, counts(keys, false).triangles);
  }
}

// The builder files voxels in 4x4x4 bricks: a set spread over many bricks,
// with voxels on every side of brick borders, and voxels at both ends of the
// key range (whose outside neighbours, keys -1 and 65536, lie in bricks of
// their own), given in shuffled order with repeats.
TEST(VoxelSurface, SetsAcrossBricksAndAtTheEndsOfTheKeyRangeAreClosed) {
  std::mt19937 rng(23);
  std::bernoulli_distribution occupied(0.45);
  std::vector<VoxelKey> unique;
  for (int i = -9; i < 9; ++i)
    for (int j = -7; j < 10; ++j)
      for (int k = -8; k < 8; ++k)
        if (occupied(rng)) unique.push_back(gridKey(i, j, k));
  const std::uint16_t last = 65535;
  for (const VoxelKey& end :
       {VoxelKey{0, 0, 0}, VoxelKey{last, last, last}, VoxelKey{0, last, 3}, VoxelKey{last, 1, 0},
        VoxelKey{1, 0, 0}, VoxelKey{last, last, last - 1}})
    unique.push_back(end);
  std::vector<VoxelKey> keys = unique;
  keys.insert(keys.end(), unique.begin(),
              unique.begin() + static_cast<std::ptrdiff_t>(unique.size() / 3));
  std::shuffle(keys.begin(), keys.end(), rng);
  // Volume and area to 1e-6: vertices lie as far as 1,638 m from the origin.
  for (const bool merge : {true, false})
    expectClosedSurface(keys, unique, merge, "across bricks", 1e-6);
  // The same set in another order gives the same mesh.
  std::vector<VoxelKey> sorted = unique;
  std::sort(sorted.begin(), sorted.end());
  const SurfaceMesh a = lom::voxelSurface(keys, kRes), b = lom::voxelSurface(sorted, kRes);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(VoxelSurface, EmptySetGivesAnEmptyMesh) {
  const SurfaceMesh mesh = lom::voxelSurface({}, kRes);
  EXPECT_TRUE(mesh.vertices.empty());
  EXPECT_TRUE(mesh.triangles.empty());
}

// The voxels whose centres are within r voxel edges of the origin.
std::vector<VoxelKey> ballKeys(double r) {
  std::vector<VoxelKey> keys;
  const int n = static_cast<int>(r) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k)
        if (i * i + j * j + k * k <= r * r) keys.push_back(gridKey(i, j, k));
  return keys;
}

TEST(SmoothSurface, SphereIsClosedAndKeepsItsVolume) {
  const double r = 6.0;
  std::vector<VoxelKey> keys = ballKeys(r);
  const SurfaceMesh mesh = lom::smoothSurface(keys, kRes);
  ASSERT_FALSE(mesh.triangles.empty());
  const auto triangles = lom::test::trianglesOf(mesh);
  const auto edges = lom::test::edgeReport(triangles);
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u);
  EXPECT_EQ(edges.directed_edges_repeated, 0u);
  // Marching cubes cuts the voxel corners (about half a voxel layer less) and
  // smoothing shrinks a little more: within 25 % of the voxel volume, outward.
  const double volume = lom::test::enclosedVolume(mesh.vertices, triangles);
  const double voxels = keys.size() * kRes * kRes * kRes;
  EXPECT_GT(volume, 0.75 * voxels);
  EXPECT_LT(volume, 1.05 * voxels);
  // Smooth: no vertex on the voxel lattice corners' staircase far from the sphere.
  for (const auto& v : mesh.vertices) EXPECT_NEAR(v.norm() / kRes, r, 1.0);
}

// Smoothing pulls small parts into their centres (a lone voxel to a point,
// a 2x2x2 block to a seventh of its volume): those keep their voxel surface,
// while a large part in the same set is still smoothed.
TEST(SmoothSurface, SmallPartsKeepTheirVolume) {
  const double voxel = kRes * kRes * kRes;
  for (const auto& keys : {std::vector<VoxelKey>{gridKey(0, 0, 0)}, blockKeys(0, 2, 0, 2, 0, 2),
                           std::vector<VoxelKey>{gridKey(0, 0, 0), gridKey(1, 1, 0)}}) {
    SCOPED_TRACE(keys.size());
    const SurfaceMesh mesh = lom::smoothSurface(keys, kRes);
    const auto triangles = lom::test::trianglesOf(mesh);
    const auto edges = lom::test::edgeReport(triangles);
    EXPECT_EQ(edges.edges_not_shared_by_two, 0u);
    EXPECT_EQ(edges.directed_edges_repeated, 0u);
    const double volume = lom::test::enclosedVolume(mesh.vertices, triangles);
    EXPECT_GT(volume, 0.5 * keys.size() * voxel);
    EXPECT_LT(volume, 1.05 * keys.size() * voxel);
  }
  const double r = 6.0;
  std::vector<VoxelKey> keys = ballKeys(r);
  const size_t sphere = keys.size();
  keys.push_back(gridKey(20, 0, 0));
  const SurfaceMesh mesh = lom::smoothSurface(keys, kRes);
  const auto triangles = lom::test::trianglesOf(mesh);
  EXPECT_EQ(lom::test::edgeReport(triangles).edges_not_shared_by_two, 0u);
  const double volume = lom::test::enclosedVolume(mesh.vertices, triangles);
  EXPECT_GT(volume, 0.75 * sphere * voxel + 0.99 * voxel);
  EXPECT_LT(volume, 1.05 * sphere * voxel + 1.01 * voxel);
  size_t smooth = 0;  // vertices of the sphere off the voxel lattice
  for (const auto& v : mesh.vertices)
    if (v.norm() < 10 * kRes && std::abs(v.x() / kRes * 2 - std::round(v.x() / kRes * 2)) > 0.01)
      ++smooth;
  EXPECT_GT(smooth, 100u) << "the sphere is smoothed";
}

// Far-apart parts of one label are meshed on grids of their own extent: one
// grid across the whole key range needed terabytes.
TEST(SmoothSurface, FarApartPartsNeedNoGridBetweenThem) {
  const std::vector<VoxelKey> keys = {VoxelKey{1, 1, 1}, VoxelKey{65534, 65534, 65534}};
  const SurfaceMesh mesh = lom::smoothSurface(keys, kRes);
  const auto triangles = lom::test::trianglesOf(mesh);
  EXPECT_EQ(lom::test::edgeReport(triangles).edges_not_shared_by_two, 0u);
  EXPECT_EQ(triangles.size(), 24u) << "two voxels' boxes";
  // One part too large for a grid is refused, saying its size.
  std::vector<VoxelKey> line;
  for (int i = 0; i < 1200; ++i)
    line.push_back(VoxelKey{static_cast<std::uint16_t>(1000 + i),
                            static_cast<std::uint16_t>(1000 + i),
                            static_cast<std::uint16_t>(1000 + i)});
  try {
    (void)lom::smoothSurface(line, kRes);
    ADD_FAILURE() << "a diagonal of 1200 voxels spans 1.7 billion grid cells";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("1200 connected voxels spanning 1200 x 1200 x 1200"),
              std::string::npos)
        << e.what();
  }
}

TEST(SmoothSurface, WithoutSmoothingVerticesLieBetweenVoxelCentres) {
  const auto keys = blockKeys(0, 3, 0, 3, 0, 3);
  const SurfaceMesh mesh = lom::smoothSurface(keys, kRes, {0, 0.1});
  const auto triangles = lom::test::trianglesOf(mesh);
  EXPECT_EQ(lom::test::edgeReport(triangles).edges_not_shared_by_two, 0u);
  // The contour passes half way between inside and outside voxel centres.
  for (const auto& v : mesh.vertices)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(v[a], 0.0 - 1e-6);  // VTK keeps float coordinates
      EXPECT_LE(v[a], 3 * kRes + 1e-6);
    }
  EXPECT_GT(lom::test::enclosedVolume(mesh.vertices, triangles), 8 * kRes * kRes * kRes);
}

}  // namespace
