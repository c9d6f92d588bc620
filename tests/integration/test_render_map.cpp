// Offscreen pictures of a known map: not blank, in the label colours, and a
// recorded pinhole camera puts each object where the camera model says.
// Needs an X server (the test run goes under xvfb-run); skips without one.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <string>

#include "lom/fusion.hpp"
#include "lom/height_colours.hpp"
#include "lom/sequence.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

#ifdef LOM_HAVE_RENDER
#include "../unit/test_mesh_checks.hpp"
#include "lom/render/map_render.hpp"
#include "lom/score_breakdown.hpp"

namespace {

using lom::test::blockKeys;

constexpr double kRes = 0.02;

#define LOM_REQUIRE_DISPLAY()                                               \
  do {                                                                      \
    if (const auto problem = lom::render::displayProblem())                 \
      GTEST_SKIP() << "no X display for offscreen rendering: " << *problem; \
  } while (0)

// Label 1: a 6x6x6 block at the origin; label 2: a 4x4x4 block beside it
// along +y; label 3: a 4x4x4 block beside it along -y.
lom::LabelMap sampleMap() {
  return lom::test::MapBuilder(4, kRes)
      .occupy(blockKeys(0, 6, 0, 6, 0, 6), 1)
      .occupy(blockKeys(1, 5, 10, 14, 1, 5), 2)
      .occupy(blockKeys(1, 5, -8, -4, 1, 5), 3)
      .build();
}

std::array<int, 3> pixel(const lom::ColorImage& image, int u, int v) {
  const size_t i = (static_cast<size_t>(v) * image.width + u) * 3;
  return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
}

std::array<int, 3> rgb(const lom::Rgb& c) { return {c[0], c[1], c[2]}; }

size_t countColour(const lom::ColorImage& image, const std::array<int, 3>& colour) {
  size_t n = 0;
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) n += pixel(image, u, v) == colour;
  return n;
}

// Pixels that are the colour scaled by one factor (a lit face of that colour).
size_t countShade(const lom::ColorImage& image, const std::array<int, 3>& colour) {
  const int top = std::max({colour[0], colour[1], colour[2]});
  size_t n = 0;
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) {
      const auto p = pixel(image, u, v);
      const double s = std::max({p[0], p[1], p[2]}) / static_cast<double>(top);
      if (s < 0.25) continue;
      bool match = true;
      for (int c = 0; c < 3; ++c) match = match && std::abs(p[c] - s * colour[c]) <= 3.0;
      n += match;
    }
  return n;
}

// Options of a flat (unlit) picture: every face exactly its colour.
lom::render::RenderOptions flatPicture(int width, int height) {
  lom::render::RenderOptions options;
  options.width = width;
  options.height = height;
  options.shading = false;
  return options;
}

TEST(RenderMap, FlatPictureShowsEveryLabelInItsColour) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options = flatPicture(320, 240);
  const lom::ColorImage image = lom::render::renderMap(map, options);
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  const size_t background = countColour(image, {255, 255, 255});
  size_t labelled = 0;
  for (int label = 1; label <= 3; ++label) {
    const size_t n = countColour(image, rgb(map.labels().at(label).color));
    EXPECT_GT(n, 200u) << "label " << label;
    labelled += n;
  }
  EXPECT_GT(labelled, 320u * 240 / 20);          // not blank: the map fills a good part of the view
  EXPECT_EQ(background + labelled, 320u * 240);  // nothing but background and label colours
}

TEST(RenderMap, ScoreColoursShowEachVoxelAgainstItsLabelsBox) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options = flatPicture(320, 240);
  // Label 1's box: x from -0.001 to 0.05 (two voxel layers inside, the third
  // half inside, three outside), all of y and z. Labels 2 and 3 have none.
  lom::GroundTruthBox box;
  box.label = 1;
  box.box.center = {0.0245, 0.06, 0.06};
  box.box.size = {0.051, 0.122, 0.122};
  options.score = lom::render::ScoreColours{{box}, lom::IouMode::Exact};
  const lom::ColorImage image = lom::render::renderMap(map, options);
  const size_t inside = countColour(image, rgb(lom::scoreShareColour(1.0)));
  const size_t partly = countColour(image, rgb(lom::scoreShareColour(0.5)));
  const size_t outside = countColour(image, rgb(lom::scoreShareColour(0.0)));
  const size_t grey = countColour(image, {195, 195, 200});
  EXPECT_GT(inside, 200u);
  EXPECT_GT(partly, 100u);
  EXPECT_GT(outside, 200u);
  EXPECT_GT(grey, 200u) << "labels without a box";
  for (int label = 1; label <= 3; ++label)
    EXPECT_EQ(countColour(image, rgb(map.labels().at(label).color)), 0u) << "label " << label;
  EXPECT_EQ(countColour(image, {255, 255, 255}) + inside + partly + outside + grey, 320u * 240)
      << "nothing but the background and the score colours";

  // Centre counting has no partial voxels: only green and red.
  options.score->mode = lom::IouMode::Center;
  const lom::ColorImage centres = lom::render::renderMap(map, options);
  EXPECT_EQ(countColour(centres, {255, 255, 255}) + countColour(centres, {195, 195, 200}) +
                countColour(centres, rgb(lom::scoreShareColour(1.0))) +
                countColour(centres, rgb(lom::scoreShareColour(0.0))),
            320u * 240);
}

TEST(RenderMap, ShadedPictureShowsShadesOfTheLabelColours) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options;
  options.width = 320;
  options.height = 240;
  options.azimuth_deg = 200;
  options.elevation_deg = 40;
  const lom::ColorImage image = lom::render::renderMap(map, options);
  for (int label = 1; label <= 3; ++label)
    EXPECT_GT(countShade(image, rgb(map.labels().at(label).color)), 200u) << "label " << label;
  EXPECT_LT(countColour(image, {255, 255, 255}), 320u * 240 * 19 / 20);
}

TEST(RenderMap, LabelSelectionHidesTheOtherLabels) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options = flatPicture(160, 120);
  options.labels = std::set<int>{2};
  const lom::ColorImage image = lom::render::renderMap(map, options);
  EXPECT_GT(countColour(image, rgb(map.labels().at(2).color)), 100u);
  EXPECT_EQ(countColour(image, rgb(map.labels().at(1).color)), 0u);
  EXPECT_EQ(countColour(image, rgb(map.labels().at(3).color)), 0u);
}

// Label 1: a 6x6x6 block; label 2: one voxel 1.2 m away, like a flying pixel.
lom::LabelMap blockAndSpeck() {
  return lom::test::MapBuilder(3, kRes)
      .occupy(blockKeys(0, 6, 0, 6, 0, 6), 1)
      .occupy(blockKeys(60, 61, 0, 1, 0, 1), 2)
      .build();
}

TEST(RenderMap, OrbitFramesTheBulkOfTheMapNotItsSpecks) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = blockAndSpeck();
  lom::render::RenderOptions options = flatPicture(320, 240);
  lom::render::OrbitFraming framing;
  const lom::ColorImage bulk = lom::render::renderMap(map, options, &framing);
  EXPECT_EQ(framing.framed.size(), 216u);
  EXPECT_EQ(framing.selected_voxels, 217u);
  EXPECT_EQ(framing.leftOut(), 1u);
  const auto block = rgb(map.labels().at(1).color), speck = rgb(map.labels().at(2).color);
  const size_t block_filling = countColour(bulk, block);
  EXPECT_GT(block_filling, 320u * 240 / 5) << "the block fills the picture";
  EXPECT_EQ(countColour(bulk, speck), 0u) << "the speck is outside it";

  options.frame_all = true;
  const lom::ColorImage all = lom::render::renderMap(map, options, &framing);
  EXPECT_EQ(framing.framed.size(), 217u);
  EXPECT_EQ(framing.leftOut(), 0u);
  EXPECT_GT(countColour(all, speck), 0u) << "every voxel is in the picture";
  EXPECT_LT(countColour(all, block) * 4, block_filling) << "so the block is small";
}

TEST(RenderMap, FramingJoinsLabelsAndKeepsEverythingWhenAllAreSpecks) {
  // Two 2x2x1 halves of different labels touch: one part of 8 voxels.
  const lom::LabelMap halves = lom::test::MapBuilder(3, kRes)
                                   .occupy(blockKeys(0, 2, 0, 2, 0, 1), 1)
                                   .occupy(blockKeys(0, 2, 0, 2, 1, 2), 2)
                                   .occupy(blockKeys(40, 41, 0, 1, 0, 1), 2)
                                   .build();
  lom::render::RenderOptions options;
  EXPECT_EQ(lom::render::orbitFraming(halves, options).framed.size(), 8u);
  // Label 1 alone is a speck of 4 voxels: with nothing larger, it is all framed.
  options.labels = std::set<int>{1};
  EXPECT_EQ(lom::render::orbitFraming(halves, options).framed.size(), 4u);
  EXPECT_EQ(lom::render::orbitFraming(halves, options).leftOut(), 0u);
}

// A 200x150 camera 0.5 m in front of the blocks (-x), looking along +x, image
// x = world -y, with its principal point at (cx, cy).
lom::render::PinholeView cameraBeforeTheBlocks(double cx, double cy) {
  lom::render::PinholeView view;
  view.intrinsics.width = 200;
  view.intrinsics.height = 150;
  view.intrinsics.fx = view.intrinsics.fy = 180.0;
  view.intrinsics.cx = cx;
  view.intrinsics.cy = cy;
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(0, -1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, -1);
  R.col(2) = Eigen::Vector3d(1, 0, 0);
  view.T_world_camera.linear() = R;
  view.T_world_camera.translation() = Eigen::Vector3d(-0.5, 0.06, 0.06);
  return view;
}

TEST(RenderMap, PinholeCameraPutsObjectsWhereTheCameraModelProjectsThem) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  const lom::render::PinholeView view = cameraBeforeTheBlocks(70.0, 80.0);  // off-centre
  lom::render::RenderOptions options = flatPicture(200, 150);
  options.camera = view;
  const lom::ColorImage image = lom::render::renderMap(map, options);

  const auto project = [&](const Eigen::Vector3d& p_world) {
    const Eigen::Vector3d p_camera = view.T_world_camera.inverse() * p_world;
    return view.intrinsics.project(p_camera);
  };
  // Centres of the blocks' faces towards the camera (x = 0 or x = 1 voxel).
  const Eigen::Vector3d faces[3] = {{0.0, 0.06, 0.06}, {0.02, 0.24, 0.06}, {0.02, -0.12, 0.06}};
  for (int label = 1; label <= 3; ++label) {
    const Eigen::Vector2d uv = project(faces[label - 1]);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    ASSERT_TRUE(u >= 0 && u < 200 && v >= 0 && v < 150) << label << ": " << uv.transpose();
    EXPECT_EQ(pixel(image, u, v), rgb(map.labels().at(label).color)) << "label " << label;
  }
  // The optical axis hits label 1's face centre: the principal point pixel.
  EXPECT_EQ(pixel(image, 70, 80), rgb(map.labels().at(1).color));
  // The edges of label 1's face project 3 voxels (0.06 m) off the axis at 0.5 m:
  // 180 * 0.06 / 0.5 = 21.6 pixels; 2 pixels inside is label 1, 2 outside is not.
  EXPECT_EQ(pixel(image, 70 + 19, 80), rgb(map.labels().at(1).color));
  EXPECT_NE(pixel(image, 70, 80 + 24), rgb(map.labels().at(1).color));
  EXPECT_EQ(pixel(image, 70, 80 - 19), rgb(map.labels().at(1).color));
  EXPECT_EQ(pixel(image, 70, 80 - 24), (std::array<int, 3>{255, 255, 255}));
}

// A camera whose pixels are not square (fx != fy): the picture is narrower
// across than down by fx / fy, as the camera model projects the blocks.
TEST(RenderMap, PinholeCameraHonoursBothFocalLengths) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::PinholeView view = cameraBeforeTheBlocks(90.0, 70.0);
  view.intrinsics.fx = 120.0;       // fy stays 180
  for (const int scale : {1, 2}) {  // the camera's size, and --size twice as large
    SCOPED_TRACE(scale);
    lom::render::RenderOptions options = flatPicture(200 * scale, 150 * scale);
    options.camera = view;
    const lom::ColorImage image = lom::render::renderMap(map, options);
    const auto label = [&](double u, double v) {
      const auto p = pixel(image, static_cast<int>(std::lround(u * scale)),
                           static_cast<int>(std::lround(v * scale)));
      for (int l = 1; l <= 3; ++l)
        if (p == rgb(map.labels().at(l).color)) return l;
      return 0;
    };
    const auto project = [&](const Eigen::Vector3d& p_world) {
      const Eigen::Vector2d uv = view.intrinsics.project(view.T_world_camera.inverse() * p_world);
      // Pixel centres of the scaled picture: (u + 0.5) * scale - 0.5.
      return Eigen::Vector2d((uv.x() + 0.5) - 0.5 / scale, (uv.y() + 0.5) - 0.5 / scale);
    };
    // Face centres of the three blocks towards the camera.
    const Eigen::Vector3d faces[3] = {{0.0, 0.06, 0.06}, {0.02, 0.24, 0.06}, {0.02, -0.12, 0.06}};
    for (int l = 1; l <= 3; ++l) {
      const Eigen::Vector2d uv = project(faces[l - 1]);
      EXPECT_EQ(label(uv.x(), uv.y()), l) << "label " << l << " at " << uv.transpose();
    }
    // Label 1's face reaches 0.06 m off the axis at 0.5 m: 14.4 pixels
    // across (fx), 21.6 down (fy).
    EXPECT_EQ(label(90 + 12, 70), 1);
    EXPECT_EQ(label(90 - 12, 70), 1);
    EXPECT_EQ(label(90 + 17, 70), 0);
    EXPECT_EQ(label(90 - 17, 70), 0);
    EXPECT_EQ(label(90, 70 - 19), 1);
    EXPECT_EQ(label(90, 70 - 24), 0);
    // Label 2's face, 0.52 m away, spans y from 0.20 to 0.28 m: u = 90 - 120 (y - 0.06) / 0.52,
    // from 57.7 to 39.2 (with fx = fy, 40.2 to 13.8).
    EXPECT_EQ(label(90 - 120 * 0.14 / 0.52 - 2, 70), 2);
    EXPECT_EQ(label(90 - 120 * 0.22 / 0.52 + 2, 70), 2);
    EXPECT_EQ(label(90 - 120 * 0.22 / 0.52 - 3, 70), 0);
  }
}

// Shaded, the background label (black in the palette) is drawn in the grey
// the studio's 3D view uses, one rule for both (lom::shadedLabelColour).
TEST(RenderMap, ShadedBackgroundIsTheStudiosGrey) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = lom::test::MapBuilder(2, kRes)
                                .occupy(blockKeys(0, 6, 0, 6, 0, 1), 0)
                                .occupy(blockKeys(2, 4, 2, 4, 1, 3), 1)
                                .build();
  ASSERT_EQ(map.labels().at(0).color, (lom::Rgb{0, 0, 0}));
  EXPECT_EQ(lom::shadedLabelColour(map.labels(), 0), lom::kShadedBackgroundColour);
  lom::render::RenderOptions options;
  options.width = 320;
  options.height = 240;
  const lom::ColorImage image = lom::render::renderMap(map, options);
  EXPECT_GT(countShade(image, rgb(lom::kShadedBackgroundColour)), 500u);
  // Flat, it keeps its palette colour (a picture that serves as a label image).
  const lom::ColorImage flat = lom::render::renderMap(map, flatPicture(320, 240));
  EXPECT_GT(countColour(flat, {0, 0, 0}), 500u);
}

// The same camera turned around sees no voxel: an error, not a blank picture.
TEST(RenderMap, CameraThatSeesNoVoxelIsAnError) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::PinholeView view = cameraBeforeTheBlocks(100.0, 75.0);
  const Eigen::Matrix3d towards = view.T_world_camera.linear();
  // Turned half a turn about its image y axis: looking along -x, away from the blocks.
  view.T_world_camera.linear() = towards * Eigen::Vector3d(-1, 1, -1).asDiagonal();
  lom::render::RenderOptions options = flatPicture(200, 150);
  options.camera = view;
  try {
    (void)lom::render::renderMap(map, options);
    ADD_FAILURE() << "rendered a picture without any voxel";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "--camera");
    EXPECT_NE(e.problem().found.find("no voxel of the map in its view"), std::string::npos);
  }
  // With --labels only those are drawn: the message is about them, not the map.
  options.labels = std::set<int>{1};
  try {
    (void)lom::render::renderMap(map, options);
    ADD_FAILURE() << "rendered a picture without any voxel";
  } catch (const lom::Error& e) {
    EXPECT_NE(e.problem().found.find("no voxel of the selected labels in its view"),
              std::string::npos)
        << e.what();
  }
  options.labels.reset();
  // Turned back towards the blocks, it renders.
  view.T_world_camera.linear() = towards;
  options.camera = view;
  EXPECT_NO_THROW((void)lom::render::renderMap(map, options));
  // Seen voxels count even when drawn in the background's colour.
  options.labels = std::set<int>{1};
  options.background = map.labels().at(1).color;
  EXPECT_NO_THROW((void)lom::render::renderMap(map, options));
}

TEST(RenderMap, RecordedCameraViewMatchesTheGroundTruthLabels) {
  LOM_REQUIRE_DISPLAY();
  lom::test::TempDir dir;
  lom::SynthOptions synth;
  synth.seed = 4;
  synth.objects = 4;
  synth.frames = 4;
  synth.views = 3;
  synth.width = 160;
  synth.height = 120;
  synth.noise = false;
  synth.segmenter_mistakes = false;
  lom::writeSyntheticScene(synth, dir.path());
  const lom::Sequence sequence = lom::loadSequence(dir.path());
  lom::FusionOptions fusion;
  fusion.map.resolution = 0.005;
  const lom::LabelMap map = lom::fuseSequence(sequence, fusion);

  const size_t frame = 1;
  lom::render::RenderOptions options = flatPicture(160, 120);
  options.camera =
      lom::render::PinholeView{sequence.cameraOf(frame), sequence.frames[frame].T_world_camera};
  const lom::ColorImage image = lom::render::renderMap(map, options);
  const lom::LabelImage truth = lom::readLabelImage(sequence.pathOf(sequence.frames[frame].label));
  // Object pixels seen in the colour of their true label. Voxels are 5 mm
  // cubes, so silhouettes differ by a few pixels from the exact shapes.
  size_t objects = 0, agree = 0;
  for (int v = 0; v < truth.height; ++v)
    for (int u = 0; u < truth.width; ++u) {
      const int label = truth.at(u, v);
      if (label == 0) continue;
      ++objects;
      agree += pixel(image, u, v) == rgb(map.labels().at(label).color);
    }
  ASSERT_GT(objects, 500u);
  EXPECT_GT(static_cast<double>(agree) / objects, 0.8) << agree << " of " << objects;
  // Fusion recorded the cameras: the generated scene's world has z up.
  EXPECT_EQ(map.cameraViews().views, sequence.frames.size());
  ASSERT_TRUE(map.upDirection());
  // Levelled by the bin's floor: within a degree of z, whatever the cameras' pitch.
  EXPECT_GT(map.upDirection()->z(), std::cos(M_PI / 180.0)) << map.upDirection()->transpose();
  ASSERT_TRUE(map.levelPlane());
  ASSERT_TRUE(map.camerasUp());
}

// Mean picture row of the pixels of a colour (-1 when there are none).
double meanRow(const lom::ColorImage& image, const std::array<int, 3>& colour) {
  double sum = 0.0;
  size_t n = 0;
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u)
      if (pixel(image, u, v) == colour) {
        sum += v;
        ++n;
      }
  return n ? sum / static_cast<double>(n) : -1.0;
}

TEST(RenderMap, OrbitViewHasTheCamerasUpUpInThePicture) {
  LOM_REQUIRE_DISPLAY();
  // Label 2 lies along +y of label 1, label 3 along -y.
  lom::LabelMap map = sampleMap();
  const std::array<int, 3> plus_y = rgb(map.labels().at(2).color);
  const std::array<int, 3> minus_y = rgb(map.labels().at(3).color);
  lom::render::RenderOptions options = flatPicture(200, 200);
  options.elevation_deg = 10.0;
  // Cameras with the world as their own frame (image y down): -y is up.
  map.noteCameraView(Eigen::Matrix3d::Identity());
  map.noteCameraView(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix());
  EXPECT_LT((lom::render::orbitUp(map, options) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-9);
  const lom::ColorImage upright = lom::render::renderMap(map, options);
  ASSERT_GE(meanRow(upright, minus_y), 0.0);
  ASSERT_GE(meanRow(upright, plus_y), 0.0);
  EXPECT_LT(meanRow(upright, minus_y) + 40, meanRow(upright, plus_y));
  // --up overrides the map's cameras.
  options.up = Eigen::Vector3d(0, 3, 0);
  const lom::ColorImage turned = lom::render::renderMap(map, options);
  EXPECT_LT(meanRow(turned, plus_y) + 40, meanRow(turned, minus_y));
  options.up = Eigen::Vector3d::Zero();
  EXPECT_THROW((void)lom::render::renderMap(map, options), lom::Error);
  // Cameras that disagree on up: world +z.
  map.noteCameraView(Eigen::AngleAxisd(3.14159, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  map.noteCameraView(Eigen::AngleAxisd(3.14159, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  options.up.reset();
  EXPECT_FALSE(map.upDirection());
  EXPECT_LT((lom::render::orbitUp(map, options) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

TEST(RenderMap, SingleLabelMapIsColouredByHeightFromBlueToRed) {
  LOM_REQUIRE_DISPLAY();
  // Geometry without labels: one label, a column 20 voxels high along +z (the
  // map records no cameras, so up is +z).
  const lom::LabelMap map =
      lom::test::MapBuilder(1, kRes).occupy(blockKeys(0, 4, 0, 4, 0, 20), 0).build();
  lom::render::RenderOptions options = flatPicture(200, 200);
  options.elevation_deg = 20.0;
  EXPECT_EQ(lom::render::colouringFor(map, options), lom::VoxelColouring::Height);
  const lom::ColorImage image = lom::render::renderMap(map, options);
  // The top face is the highest: red. The side faces of the lowest layer have
  // their centres half a voxel up a 20-voxel span: 1/40 of the ramp.
  const auto top = rgb(lom::heightRampColour(1.0));
  const auto bottom_layer = rgb(lom::heightRampColour(0.5 / 20.0));
  const auto middle_layer = rgb(lom::heightRampColour(10.5 / 20.0));
  EXPECT_GT(countColour(image, top), 50u);
  EXPECT_GT(countColour(image, bottom_layer), 50u);
  EXPECT_GT(countColour(image, middle_layer), 50u);
  EXPECT_LT(meanRow(image, top) + 40, meanRow(image, middle_layer));
  EXPECT_LT(meanRow(image, middle_layer) + 40, meanRow(image, bottom_layer));
  EXPECT_EQ(countColour(image, rgb(map.labels().at(0).color)), 0u);

  // Asked for label colours: the label's colour, no ramp.
  options.colouring = lom::VoxelColouring::Labels;
  const lom::ColorImage labelled = lom::render::renderMap(map, options);
  EXPECT_GT(countColour(labelled, rgb(map.labels().at(0).color)), 500u);
  EXPECT_EQ(countColour(labelled, top), 0u);
}

TEST(RenderMap, LabelledMapKeepsLabelColoursUnlessHeightIsAsked) {
  LOM_REQUIRE_DISPLAY();
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options = flatPicture(160, 120);
  EXPECT_EQ(lom::render::colouringFor(map, options), lom::VoxelColouring::Labels);
  options.colouring = lom::VoxelColouring::Height;
  const lom::ColorImage image = lom::render::renderMap(map, options);
  for (int label = 1; label <= 3; ++label)
    EXPECT_EQ(countColour(image, rgb(map.labels().at(label).color)), 0u) << "label " << label;
  // Label 1's block is the tallest (6 voxels, from z = 0): its top is red.
  EXPECT_GT(countColour(image, rgb(lom::heightRampColour(1.0))), 50u);
}

TEST(RenderMap, OrbitViewFillsThePictureWithTheMapCentredAndWhole) {
  LOM_REQUIRE_DISPLAY();
  // A long, flat slab and a tall post at one end: a lopsided shape whose
  // bounding sphere is much larger than what the camera sees of it.
  const lom::LabelMap map = lom::test::MapBuilder(4, kRes)
                                .occupy(blockKeys(0, 40, 0, 6, 0, 2), 1)
                                .occupy(blockKeys(36, 40, 0, 6, 2, 20), 2)
                                .build();
  for (const double azimuth : {0.0, 120.0, 210.0}) {
    lom::render::RenderOptions options = flatPicture(320, 240);
    options.azimuth_deg = azimuth;
    options.elevation_deg = 25.0;
    const lom::ColorImage image = lom::render::renderMap(map, options);
    int left = image.width, right = -1, top = image.height, bottom = -1;
    for (int v = 0; v < image.height; ++v)
      for (int u = 0; u < image.width; ++u)
        if (pixel(image, u, v) != std::array<int, 3>{255, 255, 255}) {
          left = std::min(left, u), right = std::max(right, u);
          top = std::min(top, v), bottom = std::max(bottom, v);
        }
    ASSERT_GE(right, 0) << "azimuth " << azimuth;
    // Whole: a margin of background on every side.
    EXPECT_GT(left, 0) << azimuth;
    EXPECT_GT(top, 0) << azimuth;
    EXPECT_LT(right, image.width - 1) << azimuth;
    EXPECT_LT(bottom, image.height - 1) << azimuth;
    // Filling: the map spans most of the picture's width or height.
    EXPECT_TRUE(right - left > 0.8 * image.width || bottom - top > 0.8 * image.height)
        << azimuth << ": " << left << ".." << right << " x " << top << ".." << bottom;
    // Centred: equal margins within a tenth of the picture.
    EXPECT_NEAR(left, image.width - 1 - right, image.width / 10) << azimuth;
    EXPECT_NEAR(top, image.height - 1 - bottom, image.height / 10) << azimuth;
  }
}

TEST(RenderMap, PngOnDiskMatchesThePicture) {
  LOM_REQUIRE_DISPLAY();
  lom::test::TempDir dir;
  const lom::LabelMap map = sampleMap();
  lom::render::RenderOptions options = flatPicture(160, 120);
  lom::render::renderMapToPng(map, options, dir / "view.png");
  const lom::ColorImage png = lom::readColorImage(dir / "view.png");
  const lom::ColorImage image = lom::render::renderMap(map, options);
  ASSERT_EQ(png.width, 160);
  ASSERT_EQ(png.height, 120);
  EXPECT_EQ(png.rgb, image.rgb);
}

TEST(RenderMap, WithoutDisplayTheReasonSaysHowToRunIt) {
  const char* saved = std::getenv("DISPLAY");
  const std::string display = saved ? saved : "";
  ::unsetenv("DISPLAY");
  const auto problem = lom::render::displayProblem();
  EXPECT_THROW((void)lom::render::renderMap(sampleMap(), {}), lom::render::RenderUnavailable);
  if (!display.empty()) ::setenv("DISPLAY", display.c_str(), 1);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("xvfb-run"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("DISPLAY"), std::string::npos) << *problem;
}

}  // namespace

#else

TEST(RenderMap, NotBuilt) { GTEST_SKIP() << "lom_render is not built (LOM_BUILD_UI=OFF)"; }

#endif
