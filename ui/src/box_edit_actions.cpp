#include "lom/ui/box_edit_actions.hpp"

#include <QAction>
#include <QApplication>
#include <QKeyEvent>
#include <QSettings>
#include <QWidget>
#include <algorithm>
#include <cmath>

#include "lom/box_fit.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/box_math.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

BoxSteps BoxSteps::load() {
  QSettings settings;
  BoxSteps steps;
  const auto stored = [&settings](const char* key, double fallback, double low, double high) {
    bool number = false;
    const double value = settings.value(key, fallback).toDouble(&number);
    return number && std::isfinite(value) ? std::clamp(value, low, high) : fallback;
  };
  steps.move = stored("studio/boxSteps/move", steps.move, kMinLength, kMaxLength);
  steps.turn = stored("studio/boxSteps/turn", steps.turn, kMinTurn, kMaxTurn);
  steps.resize = stored("studio/boxSteps/resize", steps.resize, kMinLength, kMaxLength);
  return steps;
}

void BoxSteps::save() const {
  QSettings settings;
  settings.setValue("studio/boxSteps/move", move);
  settings.setValue("studio/boxSteps/turn", turn);
  settings.setValue("studio/boxSteps/resize", resize);
}

BoxEditReaction::BoxEditReaction(QAction* action, Edit edit, StudioSession& session,
                                 const BoxSteps& steps, std::function<void(const QString&)> report,
                                 std::function<int(int)> box_after)
    : Reaction(action),
      edit_(edit),
      session_(session),
      steps_(steps),
      report_(std::move(report)),
      box_after_(std::move(box_after)) {
  connect(&session_.annotations(), &AnnotationsModel::selectionChanged, this,
          &BoxEditReaction::updateEnabled);
  connect(&session_.annotations(), &AnnotationsModel::boxesChanged, this,
          &BoxEditReaction::updateEnabled);
  updateEnabled();
}

void BoxEditReaction::updateEnabled() {
  AnnotationsModel& model = session_.annotations();
  const bool navigation = edit_ == Edit::Next || edit_ == Edit::Previous;
  action()->setEnabled(navigation ? model.boxCount() > 0 : model.selected() >= 0);
}

void BoxEditReaction::onTriggered() {
  AnnotationsModel& model = session_.annotations();
  if (edit_ == Edit::Next) return model.selectNext(+1);
  if (edit_ == Edit::Previous) return model.selectNext(-1);
  const int index = model.selected();
  if (index < 0) return;
  if (edit_ == Edit::Delete) {
    // From the keyboard nothing else shows which box went.
    const GroundTruthBox gone = model.box(index);
    model.removeBox(index, box_after_ ? box_after_(index) : -1);
    report_(tr("Deleted the box of %1 %2 (Ctrl+Z brings it back)")
                .arg(gone.label)
                .arg(QString::fromStdString(gone.name)));
    return;
  }

  GroundTruthBox box = model.box(index);
  const double m = steps_.move, r = steps_.resize, turn = steps_.turn * M_PI / 180.0;
  QString text = tr("Move box");
  switch (edit_) {
    case Edit::MoveForward: box.box = movedInBoxFrame(box.box, {m, 0, 0}); break;
    case Edit::MoveBack: box.box = movedInBoxFrame(box.box, {-m, 0, 0}); break;
    case Edit::MoveLeft: box.box = movedInBoxFrame(box.box, {0, m, 0}); break;
    case Edit::MoveRight: box.box = movedInBoxFrame(box.box, {0, -m, 0}); break;
    case Edit::MoveUp: box.box = movedInBoxFrame(box.box, {0, 0, m}); break;
    case Edit::MoveDown: box.box = movedInBoxFrame(box.box, {0, 0, -m}); break;
    case Edit::TurnLeft: box.box = turnedAboutZ(box.box, turn); text = tr("Rotate box"); break;
    case Edit::TurnRight: box.box = turnedAboutZ(box.box, -turn); text = tr("Rotate box"); break;
    case Edit::GrowX: box.box = resized(box.box, 0, r); text = tr("Resize box"); break;
    case Edit::ShrinkX: box.box = resized(box.box, 0, -r); text = tr("Resize box"); break;
    case Edit::GrowY: box.box = resized(box.box, 1, r); text = tr("Resize box"); break;
    case Edit::ShrinkY: box.box = resized(box.box, 1, -r); text = tr("Resize box"); break;
    case Edit::GrowZ: box.box = resized(box.box, 2, r); text = tr("Resize box"); break;
    case Edit::ShrinkZ: box.box = resized(box.box, 2, -r); text = tr("Resize box"); break;
    case Edit::Tighten: {
      std::optional<OrientedBox> tight;
      try {
        tight = tightened(box.box);
      } catch (const std::exception& error) {  // leaves standing for too many voxels
        report_(tr("Tighten Box: %1").arg(QString::fromStdString(error.what())));
        return;
      }
      if (!tight) {
        // Why: moving the box helps only where the map has object voxels.
        const MapSnapshotPtr snapshot = session_.worker().snapshot();
        const bool objects =
            snapshot && std::any_of(snapshot->voxels.begin(), snapshot->voxels.end(),
                                    [](const OccupiedVoxel& leaf) { return leaf.label != 0; });
        if (!snapshot || snapshot->voxels.empty()) {
          report_(tr("Tighten Box: the map is empty; fuse the sequence first."));
          return;
        }
        report_(objects ? tr("Tighten Box: no voxel of an object has its centre inside the box "
                             "(the background's are left out); move the box over the object "
                             "first.")
                        : tr("Tighten Box: the map has no voxel of an object, only background "
                             "(a recording without labels or probabilities), so there is "
                             "nothing to tighten onto; size the box by hand."));
        return;
      }
      box.box = *tight;
      text = tr("Tighten box");
      report_(tr("Box tightened onto the voxels inside it: %1 x %2 x %3 cm.")
                  .arg(tight->size.x() * 100.0, 0, 'f', 1)
                  .arg(tight->size.y() * 100.0, 0, 'f', 1)
                  .arg(tight->size.z() * 100.0, 0, 'f', 1));
      break;
    }
    default: return;
  }
  model.setBox(index, box, text);
}

std::optional<OrientedBox> BoxEditReaction::tightened(const OrientedBox& box) const {
  const MapSnapshotPtr snapshot = session_.worker().snapshot();
  if (!snapshot || !(snapshot->resolution > 0.0)) return std::nullopt;
  // Only leaves that can reach into the box are split into their voxels (a
  // pruned leaf of a room's floor holds thousands).
  const double box_radius = 0.5 * box.size.norm();
  std::vector<OccupiedVoxel> near;
  // Object voxels of any label: the support and the walls around (the
  // background) stay out, labels mistaken between objects do not matter.
  for (const OccupiedVoxel& leaf : snapshot->voxels)
    if (leaf.label != 0 && (leaf.center - box.center).norm() <= box_radius + leaf.size)
      near.push_back(leaf);
  return tightenBox(box, finestVoxelCentres(near, snapshot->resolution), snapshot->resolution);
}

namespace {

// Shift+Tab in the 3D view selects the previous box. Qt delivers it as
// Backtab, with or without Shift, and which shortcut that matches depends on
// the keyboard's native data (none matched on X11, or two at once): the key
// is caught before shortcuts and focus navigation see it.
class PreviousBoxKey : public QObject {
 public:
  PreviousBoxKey(QAction* action, QWidget& scene)
      : QObject(action), action_(action), scene_(scene) {
    qApp->installEventFilter(this);
  }

 protected:
  bool eventFilter(QObject*, QEvent* event) override {
    if (event->type() != QEvent::ShortcutOverride && event->type() != QEvent::KeyPress)
      return false;
    auto* key = static_cast<QKeyEvent*>(event);
    // Ctrl+Shift+Tab leaves the 3D view (createLeaveViewActions).
    if (key->key() != Qt::Key_Backtab || (key->modifiers() & Qt::ControlModifier)) return false;
    QWidget* focus = QApplication::focusWidget();
    if (!focus || !(focus == &scene_ || scene_.isAncestorOf(focus))) return false;
    if (event->type() == QEvent::ShortcutOverride) {
      if (action_->isEnabled()) action_->trigger();
      event->accept();  // no shortcut for it; the key press that follows is dropped below
    }
    return true;
  }

 private:
  QAction* action_;
  QWidget& scene_;
};

}  // namespace

std::vector<QAction*> createBoxEditActions(QWidget& window, QWidget& scene, StudioSession& session,
                                           const BoxSteps& steps,
                                           const std::function<void(const QString&)>& report,
                                           const std::function<int(int)>& box_after) {
  using Edit = BoxEditReaction::Edit;
  struct Spec {
    QString text;
    QKeySequence key;
    Edit edit;
  };
  const Spec specs[] = {
      {QObject::tr("Move Box Forward (+x)"), Qt::Key_W, Edit::MoveForward},
      {QObject::tr("Move Box Back (-x)"), Qt::Key_S, Edit::MoveBack},
      {QObject::tr("Move Box Left (+y)"), Qt::Key_A, Edit::MoveLeft},
      {QObject::tr("Move Box Right (-y)"), Qt::Key_D, Edit::MoveRight},
      {QObject::tr("Move Box Up (+z)"), Qt::Key_E, Edit::MoveUp},
      {QObject::tr("Move Box Down (-z)"), Qt::Key_Q, Edit::MoveDown},
      {QObject::tr("Rotate Box Left"), Qt::Key_Z, Edit::TurnLeft},
      {QObject::tr("Rotate Box Right"), Qt::Key_X, Edit::TurnRight},
      {QObject::tr("Grow Box Length (x)"), Qt::Key_I, Edit::GrowX},
      {QObject::tr("Shrink Box Length (x)"), Qt::Key_K, Edit::ShrinkX},
      {QObject::tr("Grow Box Width (y)"), Qt::Key_O, Edit::GrowY},
      {QObject::tr("Shrink Box Width (y)"), Qt::Key_L, Edit::ShrinkY},
      {QObject::tr("Grow Box Height (z)"), Qt::SHIFT + Qt::Key_I, Edit::GrowZ},
      {QObject::tr("Shrink Box Height (z)"), Qt::SHIFT + Qt::Key_K, Edit::ShrinkZ},
      {QObject::tr("&Next Box"), Qt::Key_Tab, Edit::Next},
      // Shift+Tab: shown so, and caught as the key it arrives as (PreviousBoxKey).
      {QObject::tr("Pre&vious Box"), Qt::SHIFT + Qt::Key_Tab, Edit::Previous},
      {QObject::tr("&Delete Box"), QKeySequence::Delete, Edit::Delete},
      {QObject::tr("&Tighten Box to the Voxels Inside"), Qt::Key_T, Edit::Tighten},
  };
  std::vector<QAction*> actions;
  for (const Spec& spec : specs) {
    auto* action = new QAction(spec.text, &window);
    action->setShortcut(spec.key);
    const bool tab = spec.edit == Edit::Next || spec.edit == Edit::Previous;
    action->setShortcutContext(tab ? Qt::WidgetWithChildrenShortcut : Qt::WindowShortcut);
    (tab ? scene : window).addAction(action);
    new BoxEditReaction(action, spec.edit, session, steps, report, box_after);
    if (spec.edit == Edit::Previous) new PreviousBoxKey(action, scene);
    actions.push_back(action);
  }
  return actions;
}

namespace {

// Gives the focus to the next (or previous) widget in the window's focus
// chain that takes Tab focus, outside `scene`.
void moveFocusOutOf(QWidget& scene, bool forward) {
  QWidget* widget = &scene;
  for (int step = 0; step < 10000; ++step) {
    widget = forward ? widget->nextInFocusChain() : widget->previousInFocusChain();
    if (!widget || widget == &scene) return;  // around the whole chain
    if (scene.isAncestorOf(widget) || widget->window() != scene.window()) continue;
    if ((widget->focusPolicy() & Qt::TabFocus) && widget->isVisible() && widget->isEnabled()) {
      widget->setFocus(forward ? Qt::TabFocusReason : Qt::BacktabFocusReason);
      return;
    }
  }
}

}  // namespace

std::vector<QAction*> createLeaveViewActions(QWidget& window, QWidget& scene) {
  std::vector<QAction*> actions;
  for (const bool forward : {true, false}) {
    auto* action = new QAction(forward ? QObject::tr("Leave 3D View (Next Field)")
                                       : QObject::tr("Leave 3D View (Previous Field)"),
                               &window);
    // Ctrl+Shift+Tab arrives as Ctrl+Backtab on X11.
    action->setShortcuts(
        forward ? QList<QKeySequence>{QKeySequence(Qt::CTRL + Qt::Key_Tab)}
                : QList<QKeySequence>{QKeySequence(Qt::CTRL + Qt::SHIFT + Qt::Key_Tab),
                                      QKeySequence(Qt::CTRL + Qt::SHIFT + Qt::Key_Backtab),
                                      QKeySequence(Qt::CTRL + Qt::Key_Backtab)});
    action->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    scene.addAction(action);
    QObject::connect(action, &QAction::triggered, &scene,
                     [&scene, forward] { moveFocusOutOf(scene, forward); });
    actions.push_back(action);
  }
  return actions;
}

}  // namespace lom::ui
