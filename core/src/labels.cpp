#include "lom/labels.hpp"

#include <fstream>
#include <map>
#include <stdexcept>
#include <system_error>

#include "file_checks.hpp"
#include "lom/error.hpp"

namespace lom {

LabelSet::LabelSet(std::vector<LabelInfo> labels) : labels_(std::move(labels)) {
  for (size_t i = 0; i < labels_.size(); ++i)
    if (labels_[i].id != static_cast<int>(i))
      throw std::invalid_argument("label ids must be 0..n-1 in order; label at position " +
                                  std::to_string(i) + " has id " +
                                  std::to_string(labels_[i].id));
}

namespace {
bool isControl(unsigned char c) { return c < 0x20 || c == 0x7f; }

// The byte where `text` stops being UTF-8 (a stray byte, a cut or overlong
// sequence, a surrogate), or npos.
size_t invalidUtf8At(const std::string& text) {
  const size_t n = text.size();
  size_t i = 0;
  while (i < n) {
    const auto c = static_cast<unsigned char>(text[i]);
    const size_t length = c < 0x80         ? 1
                          : (c >> 5) == 6  ? 2
                          : (c >> 4) == 14 ? 3
                          : (c >> 3) == 30 ? 4
                                           : 0;
    if (length == 0 || i + length > n) return i;
    for (size_t k = 1; k < length; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return i;
    const auto next = static_cast<unsigned char>(length > 1 ? text[i + 1] : 0);
    if ((length == 2 && c < 0xC2) || (length == 3 && c == 0xE0 && next < 0xA0) ||
        (length == 3 && c == 0xED && next >= 0xA0) || (length == 4 && c == 0xF0 && next < 0x90) ||
        (length == 4 && (c > 0xF4 || (c == 0xF4 && next >= 0x90))))
      return i;
    i += length;
  }
  return std::string::npos;
}
}  // namespace

std::string labelNameProblem(const std::string& name) {
  if (name.empty()) return "an empty name";
  if (name.size() > kMaxLabelNameBytes)
    return "a name of " + std::to_string(name.size()) + " bytes";
  for (size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (!isControl(c)) continue;
    const char* what = c == '\n'   ? "a line feed"
                       : c == '\r' ? "a carriage return"
                       : c == '\t' ? "a tab"
                       : c == 0    ? "a NUL character"
                                   : "a control character";
    static const char kHex[] = "0123456789abcdef";
    return std::string(what) + " (0x" + kHex[c >> 4] + kHex[c & 15] + ") at byte " +
           std::to_string(i);
  }
  // Names are written into JSON, PLY and reports as UTF-8: a name in another
  // encoding (Latin-1) would come out changed, and no longer be found by name.
  if (const size_t at = invalidUtf8At(name); at != std::string::npos)
    return "a byte that is not UTF-8 at byte " + std::to_string(at) + " (save the file as UTF-8)";
  return {};
}

std::string singleLineText(const std::string& text) {
  std::string out = text;
  for (char& c : out)
    if (isControl(static_cast<unsigned char>(c))) c = '_';
  return out;
}

const LabelInfo& LabelSet::at(int id) const {
  if (!contains(id)) throw std::out_of_range("label id " + std::to_string(id) + " not in label set");
  return labels_[static_cast<size_t>(id)];
}

std::optional<int> LabelSet::findByName(const std::string& name) const {
  for (const auto& label : labels_)
    if (label.name == name) return label.id;
  return std::nullopt;
}

bool LabelSet::operator==(const LabelSet& other) const {
  if (labels_.size() != other.labels_.size()) return false;
  for (size_t i = 0; i < labels_.size(); ++i)
    if (labels_[i].name != other.labels_[i].name || labels_[i].color != other.labels_[i].color)
      return false;
  return true;
}

LabelSet readLabelList(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string expected = "a label list file (one label name per line)";
  if (const std::string why = notARegularFile(file); !why.empty())
    throw Error(name, "", expected, why);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxLabelListBytes)
    throw Error(name, "",
                "a label list of at most " + std::to_string(kMaxLabelListBytes) + " bytes",
                "a file of " + std::to_string(size) + " bytes");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name, "", expected, "a file that cannot be opened");
  std::vector<LabelInfo> labels;
  std::map<std::string, size_t> line_of;
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    // A byte-order mark some editors put at the start of a UTF-8 file is not
    // part of the first line (which may be a comment).
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    // A UTF-16 file (Windows Notepad's "Unicode") would fail on its NUL bytes.
    if (number == 1 && (line.rfind("\xFF\xFE", 0) == 0 || line.rfind("\xFE\xFF", 0) == 0))
      throw Error(name, "", "a label list in UTF-8 (or ASCII)",
                  "a UTF-16 file (it starts with a UTF-16 byte-order mark): save it as UTF-8");
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
      line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string label = line.substr(first);
    const std::string field = "line " + std::to_string(number);
    if (const std::string problem = labelNameProblem(label); !problem.empty())
      throw Error(name, field, kLabelNameRule, problem);
    const auto [previous, inserted] = line_of.emplace(label, number);
    if (!inserted)
      throw Error(name, field, "each label name once",
                  "\"" + label + "\" again (also line " + std::to_string(previous->second) + ")");
    if (labels.size() == 256)
      throw Error(name, field, "a list of 1 to 256 label names", "more than 256 names");
    const int id = static_cast<int>(labels.size());
    labels.push_back({id, label, vocColor(id)});
  }
  if (in.bad())
    throw Error(name, "", expected, "a read error after line " + std::to_string(number));
  if (labels.empty())
    throw Error(name, "", "a list of 1 to 256 label names, one per line", "no names");
  return LabelSet(std::move(labels));
}

Rgb vocColor(int id) {
  // Bits of the id are spread over the high bits of the three channels.
  int r = 0, g = 0, b = 0;
  int c = id;
  for (int shift = 7; shift >= 0 && c; --shift) {
    r |= ((c >> 0) & 1) << shift;
    g |= ((c >> 1) & 1) << shift;
    b |= ((c >> 2) & 1) << shift;
    c >>= 3;
  }
  return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)};
}

LabelSet apc2016Labels() {
  static const char* const kNames[] = {
      "__background__",
      "barkely_hide_bones",
      "cherokee_easy_tee_shirt",
      "clorox_utility_brush",
      "cloud_b_plush_bear",
      "command_hooks",
      "cool_shot_glue_sticks",
      "crayola_24_ct",
      "creativity_chenille_stems",
      "dasani_water_bottle",
      "dove_beauty_bar",
      "dr_browns_bottle_brush",
      "easter_turtle_sippy_cup",
      "elmers_washable_no_run_school_glue",
      "expo_dry_erase_board_eraser",
      "fiskars_scissors_red",
      "fitness_gear_3lb_dumbbell",
      "folgers_classic_roast_coffee",
      "hanes_tube_socks",
      "i_am_a_bunny_book",
      "jane_eyre_dvd",
      "kleenex_paper_towels",
      "kleenex_tissue_box",
      "kyjen_squeakin_eggs_plush_puppies",
      "laugh_out_loud_joke_book",
      "oral_b_toothbrush_green",
      "oral_b_toothbrush_red",
      "peva_shower_curtain_liner",
      "platinum_pets_dog_bowl",
      "rawlings_baseball",
      "rolodex_jumbo_pencil_cup",
      "safety_first_outlet_plugs",
      "scotch_bubble_mailer",
      "scotch_duct_tape",
      "soft_white_lightbulb",
      "staples_index_cards",
      "ticonderoga_12_pencils",
      "up_glucose_bottle",
      "womens_knit_gloves",
      "woods_extension_cord",
  };
  std::vector<LabelInfo> labels;
  int id = 0;
  for (const char* name : kNames) {
    labels.push_back({id, name, vocColor(id)});
    ++id;
  }
  return LabelSet(std::move(labels));
}

LabelSet labelsOption(const std::string& value) {
  if (value == "apc2016") return apc2016Labels();
  return readLabelList(value);
}

}  // namespace lom
