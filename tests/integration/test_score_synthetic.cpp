// The paper's finding on generated scenes with occlusions, and the evaluation's
// checks of its inputs.
#include <gtest/gtest.h>

#include <iostream>
#include <set>

#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/report.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace {

using lom::test::TempDir;

lom::SynthOptions sceneOptions(std::uint64_t seed, int width, int height, int frames) {
  lom::SynthOptions options;
  options.seed = seed;
  options.objects = 6;
  options.frames = frames;
  options.views = 3;
  options.width = width;
  options.height = height;
  return options;
}

TEST(ScoreSynthetic, LabelOctoMapBeatsProjectionMaxBeatsProjectionMean) {
  // Section V.B of the paper: three views of a cluttered bin; the mean IU_3d of
  // LabelOctoMap exceeds that of the best single view, which exceeds the mean view.
  std::vector<lom::ObjectScore> objects;
  for (std::uint64_t seed : {1, 2, 3, 4, 5, 6}) {
    TempDir dir;
    const lom::SynthScene scene = lom::writeSyntheticScene(sceneOptions(seed, 320, 240, 8), dir.path());
    const lom::Sequence sequence = lom::loadSequence(dir.path());
    const lom::EvaluationOptions options;
    const lom::LabelMap map = lom::fuseSequence(sequence, options.fusion);
    const lom::EvaluationReport report = lom::evaluate(sequence, scene.annotations, map, options);

    ASSERT_EQ(report.objects.size(), scene.annotations.boxes.size());
    EXPECT_EQ(report.views.size(), 3u);
    // The transparent bottle (seed 6) has pixels of its label, though no
    // depth: not a box of a label the views never hold.
    for (const std::string& warning : report.warnings)
      EXPECT_EQ(warning.find("no pixel of the views scored has"), std::string::npos) << warning;
    for (const auto& o : report.objects) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " " + o.name);
      ASSERT_EQ(o.per_view.size(), 3u);
      EXPECT_GE(o.iou_3d.projection_max, o.iou_3d.projection_mean);
      for (double v : {o.iou_3d.projection_mean, o.iou_3d.projection_max, o.iou_3d.labeloctomap})
        EXPECT_TRUE(v >= 0.0 && v <= 1.0) << v;
      // The transparent bottle has no depth, so nothing of it is mapped or projected;
      // it scores 0 for every method and is left out of the comparison.
      if (o.label != lom::kSynthTransparentLabel) objects.push_back(o);
    }
    std::cout << "seed " << seed << ": mean IU_3d x100  Projection (Mean) "
              << 100 * report.summary.iou_3d.projection_mean << "  Projection (Max) "
              << 100 * report.summary.iou_3d.projection_max << "  LabelOctoMap "
              << 100 * report.summary.iou_3d.labeloctomap << "\n";
  }
  const lom::ScoreSummary summary = lom::summarize(objects);
  std::cout << summary.objects << " objects: mean IU_3d x100  Projection (Mean) "
            << 100 * summary.iou_3d.projection_mean << "  Projection (Max) " << 100 * summary.iou_3d.projection_max
            << "  LabelOctoMap " << 100 * summary.iou_3d.labeloctomap << "; LabelOctoMap > Projection (Max) for "
            << summary.labeloctomap_beats_projection_max << "\n";
  EXPECT_GT(summary.iou_3d.labeloctomap, summary.iou_3d.projection_max);
  EXPECT_GT(summary.iou_3d.projection_max, summary.iou_3d.projection_mean);
  // The paper: better for 29 of 39 objects. Here: for most objects too.
  EXPECT_GT(2 * summary.labeloctomap_beats_projection_max, summary.objects);
}

class ScoreChecks : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    scene_ = new lom::SynthScene(lom::writeSyntheticScene(sceneOptions(3, 160, 120, 4), dir_->path()));
    sequence_ = new lom::Sequence(lom::loadSequence(dir_->path()));
    map_ = new lom::LabelMap(lom::fuseSequence(*sequence_, lom::FusionOptions{}));
  }
  static void TearDownTestSuite() {
    delete map_;
    delete sequence_;
    delete scene_;
    delete dir_;
  }
  static lom::EvaluationOptions named() {
    lom::EvaluationOptions options;
    options.annotations_file = "boxes.json";
    options.map_file = "map.ot";
    return options;
  }
  static TempDir* dir_;
  static lom::SynthScene* scene_;
  static lom::Sequence* sequence_;
  static lom::LabelMap* map_;
};
TempDir* ScoreChecks::dir_ = nullptr;
lom::SynthScene* ScoreChecks::scene_ = nullptr;
lom::Sequence* ScoreChecks::sequence_ = nullptr;
lom::LabelMap* ScoreChecks::map_ = nullptr;

// Runs `call`, expecting a lom::Error about `file` and `field`.
template <typename Call>
void expectError(Call call, const std::string& file, const std::string& field) {
  try {
    call();
    ADD_FAILURE() << "no error for " << file << ": " << field;
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, file) << e.what();
    EXPECT_EQ(e.problem().field, field) << e.what();
  }
}

// The projection baselines project the same views whatever map is scored:
// their scores, the Box IU of the boxes fitted to their voxels included, must
// not move with the map's threshold, p_miss or the frames it was fused from
// (a table comparing fusion settings would get baselines that move with them).
// The baselines' boxes stand on the floor the views see: where the objects
// hide much of it (three views), a plane across their tops held more of all
// the views' voxels than the floor, and every baseline box was cut off under
// it (Projection (Max) Box IU 36.2 and 31.9 on these scenes, against 64.8
// and 54.4 levelled by the background's voxels).
TEST(ScoreSynthetic, TheBaselinesBoxesStandOnTheFloorTheViewsSee) {
  for (const std::uint64_t seed : {3u, 7u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    TempDir dir;
    lom::SynthOptions options;  // `labeloctomap synth --seed S`
    options.seed = seed;
    const lom::SynthScene scene = lom::writeSyntheticScene(options, dir.path());
    const lom::Sequence sequence = lom::loadSequence(dir.path());
    const lom::EvaluationOptions evaluation;
    const lom::LabelMap map = lom::fuseSequence(sequence, evaluation.fusion);
    const lom::EvaluationReport report =
        lom::evaluate(sequence, scene.annotations, map, evaluation);
    EXPECT_GT(report.summary.box_iou.projection_max, 0.5);
    EXPECT_GT(report.summary.box_iou.projection_mean, 0.35);
  }
}

TEST(ScoreSynthetic, TheBaselinesDoNotDependOnTheMapScored) {
  TempDir dir;
  const lom::SynthScene scene = lom::writeSyntheticScene(sceneOptions(1, 320, 240, 8), dir.path());
  const lom::Sequence sequence = lom::loadSequence(dir.path());
  const lom::EvaluationOptions options;
  const lom::LabelMap map = lom::fuseSequence(sequence, options.fusion);
  const lom::EvaluationReport report = lom::evaluate(sequence, scene.annotations, map, options);
  std::vector<lom::FusionOptions> others(3, options.fusion);
  others[0].map.occupancy_threshold = 0.9;
  others[1].map.p_miss = 0.45;
  others[2].last_frame = 3;
  bool labeloctomap_moved = false;  // the maps differ, so the test means something
  for (size_t k = 0; k < others.size(); ++k) {
    SCOPED_TRACE("map " + std::to_string(k));
    const lom::LabelMap other = lom::fuseSequence(sequence, others[k]);
    const lom::EvaluationReport again = lom::evaluate(sequence, scene.annotations, other, options);
    ASSERT_EQ(again.objects.size(), report.objects.size());
    for (size_t i = 0; i < report.objects.size(); ++i) {
      const lom::ObjectScore& a = report.objects[i];
      const lom::ObjectScore& b = again.objects[i];
      SCOPED_TRACE(a.name);
      EXPECT_EQ(a.per_view, b.per_view);
      EXPECT_EQ(a.per_view_box_iou, b.per_view_box_iou);
      EXPECT_EQ(a.box_iou.projection_max, b.box_iou.projection_max);
      labeloctomap_moved |= a.box_iou.labeloctomap != b.box_iou.labeloctomap;
    }
  }
  EXPECT_TRUE(labeloctomap_moved);
}

TEST_F(ScoreChecks, BoxLabelOutsideTheSequenceIsAnError) {
  lom::Annotations annotations = scene_->annotations;
  annotations.boxes[1].label = 40;  // the sequence has labels 0..39
  expectError([&] { (void)lom::evaluate(*sequence_, annotations, *map_, named()); }, "boxes.json",
              "boxes[1].label");
  annotations.boxes[1].label = 0;  // the background is no object
  expectError([&] { (void)lom::evaluate(*sequence_, annotations, *map_, named()); }, "boxes.json",
              "boxes[1].label");
  annotations.boxes[1].label = annotations.boxes[0].label;
  expectError([&] { (void)lom::evaluate(*sequence_, annotations, *map_, named()); }, "boxes.json",
              "boxes[1].label");
}

TEST_F(ScoreChecks, FrameIdMismatchIsAnError) {
  lom::Annotations annotations = scene_->annotations;
  annotations.frame_id = "base";
  expectError([&] { (void)lom::evaluate(*sequence_, annotations, *map_, named()); }, "boxes.json", "frame_id");
}

TEST_F(ScoreChecks, EmptyMapIsAnError) {
  const lom::LabelMap empty(sequence_->labels);
  expectError([&] { (void)lom::evaluate(*sequence_, scene_->annotations, empty, named()); }, "map.ot", "map");
}

TEST_F(ScoreChecks, MapWithOtherLabelsIsAnError) {
  std::vector<lom::LabelInfo> labels = sequence_->labels.all();
  labels.pop_back();
  const lom::LabelMap other{lom::LabelSet(labels)};
  expectError([&] { (void)lom::evaluate(*sequence_, scene_->annotations, other, named()); }, "map.ot", "labels");
}

TEST_F(ScoreChecks, SequenceWithoutViewsIsAnError) {
  lom::Sequence no_views = *sequence_;
  for (auto& frame : no_views.frames) frame.view = false;
  expectError([&] { (void)lom::evaluate(no_views, scene_->annotations, *map_, named()); },
              (no_views.root / "sequence.json").string(), "frames[].view");
}

TEST_F(ScoreChecks, MissingBoxesOnlyLeaveObjectsUnscored) {
  lom::Annotations annotations = scene_->annotations;
  annotations.boxes.resize(2);
  const lom::EvaluationReport report = lom::evaluate(*sequence_, annotations, *map_, named());
  ASSERT_EQ(report.objects.size(), 2u);
  EXPECT_EQ(report.summary.objects, 2u);
  EXPECT_LT(report.objects[0].label, report.objects[1].label);
}

// Boxes of another scene (the annotations of the wrong recording) sit where
// the map has voxels, of other labels: their labels are in neither the map
// nor the views, which is said. An object without depth (the transparent
// bottle) is not: its pixels hold its label.
TEST_F(ScoreChecks, BoxesOfLabelsTheMapAndTheViewsNeverHoldAreWarnedAbout) {
  const std::string said = "and no pixel of the views scored has";
  const lom::EvaluationReport plain =
      lom::evaluate(*sequence_, scene_->annotations, *map_, named());
  for (const std::string& warning : plain.warnings)
    EXPECT_EQ(warning.find(said), std::string::npos) << warning;

  lom::Annotations annotations = scene_->annotations;
  std::set<int> used;
  for (const auto& box : annotations.boxes) used.insert(box.label);
  int other = 1;
  while (used.count(other) || other == lom::kSynthTransparentLabel) ++other;
  ASSERT_GE(annotations.boxes.size(), 2u);
  annotations.boxes[1].label = other;
  const lom::EvaluationReport report = lom::evaluate(*sequence_, annotations, *map_, named());
  std::vector<std::string> found;
  for (const std::string& warning : report.warnings)
    if (warning.find(said) != std::string::npos) found.push_back(warning);
  ASSERT_EQ(found.size(), 1u) << ::testing::PrintToString(report.warnings);
  EXPECT_EQ(found[0].rfind("boxes.json: boxes[1] (label " + std::to_string(other) + ", " +
                               sequence_->labels.at(other).name +
                               "): no voxel of map.ot and no pixel of the views scored has its "
                               "label, so it scores 0 in every column.",
                           0),
            0u)
      << found[0];
  // Candidates that leave the label out say so already: not twice.
  lom::EvaluationOptions restricted = named();
  restricted.fusion.candidates = std::vector<int>{0};
  for (const auto& box : scene_->annotations.boxes)
    restricted.fusion.candidates->push_back(box.label);
  const lom::EvaluationReport narrowed = lom::evaluate(*sequence_, annotations, *map_, restricted);
  for (const std::string& warning : narrowed.warnings)
    EXPECT_EQ(warning.find(said), std::string::npos) << warning;
}

TEST_F(ScoreChecks, BoxesWithoutAnyMappedVoxelAreWarnedAbout) {
  const lom::EvaluationReport plain =
      lom::evaluate(*sequence_, scene_->annotations, *map_, named());
  for (const std::string& warning : plain.warnings)
    EXPECT_EQ(warning.find("occupied voxel"), std::string::npos) << warning;
  for (const std::string& warning : plain.warnings)
    EXPECT_EQ(warning.find("outside everything"), std::string::npos) << warning;

  lom::Annotations annotations = scene_->annotations;
  ASSERT_GE(annotations.boxes.size(), 3u);
  // Typed in millimetres: far outside everything the map observed.
  annotations.boxes[0].box.center *= 1000.0;
  annotations.boxes[0].box.center.x() += 500.0;
  // Inside what the map observed, but in free space: a box smaller than a
  // voxel, at the centre of a free one (its neighbours' centres are a voxel away).
  const auto bounds = map_->bounds();
  ASSERT_TRUE(bounds);
  std::optional<Eigen::Vector3d> free_centre;
  for (int step = 1; step < 1000 && !free_centre; ++step) {
    const Eigen::Vector3d p = bounds->first + (step / 1000.0) * (bounds->second - bounds->first);
    const lom::VoxelState state = map_->voxelAt(p);
    if (state.known && !state.occupied) free_centre = map_->centerOf(map_->keyOf(p));
  }
  ASSERT_TRUE(free_centre) << "no free voxel on the map's diagonal";
  annotations.boxes[2].box.center = *free_centre;
  annotations.boxes[2].box.size = Eigen::Vector3d::Constant(0.004);
  const lom::EvaluationReport report = lom::evaluate(*sequence_, annotations, *map_, named());
  auto warned = [&](size_t box, const std::string& what) {
    const std::string start = "boxes.json: boxes[" + std::to_string(box) + "] (label " +
                              std::to_string(annotations.boxes[box].label) + ", ";
    for (const std::string& warning : report.warnings)
      if (warning.rfind(start, 0) == 0 && warning.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned(0, "lies outside everything the map observed (its known voxels span ("))
      << ::testing::PrintToString(report.warnings);
  EXPECT_TRUE(warned(0, "other units or another frame"))
      << ::testing::PrintToString(report.warnings);
  EXPECT_TRUE(warned(2, "holds no occupied voxel of any label"))
      << ::testing::PrintToString(report.warnings);
  EXPECT_FALSE(warned(1, "voxel")) << ::testing::PrintToString(report.warnings);

  // Many such boxes are one sentence, not one each.
  annotations.boxes[1].box.center = annotations.boxes[0].box.center + Eigen::Vector3d(0, 1, 0);
  const lom::EvaluationReport two = lom::evaluate(*sequence_, annotations, *map_, named());
  size_t outside = 0;
  for (const std::string& warning : two.warnings)
    if (warning.find("outside everything") != std::string::npos) {
      ++outside;
      EXPECT_NE(warning.find("boxes[0]"), std::string::npos) << warning;
      EXPECT_NE(warning.find("boxes[1]"), std::string::npos) << warning;
      EXPECT_NE(warning.find(" lie outside"), std::string::npos) << warning;
    }
  EXPECT_EQ(outside, 1u) << ::testing::PrintToString(two.warnings);

  // Many more are named up to ten and counted.
  lom::Annotations many = scene_->annotations;
  std::set<int> used;
  for (const lom::GroundTruthBox& box : many.boxes) used.insert(box.label);
  size_t added = 0;
  for (int label = 1; label < sequence_->labels.size() && added < 15; ++label) {
    if (used.count(label)) continue;
    lom::GroundTruthBox far_box = annotations.boxes[0];  // in millimetres, far away
    far_box.label = label;
    far_box.name = sequence_->labels.at(label).name;
    many.boxes.push_back(far_box);
    ++added;
  }
  ASSERT_EQ(added, 15u) << "the scene has too few labels for this test";
  const lom::EvaluationReport fifteen = lom::evaluate(*sequence_, many, *map_, named());
  bool counted = false;
  for (const std::string& warning : fifteen.warnings)
    if (warning.find("outside everything") != std::string::npos) {
      counted = warning.find(" and 5 more lie outside") != std::string::npos;
      EXPECT_LT(warning.size(), 1000u) << warning;
    }
  EXPECT_TRUE(counted) << ::testing::PrintToString(fifteen.warnings);
}

// A box typed in millimetres about the origin holds the whole map: it is not
// empty, yet scores about 0. Said, with the likely cause.
TEST_F(ScoreChecks, BoxesFarLargerThanTheMapAreWarnedAbout) {
  lom::Annotations annotations = scene_->annotations;
  ASSERT_GE(annotations.boxes.size(), 2u);
  const auto bounds = map_->bounds();
  ASSERT_TRUE(bounds);
  annotations.boxes[1].box.center = 0.5 * (bounds->first + bounds->second);
  annotations.boxes[1].box.size *= 1000.0;
  const lom::EvaluationReport report = lom::evaluate(*sequence_, annotations, *map_, named());
  const std::string start =
      "boxes.json: boxes[1] (label " + std::to_string(annotations.boxes[1].label) + ", ";
  bool warned = false;
  for (const std::string& warning : report.warnings)
    warned = warned || (warning.rfind(start, 0) == 0 &&
                        warning.find("more than three times as large as everything the map "
                                     "observed") != std::string::npos &&
                        warning.find("given in millimetres for metres") != std::string::npos);
  EXPECT_TRUE(warned) << ::testing::PrintToString(report.warnings);
  for (const lom::ObjectScore& object : report.objects) {
    if (object.label == annotations.boxes[1].label) {
      EXPECT_LT(object.iou_3d.labeloctomap, 0.01);
    }
  }
  // The scene's own boxes are not.
  const lom::EvaluationReport plain =
      lom::evaluate(*sequence_, scene_->annotations, *map_, named());
  for (const std::string& warning : plain.warnings)
    EXPECT_EQ(warning.find("as large as everything"), std::string::npos) << warning;
}

// A pruned leaf stands for many voxels: a box inside it, away from its
// centre, holds an occupied voxel and is not warned about.
TEST_F(ScoreChecks, ABoxInsideAPrunedLeafHoldsItsVoxels) {
  std::optional<lom::OccupiedVoxel> big;
  map_->forEachOccupied([&](const lom::OccupiedVoxel& voxel) {
    if (!big && voxel.size > 1.5 * map_->parameters().resolution) big = voxel;
  });
  if (!big) GTEST_SKIP() << "the generated map has no pruned occupied leaf";
  lom::Annotations annotations = scene_->annotations;
  const Eigen::Vector3d corner_ward = big->center + Eigen::Vector3d::Constant(0.3 * big->size);
  // Any box: the warning is about voxels of any label. 0.3 of the leaf's edge
  // off its centre is more than half a finest voxel away on every axis.
  lom::OrientedBox& box = annotations.boxes[0].box;
  box.center = corner_ward;
  box.size = Eigen::Vector3d::Constant(0.001);
  box.rotation = Eigen::Quaterniond::Identity();
  const lom::EvaluationReport report = lom::evaluate(*sequence_, annotations, *map_, named());
  for (const std::string& warning : report.warnings)
    EXPECT_EQ(warning.find("no occupied voxel"), std::string::npos) << warning;
}

TEST_F(ScoreChecks, CandidatesHoldingEveryTrueLabelOnlyFixPixels) {
  // A pixel whose argmax is its true label keeps it when the other labels are
  // dropped, so 2D pixel accuracy cannot fall.
  lom::EvaluationOptions options = named();
  std::vector<int> candidates{0};
  for (const auto& box : scene_->annotations.boxes) candidates.push_back(box.label);
  options.fusion.candidates = candidates;
  const lom::EvaluationReport report = lom::evaluate(*sequence_, scene_->annotations, *map_, options);
  ASSERT_TRUE(report.metrics_2d && report.metrics_2d_candidates);
  EXPECT_GE(report.metrics_2d_candidates->pixel_accuracy, report.metrics_2d->pixel_accuracy);
  EXPECT_EQ(report.metrics_2d->pixels, report.metrics_2d_candidates->pixels);
  EXPECT_EQ(report.metrics_2d->pixels, 4u * 160u * 120u);
}

TEST_F(ScoreChecks, FramesWhoseProbaWasMadeFromTheirLabelsAreLeftOutOf2dMetrics) {
  lom::EvaluationOptions options = named();
  std::vector<int> candidates{0};
  for (const auto& box : scene_->annotations.boxes) candidates.push_back(box.label);
  options.fusion.candidates = candidates;
  const lom::EvaluationReport all = lom::evaluate(*sequence_, scene_->annotations, *map_, options);
  ASSERT_TRUE(all.metrics_2d);
  EXPECT_TRUE(all.metrics_2d_excluded_frames.empty());
  EXPECT_TRUE(all.metrics_2d_not_scored.empty());

  // Two of the four frames: the others are scored alone.
  lom::Sequence half = *sequence_;
  half.frames[0].proba_from_label = true;
  half.frames[2].proba_from_label = true;
  const lom::EvaluationReport partly = lom::evaluate(half, scene_->annotations, *map_, options);
  ASSERT_TRUE(partly.metrics_2d && partly.metrics_2d_candidates);
  EXPECT_EQ(partly.metrics_2d->pixels, 2u * 160u * 120u);
  EXPECT_EQ(partly.metrics_2d_excluded_frames, (std::vector<size_t>{0, 2}));
  EXPECT_TRUE(partly.metrics_2d_not_scored.empty());
  EXPECT_EQ(partly.views, all.views) << "the projection baseline keeps every view";
  EXPECT_NE(lom::reportTable(partly).find("2D segmentation: 2 frames (0, 2) left out: their "
                                          "probabilities were made from their label images"),
            std::string::npos)
      << lom::reportTable(partly);

  // Every frame: no 2D metrics, and the reports say why.
  lom::Sequence none = *sequence_;
  for (auto& frame : none.frames) frame.proba_from_label = true;
  const lom::EvaluationReport report = lom::evaluate(none, scene_->annotations, *map_, options);
  EXPECT_FALSE(report.metrics_2d);
  EXPECT_FALSE(report.metrics_2d_candidates);
  EXPECT_EQ(report.metrics_2d_excluded_frames, (std::vector<size_t>{0, 1, 2, 3}));
  const std::string why =
      "the probabilities were made from the label images, which are not an independent ground "
      "truth";
  EXPECT_EQ(report.metrics_2d_not_scored, why);
  ASSERT_EQ(report.objects.size(), all.objects.size());
  for (size_t i = 0; i < report.objects.size(); ++i)
    EXPECT_EQ(report.objects[i].iou_3d.projection_max, all.objects[i].iou_3d.projection_max);
  const std::string table = lom::reportTable(report);
  EXPECT_NE(table.find("2D segmentation: not scored: " + why + "\n"), std::string::npos) << table;
  EXPECT_EQ(table.find("pixel acc."), std::string::npos) << table;
  EXPECT_NE(lom::reportMarkdown(report).find("Not scored: " + why + "."), std::string::npos);
  const std::string json = lom::reportJson(report);
  EXPECT_NE(json.find("\"metrics_2d_not_scored\": \"" + why + "\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"metrics_2d_excluded_frames\": [0, 1, 2, 3]"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"metrics_2d\":"), std::string::npos) << json;
}

TEST_F(ScoreChecks, ProgressCanCancel) {
  size_t calls = 0;
  EXPECT_THROW((void)lom::evaluate(*sequence_, scene_->annotations, *map_, named(),
                                   [&](const lom::EvaluationProgress&) { return ++calls < 2; }),
               lom::EvaluationCancelled);
  EXPECT_EQ(calls, 2u);
}

}  // namespace
