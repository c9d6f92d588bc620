#include "lom/text_columns.hpp"

namespace lom {
namespace {

struct Decoded {
  char32_t code = 0;
  size_t bytes = 1;
  bool valid = false;
};

Decoded decodeAt(std::string_view text, size_t i) {
  const auto c = static_cast<unsigned char>(text[i]);
  size_t length = 0;
  char32_t code = 0;
  if (c < 0x80) return {c, 1, true};
  if (c >= 0xC2 && c <= 0xDF) {
    length = 2;
    code = c & 0x1F;
  } else if (c >= 0xE0 && c <= 0xEF) {
    length = 3;
    code = c & 0x0F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    length = 4;
    code = c & 0x07;
  } else {
    return {};
  }
  if (i + length > text.size()) return {};
  for (size_t k = 1; k < length; ++k) {
    const auto next = static_cast<unsigned char>(text[i + k]);
    if ((next & 0xC0) != 0x80) return {};
    code = (code << 6) | (next & 0x3F);
  }
  return {code, length, true};
}

bool inRange(char32_t code, char32_t first, char32_t last) { return code >= first && code <= last; }

size_t columnsOf(char32_t code) {
  // Combining marks and zero-width characters take no column of their own.
  if (inRange(code, 0x0300, 0x036F) || inRange(code, 0x1AB0, 0x1AFF) ||
      inRange(code, 0x1DC0, 0x1DFF) || inRange(code, 0x20D0, 0x20FF) ||
      inRange(code, 0xFE20, 0xFE2F) || inRange(code, 0x200B, 0x200F) || code == 0xFEFF)
    return 0;
  // East Asian wide and full-width blocks (Unicode's EastAsianWidth W and F, by block).
  if (inRange(code, 0x1100, 0x115F) || inRange(code, 0x2E80, 0x303E) ||
      inRange(code, 0x3041, 0x33FF) || inRange(code, 0x3400, 0x4DBF) ||
      inRange(code, 0x4E00, 0x9FFF) || inRange(code, 0xA000, 0xA4CF) ||
      inRange(code, 0xAC00, 0xD7A3) || inRange(code, 0xF900, 0xFAFF) ||
      inRange(code, 0xFE30, 0xFE4F) || inRange(code, 0xFF00, 0xFF60) ||
      inRange(code, 0xFFE0, 0xFFE6) || inRange(code, 0x1F300, 0x1F64F) ||
      inRange(code, 0x1F900, 0x1F9FF) || inRange(code, 0x20000, 0x3FFFD))
    return 2;
  return 1;
}

}  // namespace

size_t textColumns(std::string_view text) {
  size_t columns = 0;
  for (size_t i = 0; i < text.size();) {
    const Decoded d = decodeAt(text, i);
    columns += d.valid ? columnsOf(d.code) : 1;
    i += d.bytes;
  }
  return columns;
}

std::string cutToColumns(std::string_view text, size_t columns, std::string_view marker) {
  if (textColumns(text) <= columns) return std::string(text);
  const size_t marker_columns = textColumns(marker);
  if (marker_columns > columns) return std::string();
  const size_t budget = columns - marker_columns;
  size_t used = 0;
  size_t end = 0;
  for (size_t i = 0; i < text.size();) {
    const Decoded d = decodeAt(text, i);
    const size_t width = d.valid ? columnsOf(d.code) : 1;
    if (used + width > budget) break;
    used += width;
    i += d.bytes;
    end = i;
  }
  return std::string(text.substr(0, end)) + std::string(marker);
}

std::string padRight(std::string_view text, size_t columns) {
  const size_t width = textColumns(text);
  return std::string(text) + std::string(width < columns ? columns - width : 0, ' ');
}

std::string padLeft(std::string_view text, size_t columns) {
  const size_t width = textColumns(text);
  return std::string(width < columns ? columns - width : 0, ' ') + std::string(text);
}

}  // namespace lom
