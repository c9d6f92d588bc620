#pragma once
// Checks on input paths shared by the readers of the core's file formats.
#include <filesystem>
#include <string>

namespace lom {

// Why `path` cannot be read as a file: "no such file", "a directory",
// "a character device, not a regular file" (/dev/zero), "a named pipe (FIFO),
// not a regular file", ... Empty when `path` is a regular file (or a symbolic
// link to one). For the "found" part of lom::Error messages.
[[nodiscard]] std::string notARegularFile(const std::filesystem::path& path);

}  // namespace lom
