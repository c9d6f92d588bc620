#pragma once
// Checks on the paths a command writes, made before any work is done so that a
// command never overwrites one of its own inputs, never writes into a device, a
// FIFO or a folder given as a file, and never writes a file under a misleading
// extension. Failures are usage mistakes (UsageError, exit 2), except an output
// folder that does not exist (lom::Error, exit 1), which names the option.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lom {
struct Sequence;
}

namespace lom::cli {

// What a command reads: no output may be one of `files` (compared with
// std::filesystem::equivalent, so links and other spellings count) or lie inside
// one of `folders` (the sequence folders that fuse and score read, the folder
// import converts).
struct CommandInputs {
  struct File {
    std::filesystem::path path;
    std::string what;  // for messages, e.g. "the input map"
  };
  std::vector<File> files;
  std::vector<File> folders;

  void addFile(const std::filesystem::path& path, const std::string& what) {
    files.push_back({path, what});
  }
  void addFolder(const std::filesystem::path& path, const std::string& what) {
    folders.push_back({path, what});
  }
  // sequence.json and every frame file the sequence names.
  void addSequenceFiles(const Sequence& sequence);
  // The same, and the sequence folder itself.
  void addSequence(const Sequence& sequence);
  // A sequence given on the command line (a folder or its sequence.json), before it is
  // loaded: its sequence.json (nothing when the path does not exist).
  void addSequenceJson(const std::filesystem::path& folder_or_json);
  // The same, and the sequence folder itself.
  void addSequencePath(const std::filesystem::path& folder_or_json);
};

// Throws UsageError unless `out`, given with --`option`, is not empty and ends in
// `extension` (compared without regard to case; `what` says what is written, e.g.
// "a LabelOctoMap map (.ot)").
void requireExtension(const std::filesystem::path& out, const std::string& option,
                      const std::string& extension, const std::string& what);

// Throws UsageError when `out` is a file of a sequence that the command does not
// read: the sequence.json, the annotations (annotations.json/.yaml/.yml, the
// boxes the studio saves) or a frame file of a sequence in the folder holding
// `out` or in any folder above it. Nothing a user made is written over by an
// output path mistyped into a sequence folder.
void checkNotASequenceFile(const std::filesystem::path& out, const std::string& option);
// Whether `path` is `folder` or lies inside it (symbolic links resolved).
[[nodiscard]] bool isSameOrInside(const std::filesystem::path& path,
                                  const std::filesystem::path& folder);
// The folder `out` (whose files a command replaces) holds no frame file of a
// sequence in a folder above it; throws UsageError naming the sequence.
void checkHoldsNoFramesOfSequencesAbove(const std::filesystem::path& out, const std::string& option,
                                        const std::string& what);

// The existing file (not a folder) that stands where `folder` or one of the
// folders above it should be; none when the path can be a folder.
std::optional<std::filesystem::path> fileInPlaceOfFolder(const std::filesystem::path& folder);

// Checks an output file given with --`option`: not empty, `extension` when not
// empty (see requireExtension), not an existing folder, device or FIFO, not one of
// the inputs or inside an input folder, not a sequence's file
// (checkNotASequenceFile), and its folder exists and is writable (lom::Error
// otherwise).
void checkOutputFile(const std::filesystem::path& out, const std::string& option,
                     const std::string& extension, const std::string& what,
                     const CommandInputs& inputs);

// Throws lom::Error (file `target`, field `field`) when no file can be created
// in `folder` (read-only file system, no permission): checked before a long
// run, so that it does not end in a write error. For a folder yet to be made,
// its nearest existing ancestor is checked.
void checkFolderWritable(const std::filesystem::path& folder, const std::filesystem::path& target,
                         const std::string& field);

// The folder a file is written into: its own, or for a symbolic link that
// resolves, the folder of the file it points to (written through the link).
std::filesystem::path folderWrittenFor(const std::filesystem::path& file);

// Checks an output folder given with --`option`: not empty, not an existing file,
// not one of the inputs, not an input folder nor inside one, and files can be
// written in it (or in its nearest existing folder when it is yet to be made).
void checkOutputFolder(const std::filesystem::path& out, const std::string& option,
                       const std::string& what, const CommandInputs& inputs);

// Checks a folder that a command creates inside its output folder (DIR/<name>/ of a
// batch): not an existing file, not an input folder nor inside one. `option` names
// the option that chose the output folder, `what` says what goes into `folder`.
void checkOutputSubfolder(const std::filesystem::path& folder, const std::string& option,
                          const std::string& what, const CommandInputs& inputs);

// Checks a file that a command writes inside its output folder (e.g. DIR/report.json):
// not an existing folder, device or FIFO and not one of the inputs. `option` names
// the option that chose the folder.
void checkOutputInFolder(const std::filesystem::path& file, const std::string& option,
                         const CommandInputs& inputs);

}  // namespace lom::cli
