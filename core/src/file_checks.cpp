#include "file_checks.hpp"

namespace lom {

namespace fs = std::filesystem;

std::string notARegularFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  switch (status.type()) {
    case fs::file_type::regular:
      return {};
    case fs::file_type::not_found: {
      std::error_code link_ec;
      if (fs::is_symlink(fs::symlink_status(path, link_ec)))
        return "no such file (a symbolic link to a missing target)";
      return "no such file";
    }
    case fs::file_type::directory:
      return "a directory, not a file";
    case fs::file_type::fifo:
      return "a named pipe (FIFO), not a regular file";
    case fs::file_type::character:
      return "a character device, not a regular file";
    case fs::file_type::block:
      return "a block device, not a regular file";
    case fs::file_type::socket:
      return "a socket, not a regular file";
    case fs::file_type::none:
      return "a path that cannot be inspected (" + ec.message() + ")";
    default:
      return "not a regular file";
  }
}

}  // namespace lom
