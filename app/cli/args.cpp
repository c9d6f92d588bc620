#include "args.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace lom::cli {

Args::Args(std::vector<std::string> words, std::set<std::string> flags)
    : flag_names_(std::move(flags)) {
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word.size() > 2 && word.rfind("--", 0) == 0) {
      std::string name = word.substr(2);
      const auto eq = name.find('=');
      if (eq != std::string::npos) {
        // A switch is on by being given: --native=1 would otherwise be a
        // value nobody reads, and the switch silently off.
        if (flag_names_.count(name.substr(0, eq)))
          throw UsageError("option --" + name.substr(0, eq) +
                           " is a switch and takes no value (give --" + name.substr(0, eq) +
                           " alone), got '" + word + "'");
        options_.emplace_back(name.substr(0, eq), name.substr(eq + 1));
      } else if (flag_names_.count(name)) {
        flags_set_.insert(name);
      } else {
        if (i + 1 >= words.size()) {
          dangling_ = name;  // reported by expectOnly, once unknown options are
          break;
        }
        options_.emplace_back(name, words[++i]);
      }
    } else {
      positionals_.push_back(word);
    }
  }
}

const std::string& Args::positional(size_t i, const std::string& what) const {
  if (i >= positionals_.size()) throw UsageError("missing argument: " + what);
  return positionals_[i];
}

std::optional<std::string> Args::option(const std::string& name) const {
  std::optional<std::string> value;
  for (const auto& [key, v] : options_)
    if (key == name) value = v;  // (expectOnly refuses an option given twice)
  return value;
}

std::string Args::required(const std::string& name) const {
  auto value = option(name);
  if (!value) throw UsageError("missing option --" + name);
  if (value->empty()) throw UsageError("option --" + name + " expects a value, got an empty one");
  return *value;
}

double Args::number(const std::string& name, double fallback) const {
  auto value = option(name);
  if (!value) return fallback;
  char* end = nullptr;
  const double parsed = std::strtod(value->c_str(), &end);
  if (value->empty() || *end != '\0')
    throw UsageError("option --" + name + " expects a number, got '" + *value + "'");
  if (!std::isfinite(parsed))
    throw UsageError("option --" + name + " expects a finite number, got '" + *value + "'");
  return parsed;
}

long Args::integer(const std::string& name, long fallback, long low, long high) const {
  auto value = option(name);
  if (!value) return fallback;
  char* end = nullptr;
  errno = 0;
  const long parsed = std::strtol(value->c_str(), &end, 10);
  if (value->empty() || *end != '\0')
    throw UsageError("option --" + name + " expects an integer, got '" + *value + "'");
  if (errno == ERANGE || parsed < low || parsed > high)
    throw UsageError("option --" + name + " expects an integer from " + std::to_string(low) +
                     " to " + std::to_string(high) + ", got '" + *value + "'");
  return parsed;
}

void Args::expectOnly(const std::set<std::string>& known, size_t max_positionals) const {
  for (const auto& [key, v] : options_)
    if (!known.count(key)) throw UsageError("unknown option --" + key);
  for (const auto& f : flags_set_)
    if (!known.count(f)) throw UsageError("unknown option --" + f);
  if (dangling_) {
    if (!known.count(*dangling_)) throw UsageError("unknown option --" + *dangling_);
    throw UsageError("option --" + *dangling_ + " expects a value");
  }
  // `--out --no-noise`: the value forgotten, the next option taken for it (a
  // folder named --no-noise, the switch off).
  for (const auto& [key, v] : options_) {
    if (v.size() <= 2 || v.rfind("--", 0) != 0) continue;
    const std::string next =
        v.substr(2, v.find('=') == std::string::npos ? std::string::npos : v.find('=') - 2);
    if (known.count(next) || flag_names_.count(next))
      throw UsageError("option --" + key + " expects a value, got the option " + v);
  }
  for (size_t i = 0; i < options_.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (options_[j].first == options_[i].first)
        throw UsageError("option --" + options_[i].first + " is given twice ('" +
                         options_[j].second + "' and '" + options_[i].second + "'); give it once" +
                         (options_[i].first == "labels" || options_[i].first == "candidates"
                              ? " with a comma-separated list"
                              : ""));
  if (positionals_.size() > max_positionals)
    throw UsageError("unexpected argument '" + positionals_[max_positionals] + "'");
}

std::vector<int> parseLabelList(const std::string& text, const std::string& option) {
  std::vector<int> values;
  std::stringstream stream(text);
  std::string item;
  // Digits only between the commas (no blanks, signs or an empty last item).
  const bool trailing_comma = !text.empty() && text.back() == ',';
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(item.c_str(), &end, 10);
    const size_t first_digit =
        !item.empty() && item[0] == '-' ? 1 : 0;  // "-1": out of range, below
    if (item.size() <= first_digit || *end != '\0' || trailing_comma ||
        !std::isdigit(static_cast<unsigned char>(item[first_digit])))
      throw UsageError("option --" + option + " expects a comma-separated list of integers, got '" +
                       text + "'");
    if (errno == ERANGE || v < 0 || v > kMaxLabelId)
      throw UsageError("option --" + option + " expects label ids from 0 to " +
                       std::to_string(kMaxLabelId) + " (a map holds at most " +
                       std::to_string(kMaxLabelId + 1) + " labels), got " + item);
    values.push_back(static_cast<int>(v));
  }
  if (values.empty()) throw UsageError("option --" + option + " expects at least one integer");
  return values;
}

bool isHelpWord(const std::string& word) { return word == "--help" || word == "-h"; }

// "a,b,c,..." -> exactly `count` finite numbers; throws UsageError naming the option.
std::vector<double> parseNumbers(const std::string& text, size_t count, const std::string& option,
                                 const std::string& expected) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  const auto fail = [&]() {
    return UsageError("option --" + option + " expects " + expected + ", got '" + text + "'");
  };
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v)) throw fail();
    values.push_back(v);
  }
  if (values.size() != count || (!text.empty() && text.back() == ',')) throw fail();
  return values;
}

Eigen::Vector3d parseDirection(const std::string& text, const std::string& option) {
  const std::string expected = "a direction x,y,z of three finite numbers, not all zero";
  const auto v = parseNumbers(text, 3, option, expected);
  // Scaled by the largest component first, so that neither huge nor tiny components
  // overflow or vanish when the length is taken.
  const Eigen::Vector3d direction(v[0], v[1], v[2]);
  const double largest = direction.cwiseAbs().maxCoeff();
  const Eigen::Vector3d unit = largest > 0.0 ? (direction / largest).normalized() : direction;
  if (!(largest > 0.0) || !unit.allFinite() || !(unit.norm() > 0.5))
    throw UsageError("option --" + option + " expects " + expected + ", got '" + text + "'");
  return unit;
}

}  // namespace lom::cli
