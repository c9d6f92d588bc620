#pragma once
// Plain-text tables (the CLI's and the text reports') line up in a terminal's
// columns, not in bytes: a label name such as "Küchenrolle" or "水杯" takes
// fewer columns than it has bytes, and a name cut to fit must not end in half
// a character.
#include <string>
#include <string_view>

namespace lom {

// Terminal columns `text` (UTF-8) takes: one per character, two for East Asian
// wide and full-width characters, none for combining marks. Bytes that are not
// valid UTF-8 count one column each (they are printed as a replacement).
[[nodiscard]] size_t textColumns(std::string_view text);

// `text` cut to at most `columns` columns at a character boundary; a cut text
// ends in `marker` (counted within `columns`).
[[nodiscard]] std::string cutToColumns(std::string_view text, size_t columns,
                                       std::string_view marker = "~");

// `text` followed (padRight) or preceded (padLeft) by spaces up to `columns`
// columns; text already as wide is returned as it is.
[[nodiscard]] std::string padRight(std::string_view text, size_t columns);
[[nodiscard]] std::string padLeft(std::string_view text, size_t columns);

}  // namespace lom
