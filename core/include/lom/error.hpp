#pragma once
// Errors a user can cause: every message names the file, the field and what
// was expected, so the CLI and the studio can show it as it is.
#include <stdexcept>
#include <string>
#include <vector>

namespace lom {

struct Problem {
  std::string file;      // path of the offending file (or folder)
  std::string field;     // e.g. "frames[3].pose" or "camera.fx"
  std::string expected;  // what a valid value looks like
  std::string found;     // what was there instead (may be empty)

  [[nodiscard]] std::string message() const;
};

class Error : public std::runtime_error {
 public:
  explicit Error(Problem problem);
  Error(std::string file, std::string field, std::string expected, std::string found = {});
  [[nodiscard]] const Problem& problem() const { return problem_; }

 private:
  Problem problem_;
};

// `text` with every byte that is not part of a valid UTF-8 character replaced
// by `replacement`: names taken from the file system or a damaged file may be
// any bytes, and neither a terminal nor a UTF-8 file (JSON, SVG, Markdown)
// takes them as they are.
[[nodiscard]] std::string validUtf8(const std::string& text, const std::string& replacement = "?");

// Several problems found at once (validation lists all of them).
class ValidationError : public std::runtime_error {
 public:
  explicit ValidationError(std::vector<Problem> problems);
  [[nodiscard]] const std::vector<Problem>& problems() const { return problems_; }

 private:
  std::vector<Problem> problems_;
};

}  // namespace lom
