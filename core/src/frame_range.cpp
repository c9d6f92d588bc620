#include "lom/frame_range.hpp"

#include <limits>

namespace lom {

namespace {

constexpr size_t kLargestIndex = static_cast<size_t>(std::numeric_limits<long>::max());

std::string_view trimmed(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

// Digits only (no sign, no blanks inside); an empty part is `fallback`.
std::optional<size_t> index(std::string_view part, size_t fallback, std::string* expected) {
  part = trimmed(part);
  if (part.empty()) return fallback;
  size_t value = 0;
  for (const char c : part) {
    if (c < '0' || c > '9') {
      if (expected) *expected = "non-negative frame indices A:B";
      return std::nullopt;
    }
    const auto digit = static_cast<size_t>(c - '0');
    if (value > (kLargestIndex - digit) / 10) {
      if (expected)
        *expected = "frame indices of at most " + std::to_string(kLargestIndex) + " (frame index " +
                    std::string(part) + " is too large)";
      return std::nullopt;
    }
    value = value * 10 + digit;
  }
  return value;
}

}  // namespace

std::optional<FrameRange> parseFrameRange(std::string_view text, std::string* expected) {
  text = trimmed(text);
  if (text.empty()) return FrameRange{};
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos) {
    if (expected) *expected = "A:B (first frame, end frame exclusive), A: or :B";
    return std::nullopt;
  }
  const std::optional<size_t> first = index(text.substr(0, colon), 0, expected);
  if (!first) return std::nullopt;
  const std::optional<size_t> end = index(text.substr(colon + 1), kToTheEnd, expected);
  if (!end) return std::nullopt;
  if (*end <= *first) {
    if (expected) *expected = "an end frame B after the first frame A";
    return std::nullopt;
  }
  return FrameRange{*first, *end};
}

std::string frameRangeText(const FrameRange& range) {
  if (range.first == 0 && range.end == kToTheEnd) return {};
  return std::to_string(range.first) + ":" +
         (range.end == kToTheEnd ? std::string() : std::to_string(range.end));
}

}  // namespace lom
