// The Fusion panel's segmenter against the labels of the open sequence: a
// model whose channel count does not fit is refused when chosen, removed when
// another sequence opens, and what it warns about (an unwritable cache) shows.
#include <gtest/gtest.h>

#include <QDoubleSpinBox>
#include <QPushButton>
#include <QTest>
#include <algorithm>
#include <filesystem>
#include <fstream>

#include "demo_window_fixture.hpp"
#include "lom/segmenter.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "onnx_model_builder.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class SegmenterPanelTest : public fixture::DemoWindowTest {
 protected:
  void openAndWait(const std::filesystem::path& folder) {
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder)));
    StudioSession& session = window_.session();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
    QTest::qWait(50);  // the last snapshot and errors arrive through the event loop
  }
  // The colour model (3 channels: background, red, green) with `extra` more.
  std::filesystem::path writeColourModel(const std::string& name, int extra = 0) {
    lom::test::ConvModelSpec spec = lom::test::colourChannelModel();
    for (int i = 0; i < extra; ++i) {
      spec.outputs += 1;
      spec.weights.insert(spec.weights.end(), {0.f, 0.f, 0.5f});
      spec.bias.push_back(0.f);
    }
    const auto path = temp_ / name;
    lom::test::writeModel(path, lom::test::buildConvModel(spec));
    return path;
  }
  bool fusionFailed() const {
    return std::any_of(errors_.begin(), errors_.end(),
                       [](const QString& error) { return error.startsWith("Fusion stopped"); });
  }
};

TEST_F(SegmenterPanelTest, AModelWithAnotherChannelCountIsRefusedWhenChosen) {
  const auto wall = temp_ / "wall";
  (void)lom::test::writeColourWallSequence(wall, 1);  // 3 labels
  openAndWait(wall);
  FusionPanel& panel = window_.fusionPanel();
  // No MODEL.json: channel c is label c, so 4 channels cannot be 3 labels.
  EXPECT_FALSE(panel.setSegmenterModel(qPath(writeColourModel("four.onnx", 1))));
  const QString note = panel.noteText();
  EXPECT_TRUE(note.contains("four.onnx: output channels: expected 3 channels"))
      << note.toStdString();
  EXPECT_TRUE(note.contains("found 4 channels")) << note.toStdString();
  EXPECT_TRUE(window_.session().fusionOptions().segmenter == nullptr);
  EXPECT_FALSE(panel.refuseButton().isEnabled());  // nothing to re-fuse with
  // The reason stays in view while the panel updates its note.
  panel.maxRangeBox().setValue(2.0);
  EXPECT_TRUE(panel.noteText().contains("output channels")) << panel.noteText().toStdString();
  // A model that fits is taken, and clears the reason.
  EXPECT_TRUE(panel.setSegmenterModel(qPath(writeColourModel("three.onnx"))));
  EXPECT_FALSE(panel.noteText().contains("output channels")) << panel.noteText().toStdString();
}

TEST_F(SegmenterPanelTest, AnotherSequenceKeepsTheSegmenterOnlyIfItFitsItsLabels) {
  const auto wall = temp_ / "wall";
  const auto other_wall = temp_ / "other_wall";
  (void)lom::test::writeColourWallSequence(wall, 1);
  (void)lom::test::writeColourWallSequence(other_wall, 1);
  openAndWait(wall);
  StudioSession& session = window_.session();
  FusionPanel& panel = window_.fusionPanel();
  panel.maxRangeBox().setValue(2.0);  // the wall is 1 m away, its corners farther
  ASSERT_TRUE(panel.setSegmenterModel(qPath(writeColourModel("colours.onnx"))));
  panel.refuseButton().click();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
  ASSERT_TRUE(session.fusionOptions().segmenter != nullptr);

  // The same labels: kept, and the new sequence is fused with it.
  errors_.clear();
  openAndWait(other_wall);
  EXPECT_FALSE(fusionFailed()) << errors_.front().toStdString();
  EXPECT_TRUE(session.fusionOptions().segmenter != nullptr);
  ASSERT_TRUE(session.worker().snapshot());
  EXPECT_EQ(session.worker().snapshot()->frames_fused, 1u);

  // The demo has many more labels (and its own probability images): the
  // 3-channel model is removed, saying why, and the demo fuses without it.
  errors_.clear();
  openAndWait(folder_);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const auto snapshot = session.worker().snapshot();
        return snapshot &&
               snapshot->frames_fused == static_cast<size_t>(fixture::smallDemo().frames);
      },
      kTimeoutMs));
  EXPECT_FALSE(fusionFailed()) << errors_.front().toStdString();
  EXPECT_TRUE(session.fusionOptions().segmenter == nullptr);
  const QString note = panel.noteText();
  EXPECT_TRUE(note.contains("colours.onnx removed")) << note.toStdString();
  EXPECT_TRUE(note.contains("output channels")) << note.toStdString();
  EXPECT_FALSE(panel.hasPendingChanges());
  EXPECT_TRUE(window_.findChild<QPushButton*>("clearSegmenterButton") != nullptr &&
              !window_.findChild<QPushButton*>("clearSegmenterButton")->isEnabled());
}

// The frame views show the probabilities fusion reads: with a segmenter, its
// output for a frame without a proba of its own; without, the frame's files.
TEST_F(SegmenterPanelTest, TheFrameShowsTheSegmentersProbabilities) {
  const auto wall = temp_ / "wall";
  (void)lom::test::writeColourWallSequence(wall, 2);  // colour images, no proba
  openAndWait(wall);
  StudioSession& session = window_.session();
  SequenceController& controller = session.controller();
  FrameImagesView& images = window_.frameImages();
  images.setHeatLabel(1);  // red_block
  ASSERT_NE(controller.currentFrameData(), nullptr);
  EXPECT_FALSE(controller.currentFrameData()->proba.has_value());
  EXPECT_EQ(images.heatPane().caption(), "Probability: none");

  FusionPanel& panel = window_.fusionPanel();
  panel.maxRangeBox().setValue(2.0);
  ASSERT_TRUE(panel.setSegmenterModel(qPath(writeColourModel("colours.onnx"))));
  panel.refuseButton().click();  // applies the segmenter
  ASSERT_TRUE(session.fusionOptions().segmenter != nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !controller.isSegmentingFrame(); }, kTimeoutMs));
  EXPECT_TRUE(controller.frameUsesSegmenter());
  EXPECT_TRUE(controller.frameSegmenterProblem().isEmpty())
      << controller.frameSegmenterProblem().toStdString();
  const FrameData* frame = controller.currentFrameData();
  ASSERT_NE(frame, nullptr);
  ASSERT_TRUE(frame->proba.has_value());
  ASSERT_TRUE(frame->color.has_value());
  const ProbabilityImage expected = session.fusionOptions().segmenter->segment(
      *frame->color, frame->depth.width, frame->depth.height, controller.sequence().labels);
  ASSERT_EQ(frame->proba->channels, expected.channels);
  ASSERT_EQ(frame->proba->values.size(), expected.values.size());
  for (size_t i = 0; i < expected.values.size(); ++i)
    ASSERT_FLOAT_EQ(frame->proba->values[i], expected.values[i]) << "value " << i;
  // The left half of frame 0 is red: the red block is the most probable there.
  EXPECT_GT(frame->proba->pixel(1, 2)[1], 0.5f);
  EXPECT_EQ(images.heatPane().caption(), "Probability of red_block (segmenter colours.onnx)");
  ASSERT_TRUE(controller.currentLabels().has_value());
  EXPECT_EQ(controller.currentLabels()->ids[2 * 8 + 1], 1);

  // The next frame (red on the right) gets its own run.
  controller.stepFrames(1);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !controller.isSegmentingFrame(); }, kTimeoutMs));
  ASSERT_TRUE(controller.currentFrameData()->proba.has_value());
  EXPECT_GT(controller.currentFrameData()->proba->pixel(6, 2)[1], 0.5f);

  // Without the segmenter the frame is its files again.
  FusionOptions options = session.fusionOptions();
  options.segmenter.reset();
  session.setFusionOptions(options);
  EXPECT_FALSE(controller.frameUsesSegmenter());
  EXPECT_FALSE(controller.currentFrameData()->proba.has_value());
  EXPECT_EQ(images.heatPane().caption(), "Probability: none");
}

TEST_F(SegmenterPanelTest, AnUnwritableCacheIsSaidInTheNote) {
  const auto wall = temp_ / "wall";
  (void)lom::test::writeColourWallSequence(wall, 1);
  std::ofstream(wall / ".segmenter-cache") << "a file where the cache folder goes";
  openAndWait(wall);
  StudioSession& session = window_.session();
  FusionPanel& panel = window_.fusionPanel();
  panel.maxRangeBox().setValue(2.0);
  ASSERT_TRUE(panel.setSegmenterModel(qPath(writeColourModel("colours.onnx"))));
  errors_.clear();
  panel.refuseButton().click();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
  EXPECT_FALSE(fusionFailed()) << errors_.front().toStdString();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return panel.noteText().contains("cannot write the segmenter cache"); }, 5000))
      << panel.noteText().toStdString();
  EXPECT_TRUE(panel.noteText().contains(".segmenter-cache")) << panel.noteText().toStdString();
}

}  // namespace
}  // namespace lom::ui
