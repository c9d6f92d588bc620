#include "lom/error.hpp"

namespace lom {

std::string Problem::message() const {
  std::string text = file.empty() ? std::string() : file + ": ";
  if (!field.empty()) text += field + ": ";
  text += "expected " + expected;
  if (!found.empty()) text += ", found " + found;
  return text;
}

Error::Error(Problem problem) : std::runtime_error(problem.message()), problem_(std::move(problem)) {}

Error::Error(std::string file, std::string field, std::string expected, std::string found)
    : Error(Problem{std::move(file), std::move(field), std::move(expected), std::move(found)}) {}

namespace {
std::string joinProblems(const std::vector<Problem>& problems) {
  std::string text = std::to_string(problems.size()) +
                     (problems.size() == 1 ? " problem found:" : " problems found:");
  for (const auto& p : problems) text += "\n  " + p.message();
  return text;
}
}  // namespace

ValidationError::ValidationError(std::vector<Problem> problems)
    : std::runtime_error(joinProblems(problems)), problems_(std::move(problems)) {}

}  // namespace lom
