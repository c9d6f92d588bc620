#include "lom/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <random>

#include "lom/error.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

fs::path temporaryPathFor(const fs::path& target) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Keep the extension last: some writers (OpenCV, VTK) choose the format from it.
  return folder / ("." + target.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                   std::to_string(rng() % 1000000) + target.extension().string());
}

void checkFolder(const fs::path& target) {
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error(target.string(), "output path", "an existing, writable folder",
                "folder " + folder.string() + " does not exist");
}

void writeStream(const fs::path& target, const fs::path& temporary,
                 const std::function<void(std::ostream&)>& write, bool binary) {
  std::ofstream out(temporary, binary ? std::ios::binary | std::ios::out : std::ios::out);
  if (!out) throw Error(target.string(), "output", "a writable location", "cannot create file");
  write(out);
  out.flush();
  if (!out) throw Error(target.string(), "output", "a complete write", "write failed (disk full?)");
  out.close();
  if (!out) throw Error(target.string(), "output", "a complete write", "write failed (disk full?)");
}

}  // namespace

StagedFiles::~StagedFiles() {
  for (const auto& [target, temporary] : staged_) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
  }
}

void StagedFiles::addPath(const fs::path& target,
                          const std::function<void(const fs::path&)>& write) {
  checkFolder(target);
  const fs::path temporary = temporaryPathFor(target);
  try {
    write(temporary);
    std::error_code ec;
    if (!fs::exists(temporary, ec))
      throw Error(target.string(), "output", "the writer to produce the file", "nothing written");
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  staged_.emplace_back(target, temporary);
}

void StagedFiles::add(const fs::path& target, const std::function<void(std::ostream&)>& write,
                      bool binary) {
  addPath(target,
          [&](const fs::path& temporary) { writeStream(target, temporary, write, binary); });
}

void StagedFiles::commit() {
  while (!staged_.empty()) {
    const auto [target, temporary] = staged_.front();
    std::error_code ec;
    fs::rename(temporary, target, ec);
    if (ec)
      throw Error(target.string(), "output", "a writable location",
                  "rename failed: " + ec.message());
    staged_.erase(staged_.begin());
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

void writeTextFileAtomically(const fs::path& target, const std::string& text) {
  writeFileAtomically(target, [&](std::ostream& out) { out << text; }, false);
}

}  // namespace lom
