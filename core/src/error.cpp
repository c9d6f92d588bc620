#include "lom/error.hpp"

namespace lom {

namespace {

// Text taken from an input (a line of a list, a key of a file) can be any
// length: a message shows its start and says how long it is, instead of
// repeating a megabyte of it. Cut at a UTF-8 character boundary.
constexpr size_t kMaxQuotedBytes = 4000;

}  // namespace

// Bytes that are not UTF-8 (a damaged file's names, a topic read from a
// broken bag) become '?' in messages: a terminal or log shows the message,
// not mojibake.
std::string validUtf8(const std::string& text, const std::string& replacement) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    // RFC 3629: no overlong forms, no surrogates, nothing past U+10FFFF (as
    // JSON writers check), so the second byte's range depends on the first.
    size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;
    if (c < 0x80)
      length = 1;
    else if (c >= 0xC2 && c <= 0xDF)
      length = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
      length = 3;
      if (c == 0xE0) low = 0xA0;
      if (c == 0xED) high = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      length = 4;
      if (c == 0xF0) low = 0x90;
      if (c == 0xF4) high = 0x8F;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      valid = k == 1 ? next >= low && next <= high : (next & 0xC0) == 0x80;
    }
    if (valid) {
      out.append(text, i, length);
      i += length;
    } else {
      out += replacement;
      ++i;
    }
  }
  return out;
}

namespace {

std::string shortened(const std::string& raw) {
  const std::string text = validUtf8(raw);
  if (text.size() <= kMaxQuotedBytes) return text;
  size_t cut = kMaxQuotedBytes - 1000;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut) + "... (" + std::to_string(text.size()) + " bytes in all)";
}

}  // namespace

std::string Problem::message() const {
  std::string text = file.empty() ? std::string() : shortened(file) + ": ";
  if (!field.empty()) text += shortened(field) + ": ";
  text += "expected " + expected;  // the program's own words
  if (!found.empty()) text += ", found " + shortened(found);
  return text;
}

Error::Error(Problem problem) : std::runtime_error(problem.message()), problem_(std::move(problem)) {}

Error::Error(std::string file, std::string field, std::string expected, std::string found)
    : Error(Problem{std::move(file), std::move(field), std::move(expected), std::move(found)}) {}

namespace {
std::string joinProblems(const std::vector<Problem>& problems) {
  std::string text = std::to_string(problems.size()) +
                     (problems.size() == 1 ? " problem found:" : " problems found:");
  for (const auto& p : problems) text += "\n  " + p.message();
  return text;
}
}  // namespace

ValidationError::ValidationError(std::vector<Problem> problems)
    : std::runtime_error(joinProblems(problems)), problems_(std::move(problems)) {}

}  // namespace lom
