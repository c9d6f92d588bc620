// The adapters from core images to what the 2D panes and the 3D cloud show.
#include "lom/ui/image_conversion.hpp"

#include <gtest/gtest.h>

#include "lom/ui/frame_labels.hpp"

namespace lom::ui {
namespace {

TEST(FrameLabels, ArgmaxUsesChannelLabelsAndBreaksTiesToTheLowerId) {
  ProbabilityImage proba;
  proba.width = 3;
  proba.height = 1;
  proba.channels = 3;
  proba.channel_labels = {5, 2, 0};
  proba.values = {0.7f, 0.2f, 0.1f,   // label 5 wins
                  0.1f, 0.6f, 0.3f,   // label 2 wins
                  0.4f, 0.2f, 0.4f};  // tie between 5 and 0: the lower id
  const LabelImage labels = argmaxLabels(proba);
  ASSERT_EQ(labels.ids.size(), 3u);
  EXPECT_EQ(labels.at(0, 0), 5);
  EXPECT_EQ(labels.at(1, 0), 2);
  EXPECT_EQ(labels.at(2, 0), 0);
}

TEST(FrameLabels, LabelImageWinsOverProbabilities) {
  FrameData frame;
  frame.label = LabelImage{1, 1, {3}};
  frame.proba = ProbabilityImage{1, 1, 1, {7}, {1.f}, {}};
  ASSERT_TRUE(labelsOfFrame(frame));
  EXPECT_EQ(labelsOfFrame(frame)->at(0, 0), 3);
  EXPECT_FALSE(labelsOfFrame(FrameData{}));
}

TEST(FrameLabels, UnknownIdsAreMagenta) {
  const LabelSet labels({{0, "bg", {0, 0, 0}}, {1, "a", {10, 20, 30}}});
  EXPECT_EQ(labelColor(labels, 1), QColor(10, 20, 30));
  EXPECT_EQ(labelColor(labels, 9), QColor(255, 0, 255));
}

TEST(ImageConversion, DepthIsColourMappedAndMissingDepthIsBlack) {
  const DepthImage depth{3, 1, {0.5f, 0.f, 2.5f}};
  const auto range = validDepthRange(depth);
  ASSERT_TRUE(range);
  EXPECT_FLOAT_EQ(range->near_metres, 0.5f);
  EXPECT_FLOAT_EQ(range->far_metres, 2.5f);
  const QImage image = depthToQImage(depth, *range);
  EXPECT_EQ(image.pixelColor(0, 0), depthColor(0.0));
  EXPECT_EQ(image.pixelColor(1, 0), QColor(0, 0, 0));
  EXPECT_EQ(image.pixelColor(2, 0), depthColor(1.0));
  EXPECT_FALSE(validDepthRange(DepthImage{1, 1, {0.f}}));
}

TEST(ImageConversion, LabelsBlendOverTheBaseDimmedToGrey) {
  const LabelSet labels({{0, "bg", {0, 0, 0}}, {1, "a", {200, 0, 0}}});
  const LabelImage ids{2, 1, {0, 1}};
  QImage base(2, 1, QImage::Format_RGB32);
  base.fill(QColor(0, 0, 100));
  const QImage blended = labelsToQImage(ids, labels, base, 0.5);
  // Grey 0.6 x (0.114 x 100) = 6.84 -> 7; the label is blended over that grey.
  EXPECT_EQ(blended.pixelColor(0, 0), QColor(7, 7, 7));
  EXPECT_EQ(blended.pixelColor(1, 0), QColor(104, 4, 4));
  EXPECT_EQ(labelsToQImage(ids, labels).pixelColor(1, 0), QColor(200, 0, 0));
}

TEST(ImageConversion, ColourImageKeepsItsPixels) {
  const ColorImage color{2, 1, {1, 2, 3, 250, 251, 252}};
  const QImage image = toQImage(color);
  EXPECT_EQ(image.pixelColor(1, 0), QColor(250, 251, 252));
  EXPECT_TRUE(toQImage(ColorImage{2, 2, {1, 2, 3}}).isNull());
}

}  // namespace
}  // namespace lom::ui
