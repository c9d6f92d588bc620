#include "lom/ui/panel_layout.hpp"

#include <QAction>
#include <QDockWidget>
#include <QMainWindow>
#include <QMenu>
#include <QSettings>

namespace lom::ui {

PanelLayout::PanelLayout(QMainWindow& window, std::vector<Group> groups)
    : QObject(&window), window_(window), groups_(std::move(groups)) {}

void PanelLayout::arrangeDefault() {
  QList<QDockWidget*> shown;
  QList<int> stretches;
  for (const Group& group : groups_) {
    for (QDockWidget* dock : group.tabs) {
      dock->setFloating(false);
      // Adding a panel that is already in the window moves it: the order of
      // the calls is the order top to bottom.
      window_.addDockWidget(Qt::RightDockWidgetArea, dock, Qt::Vertical);
      dock->show();
    }
    for (size_t i = 1; i < group.tabs.size(); ++i)
      window_.tabifyDockWidget(group.tabs[i - 1], group.tabs[i]);
    if (group.raised < group.tabs.size()) {
      group.tabs[group.raised]->raise();
      shown.append(group.tabs[group.raised]);
      stretches.append(group.stretch);
    }
  }
  window_.resizeDocks(shown, stretches, Qt::Vertical);
}

void PanelLayout::addActionsTo(QMenu& menu) {
  QMenu* panels = menu.addMenu(tr("&Panels"));
  for (const Group& group : groups_)
    for (QDockWidget* dock : group.tabs) panels->addAction(dock->toggleViewAction());
  QAction* reset = menu.addAction(tr("Reset &Layout"));
  reset->setToolTip(tr("Show every panel again where the window starts with it"));
  connect(reset, &QAction::triggered, this, &PanelLayout::arrangeDefault);
}

bool PanelLayout::restoreSaved() {
  const QSettings settings;
  const QByteArray geometry = settings.value(kGeometryKey).toByteArray();
  const QByteArray panels = settings.value(kPanelsKey).toByteArray();
  const bool restored_geometry = !geometry.isEmpty() && window_.restoreGeometry(geometry);
  const bool restored_panels = !panels.isEmpty() && window_.restoreState(panels, kPanelsVersion);
  return restored_geometry || restored_panels;
}

void PanelLayout::save() const {
  QSettings settings;
  settings.setValue(kGeometryKey, window_.saveGeometry());
  settings.setValue(kPanelsKey, window_.saveState(kPanelsVersion));
}

}  // namespace lom::ui
