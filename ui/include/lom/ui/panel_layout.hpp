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
  // `short_groups` (the same panels in fewer groups) is the arrangement of a
  // window shorter than kShortWindowHeight, where `groups` would leave each
  // panel too little height; empty: `groups` at any height.
  PanelLayout(QMainWindow& window, std::vector<Group> groups, std::vector<Group> short_groups = {});

  // A window shorter than this (that of a 1366x768 or 1024x768 screen) starts
  // with the short arrangement.
  static constexpr int kShortWindowHeight = 800;
  // The panels' column takes about this share of the window's width, within
  // the panels' minimum and preferred widths: in a narrow window the 3D view
  // keeps room.
  static constexpr double kPanelsWidthShare = 0.36;
  // The width arrangeDefault gives the panels' column in the window's present width.
  [[nodiscard]] int defaultPanelsWidth() const;

  // Puts every panel back where the window starts with, shown and docked, in
  // the arrangement that suits the window's present size.
  void arrangeDefault();
  // View > Panels (one check item per panel) and Reset Layout, added to `menu`.
  void addActionsTo(QMenu& menu);

  // The settings keys and the version of what saveState writes: a layout
  // saved by a version with other panels is not restored (Qt refuses it).
  static constexpr const char* kGeometryKey = "window/geometry";
  static constexpr const char* kPanelsKey = "window/panels";
  // The window's height when its panels were saved: panels arranged in a
  // window of kShortWindowHeight or more are not restored into a shorter one
  // (a layout saved on a large monitor, the window cut to a laptop's screen),
  // which gets the short arrangement instead.
  static constexpr const char* kPanelsHeightKey = "window/panelsHeight";
  static constexpr int kPanelsVersion = 1;
  // Restores the size, position and panels saved by save(), if any; false
  // when there was nothing (usable) to restore.
  bool restoreSaved();
  // Cuts the window to its screen's free area and brings it onto it.
  void fitOnScreen();
  void save() const;

 signals:
  // arrangeDefault put the panels back (at the start, or View > Reset Layout).
  void arrangedDefault();

 private:
  QMainWindow& window_;
  std::vector<Group> groups_;
  std::vector<Group> short_groups_;
};

}  // namespace lom::ui
