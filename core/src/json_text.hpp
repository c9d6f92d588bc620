#pragma once
// JSON reading and writing shared by the core's file formats (sequence,
// annotations, segmenter configuration, exported objects). Includes
// nlohmann/json: include from .cpp files only.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace lom::json_text {

// Arrays and objects nested deeper than this are refused before parsing: no
// file format of the program nests more than a few levels, and very deep
// nesting would exhaust the stack of code that walks the tree recursively.
inline constexpr std::size_t kMaxNesting = 256;

// "the string \"abc\"", "an array [1,2]", "null", "the number 3": how a
// wrong value is named in an error message. Long values are shortened; the
// value is walked without recursion and only as far as the shortened text needs.
std::string describe(const nlohmann::json& value);

// Parses JSON text; throws lom::Error naming `file` for invalid JSON (with the
// line and column), numbers out of the range of a double (with the field
// holding them) and nesting deeper than kMaxNesting.
nlohmann::json parseText(const std::string& text, const std::string& file);

// Reads and parses a JSON file (as parseText); throws lom::Error naming the
// file, with `what` ("a readable sequence.json") in the message when it
// cannot be opened.
nlohmann::json parseFile(const std::filesystem::path& path, const std::string& what);

// One line, with a space after ':' and ',' (poses and boxes stay one line each).
std::string inlineJson(const nlohmann::ordered_json& value);

// "prefix.key" ("key" for an empty prefix) and "prefix[index]": error field names.
std::string field(const std::string& prefix, const std::string& key);
std::string indexed(const std::string& prefix, size_t index);

}  // namespace lom::json_text
