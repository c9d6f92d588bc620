#include "lom/sequence_files.hpp"

#include <system_error>
#include <utility>
#include <vector>

#include "lom/sequence.hpp"

namespace lom {

namespace fs = std::filesystem;

fs::path resolvedPath(const fs::path& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec) absolute = path;
  fs::path result = fs::weakly_canonical(absolute, ec);
  if (ec) result = absolute.lexically_normal();
  if (!result.has_filename() && result.has_parent_path()) result = result.parent_path();
  return result;
}

namespace {

// Whether `a` and `b` name the same file (existing or not).
bool samePath(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return resolvedPath(a) == resolvedPath(b) || fs::equivalent(a, b, ec);
}

}  // namespace

std::optional<OwnedSequenceFile> sequenceFileAt(const fs::path& path) {
  const fs::path target = resolvedPath(path);
  std::error_code ec;
  for (fs::path folder = target.parent_path();; folder = folder.parent_path()) {
    if (fs::is_regular_file(folder / "sequence.json", ec)) {
      std::vector<std::pair<fs::path, std::string>> owned = {
          {folder / "sequence.json", "the sequence file"},
          {folder / "annotations.json", "the ground-truth boxes"},
          {folder / "annotations.yaml", "the ground-truth boxes"},
          {folder / "annotations.yml", "the ground-truth boxes"}};
      try {
        for (const fs::path& file : frameFilesOf(loadSequence(folder)))
          owned.emplace_back(file, "a frame file");
      } catch (const std::exception&) {
        // An unreadable sequence names no frame files; its own files stay protected.
      }
      for (auto& [file, what] : owned)
        if (samePath(path, file)) {
          const bool exists = fs::exists(fs::symlink_status(file, ec));
          return OwnedSequenceFile{std::move(file), std::move(what), folder, exists};
        }
    }
    if (!folder.has_parent_path() || folder.parent_path() == folder) break;
  }
  return std::nullopt;
}

}  // namespace lom
