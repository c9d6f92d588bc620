// Which topics of a bag become the depth, colour, probability and label images,
// and which labels the channels get: decided from names and encodings alone,
// so these tests need no bag files (and run in builds without ROS).
#include <gtest/gtest.h>

#include "lom/error.hpp"
#include "lom/labels.hpp"
#include "rosbag_topics.hpp"
#include "test_support.hpp"

namespace lom::import_detail::bag {
namespace {

class RosbagTopics : public ::testing::Test {
 protected:
  void addImages(const std::string& name, const std::string& encoding, bool compressed = false) {
    Topic topic{name, compressed ? kCompressedType : kImageType, {}};
    ImageEntry entry;
    entry.encoding = encoding;
    entry.compressed = compressed;
    entry.width = 640;
    entry.height = 480;
    topic.images.push_back(entry);
    topics_[name] = topic;
  }

  ChosenTopics choose() { return chooseTopics(topics_, options_, "bag.bag", writer_); }

  std::string errorOfChoose() {
    try {
      choose();
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  }

  static std::string nameOf(const Topic* topic) { return topic ? topic->name : "(none)"; }

  TopicMap topics_;
  ImportOptions options_;
  ImportReport report_;
  test::TempDir dir_;
  SequenceWriter writer_{dir_ / "out", options_, report_, {}};
};

TEST_F(RosbagTopics, DetectsEachKindByEncodingAndName) {
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/camera/rgb/image_raw", "rgb8");
  addImages("/segmenter/probabilities", "32FC40");
  addImages("/segmenter/labels", "mono8");
  const ChosenTopics chosen = choose();
  EXPECT_EQ(nameOf(chosen.depth), "/camera/depth/image_raw");
  EXPECT_EQ(nameOf(chosen.color), "/camera/rgb/image_raw");
  EXPECT_EQ(nameOf(chosen.proba), "/segmenter/probabilities");
  EXPECT_EQ(nameOf(chosen.label), "/segmenter/labels");
}

TEST_F(RosbagTopics, LabelImagesAreNeitherDepthNorColour) {
  // A 16-bit label image looks like depth and an 8-bit one like grey colour.
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/semantic/class_ids", "16UC1");
  addImages("/camera/rgb/image_raw", "bgr8");
  const ChosenTopics chosen = choose();
  EXPECT_EQ(nameOf(chosen.depth), "/camera/depth/image_raw");
  EXPECT_EQ(nameOf(chosen.label), "/semantic/class_ids");
  EXPECT_EQ(chosen.proba, nullptr);
}

TEST_F(RosbagTopics, PrefersDepthNamesThenRegisteredDepth) {
  addImages("/camera/ir/image", "16UC1");
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/camera/depth_registered/image_raw", "16UC1");
  EXPECT_EQ(nameOf(choose().depth), "/camera/depth_registered/image_raw");
}

TEST_F(RosbagTopics, SeveralEqualDepthTopicsAskForTheOption) {
  addImages("/left/depth", "16UC1");
  addImages("/right/depth", "32FC1");
  const std::string error = errorOfChoose();
  EXPECT_NE(error.find("bag.bag"), std::string::npos) << error;
  EXPECT_NE(error.find("depth topic"), std::string::npos) << error;
  EXPECT_NE(error.find("several: /left/depth, /right/depth"), std::string::npos) << error;
}

TEST_F(RosbagTopics, NoDepthListsWhatTheBagHolds) {
  addImages("/camera/rgb/image_raw", "rgb8");
  const std::string error = errorOfChoose();
  EXPECT_NE(error.find("depth topic"), std::string::npos) << error;
  EXPECT_NE(error.find("/camera/rgb/image_raw (sensor_msgs/Image rgb8)"), std::string::npos)
      << error;
}

TEST_F(RosbagTopics, ColourOfTheDepthCamerasNamespaceWins) {
  addImages("/cam2/color/image_raw", "rgb8");
  addImages("/cam1/depth/image_raw", "16UC1");
  addImages("/cam1/color/image_raw", "rgb8");
  EXPECT_EQ(nameOf(choose().color), "/cam1/color/image_raw");
}

TEST_F(RosbagTopics, GreyImagesOnlyWhenThereIsNoColour) {
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/camera/ir/image", "mono8");
  EXPECT_EQ(nameOf(choose().color), "/camera/ir/image");
  addImages("/camera/rgb/image_color", "jpeg", /*compressed=*/true);
  EXPECT_EQ(nameOf(choose().color), "/camera/rgb/image_color");
}

TEST_F(RosbagTopics, NoColourWhenAskedForNone) {
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/camera/rgb/image_raw", "rgb8");
  options_.rosbag.no_color = true;
  EXPECT_EQ(choose().color, nullptr);
}

TEST_F(RosbagTopics, AGivenTopicMustExistAndFit) {
  addImages("/camera/depth/image_raw", "16UC1");
  addImages("/camera/rgb/image_raw", "rgb8");
  options_.rosbag.depth_topic = "/camera/depth/missing";
  std::string error = errorOfChoose();
  EXPECT_NE(error.find("'/camera/depth/missing' is not in it"), std::string::npos) << error;
  options_.rosbag.depth_topic = "/camera/rgb/image_raw";
  error = errorOfChoose();
  EXPECT_NE(error.find("depth topic"), std::string::npos) << error;
  EXPECT_NE(error.find("/camera/rgb/image_raw holds rgb8"), std::string::npos) << error;
  options_.rosbag.depth_topic = "/camera/depth/image_raw";
  options_.rosbag.proba_topic = "/camera/rgb/image_raw";
  error = errorOfChoose();
  EXPECT_NE(error.find("probability topic"), std::string::npos) << error;
}

TEST_F(RosbagTopics, AGivenDepthTopicIsTakenOverTheDetectedOne) {
  addImages("/left/depth", "16UC1");
  addImages("/right/depth", "32FC1");
  options_.rosbag.depth_topic = "/right/depth";
  EXPECT_EQ(nameOf(choose().depth), "/right/depth");
}

TEST(RosbagEncodings, ChannelsAndBytesOfMultiChannelEncodings) {
  int bytes = 0;
  EXPECT_EQ(multiChannels("32FC40", bytes), 40);
  EXPECT_EQ(bytes, 4);
  EXPECT_EQ(multiChannels("16uc5", bytes), 5);
  EXPECT_EQ(bytes, 2);
  EXPECT_EQ(multiChannels("8UC2", bytes), 2);
  EXPECT_EQ(bytes, 1);
  EXPECT_EQ(multiChannels("rgb8", bytes), 0);
  EXPECT_EQ(multiChannels("32FC4x", bytes), 0);
}

class RosbagLabels : public ::testing::Test {
 protected:
  ImportOptions options_;
  ImportReport report_;
  test::TempDir dir_;
  SequenceWriter writer_{dir_ / "out", options_, report_, {}};
};

TEST_F(RosbagLabels, FortyChannelsAreTheApcLabels) {
  chooseLabels(40, false, options_, "bag.bag", writer_);
  EXPECT_EQ(writer_.labels().size(), apc2016Labels().size());
  EXPECT_EQ(writer_.labels().at(1).name, apc2016Labels().at(1).name);
}

TEST_F(RosbagLabels, OtherChannelCountsAreNumbered) {
  chooseLabels(3, false, options_, "bag.bag", writer_);
  ASSERT_EQ(writer_.labels().size(), 3);
  EXPECT_EQ(writer_.labels().at(2).name, "label_2");
}

TEST_F(RosbagLabels, AGivenListMustHaveOneLabelPerChannel) {
  options_.labels = apc2016Labels();
  try {
    chooseLabels(3, false, options_, "bag.bag", writer_);
    FAIL() << "40 labels for 3 channels were accepted";
  } catch (const Error& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("one label per probability channel: 3"), std::string::npos) << text;
    EXPECT_NE(text.find("40 labels given"), std::string::npos) << text;
  }
}

TEST_F(RosbagLabels, LabelImagesAreReadAsApcIdsAndNoEvidenceIsBackgroundOnly) {
  chooseLabels(0, true, options_, "bag.bag", writer_);
  EXPECT_EQ(writer_.labels().size(), apc2016Labels().size());
  chooseLabels(0, false, options_, "bag.bag", writer_);
  EXPECT_EQ(writer_.labels().size(), 1);
}

}  // namespace
}  // namespace lom::import_detail::bag
