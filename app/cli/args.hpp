#pragma once
// Minimal command-line parsing for the labeloctomap subcommands:
// positionals, "--name value" options and "--flag" switches.
#include <Eigen/Core>
#include <climits>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace lom::cli {

// A mistake in how the command was called; main prints it with the usage and exits 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // `flags` are the options that take no value; every other --name takes one.
  Args(std::vector<std::string> words, std::set<std::string> flags);

  [[nodiscard]] size_t positionalCount() const { return positionals_.size(); }
  [[nodiscard]] const std::string& positional(size_t i, const std::string& what) const;
  [[nodiscard]] bool flag(const std::string& name) const { return flags_set_.count(name) > 0; }
  [[nodiscard]] std::optional<std::string> option(const std::string& name) const;
  // The value of --name; throws UsageError when it is absent or empty.
  [[nodiscard]] std::string required(const std::string& name) const;
  // A finite number (NaN and infinities are refused; no option means either).
  [[nodiscard]] double number(const std::string& name, double fallback) const;
  // An integer from `low` to `high` (by default the range of int), checked before any
  // narrowing so that a value such as 4294967302 is refused instead of wrapping around.
  [[nodiscard]] long integer(const std::string& name, long fallback, long low = INT_MIN,
                             long high = INT_MAX) const;
  // Throws UsageError for any option not in `known` (first, so that an unknown
  // option at the end is named as unknown, not as missing its value), for an
  // option without its value, for an option given twice (a second --out or
  // --labels would otherwise replace the first without a word) and for extra
  // positionals.
  void expectOnly(const std::set<std::string>& known, size_t max_positionals) const;

 private:
  std::optional<std::string> dangling_;  // the last word, an option without its value
  std::vector<std::string> positionals_;
  std::vector<std::pair<std::string, std::string>> options_;
  std::set<std::string> flag_names_;
  std::set<std::string> flags_set_;
};

// A list of label ids, "0,8,19" -> {0, 8, 19}: each from 0 to kMaxLabelId (a map holds at
// most 256 labels); throws UsageError naming `option` otherwise.
inline constexpr int kMaxLabelId = 255;
std::vector<int> parseLabelList(const std::string& text, const std::string& option);

// "a,b,c,..." -> exactly `count` finite numbers; throws UsageError naming --option and
// what was `expected`.
std::vector<double> parseNumbers(const std::string& text, size_t count, const std::string& option,
                                 const std::string& expected);
// "x,y,z" -> a unit direction; throws UsageError naming --option for anything but three
// finite numbers, not all zero.
Eigen::Vector3d parseDirection(const std::string& text, const std::string& option);

// Whether the word asks for a command's usage (--help or -h).
bool isHelpWord(const std::string& word);

}  // namespace lom::cli
