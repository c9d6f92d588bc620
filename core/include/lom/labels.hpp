#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lom {

using Rgb = std::array<std::uint8_t, 3>;

struct LabelInfo {
  int id = 0;
  std::string name;
  Rgb color{0, 0, 0};
};

// The labels of a sequence or map. Ids are 0..size()-1 in order (label 0 is
// the background); a map's number of labels is labels.size().
class LabelSet {
 public:
  LabelSet() = default;
  explicit LabelSet(std::vector<LabelInfo> labels);

  [[nodiscard]] int size() const { return static_cast<int>(labels_.size()); }
  [[nodiscard]] bool empty() const { return labels_.empty(); }
  [[nodiscard]] bool contains(int id) const { return id >= 0 && id < size(); }
  [[nodiscard]] const LabelInfo& at(int id) const;  // throws std::out_of_range
  [[nodiscard]] const std::vector<LabelInfo>& all() const { return labels_; }
  [[nodiscard]] std::optional<int> findByName(const std::string& name) const;
  bool operator==(const LabelSet& other) const;

 private:
  std::vector<LabelInfo> labels_;
};

// Label names are 1 to kMaxLabelNameBytes bytes of UTF-8 without ASCII
// control characters (docs/sequence-format.md): a name must fit on one line of
// a text header or report and in the map file.
inline constexpr std::size_t kMaxLabelNameBytes = 255;
inline constexpr const char* kLabelNameRule =
    "a label name of 1 to 255 bytes of UTF-8 without control characters (line breaks, tabs, NUL)";

// What is wrong with `name` as a label name ("a name of 300 bytes", "a line
// feed (0x0a) at byte 5"); empty when it is a valid name.
[[nodiscard]] std::string labelNameProblem(const std::string& name);

// `text` with every ASCII control character (line breaks, tabs, NUL, DEL)
// replaced by '_': safe on one line of a text header (PLY comments) or of a
// report, whatever the label names of a map hold.
[[nodiscard]] std::string singleLineText(const std::string& text);

// The 39 Amazon Picking Challenge 2016 objects in the paper's numbering 1..39
// plus "__background__" as 0, coloured with the PASCAL VOC palette.
[[nodiscard]] LabelSet apc2016Labels();

// Reads a label list: one label name per line, label 0 (the background) first;
// blank lines and lines starting with '#' are skipped, blanks around a name are
// dropped. Ids follow the order of the names, colours the PASCAL VOC palette.
// Throws lom::Error naming the file (and the line) for anything that is not a
// regular file (a device or FIFO would never end), a file larger than
// kMaxLabelListBytes, an invalid or repeated name, or not 1 to 256 names.
inline constexpr std::size_t kMaxLabelListBytes = 1 << 20;
[[nodiscard]] LabelSet readLabelList(const std::filesystem::path& file);

// What a `--labels` option names: "apc2016" (the built-in set above) or a
// label list file (readLabelList), for both programs.
[[nodiscard]] LabelSet labelsOption(const std::string& value);

// Colour of label `id` in the PASCAL VOC palette (1 -> 128,0,0).
[[nodiscard]] Rgb vocColor(int id);

}  // namespace lom
