#pragma once
// Helpers shared by the test executables.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace lom::test {

// A fresh, empty temporary folder removed when the object goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("lom-test-" + std::to_string(rd()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::filesystem::path operator/(const std::string& name) const {
    return path_ / name;
  }

 private:
  std::filesystem::path path_;
};

inline std::filesystem::path sharedDataDir() { return LOM_SHARED_DATA_DIR; }

// The bytes of a file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Skips the current test with a message when ../shared/data/<name> is absent.
#define LOM_REQUIRE_SHARED_DATA(name)                                                     \
  do {                                                                                     \
    if (!std::filesystem::exists(::lom::test::sharedDataDir() / (name)))                   \
      GTEST_SKIP() << "recorded data " << (::lom::test::sharedDataDir() / (name))          \
                   << " is absent; skipping";                                             \
  } while (0)

// Whether the tests (and so the CLI built with them) use AddressSanitizer. Its shadow
// memory reserves terabytes of address space, so that a process under a virtual memory
// limit (ulimit -v) cannot even start.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif

// Runs the labeloctomap CLI with `args`; returns the exit code, fills stdout/stderr.
struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Limits of the process (0: none): virtual memory (ulimit -v), so that an allocation beyond it
// fails, processor time (ulimit -t), after which it is killed, and elapsed time (a
// process blocked on a pipe uses no processor time), after which it is killed too.
// Under AddressSanitizer the memory limit bounds the resident memory instead (the
// process is killed beyond it; allocations do not fail).
// `file_kib` bounds the size of every file the process writes (ulimit -f, the
// signal left as a batch system leaves it: the program must ignore SIGXFSZ
// itself, so that a write beyond the limit fails as on a full disk).
struct CliLimits {
  long memory_kib = 0;
  long cpu_seconds = 0;
  long wall_seconds = 0;
  long file_kib = 0;
};
CliResult runCli(const std::string& args, const CliLimits& limits = {});

// While it lives, files this process and the processes it starts write cannot
// grow beyond `bytes` (ulimit -f). With `ignore_signal`, this process ignores
// SIGXFSZ (its writes fail with EFBIG) and so do the processes it starts;
// without, a started process must ignore it itself or be killed.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes, bool ignore_signal = true) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, ignore_signal ? SIG_IGN : SIG_DFL);
    rlimit limit = old_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit old_{};
  void (*old_handler_)(int) = SIG_DFL;
};

// How a process started by CliProcess ended.
struct CliExit {
  bool exited = false;  // by exit(); otherwise killed by `signal`
  int exit_code = -1;
  int signal = 0;
};

// The CLI started in the background (stdin /dev/null, stdout and stderr to files),
// for tests that act on it while it runs, e.g. by sending it a signal. The
// destructor kills it if it still runs.
class CliProcess {
 public:
  explicit CliProcess(const std::vector<std::string>& args);
  ~CliProcess();
  CliProcess(const CliProcess&) = delete;
  CliProcess& operator=(const CliProcess&) = delete;

  [[nodiscard]] bool running();
  void sendSignal(int signal) const;
  // Waits up to `timeout_seconds` for the process to end; nullopt if it still runs.
  std::optional<CliExit> wait(double timeout_seconds);
  [[nodiscard]] std::string out() const;
  [[nodiscard]] std::string err() const;

 private:
  TempDir dir_;
  int pid_ = -1;
  std::optional<CliExit> exit_;
};

}  // namespace lom::test
