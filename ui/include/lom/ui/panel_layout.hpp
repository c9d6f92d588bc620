#pragma once
// The arrangement of the studio's panels (dock widgets): the default one,
// View > Panels to show a closed panel again, View > Reset Layout, and the
// window's size, position and panels kept from one session to the next.
#include <QByteArray>
#include <QObject>
#include <vector>

class QDockWidget;
class QMainWindow;
class QMenu;

namespace lom::ui {

class PanelLayout : public QObject {
  Q_OBJECT

 public:
  // The panels of a group are tabbed together, in this order, the one at
  // `raised` in front; the groups are stacked top to bottom on the right,
  // their heights in the proportions of `stretch`.
  struct Group {
    std::vector<QDockWidget*> tabs;
    int stretch = 1;
    size_t raised = 0;
  };
  PanelLayout(QMainWindow& window, std::vector<Group> groups);

  // Puts every panel back where the window starts with, shown and docked.
  void arrangeDefault();
  // View > Panels (one check item per panel) and Reset Layout, added to `menu`.
  void addActionsTo(QMenu& menu);

  // The settings keys and the version of what saveState writes: a layout
  // saved by a version with other panels is not restored (Qt refuses it).
  static constexpr const char* kGeometryKey = "window/geometry";
  static constexpr const char* kPanelsKey = "window/panels";
  static constexpr int kPanelsVersion = 1;
  // Restores the size, position and panels saved by save(), if any; false
  // when there was nothing (usable) to restore.
  bool restoreSaved();
  void save() const;

 private:
  QMainWindow& window_;
  std::vector<Group> groups_;
};

}  // namespace lom::ui
