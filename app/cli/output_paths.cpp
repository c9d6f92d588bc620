#include "output_paths.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "args.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/sequence.hpp"
#include "lom/sequence_files.hpp"

namespace lom::cli {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool isInside(const fs::path& path, const fs::path& folder) {
  const fs::path inner = resolvedPath(path), outer = resolvedPath(folder);
  const auto [outer_end, inner_end] =
      std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
  return outer_end == outer.end();
}

// What an existing path is when it is not a regular file; empty otherwise (and when absent).
std::string notARegularFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || status.type() == fs::file_type::not_found || fs::is_regular_file(status)) return {};
  if (fs::is_directory(status)) return "an existing folder";
  if (fs::is_character_file(status) || fs::is_block_file(status)) return "a device";
  if (fs::is_fifo(status)) return "a FIFO";
  if (fs::is_socket(status)) return "a socket";
  return "an existing file that is not a regular file";
}

// Whether `path` exists and is not a folder (so no output folder can be made there).
bool isExistingFile(const fs::path& path) {
  std::error_code ec;
  return fs::exists(path, ec) && !fs::is_directory(path, ec);
}

// The input folder that `path` lies inside (or is); nullptr when none.
const CommandInputs::File* inputFolderHolding(const fs::path& path, const CommandInputs& inputs) {
  for (const auto& folder : inputs.folders)
    if (isInside(path, folder.path)) return &folder;
  return nullptr;
}

void checkNotAnInput(const fs::path& out, const std::string& option, const CommandInputs& inputs) {
  std::error_code ec;
  for (const auto& input : inputs.files)
    if (fs::equivalent(out, input.path, ec))
      throw UsageError("--" + option + " " + out.string() + " is " + input.what + " " +
                       input.path.string() + " itself; choose another path");
}

// Neither one of the inputs nor inside an input sequence folder.
void checkOutsideInputs(const fs::path& out, const std::string& option, const std::string& what,
                        const CommandInputs& inputs) {
  checkNotAnInput(out, option, inputs);
  if (const auto* folder = inputFolderHolding(out, inputs))
    throw UsageError("--" + option + " " + out.string() + " lies inside " + folder->what + " " +
                     folder->path.string() + "; write " + what + " outside it");
}

}  // namespace

void checkNotASequenceFile(const fs::path& out, const std::string& option) {
  if (const std::optional<OwnedSequenceFile> owned = sequenceFileAt(out))
    throw UsageError("--" + option + " " + out.string() +
                     (owned->exists ? " would overwrite " : " is the name reserved for ") +
                     owned->what + " " + owned->file.string() + " of the sequence in " +
                     owned->folder.string() + "; choose another path");
}

bool isSameOrInside(const fs::path& path, const fs::path& folder) { return isInside(path, folder); }

void checkHoldsNoFramesOfSequencesAbove(const fs::path& out, const std::string& option,
                                        const std::string& what) {
  const fs::path target = resolvedPath(out);
  std::error_code ec;
  for (fs::path folder = target.parent_path(); !folder.empty(); folder = folder.parent_path()) {
    if (fs::is_regular_file(folder / "sequence.json", ec)) {
      std::vector<fs::path> frames;
      try {
        frames = frameFilesOf(loadSequence(folder));
      } catch (const std::exception&) {
        // An unreadable sequence names no frame files.
      }
      for (const fs::path& file : frames)
        if (isInside(file, target))
          throw UsageError("--" + option + " " + out.string() + " holds frame files of the " +
                           "sequence in " + folder.string() + " (" + file.string() + "), which " +
                           what + " would overwrite; choose another folder");
    }
    if (!folder.has_parent_path() || folder.parent_path() == folder) break;
  }
}

void CommandInputs::addSequenceFiles(const Sequence& sequence) {
  addFile(sequence.root / "sequence.json", "the sequence file");
  for (const auto& file : frameFilesOf(sequence)) addFile(file, "the frame file");
}

void CommandInputs::addSequence(const Sequence& sequence) {
  addSequenceFiles(sequence);
  addFolder(sequence.root, "the input sequence folder");
}

void CommandInputs::addSequenceJson(const fs::path& folder_or_json) {
  std::error_code ec;
  if (fs::is_directory(folder_or_json, ec))
    addFile(folder_or_json / "sequence.json", "the sequence file");
  else if (fs::is_regular_file(folder_or_json, ec))
    addFile(folder_or_json, "the sequence file");
}

void CommandInputs::addSequencePath(const fs::path& folder_or_json) {
  addSequenceJson(folder_or_json);
  std::error_code ec;
  if (fs::is_directory(folder_or_json, ec))
    addFolder(folder_or_json, "the input sequence folder");
  else if (fs::is_regular_file(folder_or_json, ec))
    addFolder(resolvedPath(folder_or_json).parent_path(), "the input sequence folder");
}

void requireExtension(const fs::path& out, const std::string& option, const std::string& extension,
                      const std::string& what) {
  if (out.empty()) throw UsageError("option --" + option + " expects a file name, got none");
  if (lower(out.extension().string()) != lower(extension))
    throw UsageError("option --" + option + " expects a file name ending in " + extension + " (" +
                     what + "), got '" + out.string() + "'");
}

std::optional<fs::path> fileInPlaceOfFolder(const fs::path& folder) {
  std::error_code ec;
  for (fs::path part = folder; !part.empty(); part = part.parent_path()) {
    if (fs::is_directory(part, ec)) break;
    if (fs::exists(part, ec)) return part;
    if (part == part.parent_path()) break;
  }
  return std::nullopt;
}

namespace {

// Why `folder` is not a folder: it is a file, a file above it hides the rest
// of the path, or it does not exist.
std::string missingFolderProblem(const fs::path& folder) {
  if (const auto file = fileInPlaceOfFolder(folder))
    return file->string() + " is a file, not a folder";
  return "folder " + folder.string() + " does not exist";
}

}  // namespace

void checkFolderWritable(const fs::path& folder, const fs::path& target, const std::string& field) {
  fs::path existing = folder.empty() ? fs::path(".") : folder;
  std::error_code ec;
  while (!fs::exists(existing, ec)) {
    // A relative path's first missing folder is created in the working folder
    // ("report" has no parent of its own).
    if (!existing.has_parent_path()) {
      if (existing.is_relative()) existing = ".";
      break;
    }
    if (existing.parent_path() == existing) break;
    existing = existing.parent_path();
  }
  if (fs::exists(existing, ec) && !fs::is_directory(existing, ec))
    throw Error(target.string(), field, "a folder where files can be written",
                existing.string() + ", which is not a folder");
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw Error(target.string(), field, "a folder where files can be written",
                "folder " + existing.string() + ": " + std::strerror(errno));
}

fs::path folderWrittenFor(const fs::path& file) {
  // Writing through a symbolic link replaces the file it points to, beside it.
  const fs::path written = writtenFileOf(file);
  return written.has_parent_path() ? written.parent_path() : fs::path(".");
}

void checkOutputFile(const fs::path& out, const std::string& option, const std::string& extension,
                     const std::string& what, const CommandInputs& inputs) {
  if (out.empty()) throw UsageError("option --" + option + " expects a file name, got none");
  if (!extension.empty()) requireExtension(out, option, extension, what);
  if (const std::string kind = notARegularFile(out); !kind.empty())
    throw UsageError("--" + option + " " + out.string() + " is " + kind +
                     "; expected a file name for " + what);
  checkOutsideInputs(out, option, what, inputs);
  checkNotASequenceFile(out, option);
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(out.string(), "--" + option, "a path in an existing folder",
                missingFolderProblem(folder));
  checkFolderWritable(folderWrittenFor(out), out, "--" + option);
}

void checkOutputFolder(const fs::path& out, const std::string& option, const std::string& what,
                       const CommandInputs& inputs) {
  if (out.empty()) throw UsageError("option --" + option + " expects a folder, got none");
  if (isExistingFile(out))
    throw UsageError("--" + option + " " + out.string() +
                     " is an existing file; expected a folder for " + what +
                     " (created when missing)");
  checkOutsideInputs(out, option, what, inputs);
  checkFolderWritable(out, out, "--" + option);
}

void checkOutputSubfolder(const fs::path& folder, const std::string& option,
                          const std::string& what, const CommandInputs& inputs) {
  // The rules of checkOutputFolder, worded for a folder inside the output folder
  // (an input file there is an existing file, refused first).
  if (isExistingFile(folder))
    throw UsageError("--" + option + ": " + folder.string() +
                     " is an existing file; expected a folder for " + what);
  if (const auto* input = inputFolderHolding(folder, inputs))
    throw UsageError("--" + option + ": " + what + " would be written to " + folder.string() +
                     ", which lies inside " + input->what + " " + input->path.string() +
                     "; choose another --" + option);
}

void checkOutputInFolder(const fs::path& file, const std::string& option,
                         const CommandInputs& inputs) {
  if (const std::string kind = notARegularFile(file); !kind.empty())
    throw UsageError("--" + option + ": " + file.string() + " is " + kind +
                     "; expected a regular file or nothing there");
  std::error_code ec;
  for (const auto& input : inputs.files)
    if (fs::equivalent(file, input.path, ec))
      throw UsageError("--" + option + ": writing " + file.string() + " would overwrite " +
                       input.what + " " + input.path.string() + "; choose another folder");
}

}  // namespace lom::cli
