#include "lom/ui/demo_scene.hpp"

#include <QDir>
#include <QStandardPaths>
#include <filesystem>

namespace lom::ui {

QString defaultDemoFolder() {
  QString cache = QStandardPaths::writableLocation(QStandardPaths::CacheLocation);
  if (cache.isEmpty()) cache = QDir::tempPath() + "/labeloctomap-studio";
  return cache + "/demo-shelf";
}

QString prepareDemoScene(const QString& folder, const SynthOptions& options) {
  const std::filesystem::path out(folder.toStdString());
  std::error_code ec;
  // A complete earlier output has sequence.json (written last) and the same options.
  const bool complete = std::filesystem::exists(out / "sequence.json", ec) &&
                        std::filesystem::exists(out / "synth.json", ec);
  if (!complete || options.seed != SynthOptions{}.seed || options.frames != SynthOptions{}.frames ||
      options.width != SynthOptions{}.width)
    writeSyntheticScene(options, out);
  return folder;
}

}  // namespace lom::ui
