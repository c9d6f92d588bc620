#pragma once
// JSON reading and writing shared by the core's file formats (sequence,
// annotations, segmenter configuration, exported objects). Includes
// nlohmann/json: include from .cpp files only.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace lom::json_text {

// "the string \"abc\"", "an array [1, 2]", "null", "the number 3": how a
// wrong value is named in an error message (long values are shortened).
std::string describe(const nlohmann::json& value);

// Reads and parses a JSON file; throws lom::Error naming the file, with
// `what` ("a readable sequence.json") in the message when it cannot be opened.
nlohmann::json parseFile(const std::filesystem::path& path, const std::string& what);

// One line, with a space after ':' and ',' (poses and boxes stay one line each).
std::string inlineJson(const nlohmann::ordered_json& value);

// "prefix.key" ("key" for an empty prefix) and "prefix[index]": error field names.
std::string field(const std::string& prefix, const std::string& key);
std::string indexed(const std::string& prefix, size_t index);

}  // namespace lom::json_text
