#pragma once
// Most recently opened sequences, newest first, kept in QSettings.
#include <QStringList>

namespace lom::ui {

class RecentSequences {
 public:
  static constexpr int kMaxEntries = 8;

  [[nodiscard]] QStringList paths() const;
  // Adds `path` first (a sequence.json as its folder; the same sequence
  // under another name only once). Nothing while frozen.
  void add(const QString& path);
  void remove(const QString& path);  // an entry that no longer opens
  void clear();
  // Runs that are not the user's own sessions (the --screenshot mode) leave
  // the list as it was.
  void freeze() { frozen_ = true; }

 private:
  bool frozen_ = false;
};

}  // namespace lom::ui
