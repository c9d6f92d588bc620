#include "lom/ui/recent_sequences.hpp"

#include <QSettings>

namespace lom::ui {

namespace {
const char* const kSettingsKey = "recentSequences";
}

QStringList RecentSequences::paths() const {
  return QSettings().value(kSettingsKey).toStringList();
}

void RecentSequences::add(const QString& path) {
  if (frozen_) return;
  QStringList list = paths();
  list.removeAll(path);
  list.prepend(path);
  while (list.size() > kMaxEntries) list.removeLast();
  QSettings().setValue(kSettingsKey, list);
}

void RecentSequences::clear() { QSettings().remove(kSettingsKey); }

}  // namespace lom::ui
