#include "lom/ui/panel_layout.hpp"

#include <QAction>
#include <QDockWidget>
#include <QMainWindow>
#include <QMenu>
#include <QScreen>
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
    for (QDockWidget* dock : group.tabs) {
      QAction* toggle = dock->toggleViewAction();
      panels->addAction(toggle);
      // A panel shown again comes to the front of its tab group, where its
      // fields can be reached (from the keyboard too).
      connect(toggle, &QAction::triggered, dock, [dock](bool shown) {
        if (shown) dock->raise();
      });
    }
  QAction* reset = menu.addAction(tr("Reset La&yout"));
  reset->setToolTip(tr("Show every panel again where the window starts with it"));
  connect(reset, &QAction::triggered, this, &PanelLayout::arrangeDefault);
}

namespace {

// Whether `state` restores: tried on a stand-in window with panels of the
// same names first, since a state that fails halfway leaves the real
// window's panels broken (lost title bars) beyond what Reset Layout mends.
bool panelsRestore(const QByteArray& state, const QMainWindow& window, int version) {
  QMainWindow stand_in;
  stand_in.setAttribute(Qt::WA_DontShowOnScreen);
  for (const QDockWidget* dock : window.findChildren<QDockWidget*>()) {
    auto* copy = new QDockWidget(&stand_in);
    copy->setObjectName(dock->objectName());
    copy->setAttribute(Qt::WA_DontShowOnScreen);  // a floating one is a window of its own
    stand_in.addDockWidget(Qt::RightDockWidgetArea, copy);
  }
  return stand_in.restoreState(state, version);
}

}  // namespace

bool PanelLayout::restoreSaved() {
  const QSettings settings;
  const QByteArray geometry = settings.value(kGeometryKey).toByteArray();
  const QByteArray panels = settings.value(kPanelsKey).toByteArray();
  const bool restored_geometry = !geometry.isEmpty() && window_.restoreGeometry(geometry);
  if (restored_geometry) fitOnScreen();
  const int saved_for = settings.value(kPanelsHeightKey, 0).toInt();
  if (!panels.isEmpty() && !short_groups_.empty() && saved_for >= kShortWindowHeight &&
      window_.height() < kShortWindowHeight) {
    arrangeDefault();  // the short arrangement, for this height
    return true;
  }
  const bool restored_panels = !panels.isEmpty() &&
                               panelsRestore(panels, window_, kPanelsVersion) &&
                               window_.restoreState(panels, kPanelsVersion);
  return restored_geometry || restored_panels;
}

void PanelLayout::fitOnScreen() {
  // A size saved on a larger screen (or edited by hand) is cut to this one's
  // free area, and a window off it is brought back: the status bar and the
  // panels stay in reach.
  const QScreen* screen = window_.screen();
  if (!screen) return;
  const QRect free = screen->availableGeometry();
  if (window_.isMaximized() || window_.isFullScreen()) return;
  // The frame a window manager adds (title bar, borders) counts too.
  const QSize frame = window_.frameGeometry().size() - window_.size();
  const QSize size = window_.size().boundedTo(free.size() - frame);
  if (size != window_.size()) window_.resize(size);
  QPoint corner = window_.pos();
  corner.setX(
      std::clamp(corner.x(), free.left(), std::max(free.left(), free.right() - size.width())));
  corner.setY(
      std::clamp(corner.y(), free.top(), std::max(free.top(), free.bottom() - size.height())));
  if (corner != window_.pos()) window_.move(corner);
}

void PanelLayout::save() const {
  QSettings settings;
  settings.setValue(kGeometryKey, window_.saveGeometry());
  settings.setValue(kPanelsKey, window_.saveState(kPanelsVersion));
  settings.setValue(kPanelsHeightKey, window_.height());
}

}  // namespace lom::ui
