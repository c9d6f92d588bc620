#include "lom/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>
#include <random>
#include <regex>
#include <set>

#include "lom/error.hpp"

namespace lom {

namespace fs = std::filesystem;

// ---- The record of pending outputs ----

namespace {

// A slot's state: free, being filled by PendingOutput, recorded, or taken by
// a signal handler that is removing it (the process is about to end).
enum SlotState : int { kFree = 0, kFilling = 1, kRecorded = 2, kRemoving = 3 };

struct PendingSlot {
  std::atomic<int> state{kFree};
  PendingOutput::Kind kind = PendingOutput::Kind::File;
  char path[PATH_MAX] = {};
};

PendingSlot g_pending[PendingOutput::kMaxPendingOutputs];

// Removes `name` in `parent` with everything in it, by system calls only
// (async-signal-safe): no allocation, a fixed buffer per level.
void removeTreeAt(int parent, const char* name, int depth) noexcept {
  if (::unlinkat(parent, name, 0) == 0 || errno == ENOENT) return;  // not a folder
  const int fd = ::openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[2048];
  // Entries removed while the folder is read may hide others: read it again
  // until a pass finds nothing left to remove.
  for (int pass = 0; pass < 8; ++pass) {
    if (::lseek(fd, 0, SEEK_SET) != 0) break;
    bool found = false;
    for (;;) {
      const ssize_t n = ::getdents64(fd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (ssize_t offset = 0; offset < n;) {
        const auto* entry = reinterpret_cast<const struct dirent64*>(buffer + offset);
        offset += entry->d_reclen;
        const char* child = entry->d_name;
        if (child[0] == '.' && (child[1] == '\0' || (child[1] == '.' && child[2] == '\0')))
          continue;
        found = true;
        if (::unlinkat(fd, child, 0) != 0 && depth < 32) removeTreeAt(fd, child, depth + 1);
      }
    }
    if (!found) break;
  }
  ::close(fd);
  ::unlinkat(parent, name, AT_REMOVEDIR);
}

extern "C" void onPendingOutputSignal(int signal) { removePendingOutputsAndDie(signal); }

}  // namespace

PendingOutput::PendingOutput(const fs::path& path, Kind kind) {
  std::error_code ec;
  // As given (made absolute), not lexically normalised: the kernel resolves
  // "link/.." through the link, as it did when the output was made.
  const std::string text = fs::absolute(path, ec).string();
  if (ec || text.size() >= PATH_MAX) return;
  for (int i = 0; i < kMaxPendingOutputs; ++i) {
    int expected = kFree;
    if (!g_pending[i].state.compare_exchange_strong(expected, kFilling)) continue;
    g_pending[i].kind = kind;
    std::memcpy(g_pending[i].path, text.c_str(), text.size() + 1);
    g_pending[i].state.store(kRecorded, std::memory_order_release);
    slot_ = i;
    return;
  }
}

PendingOutput& PendingOutput::operator=(PendingOutput&& other) noexcept {
  if (this != &other) {
    release();
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

void PendingOutput::release() noexcept {
  if (slot_ < 0) return;
  int expected = kRecorded;
  if (!g_pending[slot_].state.compare_exchange_strong(expected, kFree)) {
    // A signal handler on another thread is removing it and ends the process.
    for (;;) ::sched_yield();
  }
  slot_ = -1;
}

void removePendingOutputs() noexcept {
  using Kind = PendingOutput::Kind;
  // Files first, then whole folders, then empty folders; those last in
  // several passes, so that a folder goes once the folders inside it are gone.
  for (const Kind kind : {Kind::File, Kind::Tree, Kind::EmptyFolder}) {
    for (int pass = 0; pass < (kind == Kind::EmptyFolder ? 8 : 1); ++pass)
      for (PendingSlot& slot : g_pending) {
        // Claimed before its kind and path are read: no other thread refills it meanwhile.
        int expected = kRecorded;
        if (!slot.state.compare_exchange_strong(expected, kRemoving)) continue;
        if (slot.kind != kind) {
          slot.state.store(kRecorded);
          continue;
        }
        if (kind == Kind::File) {
          ::unlink(slot.path);
        } else if (kind == Kind::Tree) {
          removeTreeAt(AT_FDCWD, slot.path, 0);
        } else if (::rmdir(slot.path) != 0 && errno == ENOTEMPTY) {
          slot.state.store(kRecorded);  // another pass, once the folders inside are gone
        }
      }
  }
}

void removePendingOutputsAndDie(int signal) noexcept {
  // A second signal handled on another thread (each thread blocks only the
  // signals of its own handler) waits for the first to finish and end the
  // process, instead of ending it halfway through the removal.
  static std::atomic<bool> handling{false};
  if (handling.exchange(true))
    for (;;) ::pause();
  removePendingOutputs();
  std::signal(signal, SIG_DFL);
  // Inside its handler the signal is blocked: unblocked, the raise below
  // takes the default action at once.
  sigset_t only;
  sigemptyset(&only);
  sigaddset(&only, signal);
  sigprocmask(SIG_UNBLOCK, &only, nullptr);
  std::raise(signal);
  ::_exit(128 + signal);  // not reached
}

void removePendingOutputsOnSignals() {
  const int signals[] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction action {};
  action.sa_handler = onPendingOutputSignal;
  sigemptyset(&action.sa_mask);
  // On one thread, one handler at a time; across threads, see removePendingOutputsAndDie.
  for (const int signal : signals) sigaddset(&action.sa_mask, signal);
  for (const int signal : signals) {
    struct sigaction previous {};
    // A signal the process was started to ignore (nohup, a background job) stays ignored.
    if (sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler != SIG_IGN)
      sigaction(signal, &action, nullptr);
  }
}

namespace {

fs::path temporaryPathFor(const fs::path& target) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Keep the extension last: some writers (OpenCV, VTK) choose the format from it.
  return folder / ("." + target.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                   std::to_string(rng() % 1000000) + target.extension().string());
}

fs::path folderOf(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

// A writer killed outright (kill -9, a crash, a power cut) leaves its hidden
// temporary file (temporaryPathFor) beside the output. The first write into a
// folder in a process removes those of processes that no longer run. Left
// alone: files of a process that runs (or of an id now taken by another
// process), of another user, and files changed in the last hour (a writer of
// the same process id on another machine may still write them into a shared
// folder).
void removeAbandonedTemporaries(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<std::string> swept;
  std::error_code ec;
  const fs::path absolute = fs::absolute(folder, ec);
  {
    const std::lock_guard lock(mutex);
    if (ec || !swept.insert(absolute.string()).second) return;
  }
  static const std::regex temporary_name(R"(^\..*\.tmp([0-9]{1,9})-[0-9]{1,6}(\.[^.]*)?$)");
  const auto now = std::chrono::system_clock::now();
  for (fs::directory_iterator it(absolute, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::smatch match;
    if (!std::regex_match(name, match, temporary_name)) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(match[1].str()));
    if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    struct stat info {};
    if (::lstat(it->path().c_str(), &info) != 0 || !S_ISREG(info.st_mode) ||
        info.st_uid != ::geteuid())
      continue;
    if (now - std::chrono::system_clock::from_time_t(info.st_mtime) < std::chrono::hours(1))
      continue;
    std::error_code ignored;
    fs::remove(it->path(), ignored);
  }
}

void checkFolder(const fs::path& target) {
  const fs::path folder = folderOf(target);
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(target.string(), "output path", "an existing, writable folder",
                "folder " + folder.string() + " does not exist");
}

// Flushes the written file to the disk, so that the rename never publishes a
// file whose content is still only in memory (a power cut would leave it empty).
void syncFile(const fs::path& temporary, const fs::path& target) {
  const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw Error(target.string(), "output", "a written file",
                "cannot reopen it to flush: " + std::string(std::strerror(errno)));
  const bool synced = ::fsync(fd) == 0;
  const int sync_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!synced || !closed)
    throw Error(
        target.string(), "output", "a complete write",
        "flushing to disk failed: " + std::string(std::strerror(synced ? errno : sync_errno)));
}

// A replaced file keeps its permission bits (a file only its owner may read
// stays so); a new file gets the writer's defaults.
void keepPermissions(const fs::path& temporary, const fs::path& target) {
  struct stat existing {};
  if (::stat(target.c_str(), &existing) != 0 || !S_ISREG(existing.st_mode)) return;
  if (::chmod(temporary.c_str(), existing.st_mode & 07777) != 0)
    throw Error(target.string(), "output", "the permissions of the file it replaces",
                "chmod failed: " + std::string(std::strerror(errno)));
}

// Makes the rename itself durable. Best effort: some file systems refuse to
// sync a folder, and the file is in place either way.
void syncFolder(const fs::path& target) {
  const int fd = ::open(folderOf(target).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  (void)::close(fd);
}

void writeStream(const fs::path& target, const fs::path& temporary,
                 const std::function<void(std::ostream&)>& write, bool binary) {
  std::ofstream out(temporary, binary ? std::ios::binary | std::ios::out : std::ios::out);
  if (!out) throw Error(target.string(), "output", "a writable location", "cannot create file");
  write(out);
  out.flush();
  if (!out)
    throw Error(target.string(), "output", "a complete write",
                streamWriteFailure(target, "write failed"));
  // Closing writes what the stream still buffers: a failure there is a lost write too.
  out.close();
  if (out.fail())
    throw Error(target.string(), "output", "a complete write",
                streamWriteFailure(target, "closing failed"));
}

}  // namespace

fs::path writtenFileOf(const fs::path& target) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(target, ec))) return target;
  const fs::path resolved = fs::canonical(target, ec);
  if (!ec) return resolved;
  // A dangling link names the file to make (`echo > link` makes it too),
  // followed link by link, each relative to the folder it is in; a cycle
  // or an unreadable link is written as the link itself.
  fs::path file = target;
  for (int hops = 0; hops < 40; ++hops) {
    if (!fs::is_symlink(fs::symlink_status(file, ec))) {
      const fs::path made = fs::weakly_canonical(fs::absolute(file, ec), ec);
      return ec ? file.lexically_normal() : made;
    }
    const fs::path next = fs::read_symlink(file, ec);
    if (ec) return target;
    file = next.is_absolute() ? next : file.parent_path() / next;
  }
  return target;
}

fs::path createStagingFolder(const fs::path& parent, const std::string& what,
                             PendingOutput& record) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  const fs::path folder = parent / (".labeloctomap-" + what + "-" + std::to_string(::getpid()) +
                                    "-" + std::to_string(rng() % 1000000));
  // Recorded before it exists: a signal in between finds nothing to remove.
  record = PendingOutput(folder, PendingOutput::Kind::Tree);
  std::error_code ec;
  if (!fs::create_directory(folder, ec) || ec)
    throw Error(
        parent.string(), "output", "a writable folder",
        "a folder where no folder can be created" + (ec ? ": " + ec.message() : std::string()));
  return folder;
}

StagedFiles::~StagedFiles() {
  for (const Staged& staged : staged_) {
    std::error_code ignored;
    fs::remove(staged.temporary, ignored);
  }
}

void StagedFiles::addPath(const fs::path& target,
                          const std::function<void(const fs::path&)>& write) {
  checkFolder(target);
  const fs::path file = writtenFileOf(target);
  removeAbandonedTemporaries(folderOf(file));
  const fs::path temporary = temporaryPathFor(file);
  // Created here first (and only here: O_EXCL): a folder that takes no new
  // file is reported in the program's words, naming the output, before a
  // library writer (VTK, PCL, OpenCV) prints its own complaint with the
  // temporary name.
  // Recorded before it exists: a signal in between finds nothing to remove.
  PendingOutput pending(temporary, PendingOutput::Kind::File);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0)
    throw Error(target.string(), "output path", "a folder where files can be created",
                "cannot create a file in " + folderOf(file).string() + ": " + std::strerror(errno));
  ::close(fd);
  try {
    write(temporary);
    // Created empty above: a writer that failed without saying so leaves it
    // empty (or removes it), and no format written here is empty.
    std::error_code ec;
    if (!fs::exists(temporary, ec) || fs::file_size(temporary, ec) == 0 || ec)
      throw Error(target.string(), "output", "the writer to produce the file", "nothing written");
    syncFile(temporary, target);
    keepPermissions(temporary, file);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  staged_.push_back({file, temporary, std::move(pending)});
}

void StagedFiles::add(const fs::path& target, const std::function<void(std::ostream&)>& write,
                      bool binary) {
  addPath(target,
          [&](const fs::path& temporary) { writeStream(target, temporary, write, binary); });
}

void StagedFiles::commit() {
  while (!staged_.empty()) {
    const fs::path target = staged_.front().target;
    std::error_code ec;
    fs::rename(staged_.front().temporary, target, ec);
    if (ec)
      throw Error(target.string(), "output", "a writable location",
                  "rename failed: " + ec.message());
    staged_.erase(staged_.begin());
    syncFolder(target);
  }
}

void writePathAtomically(const fs::path& target,
                         const std::function<void(const fs::path&)>& write) {
  StagedFiles files;
  files.addPath(target, write);
  files.commit();
}

void writeFileAtomically(const fs::path& target, const std::function<void(std::ostream&)>& write,
                         bool binary) {
  StagedFiles files;
  files.add(target, write, binary);
  files.commit();
}

std::vector<fs::path> missingFolders(const fs::path& folder) {
  std::vector<fs::path> missing;
  std::error_code ec;
  // Not lexically normalised: "link/../x" is x beside the link's target, as
  // the kernel resolves it, not beside the link (which exists: the walk stops).
  for (fs::path p = fs::absolute(folder, ec); !p.empty(); p = p.parent_path()) {
    if (p.filename().empty() && p.has_parent_path() && p != p.parent_path()) continue;  // "a/b/"
    // "x/." is x, and "x/.." needs x (which create_directories makes when
    // it is missing): both go on with x.
    if (p.filename() == "." || p.filename() == "..") continue;
    // A symbolic link is there even when it leads nowhere (a drive not
    // mounted): it is not made here, so it is never removed here either.
    const fs::file_status status = fs::symlink_status(p, ec);
    if (fs::exists(status) || (ec && status.type() != fs::file_type::not_found)) break;
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  return missing;
}

NewFolders::NewFolders(const fs::path& folder) : missing_(missingFolders(folder)) {
  for (const fs::path& p : missing_) pending_.emplace_back(p, PendingOutput::Kind::EmptyFolder);
}

NewFolders::~NewFolders() {
  std::error_code ignored;
  for (const fs::path& p : missing_) fs::remove(p, ignored);  // fails, as wanted, unless empty
}

void writeTextFileAtomically(const fs::path& target, const std::string& text) {
  writeFileAtomically(target, [&](std::ostream& out) { out << text; }, false);
}

namespace {

// "1 KiB", "20 MiB", "1.5 GiB".
std::string byteSize(std::uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double value = static_cast<double>(bytes);
  size_t unit = 0;
  while (value >= 1024.0 && unit + 1 < std::size(units)) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, value == std::floor(value) ? "%.0f %s" : "%.1f %s", value,
                units[unit]);
  return text;
}

std::string writeFailure(std::uint64_t free_bytes, std::optional<std::uint64_t> file_size_limit,
                         const std::string& verb, const std::string& otherwise) {
  constexpr std::uint64_t kNearlyFull = std::uint64_t{1} << 20;
  if (free_bytes < kNearlyFull) return verb + " (disk full?)";
  if (file_size_limit)
    return verb + " (the file-size limit of " + byteSize(*file_size_limit) + " set by ulimit -f?)";
  return otherwise;
}

struct WriteLimits {
  std::uint64_t free_bytes = ~std::uint64_t{0};  // unknown: plenty
  std::optional<std::uint64_t> file_size_limit;
};

WriteLimits writeLimitsFor(const fs::path& target) {
  WriteLimits limits;
  struct statvfs space {};
  if (::statvfs(folderOf(target).c_str(), &space) == 0)
    limits.free_bytes =
        static_cast<std::uint64_t>(space.f_bavail) * static_cast<std::uint64_t>(space.f_frsize);
  struct rlimit file_size {};
  if (::getrlimit(RLIMIT_FSIZE, &file_size) == 0 && file_size.rlim_cur != RLIM_INFINITY)
    limits.file_size_limit = static_cast<std::uint64_t>(file_size.rlim_cur);
  return limits;
}

}  // namespace

std::string libraryWriteFailure(std::uint64_t free_bytes, const std::string& library,
                                std::optional<std::uint64_t> file_size_limit) {
  return writeFailure(free_bytes, file_size_limit, "write failed", library + " could not write it");
}

std::string libraryWriteFailure(const fs::path& target, const std::string& library) {
  const WriteLimits limits = writeLimitsFor(target);
  return libraryWriteFailure(limits.free_bytes, library, limits.file_size_limit);
}

std::string streamWriteFailure(const fs::path& target, const std::string& verb) {
  const WriteLimits limits = writeLimitsFor(target);
  return writeFailure(limits.free_bytes, limits.file_size_limit, verb, verb + " (disk full?)");
}

}  // namespace lom
