#pragma once
// The files that belong to a sequence, which no output may replace.
#include <filesystem>
#include <optional>
#include <string>

namespace lom {

struct OwnedSequenceFile {
  std::filesystem::path file;    // as the sequence names it
  std::string what;              // "the sequence file", "the ground-truth boxes", "a frame file"
  std::filesystem::path folder;  // the sequence folder
  bool exists = false;           // names of absent files are reserved too
};

// `path` absolute, with the symbolic links of its existing part resolved and
// no trailing separator: the same text for every name of a file or folder.
[[nodiscard]] std::filesystem::path resolvedPath(const std::filesystem::path& path);

// The file of a sequence that writing `path` would replace, under any name
// (symbolic links of the existing part resolved): the sequence.json, the
// ground-truth boxes (annotations.json, .yaml, .yml) or a frame file of any
// sequence folder that holds `path` (a folder above it with a sequence.json).
// The boxes' names are reserved while the file is absent (the studio makes it
// later). nullopt when `path` is none of these; an unreadable sequence.json
// names no frame files.
[[nodiscard]] std::optional<OwnedSequenceFile> sequenceFileAt(const std::filesystem::path& path);

}  // namespace lom
