#pragma once
// Outputs are written to a temporary file beside the target, flushed to the disk
// and renamed into place, so a failure (or a power cut) never leaves half a file
// and never destroys the old one. A replaced file keeps its permissions.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lom {

// ---- Outputs being written, removed when a signal stops the process ----
// Temporary files, staging folders and folders made for outputs are recorded
// process-wide while they are incomplete (StagedFiles, NewFolders and the
// writers that stage whole folders record theirs), so that a process stopped
// by SIGINT, SIGTERM or SIGHUP removes them instead of leaving hidden files
// behind. This record is the one piece of process-wide state of lom_core: a
// signal handler can reach nothing else.
class PendingOutput {
 public:
  enum class Kind {
    File,         // a temporary file
    Tree,         // a folder and everything in it (made by this process)
    EmptyFolder,  // a folder made for outputs: removed only while empty
  };
  PendingOutput() = default;
  // Records `path` (made absolute). At most kMaxPendingOutputs are recorded at
  // once; beyond that, or for a path longer than 4095 bytes, nothing is.
  PendingOutput(const std::filesystem::path& path, Kind kind);
  ~PendingOutput() { release(); }
  PendingOutput(PendingOutput&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  PendingOutput& operator=(PendingOutput&& other) noexcept;
  PendingOutput(const PendingOutput&) = delete;
  PendingOutput& operator=(const PendingOutput&) = delete;
  // No longer removed by a signal: renamed into place, or holding what a
  // signal must not remove (the files an import is replacing).
  void release() noexcept;
  [[nodiscard]] bool recorded() const { return slot_ >= 0; }

  static constexpr int kMaxPendingOutputs = 256;

 private:
  int slot_ = -1;
};

// Removes every recorded output: files, then folders with their contents,
// then empty folders (innermost first). Async-signal-safe: system calls only.
void removePendingOutputs() noexcept;

// The signal handler of removePendingOutputsOnSignals, for handlers of one's
// own that stop the process: removes the recorded outputs, then ends the
// process by `signal`'s default action (its exit status names the signal).
[[noreturn]] void removePendingOutputsAndDie(int signal) noexcept;

// Handles SIGINT, SIGTERM and SIGHUP (those not ignored when called) with
// removePendingOutputsAndDie. Call once, early in main.
void removePendingOutputsOnSignals();

// The file a write of `target` replaces: for a symbolic link, the file it
// points to (a link into a shared folder of annotations keeps pointing at the
// saved boxes), also when that file does not exist yet (it is made there, and
// a write into a folder that does not exist fails, naming it); else `target`
// itself, and for a link that cannot be followed (a cycle) the link.
[[nodiscard]] std::filesystem::path writtenFileOf(const std::filesystem::path& target);

// Calls write(stream) on a temporary file next to `target`, then renames it over
// `target`. Throws lom::Error naming `target` if the folder is not writable or
// the stream fails; the temporary file is removed on any failure.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(std::ostream&)>& write, bool binary = true);

// Same, for writers that need a file name (e.g. OpenCV, PCL, VTK): `write`
// receives the temporary path to write to.
void writePathAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path&)>& write);

void writeTextFileAtomically(const std::filesystem::path& target, const std::string& text);

// Why a library (OpenCV, VTK, PCL, OctoMap) that reports only failure did not
// write `target`: "write failed (disk full?)" when the target's file system
// has less than a mebibyte free, as the stream writers say; else, when the
// process may write files of at most some size (ulimit -f, as batch systems
// set), "write failed (the file-size limit of N KiB set by ulimit -f?)"; else
// "LIBRARY could not write it".
[[nodiscard]] std::string libraryWriteFailure(const std::filesystem::path& target,
                                              const std::string& library);
// The same from the free bytes and the file-size limit (none: unlimited): the
// rule, apart from asking the system.
[[nodiscard]] std::string libraryWriteFailure(
    std::uint64_t free_bytes, const std::string& library,
    std::optional<std::uint64_t> file_size_limit = std::nullopt);
// Why writing (`verb`: "write failed", "closing failed") a stream to `target`
// failed: the same rule, with "VERB (disk full?)" when neither is known.
[[nodiscard]] std::string streamWriteFailure(const std::filesystem::path& target,
                                             const std::string& verb);

// The folders of `folder`'s path that do not exist, innermost first (made
// absolute, walked along the path as given: ".." is left to the kernel,
// which resolves it through symbolic links).
[[nodiscard]] std::vector<std::filesystem::path> missingFolders(
    const std::filesystem::path& folder);

// The folders a command is about to create for its outputs: `folder` and those
// of its parents that do not exist yet, recorded before they are created.
// Unless keep() is called (once the outputs are in place), the destructor
// removes them again, innermost first and only while empty, so that a command
// that fails leaves no empty output folders behind.
class NewFolders {
 public:
  explicit NewFolders(const std::filesystem::path& folder);
  NewFolders(const NewFolders&) = delete;
  NewFolders& operator=(const NewFolders&) = delete;
  ~NewFolders();
  void keep() {
    missing_.clear();
    pending_.clear();
  }

 private:
  std::vector<std::filesystem::path> missing_;  // innermost first
  std::vector<PendingOutput> pending_;          // the same, for a signal
};

// Creates a new hidden folder `.labeloctomap-<what>-<pid>-<random>` inside
// `parent` (which must exist), where outputs are staged before they are
// moved into place; throws lom::Error naming `parent` when it cannot be made.
// `record` holds it (PendingOutput::Kind::Tree, recorded before the folder
// is made) for as long as a signal may remove it: release it, or let it go,
// once the folder holds what a signal must not remove or is gone.
std::filesystem::path createStagingFolder(const std::filesystem::path& parent,
                                          const std::string& what, PendingOutput& record);

// Files that belong together (an OBJ and its MTL): each is written to a
// temporary file beside its target, and commit() renames them into place, in
// the order added, only once every one is complete. Until then no target is
// touched: a failure while writing any of them leaves all the old files as
// they were. Temporary files not committed are removed on destruction.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();

  // Throws lom::Error naming `target` as writeFileAtomically does.
  void add(const std::filesystem::path& target, const std::function<void(std::ostream&)>& write,
           bool binary = true);
  void addPath(const std::filesystem::path& target,
               const std::function<void(const std::filesystem::path&)>& write);
  void commit();

 private:
  struct Staged {
    std::filesystem::path target;
    std::filesystem::path temporary;
    PendingOutput pending;
  };
  // Each output, in the order added.
  std::vector<Staged> staged_;
};

}  // namespace lom
