#pragma once
// A check of a ROS 1 bag's record structure before the bag library reads it
// (rosbag_check.cpp).
#include <string>

namespace lom::import_detail {

// Walks the records of a format 2.0 bag: every length within the file (and
// within its chunk), header fields well formed, index entries on records of
// their chunk (for uncompressed chunks; within the stated size for
// compressed ones), chunk infos on chunks. Throws lom::Error(file, "bag",
// ...) naming the first problem and its byte offset. Files of another format
// or that cannot be opened are left to the bag library.
void checkBagStructure(const std::string& file);

}  // namespace lom::import_detail
