#pragma once
// Frame ranges as `fuse --frames` and the studio's Frames field read them.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace lom {

// An end frame of "to the last frame".
inline constexpr size_t kToTheEnd = static_cast<size_t>(-1);

// Frames first to end - 1.
struct FrameRange {
  size_t first = 0;
  size_t end = kToTheEnd;
};

// "A:B", "A:" (to the end) or ":B" (the first B), blanks around the numbers
// allowed; an empty text is every frame. On any other text, or B not after A,
// nullopt, and `expected` (when given) says what a range must be, to follow
// "expects" in a message: "non-negative frame indices A:B", ...
[[nodiscard]] std::optional<FrameRange> parseFrameRange(std::string_view text,
                                                        std::string* expected = nullptr);

// The text parseFrameRange reads back as `range`; empty for every frame.
[[nodiscard]] std::string frameRangeText(const FrameRange& range);

}  // namespace lom
