#pragma once
// Most recently opened sequences, newest first, kept in QSettings.
#include <QStringList>

namespace lom::ui {

class RecentSequences {
 public:
  static constexpr int kMaxEntries = 8;

  [[nodiscard]] QStringList paths() const;
  void add(const QString& path);
  void clear();
};

}  // namespace lom::ui
