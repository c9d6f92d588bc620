#include "json_text.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "file_checks.hpp"
#include "lom/error.hpp"

namespace lom::json_text {

namespace {

using Json = nlohmann::json;

constexpr size_t kDescribeLength = 60;

// Drops nlohmann's "[json.exception.parse_error.101] " prefix.
std::string withoutExceptionId(std::string message) {
  const auto bracket = message.find("] ");
  if (message.rfind("[json.exception", 0) == 0 && bracket != std::string::npos)
    message = message.substr(bracket + 2);
  return message;
}

// "line 3, column 12" of the byte `offset` (lines and columns from 1, as nlohmann counts them).
std::string positionText(const std::string& text, size_t offset) {
  offset = std::min(offset, text.size());
  size_t line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < offset; ++i)
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}

// Refuses nesting deeper than kMaxNesting before the parser builds anything.
void checkNesting(const std::string& text, const std::string& file) {
  size_t depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw Error(file, "",
                    "JSON with arrays and objects nested at most " + std::to_string(kMaxNesting) +
                        " levels deep",
                    "deeper nesting at " + positionText(text, i));
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// Builds the tree with nlohmann's own DOM builder and keeps track of where in
// the tree the parser is, so that a number too large for a double is reported
// with its field ("frames[0].pose[3]") and position instead of an exception.
class TrackingBuilder {
 public:
  explicit TrackingBuilder(Json& result) : dom_(result, false) {}

  bool null() { return value() && dom_.null(); }
  bool boolean(bool v) { return value() && dom_.boolean(v); }
  bool number_integer(Json::number_integer_t v) { return value() && dom_.number_integer(v); }
  bool number_unsigned(Json::number_unsigned_t v) { return value() && dom_.number_unsigned(v); }
  bool number_float(Json::number_float_t v, const Json::string_t& s) {
    return value() && dom_.number_float(v, s);
  }
  bool string(Json::string_t& v) { return value() && dom_.string(v); }
  bool binary(Json::binary_t& v) { return value() && dom_.binary(v); }
  bool start_object(std::size_t size) {
    if (!value()) return false;
    path_.push_back({false, 0, {}, {}});
    return dom_.start_object(size);
  }
  // A key given twice in one object would silently keep the last value:
  // refused, naming the field.
  bool key(Json::string_t& k) {
    path_.back().key = k;
    if (!path_.back().keys.insert(k).second) {
      duplicate_field_ = nextField();
      duplicate_key_ = k;
      return false;
    }
    return dom_.key(k);
  }
  bool end_object() {
    path_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t size) {
    if (!value()) return false;
    path_.push_back({true, 0, {}, {}});
    return dom_.start_array(size);
  }
  bool end_array() {
    path_.pop_back();
    return dom_.end_array();
  }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception& e) {
    error_position_ = position;
    error_token_ = token;
    error_id_ = e.id;
    error_message_ = e.what();
    error_field_ = nextField();
    return false;
  }

  [[nodiscard]] size_t errorPosition() const { return error_position_; }
  [[nodiscard]] const std::string& errorToken() const { return error_token_; }
  [[nodiscard]] int errorId() const { return error_id_; }
  [[nodiscard]] const std::string& errorMessage() const { return error_message_; }
  [[nodiscard]] const std::string& errorField() const { return error_field_; }
  // The field of a key given twice in its object; empty when none was.
  [[nodiscard]] const std::string& duplicateField() const { return duplicate_field_; }
  [[nodiscard]] const std::string& duplicateKey() const { return duplicate_key_; }

 private:
  struct Level {
    bool array;
    size_t count;     // values seen so far (arrays)
    std::string key;  // the current key (objects)
    std::set<std::string> keys;  // the keys seen so far (objects)
  };

  // Every value advances the index of the array holding it.
  bool value() {
    if (!path_.empty() && path_.back().array) ++path_.back().count;
    return true;
  }

  // The field of the value the parser reads next (or has just started).
  std::string nextField() const {
    std::string text;
    for (size_t i = 0; i < path_.size(); ++i) {
      const Level& level = path_[i];
      const bool last = i + 1 == path_.size();
      if (level.array) {
        // Inner levels were counted when they started; the last one counts
        // the value being read only once it is complete.
        const size_t index = last ? level.count : level.count - 1;
        text = indexed(text, index);
      } else {
        text = field(text, level.key);
      }
    }
    return text;
  }

  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  std::vector<Level> path_;
  size_t error_position_ = 0;
  std::string error_token_;
  int error_id_ = 0;
  std::string error_message_;
  std::string error_field_;
  std::string duplicate_field_;
  std::string duplicate_key_;
};

void appendScalar(const Json& value, std::string& out) {
  if (value.is_string()) {
    const std::string& s = value.get_ref<const std::string&>();
    // Only the start of a long string can be shown; cut it before dumping.
    out += Json(s.size() > kDescribeLength ? s.substr(0, kDescribeLength) : s)
               .dump(-1, ' ', false, Json::error_handler_t::replace);
    return;
  }
  out += value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Compact JSON text of `value` (as dump() writes it), stopping once `out` is
// longer than `limit`: an explicit stack instead of recursion.
void appendPrefix(const Json& value, size_t limit, std::string& out) {
  struct Open {
    const Json* container;
    Json::const_iterator next;
    bool first;
  };
  std::vector<Open> stack;
  const Json* pending = &value;
  while (out.size() <= limit) {
    if (pending) {
      if (pending->is_structured()) {
        out += pending->is_array() ? '[' : '{';
        stack.push_back({pending, pending->cbegin(), true});
      } else {
        appendScalar(*pending, out);
      }
      pending = nullptr;
    }
    if (stack.empty()) return;
    Open& open = stack.back();
    if (open.next == open.container->cend()) {
      out += open.container->is_array() ? ']' : '}';
      stack.pop_back();
      continue;
    }
    if (!open.first) out += ',';
    open.first = false;
    if (open.container->is_object())
      out += Json(open.next.key()).dump(-1, ' ', false, Json::error_handler_t::replace) + ":";
    pending = &*open.next;
    ++open.next;
  }
}

}  // namespace

std::string describe(const Json& value) {
  std::string text;
  appendPrefix(value, kDescribeLength, text);
  if (text.size() > kDescribeLength) text = text.substr(0, kDescribeLength - 3) + "...";
  switch (value.type()) {
    case Json::value_t::string:
      return "the string " + text;
    case Json::value_t::boolean:
      return "the boolean " + text;
    case Json::value_t::null:
      return "null";
    case Json::value_t::array:
      return "an array " + text;
    case Json::value_t::object:
      return "an object " + text;
    default:
      return "the number " + text;
  }
}

Json parseText(const std::string& text, const std::string& file) {
  // The parser takes a NUL byte for the end of its input, which would call a
  // binary or damaged file "unexpected end of input".
  if (const size_t nul = text.find('\0'); nul != std::string::npos)
    throw Error(file, "", "a JSON text file",
                "a NUL byte at " + positionText(text, nul) + " (a binary or damaged file?)");
  checkNesting(text, file);
  Json result;
  TrackingBuilder builder(result);
  if (Json::sax_parse(text, &builder, Json::input_format_t::json, /*strict=*/true)) return result;
  if (!builder.duplicateField().empty())
    throw Error(file, builder.duplicateField(), "each key once in its object",
                "the key \"" + builder.duplicateKey() + "\" a second time");
  // 406: a number that does not fit a double ("1e999"); nlohmann reports it
  // as out of range, and as the parser's error only to a SAX handler. The
  // position is where the number ends: report where it starts.
  if (builder.errorId() == 406) {
    const size_t end = builder.errorPosition();
    const size_t length = builder.errorToken().size();
    const std::string where = positionText(text, end >= length ? end - length : end);
    throw Error(file, builder.errorField(),
                "a finite number (JSON numbers here must fit a double, at most about 1.8e308)",
                "'" + builder.errorToken() + "' at " + where);
  }
  // NaN and Infinity are no JSON, but Python's json.dump writes them (unless
  // allow_nan=False): name the field, and the fix, not only a lexer error.
  {
    // The lexer stops just after the first character that cannot go on a
    // literal ('N', the 'a' of "nan", the 'I' of "-Infinity"): the word is
    // the letters (and sign) around it.
    const auto wordChar = [](char c) {
      return std::isalpha(static_cast<unsigned char>(c)) || c == '-';
    };
    size_t start = std::min(builder.errorPosition(), text.size());
    while (start > 0 && wordChar(text[start - 1])) --start;
    size_t word_end = start;
    while (word_end < text.size() && word_end - start < 12 && wordChar(text[word_end])) ++word_end;
    std::string word = text.substr(start, word_end - start);
    std::string bare = word.rfind('-', 0) == 0 ? word.substr(1) : word;
    for (char& c : bare) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (bare == "nan" || bare == "infinity" || bare == "inf")
      throw Error(file, builder.errorField(),
                  "a finite number (JSON has no NaN or Infinity; Python's json.dump writes them "
                  "unless given allow_nan=False)",
                  "'" + word + "' at " + positionText(text, start));
  }
  throw Error(file, "", "valid JSON", withoutExceptionId(builder.errorMessage()));
}

Json parseFile(const std::filesystem::path& path, const std::string& what) {
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(path.string(), "", "an existing file (" + what + ")", why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string(), "", what, "cannot open it");
  std::stringstream text;
  text << in.rdbuf();
  return parseText(text.str(), path.string());
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
