#include "json_text.hpp"

#include <fstream>
#include <sstream>

#include "lom/error.hpp"

namespace lom::json_text {

std::string describe(const nlohmann::json& value) {
  std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  switch (value.type()) {
    case nlohmann::json::value_t::string:
      return "the string " + text;
    case nlohmann::json::value_t::boolean:
      return "the boolean " + text;
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::array:
      return "an array " + text;
    case nlohmann::json::value_t::object:
      return "an object " + text;
    default:
      return "the number " + text;
  }
}

nlohmann::json parseFile(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(path.string(), "", "an existing file (" + what + ")", "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string(), "", what, "cannot open it");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    // Drop nlohmann's "[json.exception.parse_error.101] " prefix.
    std::string message = e.what();
    const auto bracket = message.find("] ");
    if (message.rfind("[json.exception", 0) == 0 && bracket != std::string::npos)
      message = message.substr(bracket + 2);
    throw Error(path.string(), "", "valid JSON", message);
  }
}

std::string inlineJson(const nlohmann::ordered_json& value) {
  if (!value.is_object() && !value.is_array())
    return value.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  std::string text = value.is_object() ? "{" : "[";
  bool first = true;
  for (auto it = value.begin(); it != value.end(); ++it, first = false) {
    if (!first) text += ", ";
    if (value.is_object()) text += nlohmann::ordered_json(it.key()).dump() + ": ";
    text += inlineJson(it.value());
  }
  return text + (value.is_object() ? "}" : "]");
}

std::string field(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

std::string indexed(const std::string& prefix, size_t index) {
  return prefix + "[" + std::to_string(index) + "]";
}

}  // namespace lom::json_text
