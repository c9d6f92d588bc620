#include "lom/ui/demo_scene.hpp"

#include <QDir>
#include <QStandardPaths>
#include <filesystem>

#include "lom/sequence.hpp"

namespace lom::ui {

QString defaultDemoFolder() {
  QString cache = QStandardPaths::writableLocation(QStandardPaths::CacheLocation);
  if (cache.isEmpty()) cache = QDir::tempPath() + "/labeloctomap-studio";
  return cache + "/demo-shelf";
}

namespace {

// A complete earlier output has synth.json, a sequence.json that reads (it is
// written last) and every frame file it names, none empty: a cache damaged
// since (a file deleted or cut short by a full disk) is written again rather
// than fail to open at every start.
bool completeScene(const std::filesystem::path& out) {
  std::error_code ec;
  if (!std::filesystem::exists(out / "synth.json", ec) ||
      !std::filesystem::exists(out / "sequence.json", ec))
    return false;
  try {
    for (const std::filesystem::path& file : frameFilesOf(loadSequence(out)))
      if (std::filesystem::file_size(file, ec) == 0 || ec) return false;
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

}  // namespace

QString prepareDemoScene(const QString& folder, const SynthOptions& options) {
  const std::filesystem::path out(folder.toStdString());
  if (!completeScene(out) || options.seed != SynthOptions{}.seed ||
      options.frames != SynthOptions{}.frames || options.width != SynthOptions{}.width)
    writeSyntheticScene(options, out);
  return folder;
}

}  // namespace lom::ui
