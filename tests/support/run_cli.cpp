#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "test_support.hpp"

namespace lom::test {

namespace {}  // namespace

CliResult runCli(const std::string& args, const CliLimits& limits) {
  TempDir dir;
  const auto out = dir / "stdout.txt";
  const auto err = dir / "stderr.txt";
  std::string limit;
  if (limits.memory_kib > 0 && kAddressSanitizer)
    limit += "export ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=" +
             std::to_string(limits.memory_kib / 1024) + "\" && ";
  else if (limits.memory_kib > 0)
    limit += "ulimit -v " + std::to_string(limits.memory_kib) + " && ";
  if (limits.cpu_seconds > 0) limit += "ulimit -t " + std::to_string(limits.cpu_seconds) + " && ";
  // The file-size limit as a batch system sets it: the program itself must
  // turn the signal such a limit raises into a failed write (main.cpp).
  if (limits.file_kib > 0) limit += "ulimit -f " + std::to_string(limits.file_kib) + " && ";
  if (limits.wall_seconds > 0)
    limit += "timeout -s KILL " + std::to_string(limits.wall_seconds) + " ";
  const std::string command = limit + "'" + LOM_CLI_PATH + "' " + args + " >'" + out.string() +
                              "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = slurp(out);
  result.err = slurp(err);
  return result;
}

CliProcess::CliProcess(const std::vector<std::string>& args) {
  std::vector<std::string> words{LOM_CLI_PATH};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  const std::string out = (dir_ / "stdout.txt").string();
  const std::string err = (dir_ / "stderr.txt").string();
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  // The child starts with the default handling of SIGINT and SIGTERM, whatever the
  // test runner set up for itself.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) throw std::runtime_error(std::string("cannot start ") + LOM_CLI_PATH);
  pid_ = pid;
}

CliProcess::~CliProcess() {
  if (exit_ || pid_ < 0) return;
  ::kill(pid_, SIGKILL);
  int status = 0;
  ::waitpid(pid_, &status, 0);
}

bool CliProcess::running() { return !wait(0.0); }

void CliProcess::sendSignal(int signal) const {
  if (!exit_) ::kill(pid_, signal);
}

std::optional<CliExit> CliProcess::wait(double timeout_seconds) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (!exit_) {
    int status = 0;
    const pid_t done = ::waitpid(pid_, &status, WNOHANG);
    if (done == pid_) {
      CliExit result;
      result.exited = WIFEXITED(status);
      result.exit_code = result.exited ? WEXITSTATUS(status) : -1;
      result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
      exit_ = result;
      break;
    }
    if (done < 0 && errno != EINTR) throw std::runtime_error("waitpid failed");
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return exit_;
}

std::string CliProcess::out() const { return slurp(dir_ / "stdout.txt"); }
std::string CliProcess::err() const { return slurp(dir_ / "stderr.txt"); }

}  // namespace lom::test
