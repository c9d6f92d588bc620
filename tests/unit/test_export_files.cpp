// Every exported file read back with the reader of the tool that uses the
// format (VTK's PLY/OBJ/STL readers, PCL's PCD/PLY readers, OctoMap's own
// tree readers) and compared with the map.
#include <gtest/gtest.h>
#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/height_colours.hpp"
#include "lom/objects.hpp"
#include "test_mesh_checks.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::blockKeys;
using lom::test::TempDir;

constexpr double kRes = 0.02;

// Label 1: a 3x3x3 block; label 2: a 2x2x2 block against its +x side (faces
// between two labels); label 3: an aligned 2x2x2 block that the tree prunes
// into one coarser leaf; a layer of free voxels underneath.
lom::LabelMap sampleMap() {
  return lom::test::MapBuilder(4, kRes)
      .occupy(blockKeys(0, 3, 0, 3, 0, 3), 1)
      .occupy(blockKeys(3, 5, 0, 2, 0, 2), 2)
      .occupy(blockKeys(8, 10, 0, 2, 0, 2), 3)
      .clear(blockKeys(-1, 11, -1, 4, -1, 0))
      .build();
}

const std::map<int, size_t> kVoxelsPerLabel = {{1, 27}, {2, 8}, {3, 8}};
constexpr double kCell = kRes * kRes * kRes;

struct ReadMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<lom::test::Triangle> triangles;
  vtkSmartPointer<vtkPolyData> poly;
};

ReadMesh fromPolyData(vtkPolyData* poly) {
  ReadMesh mesh;
  mesh.poly = poly;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    mesh.vertices.emplace_back(p[0], p[1], p[2]);
  }
  const auto it = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    EXPECT_EQ(n, 3);
    if (n == 3) mesh.triangles.push_back({ids[0], ids[1], ids[2]});
  }
  return mesh;
}

template <class Reader>
ReadMesh readWithVtk(const fs::path& path) {
  vtkNew<Reader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  return fromPolyData(reader->GetOutput());
}

void expectClosed(const ReadMesh& mesh, double volume, const std::string& what) {
  ASSERT_FALSE(mesh.triangles.empty()) << what;
  const auto edges = lom::test::edgeReport(mesh.triangles);
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u) << what;
  EXPECT_EQ(edges.directed_edges_repeated, 0u) << what;
  EXPECT_NEAR(lom::test::enclosedVolume(mesh.vertices, mesh.triangles), volume, 1e-9) << what;
}

using lom::test::slurp;

std::array<int, 3> rgbOf(const lom::Rgb& c) { return {c[0], c[1], c[2]}; }
template <class WithRgb>
std::array<int, 3> rgbOf(const WithRgb& p) {
  return {p.r, p.g, p.b};
}

lom::ExportOptions options(lom::ExportFormat format) {
  lom::ExportOptions o;
  o.format = format;
  return o;
}

size_t totalVoxels() {
  size_t n = 0;
  for (const auto& [label, count] : kVoxelsPerLabel) n += count;
  return n;
}

// Finest-resolution occupied keys of an OctoMap tree (pruned leaves expanded).
template <class Tree>
std::set<lom::VoxelKey> occupiedKeys(const Tree& tree) {
  std::set<lom::VoxelKey> keys;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const auto base = it.getIndexKey();
    const unsigned span = 1u << (tree.getTreeDepth() - it.getDepth());
    for (unsigned dx = 0; dx < span; ++dx)
      for (unsigned dy = 0; dy < span; ++dy)
        for (unsigned dz = 0; dz < span; ++dz)
          keys.insert({static_cast<std::uint16_t>(base[0] + dx),
                       static_cast<std::uint16_t>(base[1] + dy),
                       static_cast<std::uint16_t>(base[2] + dz)});
  }
  return keys;
}

std::set<lom::VoxelKey> mapOccupied(const lom::LabelMap& map) {
  std::set<lom::VoxelKey> keys;
  for (const auto& [label, list] : lom::occupiedVoxelsByLabel(map))
    keys.insert(list.begin(), list.end());
  return keys;
}

TEST(ExportFiles, VoxelsByLabelExpandPrunedLeaves) {
  const lom::LabelMap map = sampleMap();
  const auto voxels = lom::occupiedVoxelsByLabel(map);
  ASSERT_EQ(voxels.size(), 3u);
  for (const auto& [label, count] : kVoxelsPerLabel) {
    EXPECT_EQ(voxels.at(label).size(), count) << label;
    EXPECT_EQ(voxels.at(label), map.voxelsOfLabel(label)) << label;
  }
  EXPECT_EQ(lom::occupiedVoxelsByLabel(map, std::set<int>{2}).size(), 1u);
}

TEST(ExportFiles, PlyMeshReadsBackInVtkAndPcl) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  const auto summary = lom::exportMap(map, options(lom::ExportFormat::Ply), dir / "map.ply");
  ASSERT_EQ(summary.files, std::vector<fs::path>{dir / "map.ply"});

  const ReadMesh mesh = readWithVtk<vtkPLYReader>(dir / "map.ply");
  EXPECT_EQ(mesh.triangles.size(), summary.items);
  // Each label is closed on its own; faces between labels 1 and 2 are in both.
  expectClosed(mesh, totalVoxels() * kCell, "all labels");
  auto* colors = vtkUnsignedCharArray::SafeDownCast(mesh.poly->GetPointData()->GetArray("RGB"));
  ASSERT_NE(colors, nullptr);
  std::set<std::array<int, 3>> seen;
  for (vtkIdType i = 0; i < colors->GetNumberOfTuples(); ++i)
    seen.insert(
        {colors->GetValue(3 * i), colors->GetValue(3 * i + 1), colors->GetValue(3 * i + 2)});
  std::set<std::array<int, 3>> expected;
  for (int label = 1; label <= 3; ++label) {
    const auto c = map.labels().at(label).color;
    expected.insert({c[0], c[1], c[2]});
  }
  EXPECT_EQ(seen, expected);

  // PCL sees the label property on every vertex, with the label's colour.
  pcl::PolygonMesh pcl_mesh;
  ASSERT_EQ(pcl::io::loadPLYFile((dir / "map.ply").string(), pcl_mesh), 0);
  EXPECT_EQ(pcl_mesh.polygons.size(), summary.items);
  pcl::PointCloud<pcl::PointXYZRGBL> cloud;
  pcl::fromPCLPointCloud2(pcl_mesh.cloud, cloud);
  ASSERT_EQ(cloud.size(), mesh.vertices.size());
  std::map<int, size_t> vertices_per_label;
  for (const auto& p : cloud) {
    ++vertices_per_label[static_cast<int>(p.label)];
    const auto c = map.labels().at(static_cast<int>(p.label)).color;
    EXPECT_EQ(rgbOf(p), rgbOf(c));
  }
  EXPECT_EQ(vertices_per_label.size(), 3u);
  EXPECT_EQ(vertices_per_label.at(1), 8u);  // label 2 against its side does not change its box
  EXPECT_EQ(vertices_per_label.at(3), 8u);
}

TEST(ExportFiles, PerLabelFilesAreEachClosedAndNamedByLabel) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  auto o = options(lom::ExportFormat::Ply);
  o.per_label = true;
  const auto summary = lom::exportMap(map, o, dir / "meshes");
  ASSERT_EQ(summary.files.size(), 3u);
  for (const auto& [label, count] : kVoxelsPerLabel) {
    const fs::path file =
        dir / "meshes" / ("0" + std::to_string(label) + "_label_" + std::to_string(label) + ".ply");
    ASSERT_TRUE(fs::exists(file)) << file;
    expectClosed(readWithVtk<vtkPLYReader>(file), count * kCell, file.string());
  }
}

TEST(ExportFiles, ObjHasOneMaterialPerLabelAndReadsBackInVtk) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  const auto summary = lom::exportMap(map, options(lom::ExportFormat::Obj), dir / "map.obj");
  ASSERT_EQ(summary.files.size(), 2u);
  ASSERT_TRUE(fs::exists(dir / "map.mtl"));
  const ReadMesh mesh = readWithVtk<vtkOBJReader>(dir / "map.obj");
  EXPECT_EQ(mesh.triangles.size(), summary.items);
  expectClosed(mesh, totalVoxels() * kCell, "obj");
  const std::string obj = slurp(dir / "map.obj");
  const std::string mtl = slurp(dir / "map.mtl");
  EXPECT_NE(obj.find("mtllib map.mtl\n"), std::string::npos);
  for (int label = 1; label <= 3; ++label) {
    const std::string name = "0" + std::to_string(label) + "_label_" + std::to_string(label);
    EXPECT_NE(obj.find("usemtl " + name + "\n"), std::string::npos) << name;
    const auto at = mtl.find("newmtl " + name + "\n");
    ASSERT_NE(at, std::string::npos) << name;
    std::istringstream kd(mtl.substr(mtl.find("Kd ", at) + 3));
    double r, g, b;
    kd >> r >> g >> b;
    const auto c = map.labels().at(label).color;
    EXPECT_NEAR(r * 255, c[0], 1e-6);
    EXPECT_NEAR(g * 255, c[1], 1e-6);
    EXPECT_NEAR(b * 255, c[2], 1e-6);
  }
}

// The background is black in the VOC palette: meshes of it (every
// geometry-only recording) take the grey the studio and render shade it in.
TEST(ExportFiles, TheBackgroundsMeshIsGreyNotBlack) {
  TempDir dir;
  lom::LabelMap map(lom::apc2016Labels());
  lom::OrientedBox block;
  block.size = Eigen::Vector3d(0.05, 0.05, 0.05);
  ASSERT_GT(lom::rasterizeBox(map, block, 0, 0.9), 0u);
  auto o = options(lom::ExportFormat::Obj);
  o.labels = std::set<int>{0};
  (void)lom::exportMap(map, o, dir / "map.obj");
  const std::string mtl = slurp(dir / "map.mtl");
  std::istringstream kd(mtl.substr(mtl.find("Kd ") + 3));
  double r, g, b;
  kd >> r >> g >> b;
  EXPECT_NEAR(r * 255, 150, 1e-6) << mtl;
  EXPECT_NEAR(g * 255, 150, 1e-6) << mtl;
  EXPECT_NEAR(b * 255, 160, 1e-6) << mtl;

  // Point clouds and the colour octree too: black points vanish on a viewer's
  // black background.
  (void)lom::exportMap(map, options(lom::ExportFormat::Pcd), dir / "map.pcd");
  auto points = options(lom::ExportFormat::Ply);
  points.points = true;
  (void)lom::exportMap(map, points, dir / "points.ply");
  for (const fs::path& file : {dir / "map.pcd", dir / "points.ply"}) {
    pcl::PCLPointCloud2 blob;
    ASSERT_EQ(file.extension() == ".pcd" ? pcl::io::loadPCDFile(file.string(), blob)
                                         : pcl::io::loadPLYFile(file.string(), blob),
              0)
        << file;
    pcl::PointCloud<pcl::PointXYZRGBL> cloud;
    pcl::fromPCLPointCloud2(blob, cloud);
    ASSERT_FALSE(cloud.empty()) << file;
    for (const auto& p : cloud) {
      ASSERT_EQ(p.label, 0u) << file;
      ASSERT_EQ(rgbOf(p), rgbOf(lom::kShadedBackgroundColour)) << file;
    }
  }
  (void)lom::exportMap(map, options(lom::ExportFormat::Ot), dir / "color.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(
      octomap::AbstractOcTree::read((dir / "color.ot").string()));
  auto* color = dynamic_cast<octomap::ColorOcTree*>(tree.get());
  ASSERT_NE(color, nullptr);
  size_t occupied = 0;
  for (auto it = color->begin_leafs(), end = color->end_leafs(); it != end; ++it)
    if (color->isNodeOccupied(*it)) {
      ++occupied;
      EXPECT_EQ(rgbOf(it->getColor()), rgbOf(lom::kShadedBackgroundColour));
    }
  EXPECT_GT(occupied, 0u);
}

// A recording's world is its first camera's frame (y down): --level turns
// the map's up onto +z for tools that take z as up, says the rotation in the
// header, and keeps the meshes closed and the points where the voxels are.
TEST(ExportFiles, LevelledExportsTurnTheMapsUpOntoZ) {
  TempDir dir;
  lom::LabelMap map(lom::apc2016Labels());
  lom::OrientedBox slab;  // thin along the cameras' up (world -y)
  slab.center = Eigen::Vector3d(0.1, 0.3, 0.8);
  slab.size = Eigen::Vector3d(0.2, 0.04, 0.1);
  ASSERT_GT(lom::rasterizeBox(map, slab, 5, 0.9), 0u);
  EXPECT_FALSE(lom::levellingRotation(map));                   // no camera recorded: no up
  const Eigen::Matrix3d camera = Eigen::Matrix3d::Identity();  // looking along +z, image y down
  map.noteCameraView(camera);
  map.noteCameraView(camera);
  const auto rotation = lom::levellingRotation(map);
  ASSERT_TRUE(rotation);
  // The map's up: the cameras' (-y) levelled by the slab's plane, within 30 degrees of it.
  const auto up = map.upDirection();
  ASSERT_TRUE(up);
  EXPECT_GT(up->dot(Eigen::Vector3d(0, -1, 0)), std::cos(30.0 * M_PI / 180.0));
  EXPECT_NEAR((*rotation * *up - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(rotation->determinant(), 1.0, 1e-12);

  auto plain = options(lom::ExportFormat::Ply);
  (void)lom::exportMap(map, plain, dir / "plain.ply");
  auto level = plain;
  level.rotation = rotation;
  (void)lom::exportMap(map, level, dir / "level.ply");
  const ReadMesh before = readWithVtk<vtkPLYReader>(dir / "plain.ply");
  const ReadMesh after = readWithVtk<vtkPLYReader>(dir / "level.ply");
  ASSERT_EQ(after.vertices.size(), before.vertices.size());
  for (size_t i = 0; i < before.vertices.size(); ++i)
    ASSERT_LT((after.vertices[i] - *rotation * before.vertices[i]).norm(), 1e-5) << i;
  expectClosed(after, static_cast<double>(lom::occupiedVoxelsByLabel(map).at(5).size()) * 1e-6,
               "level.ply");
  const std::string header = slurp(dir / "level.ply").substr(0, 600);
  EXPECT_NE(header.find("comment frame: levelled, the map's world rotated about its origin by R ="),
            std::string::npos)
      << header;
  EXPECT_NE(slurp(dir / "plain.ply")
                .substr(0, 600)
                .find("comment frame: the map's world (the "
                      "sequence's poses), metres; its up is ("),
            std::string::npos);

  auto obj = options(lom::ExportFormat::Obj);
  obj.rotation = rotation;
  (void)lom::exportMap(map, obj, dir / "level.obj");
  EXPECT_EQ(slurp(dir / "level.obj").find("# frame: levelled"),
            slurp(dir / "level.obj").find('\n') + 1);

  auto points = options(lom::ExportFormat::Pcd);
  points.rotation = rotation;
  (void)lom::exportMap(map, points, dir / "level.pcd");
  pcl::PointCloud<pcl::PointXYZRGBL> cloud;
  ASSERT_EQ(pcl::io::loadPCDFile((dir / "level.pcd").string(), cloud), 0);
  ASSERT_FALSE(cloud.empty());
  for (const auto& p : cloud) {
    const Eigen::Vector3d world = rotation->transpose() * Eigen::Vector3d(p.x, p.y, p.z);
    ASSERT_TRUE(map.voxelAt(world).occupied) << world.transpose();
  }

  auto octree = options(lom::ExportFormat::Ot);
  octree.rotation = rotation;
  EXPECT_THROW((void)lom::exportMap(map, octree, dir / "level.ot"), lom::Error);
}

TEST(ExportFiles, StlPerLabelIsClosedAfterVtkMergesItsPoints) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  auto o = options(lom::ExportFormat::Stl);
  o.per_label = true;
  o.labels = std::set<int>{1, 3};
  const auto summary = lom::exportMap(map, o, dir / "stl");
  ASSERT_EQ(summary.files.size(), 2u);
  EXPECT_FALSE(fs::exists(dir / "stl" / "02_label_2.stl"));
  // 3x3x3 block: 12 triangles; the pruned 2x2x2 block: 12 triangles.
  for (const auto& [label, file] :
       {std::pair{1, "01_label_1.stl"}, std::pair{3, "03_label_3.stl"}}) {
    const ReadMesh mesh = readWithVtk<vtkSTLReader>(dir / "stl" / file);
    EXPECT_EQ(mesh.triangles.size(), 12u) << file;
    EXPECT_EQ(mesh.vertices.size(), 8u) << file;
    expectClosed(mesh, kVoxelsPerLabel.at(label) * kCell, file);
  }
}

TEST(ExportFiles, SmoothMeshesAreClosed) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  auto o = options(lom::ExportFormat::Ply);
  o.smooth = true;
  o.labels = std::set<int>{1};
  lom::exportMap(map, o, dir / "smooth.ply");
  const ReadMesh mesh = readWithVtk<vtkPLYReader>(dir / "smooth.ply");
  const auto edges = lom::test::edgeReport(mesh.triangles);
  EXPECT_EQ(edges.edges_not_shared_by_two, 0u);
  const double volume = lom::test::enclosedVolume(mesh.vertices, mesh.triangles);
  EXPECT_GT(volume, 0.3 * 27 * kCell);  // a rounded cube, smaller than the voxels
  EXPECT_LT(volume, 27 * kCell);
}

TEST(ExportFiles, PointCloudsReadBackInPcl) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  lom::exportMap(map, options(lom::ExportFormat::Pcd), dir / "v.pcd");
  auto ply = options(lom::ExportFormat::Ply);
  ply.points = true;
  lom::exportMap(map, ply, dir / "v.ply");
  for (const fs::path& file : {dir / "v.pcd", dir / "v.ply"}) {
    pcl::PCLPointCloud2 blob;
    const int rc = file.extension() == ".pcd" ? pcl::io::loadPCDFile(file.string(), blob)
                                              : pcl::io::loadPLYFile(file.string(), blob);
    ASSERT_EQ(rc, 0) << file;
    std::set<std::string> fields;
    for (const auto& f : blob.fields) fields.insert(f.name);
    for (const char* name : {"x", "y", "z", "rgb", "label", "probability"})
      EXPECT_TRUE(fields.count(name)) << file << " " << name;
    pcl::PointCloud<pcl::PointXYZRGBL> cloud;
    pcl::fromPCLPointCloud2(blob, cloud);
    ASSERT_EQ(cloud.size(), totalVoxels()) << file;
    std::set<lom::VoxelKey> keys;
    for (const auto& p : cloud) {
      const lom::VoxelKey key = map.keyOf(Eigen::Vector3d(p.x, p.y, p.z));
      EXPECT_LT((map.centerOf(key) - Eigen::Vector3d(p.x, p.y, p.z)).norm(), 1e-6);
      const lom::VoxelState state = map.voxelAt(key);
      EXPECT_TRUE(state.occupied);
      EXPECT_EQ(static_cast<int>(p.label), state.label);
      const auto c = map.labels().at(state.label).color;
      EXPECT_EQ(rgbOf(p), rgbOf(c));
      keys.insert(key);
    }
    EXPECT_EQ(keys, mapOccupied(map)) << file;
  }
}

TEST(ExportFiles, ColorOcTreeReadsBackWithOctomapAndKeepsOccupancyAndColours) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  lom::exportMap(map, options(lom::ExportFormat::Ot), dir / "color.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(
      octomap::AbstractOcTree::read((dir / "color.ot").string()));
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(tree->getTreeType(), "ColorOcTree");
  auto* color = dynamic_cast<octomap::ColorOcTree*>(tree.get());
  ASSERT_NE(color, nullptr);
  EXPECT_DOUBLE_EQ(color->getResolution(), kRes);
  EXPECT_EQ(occupiedKeys(*color), mapOccupied(map));
  for (auto it = color->begin_leafs(), end = color->end_leafs(); it != end; ++it) {
    if (!color->isNodeOccupied(*it)) continue;
    const octomap::point3d c = it.getCoordinate();
    const lom::VoxelState state = map.voxelAt(Eigen::Vector3d(c.x(), c.y(), c.z()));
    const auto expected = map.labels().at(state.label).color;
    const auto got = it->getColor();
    EXPECT_EQ(rgbOf(got), rgbOf(expected));
  }
  // Free space comes along: every cleared voxel is known and free.
  for (const auto& k : blockKeys(-1, 11, -1, 4, -1, 0)) {
    const auto* node = color->search(octomap::OcTreeKey(k.x, k.y, k.z));
    ASSERT_NE(node, nullptr);
    EXPECT_FALSE(color->isNodeOccupied(node));
  }
}

TEST(ExportFiles, ColorOcTreeWithLabelsKeepsOnlyThoseLabels) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  auto o = options(lom::ExportFormat::Ot);
  o.labels = std::set<int>{2};
  lom::exportMap(map, o, dir / "two.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(
      octomap::AbstractOcTree::read((dir / "two.ot").string()));
  auto* color = dynamic_cast<octomap::ColorOcTree*>(tree.get());
  ASSERT_NE(color, nullptr);
  const auto keys = map.voxelsOfLabel(2);
  EXPECT_EQ(occupiedKeys(*color), std::set<lom::VoxelKey>(keys.begin(), keys.end()));
}

TEST(ExportFiles, ThresholdOtherThanOneHalfIsCarriedIntoTheOccupancy) {
  TempDir dir;
  lom::LabelMap map = sampleMap();
  map.setOccupancyThreshold(0.9);  // p = 0.88 voxels become free
  EXPECT_TRUE(mapOccupied(map).empty());
  map.setOccupancyThreshold(0.25);  // missed voxels (p = 0.3) become occupied
  lom::exportMap(map, options(lom::ExportFormat::Bt), dir / "t.bt");
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary((dir / "t.bt").string()));
  EXPECT_EQ(occupiedKeys(tree), mapOccupied(map));
}

TEST(ExportFiles, BinaryOcTreeReadsBackWithOctomap) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  const auto summary = lom::exportMap(map, options(lom::ExportFormat::Bt), dir / "map.bt");
  EXPECT_GT(summary.items, 0u);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary((dir / "map.bt").string()));
  EXPECT_DOUBLE_EQ(tree.getResolution(), kRes);
  EXPECT_EQ(occupiedKeys(tree), mapOccupied(map));
  // The count reported is what the file holds (OctoMap prunes when writing it).
  EXPECT_EQ(summary.items, tree.getNumLeafNodes());
  const auto* free_node = tree.search(octomap::OcTreeKey(32768, 32768, 32767));
  ASSERT_NE(free_node, nullptr);
  EXPECT_FALSE(tree.isNodeOccupied(free_node));
}

TEST(ExportFiles, NativeOtIsTheLabelOcTree) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  auto o = options(lom::ExportFormat::Ot);
  o.native = true;
  lom::exportMap(map, o, dir / "native.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(
      octomap::AbstractOcTree::read((dir / "native.ot").string()));
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(tree->getTreeType(), "LabelOcTree");
  const lom::LabelMap back = lom::LabelMap::load(dir / "native.ot");
  EXPECT_EQ(back.occupiedCountPerLabel(), map.occupiedCountPerLabel());
  EXPECT_EQ(back.labels(), map.labels());
}

TEST(ExportFiles, ObjectsJsonHasBoxCentroidAndCountPerLabel) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  const auto summary = lom::exportMap(map, options(lom::ExportFormat::Objects), dir / "o.json");
  EXPECT_EQ(summary.items, 3u);
  const auto json = nlohmann::json::parse(slurp(dir / "o.json"));
  EXPECT_EQ(json.at("format"), "labeloctomap-objects");
  EXPECT_EQ(json.at("version"), 1);
  EXPECT_DOUBLE_EQ(json.at("resolution").get<double>(), kRes);
  ASSERT_EQ(json.at("objects").size(), 3u);
  for (const auto& object : json.at("objects")) {
    const int label = object.at("label");
    const auto keys = map.voxelsOfLabel(label);
    EXPECT_EQ(object.at("voxels").get<size_t>(), keys.size());
    EXPECT_EQ(object.at("cluster_voxels").get<size_t>(), keys.size());
    EXPECT_EQ(object.at("name"), map.labels().at(label).name);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& k : keys) mean += map.centerOf(k);
    mean /= static_cast<double>(keys.size());
    const auto centroid = object.at("centroid").get<std::vector<double>>();
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(centroid[static_cast<size_t>(a)], mean[a], 1e-12);
    lom::OrientedBox box;
    const auto c = object.at("center").get<std::vector<double>>();
    const auto s = object.at("size").get<std::vector<double>>();
    const auto q = object.at("rotation").get<std::vector<double>>();
    box.center = {c[0], c[1], c[2]};
    box.size = {s[0], s[1], s[2]};
    box.rotation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    EXPECT_NEAR(box.volume(), keys.size() * kCell, 1e-9) << label;  // blocks fit exactly
    for (const auto& k : keys) EXPECT_TRUE(box.contains(map.centerOf(k), 1e-9));
  }
}

TEST(ExportFiles, ObjectsDropOutlierVoxelsFromTheBox) {
  TempDir dir;
  const lom::LabelMap map = lom::test::MapBuilder(3, kRes)
                                .occupy(blockKeys(0, 4, 0, 4, 0, 4), 1)
                                .occupy(blockKeys(20, 21, 0, 1, 0, 1), 1)  // a stray voxel
                                .build();
  lom::exportMap(map, options(lom::ExportFormat::Objects), dir / "o.json");
  const auto json = nlohmann::json::parse(slurp(dir / "o.json"));
  ASSERT_EQ(json.at("objects").size(), 1u);
  const auto& object = json.at("objects")[0];
  EXPECT_EQ(object.at("voxels"), 65);
  EXPECT_EQ(object.at("label_voxels"), 65) << "as plan.json names them";
  EXPECT_EQ(object.at("cluster_voxels"), 64);
  const auto size = object.at("size").get<std::vector<double>>();
  EXPECT_NEAR(size[0] * size[1] * size[2], 64 * kCell, 1e-9);
  EXPECT_NEAR(object.at("centroid")[0].get<double>(), 2 * kRes, 1e-12);
  EXPECT_NEAR(object.at("mean_probability").get<double>(), lom::probabilityFromLogOdds(2.0), 1e-6);
}

TEST(ExportFiles, FileStemsArePaddedIdsAndSafeNames) {
  const lom::LabelSet apc = lom::apc2016Labels();
  EXPECT_EQ(lom::labelFileStem(apc.at(8), apc.size()), "08_creativity_chenille_stems");
  EXPECT_EQ(lom::labelFileStem({3, "Big Box/2", {}}, 200), "003_big_box_2");
  EXPECT_EQ(lom::labelFileStem({5, "", {}}, 10), "05");
  // The longest label names make file names that fit, with room for a temporary prefix and suffix.
  const std::string stem = lom::labelFileStem({12, std::string(255, 'a'), {}}, 40);
  EXPECT_EQ(stem, "12_" + std::string(200, 'a'));
}

TEST(ExportFiles, UnusableRequestsNameTheOptionAndWriteNothing) {
  TempDir dir;
  const lom::LabelMap map = sampleMap();
  const auto expectError = [&](lom::ExportOptions o, const fs::path& out,
                               const std::string& field) {
    try {
      lom::exportMap(map, o, out);
      ADD_FAILURE() << "no error for " << field;
    } catch (const lom::Error& e) {
      EXPECT_EQ(e.problem().field, field) << e.what();
    }
  };
  expectError(options(lom::ExportFormat::Ply), dir / "map.stl", "output path");
  auto o = options(lom::ExportFormat::Ply);
  o.labels = std::set<int>{1, 9};
  expectError(o, dir / "map.ply", "labels");
  o = options(lom::ExportFormat::Pcd);
  o.smooth = true;
  expectError(o, dir / "map.pcd", "smooth");
  o = options(lom::ExportFormat::Bt);
  o.per_label = true;
  expectError(o, dir / "bt", "per-label");
  o = options(lom::ExportFormat::Ply);
  o.labels = std::set<int>{0};  // known label without occupied voxels
  expectError(o, dir / "map.ply", "map");
  expectError(options(lom::ExportFormat::Ply), dir / "missing" / "map.ply", "output path");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
