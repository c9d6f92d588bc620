#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "test_support.hpp"

namespace lom::test {

namespace {
std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}
}  // namespace

CliResult runCli(const std::string& args, const CliLimits& limits) {
  TempDir dir;
  const auto out = dir / "stdout.txt";
  const auto err = dir / "stderr.txt";
  std::string limit;
  if (limits.memory_kib > 0) limit += "ulimit -v " + std::to_string(limits.memory_kib) + " && ";
  if (limits.cpu_seconds > 0) limit += "ulimit -t " + std::to_string(limits.cpu_seconds) + " && ";
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

}  // namespace lom::test
