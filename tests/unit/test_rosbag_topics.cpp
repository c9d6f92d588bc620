// Which topics of a bag become the depth, colour, probability and label images,
// and which labels the channels get: decided from names and encodings alone,
// so these tests need no bag files (and run in builds without ROS).
#include <gtest/gtest.h>

#include <limits>

#include "lom/error.hpp"
#include "lom/labels.hpp"
#include "rosbag_check.hpp"
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

// The depth camera's own image_transport republish (a PNG or JPEG
// CompressedImage, not compressedDepth) shares the longest prefix with the
// depth topic, and was taken for colour.
TEST_F(RosbagTopics, ARepublishOfTheDepthTopicIsNeverColour) {
  addImages("/camera/color/image_raw", "rgb8");
  addImages("/camera/depth/image_rect_raw", "16UC1");
  addImages("/camera/depth/image_rect_raw/compressed", "16UC1; png compressed", true);
  EXPECT_EQ(nameOf(choose().color), "/camera/color/image_raw");
  // Nor when it is the only candidate.
  topics_.erase("/camera/color/image_raw");
  EXPECT_EQ(nameOf(choose().color), "(none)");
  // A compressedDepth depth topic: the raw topic's other republishes are its own.
  topics_.clear();
  addImages("/camera/depth/image_raw/compressedDepth", "16UC1; compressedDepth png", true);
  addImages("/camera/depth/image_raw/theora", "theora", true);
  addImages("/camera/depth/image_raw/compressed", "mono8; jpeg compressed mono8", true);
  addImages("/camera/color/image_raw/compressed", "bgr8; jpeg compressed bgr8", true);
  EXPECT_EQ(nameOf(choose().color), "/camera/color/image_raw/compressed");
}

// RealSense's bag with image_transport republishes of both cameras: the raw
// topics are the depth and the colour, not an ambiguity between the raw
// depth and its compressedDepth republish.
TEST_F(RosbagTopics, RawTopicsWinOverTheirRepublishes) {
  addImages("/camera/color/image_raw", "rgb8");
  addImages("/camera/color/image_raw/compressed", "rgb8; jpeg compressed bgr8", true);
  addImages("/camera/depth/image_rect_raw", "16UC1");
  addImages("/camera/depth/image_rect_raw/compressed", "16UC1; jpeg compressed ", true);
  addImages("/camera/depth/image_rect_raw/compressedDepth", "16UC1; compressedDepth", true);
  const ChosenTopics chosen = choose();
  EXPECT_EQ(nameOf(chosen.depth), "/camera/depth/image_rect_raw");
  EXPECT_EQ(nameOf(chosen.color), "/camera/color/image_raw");
  // Republishes without their raw topic are still colour.
  topics_.erase("/camera/color/image_raw");
  addImages("/camera/color/image_raw/theora", "theora", true);
  EXPECT_EQ(nameOf(choose().color), "/camera/color/image_raw/compressed");
}

// Lengths inside serialised messages are checked against the bytes that
// follow them before the ROS deserialiser allocates what they claim.
TEST(RosbagMessageLengths, LengthsBeyondTheMessageNameTheirField) {
  const auto u32 = [](std::uint32_t v) {
    return std::vector<std::uint8_t>{
        static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
        static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 24)};
  };
  // A TFMessage claiming 4 Gi transforms in 4 bytes.
  std::vector<std::uint8_t> tf = u32(0xffffffffu);
  auto problem = messageLengthProblem("tf2_msgs/TFMessage", tf.data(), tf.size());
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->field, "transforms");
  EXPECT_EQ(problem->expected, "a length that fits in the 0 bytes left in the message");
  EXPECT_EQ(problem->found, "4294967295 transforms");
  // One transform whose child frame name claims 1000 characters.
  tf = u32(1);
  for (const auto& part : {u32(0), u32(0), u32(0), u32(0), u32(1000)})
    tf.insert(tf.end(), part.begin(), part.end());
  tf.resize(tf.size() + 56);
  problem = messageLengthProblem("tf2_msgs/TFMessage", tf.data(), tf.size());
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->field, "transforms[0].child_frame_id");
  EXPECT_EQ(problem->found, "1000 characters");
  // The same transform with its child frame named "a": fits, and one byte
  // less does not.
  tf = u32(1);
  for (const auto& part : {u32(0), u32(0), u32(0), u32(0), u32(1)})
    tf.insert(tf.end(), part.begin(), part.end());
  tf.push_back('a');
  tf.resize(tf.size() + 56);
  EXPECT_FALSE(messageLengthProblem("tf2_msgs/TFMessage", tf.data(), tf.size()).has_value());
  problem = messageLengthProblem("tf2_msgs/TFMessage", tf.data(), tf.size() - 1);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->field, "transforms[0].transform");
  EXPECT_EQ(problem->found, "the message ends 55 bytes into it");
  // Other types are not walked.
  EXPECT_FALSE(messageLengthProblem("std_msgs/String", tf.data(), 2).has_value());
}

TEST(RosbagStamps, NearestNanosecondsIsExact) {
  const std::int64_t second = 1700000000LL * 1000000000LL;
  const std::vector<std::int64_t> stamps{second + 100000000, second + 120000000};
  EXPECT_EQ(nearestNanoseconds(stamps, second + 100000000, 0), std::optional<size_t>(0));
  EXPECT_EQ(nearestNanoseconds(stamps, second + 100000001, 0), std::nullopt);
  EXPECT_EQ(nearestNanoseconds(stamps, second + 140000000, toNanoseconds(0.02)),
            std::optional<size_t>(1));
  EXPECT_EQ(nearestNanoseconds(stamps, second + 110000000, toNanoseconds(0.02)),
            std::optional<size_t>(0))
      << "the earlier of two equally near";
  EXPECT_EQ(toNanoseconds(1e30), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(addNanoseconds(toNanoseconds(1e30), 5), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(nearestNanoseconds(stamps, second, toNanoseconds(1e30)), std::optional<size_t>(0));
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
