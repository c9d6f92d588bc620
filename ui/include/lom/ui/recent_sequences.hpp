#pragma once
// Most recently opened sequences, newest first, kept in QSettings.
#include <QStringList>

namespace lom::ui {

class RecentSequences {
 public:
  static constexpr int kMaxEntries = 8;

  [[nodiscard]] QStringList paths() const;
  void add(const QString& path);  // nothing while frozen
  void clear();
  // Runs that are not the user's own sessions (the --screenshot mode) leave
  // the list as it was.
  void freeze() { frozen_ = true; }

 private:
  bool frozen_ = false;
};

}  // namespace lom::ui
