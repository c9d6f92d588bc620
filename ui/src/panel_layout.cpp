#include "lom/ui/panel_layout.hpp"

#include <QAction>
#include <QDockWidget>
#include <QMainWindow>
#include <QMenu>
#include <QSettings>
#include <algorithm>

namespace lom::ui {

PanelLayout::PanelLayout(QMainWindow& window, std::vector<Group> groups,
                         std::vector<Group> short_groups)
    : QObject(&window),
      window_(window),
      groups_(std::move(groups)),
      short_groups_(std::move(short_groups)) {}

void PanelLayout::arrangeDefault() {
  const bool short_window = !short_groups_.empty() && window_.height() < kShortWindowHeight;
  QList<QDockWidget*> shown;
  QList<int> stretches;
  for (const Group& group : short_window ? short_groups_ : groups_) {
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
  if (!shown.isEmpty())
    window_.resizeDocks({shown.front()}, {defaultPanelsWidth()}, Qt::Horizontal);
  emit arrangedDefault();
}

int PanelLayout::defaultPanelsWidth() const {
  // As wide as the widest panel asks, unless that leaves the views (frame
  // images, 3D view) too little of a narrow window.
  int preferred = 0;
  int minimum = 0;
  for (const Group& group : groups_)
    for (const QDockWidget* dock : group.tabs) {
      preferred = std::max(preferred, dock->sizeHint().width());
      minimum = std::max(minimum, dock->minimumSizeHint().width());
    }
  const auto share = static_cast<int>(kPanelsWidthShare * window_.width());
  return std::clamp(share, minimum, std::max(minimum, preferred));
}

void PanelLayout::addActionsTo(QMenu& menu) {
  QMenu* panels = menu.addMenu(tr("Pan&els"));
  for (const Group& group : groups_)
    for (QDockWidget* dock : group.tabs) panels->addAction(dock->toggleViewAction());
  QAction* reset = menu.addAction(tr("Reset La&yout"));
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
