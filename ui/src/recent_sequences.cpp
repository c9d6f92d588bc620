#include "lom/ui/recent_sequences.hpp"

#include <QFileInfo>
#include <QSettings>

namespace lom::ui {

namespace {
const char* const kSettingsKey = "recentSequences";

// One name per sequence: its folder rather than its sequence.json, without
// "..", symbolic links or a trailing separator where it exists.
QString normalised(const QString& path) {
  QFileInfo info(path);
  if (info.isFile() && info.fileName() == QLatin1String("sequence.json"))
    info = QFileInfo(info.absolutePath());
  const QString canonical = info.canonicalFilePath();
  return canonical.isEmpty() ? info.absoluteFilePath() : canonical;
}
}  // namespace

QStringList RecentSequences::paths() const {
  // At most kMaxEntries, however many the settings hold (edited by hand).
  return QSettings().value(kSettingsKey).toStringList().mid(0, kMaxEntries);
}

void RecentSequences::add(const QString& path) {
  if (frozen_) return;
  const QString entry = normalised(path);
  QStringList list;
  for (const QString& old : paths())
    if (normalised(old) != entry) list << old;
  list.prepend(entry);
  while (list.size() > kMaxEntries) list.removeLast();
  QSettings().setValue(kSettingsKey, list);
}

void RecentSequences::remove(const QString& path) {
  if (frozen_) return;
  QStringList list = paths();
  list.removeAll(path);
  QSettings().setValue(kSettingsKey, list);
}

void RecentSequences::clear() { QSettings().remove(kSettingsKey); }

}  // namespace lom::ui
