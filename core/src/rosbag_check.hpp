#pragma once
// A check of a ROS 1 bag's record structure before the bag library reads it
// (rosbag_check.cpp).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace lom::import_detail {

// Walks the records of a format 2.0 bag: every length within the file (and
// within its chunk), header fields well formed, index entries on records of
// their chunk (for uncompressed chunks; within the stated size for
// compressed ones), chunk infos on chunks. Throws lom::Error(file, "bag",
// ...) naming the first problem and its byte offset; a folder, an empty file
// or one that does not start with #ROSBAG are said to be no bag. Bags of
// another format version and files that cannot be opened are left to the
// bag library.
//
// `keep_going` is told the bytes checked so far and the file's size before
// each record outside the chunks: decompressing a large bz2 bag takes
// minutes, which a cancel must not wait out. Its false stops the check, which
// then returns false.
using BagCheckProgress = std::function<bool(std::uint64_t checked, std::uint64_t size)>;
[[nodiscard]] bool checkBagStructure(const std::string& file,
                                     const BagCheckProgress& keep_going = {});

// A length inside a serialised message that its bytes cannot hold: `field`
// as the message definition names it ("D", "data", "transforms[2].
// child_frame_id"), with what fits and what the message says.
struct MessageLengthProblem {
  std::string field;
  std::string expected;
  std::string found;
};

// Walks the serialised bytes of a sensor_msgs/Image, CompressedImage,
// CameraInfo or tf2_msgs/TFMessage (`type` as the bag names it) without
// allocating: the ROS deserialiser sizes each array by its stated length
// before reading it, so a corrupted length asked for gigabytes. Empty when
// every length fits (and for other types).
std::optional<MessageLengthProblem> messageLengthProblem(const std::string& type,
                                                         const std::uint8_t* bytes, size_t size);

}  // namespace lom::import_detail
