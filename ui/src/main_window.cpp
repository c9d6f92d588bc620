#include "lom/ui/main_window.hpp"

#include <QAbstractButton>
#include <QAbstractItemView>
#include <QAbstractSpinBox>
#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QEventLoop>
#include <QFileInfo>
#include <QFocusEvent>
#include <QIcon>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QStyle>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <memory>
#include <optional>

#include "lom/ui/about_reaction.hpp"
#include "lom/ui/add_box_reaction.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/box_editor_panel.hpp"
#include "lom/ui/box_file_reaction.hpp"
#include "lom/ui/box_math.hpp"
#include "lom/ui/conversion_progress.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/export_map_reaction.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/frame_step_reaction.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/fusion_reactions.hpp"
#include "lom/ui/fusion_status.hpp"
#include "lom/ui/map_legend_panel.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/measure_reaction.hpp"
#include "lom/ui/media_icons.hpp"
#include "lom/ui/objects_panel.hpp"
#include "lom/ui/open_map_reaction.hpp"
#include "lom/ui/open_sequence_reaction.hpp"
#include "lom/ui/panel_layout.hpp"
#include "lom/ui/picked_voxel_view.hpp"
#include "lom/ui/recent_sequences_reaction.hpp"
#include "lom/ui/reset_camera_reaction.hpp"
#include "lom/ui/save_screenshot_reaction.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/scene_view_reaction.hpp"
#include "lom/ui/score_breakdown_reaction.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/sequence_drop_handler.hpp"
#include "lom/ui/shortcuts_help_reaction.hpp"
#include "lom/ui/studio_session.hpp"

// Resources compiled into a static library are only registered on request;
// Q_INIT_RESOURCE must be used outside any namespace.
static void registerStudioResources() { Q_INIT_RESOURCE(studio); }

namespace lom::ui {

namespace {

// The size the window opens at when the screen has room for it.
constexpr QSize kPreferredWindowSize(1280, 1000);
// Room left on the screen for the window manager's title bar and borders.
constexpr QSize kWindowFrameAllowance(16, 40);
// The widths the frame images and the 3D view start with when the window has
// room for both.
constexpr int kPreferredFrameImagesWidth = 430;
constexpr int kPreferredSceneWidth = 380;
// A dock shrinks to this height and scrolls its content when the window is
// too short for it, so that the docks of a 1366x768 screen fit beside each other.
constexpr int kMinimumDockContentHeight = 80;

// The content of a dock, scrolled vertically when the dock is shorter than it.
// Its width follows the content's, as without the scroll area.
class DockScrollArea : public QScrollArea {
 public:
  explicit DockScrollArea(QWidget* content) {
    setObjectName(content->objectName() + "Scroll");
    setWidget(content);
    setWidgetResizable(true);
    setFrameShape(QFrame::NoFrame);
    setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    // Tab goes to the panel's controls: the frameless area itself showed no
    // focus (the wheel still scrolls it, and a control's focus brings it into view).
    setFocusPolicy(Qt::NoFocus);
  }

  [[nodiscard]] QSize sizeHint() const override {
    const QSize content = widget()->sizeHint().expandedTo(widget()->minimumSizeHint());
    return {content.width() + scrollBarWidth(), content.height()};
  }
  [[nodiscard]] QSize minimumSizeHint() const override {
    const QSize content = widget()->minimumSizeHint();
    return {content.width() + scrollBarWidth(),
            std::min(content.height(), kMinimumDockContentHeight)};
  }

 protected:
  bool viewportEvent(QEvent* event) override {
    // The content's size hints changed (a row shown or hidden): so do ours.
    if (event->type() == QEvent::LayoutRequest) updateGeometry();
    return QScrollArea::viewportEvent(event);
  }

 private:
  [[nodiscard]] int scrollBarWidth() const { return verticalScrollBar()->sizeHint().width(); }
};

QString describeFrame(const SequenceController& controller) {
  if (!controller.hasSequence()) return QObject::tr("No sequence open");
  const int index = controller.currentFrame();
  if (index < 0) return QObject::tr("%1 — no frames").arg(controller.sequenceName());
  const std::optional<double> stamp =
      controller.sequence().frames[static_cast<size_t>(index)].stamp;
  if (!stamp)
    return QObject::tr("%1 — frame %2 of %3 (frames[%4])")
        .arg(controller.sequenceName())
        .arg(index + 1)
        .arg(controller.frameCount())
        .arg(index);
  return QObject::tr("%1 — frame %2 of %3 (frames[%4], t = %5 s)")
      .arg(controller.sequenceName())
      .arg(index + 1)
      .arg(controller.frameCount())
      .arg(index)
      .arg(*stamp, 0, 'f', 3);
}

}  // namespace

QSize initialWindowSize(const QSize& available) {
  return kPreferredWindowSize.boundedTo(available - kWindowFrameAllowance);
}

namespace {

// Keys the window has shortcuts for (Space plays the frames, Home/End and
// Page Up/Down step them, letters and Delete edit the selected box), left to
// a focused control that has a use for them, as it expects: Qt gives a
// window-wide shortcut the key before the widget; accepting the override
// gives it back.
// - Space: a Map Labels row's check box, a button, a field, a drop-down.
// - Letters and Delete: a drop-down (its entries are found by typing) and a
//   list or table, except the box list and the Evaluation table, whose
//   selected row is the box the keys edit.
// - Home/End, Page Up/Down: those lists and tables too (their rows).
// Text fields take their keys themselves (ShortcutKeys where needed). The
// filter also brings a panel forward when Tab moves the focus into it.
class KeysForFocusedControls : public QObject {
 public:
  explicit KeysForFocusedControls(QMainWindow* window) : QObject(window), window_(window) {}

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() == QEvent::FocusIn) {
      bringPanelForward(qobject_cast<QWidget*>(watched), static_cast<QFocusEvent*>(event));
      return false;
    }
    if (event->type() != QEvent::ShortcutOverride) return false;
    const auto* key = static_cast<QKeyEvent*>(event);
    auto* widget = qobject_cast<QWidget*>(watched);
    if (!widget || !inWindow(widget)) return false;
    const bool view = qobject_cast<QAbstractItemView*>(widget) != nullptr;
    const bool combo = qobject_cast<QComboBox*>(widget) != nullptr;
    if (key->key() == Qt::Key_Space && key->modifiers() == Qt::NoModifier) {
      if (view || combo || qobject_cast<QAbstractButton*>(widget) ||
          qobject_cast<QAbstractSpinBox*>(widget) || qobject_cast<QLineEdit*>(widget))
        event->accept();
      return false;
    }
    const Qt::KeyboardModifiers chords = Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier;
    if (key->modifiers() & chords) return false;
    // The box list's and the Evaluation table's rows are the boxes: there the
    // keys stay the window's (PageDown steps the frame, W moves the box).
    const bool box_rows = widget->objectName() == QLatin1String("boxList") ||
                          widget->objectName() == QLatin1String("evaluationTable");
    if (box_rows) return false;
    switch (key->key()) {
      case Qt::Key_Home:
      case Qt::Key_End:
      case Qt::Key_PageUp:
      case Qt::Key_PageDown:
        if (view) event->accept();
        return false;
      default:
        break;
    }
    const bool typed = !key->text().isEmpty() && key->text().at(0).isPrint();
    const bool deletes = key->key() == Qt::Key_Delete || key->key() == Qt::Key_Backspace;
    if ((combo || view) && (typed || deletes)) event->accept();
    return false;
  }

 private:
  // In the window or one of its panels, floating ones too (a floating
  // panel is a window of its own, whose parent is still the main window).
  [[nodiscard]] bool inWindow(const QWidget* widget) const {
    for (const QWidget* up = widget; up != nullptr; up = up->parentWidget())
      if (up == window_) return true;
    return false;
  }

  // The panels of a tab group that are not in front stay "visible" to Qt, off
  // the window: Tab walks into them, and what is typed there (a box's centre)
  // changes what nobody sees. The focus coming into such a panel from the
  // keyboard brings it to the front (not the focus coming back with the
  // window: a panel put behind by a click on another tab stays there).
  void bringPanelForward(QWidget* widget, const QFocusEvent* focus) const {
    const Qt::FocusReason reason = focus->reason();
    if (!widget || (reason != Qt::TabFocusReason && reason != Qt::BacktabFocusReason &&
                    reason != Qt::ShortcutFocusReason))
      return;
    for (QWidget* up = widget; up != nullptr && up != window_; up = up->parentWidget())
      if (auto* dock = qobject_cast<QDockWidget*>(up)) {
        if (!dock->isFloating() && !window_->tabifiedDockWidgets(dock).isEmpty() &&
            dock->visibleRegion().isEmpty())
          dock->raise();
        return;
      }
  }

  QMainWindow* window_;
};

}  // namespace

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent),
      report_error_(messageBoxErrorReporter(this)),
      report_warning_(messageBoxErrorReporter(this)),
      session_(new StudioSession(this)),
      controller_(&session_->controller()),
      frame_images_(new FrameImagesView),
      scene_view_(new SceneView),
      status_label_(new QLabel) {
  registerStudioResources();
  qApp->installEventFilter(new KeysForFocusedControls(this));
  steps_ = BoxSteps::load();
  setWindowTitle(tr("LabelOctoMap Studio"));
  setWindowIcon(QIcon(":/icons/labeloctomap-studio.svg"));
  const QScreen* shown_on = screen();
  resize(shown_on ? initialWindowSize(shown_on->availableGeometry().size()) : kPreferredWindowSize);

  const TimelineWidget::StepActions step_actions = createStepActions();
  timeline_ = new TimelineWidget(step_actions);
  timeline_->setObjectName("timeline");

  views_ = new QSplitter(Qt::Horizontal);
  views_->addWidget(frame_images_);
  views_->addWidget(scene_view_);
  views_->setStretchFactor(1, 1);
  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(0);
  layout->addWidget(views_, 1);
  layout->addWidget(timeline_);
  setCentralWidget(central);

  status_label_->setObjectName("frameStatus");
  statusBar()->addWidget(status_label_, 1);
  status_label_->setText(describeFrame(*controller_));
  fusion_status_ = new FusionStatus(session_->worker());
  statusBar()->addPermanentWidget(fusion_status_);
  // A message wider than the status bar is cut off at its edge: its whole
  // text is the status bar's tooltip while it is shown.
  connect(statusBar(), &QStatusBar::messageChanged, this, [this](const QString& message) {
    statusBar()->setToolTip(statusMessageFits(message) ? QString() : message);
  });

  createDocks();
  createMenus(step_actions);
  connectScene();
  auto* drops = new SequenceDropHandler(this, *controller_);
  drops->setMapOpener([this](const QString& map) {
    if (session_->sequence())
      session_->openMap(map);
    else
      report_error_(
          tr("No sequence open"),
          tr("%1 is a fused map: open the sequence it was fused from first, then drop the map.")
              .arg(map));
  });
  new ConversionProgress(this, *controller_);
  controller_->setDiscardGuard([this] { return confirmDiscard(tr("Opening another sequence")); });
  session_->setMapDiscardGuard(
      [this](const QString& replaced_by) { return confirmDiscardMap(replaced_by); });

  connect(controller_, &SequenceController::errorOccurred, this,
          [this](const QString& title, const QString& message) { report_error_(title, message); });
  connect(
      controller_, &SequenceController::warningOccurred, this,
      [this](const QString& title, const QString& message) { report_warning_(title, message); });
  // Cancel's "Stopping…" stays until the fusion has stopped (a frame of a
  // fine room-scale map takes a minute); other notes for 15 s.
  // A note cut off at the status bar's edge stays twice as long, to be read
  // in its tooltip.
  connect(controller_, &SequenceController::noteOccurred, this, [this](const QString& message) {
    statusBar()->showMessage(message, message == FusionReaction::stoppingNote() ? 0
                                      : statusMessageFits(message)              ? 15000
                                                                                : 30000);
  });
  // A fusion started meanwhile replaced the one stopping, which never says
  // it finished.
  const auto stopped = [this] {
    if (statusBar()->currentMessage() == FusionReaction::stoppingNote())
      statusBar()->clearMessage();
  };
  connect(&session_->worker(), &MapWorker::fusionFinished, this, stopped);
  connect(&session_->worker(), &MapWorker::fusionStarted, this, stopped);
  connect(controller_, &SequenceController::conversionFinished, this,
          [this](const QString& name, bool cancelled) {
            if (cancelled)
              statusBar()->showMessage(tr("Conversion of %1 cancelled").arg(name), 8000);
          });
  connect(controller_, &SequenceController::sequenceAboutToChange, frame_images_,
          &FrameImagesView::clear);
  connect(controller_, &SequenceController::sequenceChanged, this, &MainWindow::onSequenceChanged);
  connect(controller_, &SequenceController::currentFrameChanged, this,
          &MainWindow::onCurrentFrameChanged);
  connect(controller_, &SequenceController::currentFrameDataChanged, this,
          &MainWindow::onCurrentFrameChanged);
  connect(timeline_, &TimelineWidget::frameRequested, controller_,
          &SequenceController::setCurrentFrame);
  // It asks about recovered boxes once the switch to the new sequence has
  // finished (every panel, the frame and the status bar show it): a fusion
  // that finishes while the question waits then reaches panels that are
  // ready for it. The question names the sequence: the window behind it may
  // be hidden, and the recovery file's name is a hash.
  autosave_ = new BoxesAutosave(*session_, [this](const QString& file) {
    return QMessageBox::question(
               this, tr("Recover unsaved boxes?"),
               tr("Boxes of %1 were not saved when the studio last closed.\n"
                  "Restore them from %2?\n\n"
                  "No keeps them as a boxes file, %3 (numbered when an earlier one is there), "
                  "that File ▸ Open Boxes… opens (they are not offered again).")
                   .arg(controller_->sequenceName(), file, BoxesAutosave::declinedPath(file))) ==
           QMessageBox::Yes;
  });
}

MainWindow::~MainWindow() = default;

TimelineWidget::StepActions MainWindow::createStepActions() {
  auto make = [this](const QString& text, MediaIcon icon, const QKeySequence& key,
                     FrameStepReaction::Step step) {
    auto* action = new QAction(mediaIcon(icon, palette()), text, this);
    action->setShortcut(key);
    new FrameStepReaction(action, step, *controller_);
    return action;
  };
  using Step = FrameStepReaction::Step;
  return {make(tr("&First Frame"), MediaIcon::First, Qt::Key_Home, Step::First),
          make(tr("&Previous Frame"), MediaIcon::Previous, Qt::Key_PageUp, Step::Previous),
          make(tr("&Next Frame"), MediaIcon::Next, Qt::Key_PageDown, Step::Next),
          make(tr("&Last Frame"), MediaIcon::Last, Qt::Key_End, Step::Last)};
}

void MainWindow::createDocks() {
  auto dock = [this](QWidget* content, const QString& title, const QString& name) {
    auto* widget = new QDockWidget(title, this);
    widget->setObjectName(name);  // saveState and restoreState find panels by name
    widget->setWidget(new DockScrollArea(content));
    return widget;
  };
  map_legend_ = new MapLegendPanel(*session_);
  fusion_panel_ = new FusionPanel(*session_);
  QDockWidget* labels = dock(map_legend_, tr("Map Labels"), "mapLegendDock");
  QDockWidget* fusion = dock(fusion_panel_, tr("Fusion"), "fusionDock");
  // When the depth-range note and its Re-fuse button appear (at the panel's
  // top, after the panel has laid them out), the dock is raised and scrolled
  // to them.
  connect(&session_->worker(), &MapWorker::fusionStarted, this, &MainWindow::renewSettingsNote);
  connect(&session_->worker(), &MapWorker::depthRangesMeasured, this, [this, fusion] {
    QTimer::singleShot(0, fusion, [this, fusion] {
      QPushButton& button = fusion_panel_->extendRangeButton();
      if (button.isHidden()) return;
      fusion->raise();
      static_cast<QScrollArea*>(fusion->widget())->ensureWidgetVisible(&button);
    });
  });
  QDockWidget* picked = dock(new PickedVoxelView(*session_), tr("Picked Voxel"), "pickedVoxelDock");
  box_editor_ = new BoxEditorPanel(*session_, steps_);
  QDockWidget* boxes = dock(box_editor_, tr("Boxes"), "boxesDock");
  evaluation_panel_ = new EvaluationPanel(*session_);
  QDockWidget* scores = dock(evaluation_panel_, tr("Evaluation"), "evaluationDock");
  objects_panel_ = new ObjectsPanel(*session_);
  QDockWidget* objects = dock(objects_panel_, tr("Objects"), "objectsDock");
  // The three dock groups share the height in about these proportions (each
  // scrolls what does not fit) rather than the map's labels shrinking to two
  // rows. A window shorter than 800 pixels (a 1366x768 or 1024x768 screen)
  // has two groups, the map's labels in front of the fusion settings, so that
  // the scores keep the table, the summary and a readable chart. The
  // Evaluation tab is raised in its group.
  panel_layout_ = new PanelLayout(
      *this, {{{labels}, 6}, {{fusion, picked}, 6}, {{boxes, scores, objects}, 10, 1}},
      {{{labels, fusion, picked}, 2}, {{boxes, scores, objects}, 3, 1}});
  connect(panel_layout_, &PanelLayout::arrangedDefault, this, [this] {
    // The frame images take their preferred width, less in a narrow window,
    // where the 3D view keeps kPreferredSceneWidth; the 3D view takes the rest.
    // (In a window on screen the panels take their new width first: the
    // splitter keeps the frame images' width through later resizes.)
    if (isVisible()) layout()->activate();
    const int views_width = width() - panel_layout_->defaultPanelsWidth();
    views_->setSizes({std::min(kPreferredFrameImagesWidth, views_width - kPreferredSceneWidth),
                      kPreferredSceneWidth});
  });
  panel_layout_->arrangeDefault();
  connect(objects_panel_, &ObjectsPanel::objectBoxesChanged, this,
          [this](const std::vector<ObjectInstance>& shown) {
            if (!session_->sequence()) return scene_view_->showObjectBoxes({}, {});
            scene_view_->showObjectBoxes(shown, session_->sequence()->labels);
          });
  connect(objects_panel_, &ObjectsPanel::pickPlanChanged, scene_view_, &SceneView::showPickPlan);
}

void MainWindow::createAnnotateMenu() {
  QMenu* menu = menuBar()->addMenu(tr("&Annotate"));
  QUndoStack& undo_stack = session_->annotations().undoStack();
  QAction* undo = undo_stack.createUndoAction(this, tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = undo_stack.createRedoAction(this, tr("&Redo"));
  // The platform's Redo keys (Ctrl+Shift+Z here) and Ctrl+Y, which many
  // annotation tools use.
  QList<QKeySequence> redo_keys = QKeySequence::keyBindings(QKeySequence::Redo);
  if (!redo_keys.contains(QKeySequence(tr("Ctrl+Y")))) redo_keys << QKeySequence(tr("Ctrl+Y"));
  redo->setShortcuts(redo_keys);
  menu->addActions({undo, redo});
  menu->addSeparator();
  auto add_box = [&](const QString& text, AddBoxReaction::Mode mode, const QKeySequence& key) {
    QAction* action = menu->addAction(text);
    action->setShortcut(key);
    auto* reaction = new AddBoxReaction(action, mode, *session_);
    connect(
        reaction, &AddBoxReaction::failed, this,
        [this](const QString& title, const QString& message) { report_error_(title, message); });
    connect(reaction, &AddBoxReaction::status, this, [this](const QString& message) {
      if (message.isEmpty())
        statusBar()->clearMessage();
      else
        statusBar()->showMessage(message);
    });
  };
  add_box(tr("Add Box from &Label Voxels"), AddBoxReaction::Mode::FitLabelVoxels, Qt::Key_B);
  add_box(tr("Add Box at Clic&ked Point"), AddBoxReaction::Mode::AtPickedPoint,
          Qt::SHIFT + Qt::Key_B);
  add_box(tr("Add Boxes for &All Labels"), AddBoxReaction::Mode::FitAllLabels,
          Qt::CTRL + Qt::Key_B);
  menu->addSeparator();
  for (QAction* action : createBoxEditActions(
           *this, *scene_view_, *session_, steps_,
           [this](const QString& message) { statusBar()->showMessage(message, 8000); },
           [this](int box) { return evaluation_panel_->boxAfterIfFocused(box); }))
    menu->addAction(action);
  menu->addSeparator();
  for (QAction* action : createLeaveViewActions(*this, *scene_view_)) menu->addAction(action);
}

bool MainWindow::confirmDiscard(const QString& replaced_by, bool ask_map) {
  // The recovery file stays until the boxes are really replaced: when the
  // other sequence fails to open, they are still the ones being worked on.
  if (session_->annotations().isDirty()) {
    switch (askAboutUnsavedBoxes(this)) {
      case UnsavedBoxesAnswer::Discard:
        break;
      case UnsavedBoxesAnswer::Cancel:
        return false;
      case UnsavedBoxesAnswer::Save:
        // Saving asks where it must (an unreadable file); a save that did not
        // happen keeps the boxes and the window as they are.
        findAction(tr("Save Boxes"))->trigger();
        if (session_->annotations().isDirty()) return false;
        break;
    }
  }
  return !ask_map || !session_->worker().hasUnsavedMap() || confirmDiscardMap(replaced_by);
}

bool MainWindow::confirmDiscardMap(const QString& replaced_by) {
  if (map_discard_question_) return map_discard_question_(replaced_by);
  // A map still being fused is saved once fusion ends (Cancel Fusion ends
  // it now): not from this question, which would wait for it. A fusion that
  // ends while the question is open turns it into the question about a
  // whole map, with its Save Map… button.
  MapWorker& worker = session_->worker();
  QMessageBox question(QMessageBox::Question, tr("Save the fused map?"), QString(),
                       QMessageBox::Cancel, this);
  QPushButton* save = nullptr;
  QPushButton* discard = question.addButton(tr("Discard Map"), QMessageBox::DestructiveRole);
  auto ask = [&] {
    const bool fusing = worker.isFusing();
    question.setText(tr("The map %1 %2 has not been saved. %3 discards it.")
                         .arg(fusing ? tr("being fused from") : tr("fused from"),
                              controller_->sequenceName(), replaced_by) +
                     (fusing
                          ? tr("\n\nTo keep it, choose Cancel and save it (File ▸ Save Map…) once "
                               "fusion ends.")
                          : QString()));
    if (!fusing && !save && map_saver_) {
      save = question.addButton(tr("Save Map…"), QMessageBox::AcceptRole);
      question.setDefaultButton(save);
    }
  };
  ask();
  if (!save) question.setDefaultButton(QMessageBox::Cancel);
  const QMetaObject::Connection ended =
      connect(&worker, &MapWorker::fusionFinished, &question, [&](bool /*completed*/) { ask(); });
  question.exec();
  disconnect(ended);
  if (save && question.clickedButton() == save)
    return map_saver_->exportAndWait() && !worker.hasUnsavedMap();
  return question.clickedButton() == discard;
}

void MainWindow::showProgressOf(ExportMapReaction* reaction) {
  connect(reaction, &ExportMapReaction::queued, this,
          [this](const QString& message) { statusBar()->showMessage(message); });
  connect(reaction, &ExportMapReaction::finished, this, [this](const QString& message, bool ok) {
    if (ok)
      statusBar()->showMessage(message, 8000);
    else
      statusBar()->clearMessage();
  });
}

QStringList MainWindow::workInProgress() const {
  const MapWorker& worker = session_->worker();
  QStringList work;
  if (controller_->isConverting())
    work << tr("conversion of %1").arg(controller_->conversionName());
  if (worker.isFusing())
    work << (worker.state() == MapWorker::State::Paused ? tr("fusion of %1 (paused)")
                                                        : tr("fusion of %1"))
                .arg(controller_->sequenceName());
  work << worker.pendingWork();
  return work;
}

bool MainWindow::confirmStopWork() {
  if (workInProgress().isEmpty()) return true;
  QMessageBox question(QMessageBox::Question, tr("Stop the work in progress?"), QString(),
                       QMessageBox::Cancel, this);
  QPushButton* close = question.addButton(tr("Close Anyway"), QMessageBox::DestructiveRole);
  // A fusion under way need not take the frames fused so far with it: it
  // stops as Cancel Fusion stops it, and the map is then asked about (Save
  // Map…, Discard Map or Cancel) as a finished one is.
  QPushButton* keep = nullptr;
  if (session_->worker().isFusing())
    keep = question.addButton(tr("Stop Fusion and Keep the Map…"), QMessageBox::AcceptRole);
  question.setDefaultButton(QMessageBox::Cancel);
  // The work goes on while the question is open: it lists what closing
  // would stop now, not what ran when it was asked.
  auto describe = [&] {
    const QStringList work = workInProgress();
    if (work.isEmpty()) {
      question.setText(
          tr("The work in progress has finished: closing the studio now stops "
             "nothing."));
      close->setText(tr("Close"));
    } else {
      question.setText(tr("Closing the studio now stops:\n\n• %1\n\nWhat has not finished is "
                          "dropped.")
                           .arg(work.join("\n• ")));
    }
  };
  describe();
  QTimer refresh;
  refresh.setInterval(200);
  connect(&refresh, &QTimer::timeout, &question, describe);
  refresh.start();
  question.exec();
  if (keep && question.clickedButton() == keep) {
    MapWorker& worker = session_->worker();
    worker.cancel();
    // Cancelling is heard between a frame's phases: the wait is at most its
    // map update (FrameCancelled).
    QEventLoop stopped;
    const QMetaObject::Connection finished =
        connect(&worker, &MapWorker::stateChanged, &stopped, [&] {
          if (!worker.isFusing()) stopped.quit();
        });
    if (worker.isFusing()) stopped.exec(QEventLoop::ExcludeUserInputEvents);
    disconnect(finished);
    // Work that waited for the fusion (an export) or ran beside it (a
    // conversion) is not the user's to lose unasked.
    return workInProgress().isEmpty() || confirmStopWork();
  }
  return question.clickedButton() == close;
}

void MainWindow::setRecoveryOffer(std::function<bool(const QString&)> offer) {
  autosave_->setOffer(std::move(offer));
}

QAction* MainWindow::findAction(const QString& text) const {
  for (QAction* action : findChildren<QAction*>())
    if (action->text().remove('&') == text) return action;
  return nullptr;
}

void MainWindow::connectScene() {
  auto show_voxels = [this] {
    if (!session_->sequence()) return;
    scene_view_->showVoxels(*session_->worker().snapshot(), session_->sequence()->labels,
                            session_->hiddenLabels());
  };
  connect(&session_->worker(), &MapWorker::snapshotChanged, this, show_voxels);
  connect(session_, &StudioSession::hiddenLabelsChanged, this, show_voxels);
  connect(&session_->worker(), &MapWorker::errorOccurred, this,
          [this](const QString& title, const QString& message) { report_error_(title, message); });
  connect(&session_->worker(), &MapWorker::workFailed, this,
          [this](const QString& title, const QString& message) { report_error_(title, message); });
  connect(session_, &StudioSession::mapOpenStarted, this, [this](const QString& path) {
    fusion_status_->showOpeningMap(QFileInfo(path).fileName());
  });
  connect(session_, &StudioSession::mapOpenFailed, this,
          [this](const QString& title, const QString& message) {
            fusion_status_->endOpeningMap();
            report_error_(title, message);
          });
  connect(session_, &StudioSession::mapOpened, this, [this](const QString& path) {
    statusBar()->showMessage(
        tr("Map read from %1 (not fused here; Fuse re-fuses the sequence).").arg(path), 8000);
  });
  auto show_boxes = [this] {
    if (!session_->sequence()) return;
    AnnotationsModel& boxes = session_->annotations();
    scene_view_->showBoxes(boxes.annotations(), boxes.selected(), session_->sequence()->labels);
  };
  connect(&session_->annotations(), &AnnotationsModel::boxesChanged, this, show_boxes);
  connect(&session_->annotations(), &AnnotationsModel::selectionChanged, this, show_boxes);
  connect(&session_->annotations(), &AnnotationsModel::dirtyChanged, this,
          &MainWindow::updateTitle);
  // Every change of the map (a fusion's snapshots, Reset Map, a map opened).
  connect(&session_->worker(), &MapWorker::snapshotChanged, this, &MainWindow::updateTitle);
  connect(scene_view_, &SceneView::boxEdited, this, [this](const OrientedBox& edited) {
    AnnotationsModel& boxes = session_->annotations();
    if (boxes.selected() < 0) return;
    GroundTruthBox box = boxes.box(boxes.selected());
    // A click on the handles that moved nothing is not an edit.
    if (sameBoxUpToRounding(box.box, edited)) return;
    box.box = edited;
    boxes.setBox(boxes.selected(), box, tr("Edit box with handles"));
  });
  connect(scene_view_, &SceneView::pointPicked, this, [this](const Eigen::Vector3d& point) {
    session_->setPickedPoint(point);
    session_->worker().pick(point);
  });
  connect(session_, &StudioSession::selectedLabelChanged, frame_images_,
          &FrameImagesView::setHeatLabel);
  connect(scene_view_, &SceneView::heightColoursShown, map_legend_,
          &MapLegendPanel::showHeightColours);
  // The background is no label to box, but its probability can be looked at.
  connect(map_legend_, &MapLegendPanel::currentLabelChanged, session_, [this](int label) {
    if (label > 0) session_->setSelectedLabel(label);
    if (label >= 0) frame_images_->setHeatLabel(label);
  });
}

void MainWindow::updateTitle() {
  const QString name =
      controller_->hasSequence() ? controller_->sequenceName() + "[*] — " : QString();
  setWindowTitle(name + tr("LabelOctoMap Studio"));
  // Unsaved boxes, or a map fused here and not saved: what closing would lose.
  setWindowModified(session_->annotations().isDirty() || session_->worker().hasUnsavedMap());
}

QString MainWindow::fusionStatusText() const { return fusion_status_->text(); }

void MainWindow::createMenus(const TimelineWidget::StepActions& step_actions) {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  auto* open = file->addAction(tr("&Open Sequence…"));
  open->setShortcut(QKeySequence::Open);
  new OpenSequenceReaction(open, OpenSequenceReaction::Pick::SequenceJson, *controller_, recent_,
                           this);
  auto* open_folder = file->addAction(tr("Open Sequence &Folder…"));
  open_folder->setShortcut(tr("Ctrl+Shift+O"));
  new OpenSequenceReaction(open_folder, OpenSequenceReaction::Pick::Folder, *controller_, recent_,
                           this);
  new RecentSequencesReaction(file->addMenu(tr("Open &Recent")), recent_, *controller_);
  QAction* open_map = file->addAction(tr("Open &Map…"));
  open_map->setShortcut(tr("Ctrl+Alt+O"));
  new OpenMapReaction(open_map, *session_, this);
  {  // The map itself (a LabelOcTree .ot, as `labeloctomap fuse` writes it), every label.
    ExportOptions options;
    options.format = ExportFormat::Ot;
    options.native = true;
    QAction* save_map = file->addAction(tr("Save Ma&p…"));
    save_map->setShortcut(tr("Ctrl+Alt+S"));
    map_saver_ = new ExportMapReaction(save_map, options, *session_, this, report_error_);
    showProgressOf(map_saver_);
    connect(map_saver_, &ExportMapReaction::finished, this, &MainWindow::updateTitle);
  }
  file->addSeparator();
  auto box_file = [&](const QString& text, BoxFileReaction::Kind kind, const QKeySequence& key) {
    QAction* action = file->addAction(text);
    action->setShortcut(key);
    new BoxFileReaction(action, kind, *session_, this, report_error_);
  };
  box_file(tr("&Save Boxes"), BoxFileReaction::Kind::Save, QKeySequence::Save);
  // Not QKeySequence::SaveAs: Qt binds it only on some desktops (GNOME, KDE).
  box_file(tr("Save Boxes &As…"), BoxFileReaction::Kind::SaveAs, QKeySequence(tr("Ctrl+Shift+S")));
  box_file(tr("Open &Boxes…"), BoxFileReaction::Kind::Open, QKeySequence(tr("Ctrl+Alt+B")));
  box_file(tr("&Import YAML Boxes…"), BoxFileReaction::Kind::ImportYaml, QKeySequence());
  file->addSeparator();
  QAction* screenshot = file->addAction(tr("Save Screens&hot…"));
  screenshot->setShortcut(Qt::Key_F12);
  new SaveScreenshotReaction(screenshot, *this, *scene_view_, *controller_);
  QAction* scene_picture = file->addAction(tr("Save 3D &View…"));
  scene_picture->setShortcut(Qt::SHIFT + Qt::Key_F12);
  auto* scene_saver = new SaveScreenshotReaction(scene_picture, *this, *scene_view_, *controller_,
                                                 SaveScreenshotReaction::Kind::SceneView);
  // For figures larger than the view on screen.
  QMenu* picture_size = file->addMenu(tr("3D View Picture Si&ze"));
  auto* sizes = new QActionGroup(picture_size);
  for (int magnification = 1; magnification <= 4; ++magnification) {
    QAction* size = picture_size->addAction(magnification == 1 ? tr("&1x (as on screen)")
                                                               : tr("&%1x").arg(magnification));
    size->setCheckable(true);
    size->setChecked(magnification == 1);
    sizes->addAction(size);
    picture_sizes_.push_back(size);
    connect(size, &QAction::triggered, scene_saver,
            [scene_saver, magnification] { scene_saver->setMagnification(magnification); });
  }
  file->addSeparator();
  auto* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  QMenu* export_menu = menuBar()->addMenu(tr("E&xport"));
  // Checked: exports leave out the labels unticked in Map Labels.
  auto* only_shown = new QAction(tr("Only Labels &Shown"), this);
  only_shown->setCheckable(true);
  only_shown->setToolTip(tr("Leave out of exports the labels hidden in the 3D view"));
  auto export_action = [&](const QString& text, ExportFormat format) {
    ExportOptions options;
    options.format = format;
    auto* reaction = new ExportMapReaction(export_menu->addAction(text), options, *session_, this,
                                           report_error_);
    reaction->setOnlyShownAction(only_shown);
    showProgressOf(reaction);
  };
  export_action(tr("Voxel Mesh (&PLY)…"), ExportFormat::Ply);
  export_action(tr("Voxel Mesh (&OBJ)…"), ExportFormat::Obj);
  export_action(tr("Voxel Mesh (ST&L)…"), ExportFormat::Stl);
  export_action(tr("Point Clou&d (PCD)…"), ExportFormat::Pcd);
  export_action(tr("&Colour Octree (OT)…"), ExportFormat::Ot);
  export_action(tr("&Binary Octree (BT)…"), ExportFormat::Bt);
  export_menu->addSeparator();
  export_menu->addAction(only_shown);

  QMenu* fusion = menuBar()->addMenu(tr("F&usion"));
  auto fusion_action = [&](const QString& text, FusionReaction::Kind kind,
                           const QKeySequence& key) {
    QAction* action = fusion->addAction(text);
    action->setShortcut(key);
    if (kind == FusionReaction::Kind::Fuse)  // with the settings the Fusion panel shows
      new FusionReaction(action, kind, *session_, [this] {
        if (!fusion_panel_->fuseWithShownSettings())
          statusBar()->showMessage(tr("Not fused: %1").arg(fusion_panel_->noteText()), 8000);
      });
    else
      new FusionReaction(action, kind, *session_);
  };
  fusion_action(tr("&Fuse Sequence"), FusionReaction::Kind::Fuse, Qt::Key_F5);
  fusion_action(tr("&Pause Fusion"), FusionReaction::Kind::Pause, Qt::Key_F6);
  fusion_action(tr("&Cancel Fusion"), FusionReaction::Kind::Cancel, Qt::SHIFT + Qt::Key_F5);
  fusion_action(tr("&Reset Map"), FusionReaction::Kind::Reset, Qt::CTRL + Qt::Key_F5);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  view->addActions(
      {step_actions.first, step_actions.previous, step_actions.next, step_actions.last});
  view->addSeparator();
  QAction* reset_camera = view->addAction(tr("&Reset Camera"));
  new ResetCameraReaction(reset_camera, *scene_view_);
  scene_view_actions_.push_back(reset_camera);
  auto scene_action = [&](const QString& text, SceneViewReaction::Kind kind,
                          const QKeySequence& key) {
    QAction* action = view->addAction(text);
    action->setShortcut(key);
    new SceneViewReaction(action, kind, *session_, *scene_view_);
    using Kind = SceneViewReaction::Kind;
    // Colour by Height is chosen per sequence (by its labels), so not kept.
    const std::pair<Kind, const char*> kept[] = {
        {Kind::FramePoints, "framePoints"},
        {Kind::Cameras, "cameraFrustums"},
        {Kind::Axes, "axesMarker"},
        {Kind::Boxes, "boxOutlines"},
        {Kind::OpacityByProbability, "opacityByProbability"}};
    for (const auto& [toggle, key] : kept)
      if (kind == toggle)
        remembered_toggles_.emplace_back(action, QString(kViewOptionsGroup) + "/" + key);
    if (kind == Kind::LookFromFrame || kind == Kind::FramePoints || kind == Kind::ProjectionVoxels)
      sequence_view_actions_.push_back(action);
    else if (kind != Kind::OpacityByProbability && kind != Kind::ColourByHeight &&
             kind != Kind::Cameras && kind != Kind::Axes && kind != Kind::Boxes)
      scene_view_actions_.push_back(action);  // display settings stay available
  };
  scene_action(tr("Look from &Current Camera"), SceneViewReaction::Kind::LookFromFrame,
               Qt::CTRL + Qt::Key_L);
  scene_action(tr("&Zoom to Map"), SceneViewReaction::Kind::ZoomToMap, Qt::CTRL + Qt::Key_M);
  scene_action(tr("Look from &Above"), SceneViewReaction::Kind::LookFromAbove,
               Qt::CTRL + Qt::Key_1);
  scene_action(tr("Look from the Fron&t"), SceneViewReaction::Kind::LookFromFront,
               Qt::CTRL + Qt::Key_2);
  scene_action(tr("Look from the &Side"), SceneViewReaction::Kind::LookFromSide,
               Qt::CTRL + Qt::Key_3);
  scene_action(tr("Sho&w Frame Points"), SceneViewReaction::Kind::FramePoints, QKeySequence());
  scene_action(tr("Show Pro&jection Voxels of This View"),
               SceneViewReaction::Kind::ProjectionVoxels, QKeySequence());
  // What a figure may leave out.
  scene_action(tr("Show Camera Fr&ustums"), SceneViewReaction::Kind::Cameras, QKeySequence());
  scene_action(tr("Show Axes Mar&ker"), SceneViewReaction::Kind::Axes, QKeySequence());
  scene_action(tr("Show Bo&x Outlines"), SceneViewReaction::Kind::Boxes, QKeySequence());
  auto toggle = [&](const QString& text, const QKeySequence& key, auto make) {
    QAction* action = view->addAction(text);
    action->setShortcut(key);
    SceneToggleReaction* reaction = make(action);
    connect(reaction, &SceneToggleReaction::status, this, &MainWindow::showStatusMessage);
    scene_view_actions_.push_back(action);
  };
  toggle(tr("Show Score &Breakdown"), Qt::CTRL + Qt::Key_E, [this](QAction* action) {
    return new ScoreBreakdownReaction(action, *session_, *scene_view_);
  });
  toggle(tr("&Measure Distance"), Qt::CTRL + Qt::Key_D,
         [this](QAction* action) { return new MeasureReaction(action, *session_, *scene_view_); });
  scene_action(tr("&Opacity by Probability"), SceneViewReaction::Kind::OpacityByProbability,
               QKeySequence());
  scene_action(tr("Colour by &Height"), SceneViewReaction::Kind::ColourByHeight, QKeySequence());
  view->addSeparator();
  panel_layout_->addActionsTo(*view);
  connect(controller_, &SequenceController::sequenceChanged, this, &MainWindow::updateViewActions);
  connect(&session_->worker(), &MapWorker::snapshotChanged, this, &MainWindow::updateViewActions);
  connect(&session_->worker(), &MapWorker::mapAdopted, this, &MainWindow::updateViewActions);
  updateViewActions();

  createAnnotateMenu();
  QMenu* help = menuBar()->addMenu(tr("&Help"));
  QAction* shortcuts = help->addAction(tr("&Keyboard Shortcuts"));
  shortcuts->setShortcut(QKeySequence::HelpContents);
  new ShortcutsHelpReaction(shortcuts, this);
  new AboutReaction(help->addAction(tr("&About LabelOctoMap Studio")), this);
}

QString MainWindow::statusText() const { return status_label_->text(); }

bool MainWindow::statusMessageFits(const QString& message) const {
  const QStatusBar* bar = statusBar();
  const int permanent = fusion_status_ && fusion_status_->isVisible() ? fusion_status_->width() : 0;
  const int room =
      bar->width() - permanent - 2 * bar->style()->pixelMetric(QStyle::PM_LayoutLeftMargin);
  return bar->fontMetrics().horizontalAdvance(message) <= room;
}

void MainWindow::showStatusMessage(const QString& message) {
  if (message.isEmpty())
    statusBar()->clearMessage();
  else
    statusBar()->showMessage(message);
}

void MainWindow::updateViewActions() {
  const bool sequence = controller_->hasSequence();
  const MapSnapshotPtr map = session_->worker().snapshot();
  const bool scene = sequence || (map && !map->empty());
  for (QAction* action : sequence_view_actions_) action->setEnabled(sequence);
  for (QAction* action : scene_view_actions_) {
    // A measurement or breakdown left on by an earlier sequence is turned off
    // with the scene it belonged to.
    if (!scene && action->isCheckable() && action->isChecked()) action->trigger();
    action->setEnabled(scene);
  }
}

void MainWindow::onSequenceChanged() {
  updateTitle();
  timeline_->setPlaying(false);  // another sequence starts still, on its first frame
  timeline_->setFrameCount(controller_->frameCount());
  scene_view_->showSequence(controller_->sequence());
  // Settings changed for an earlier sequence fuse this one too, which changes
  // its scores: said, not done silently. Shown until another message comes.
  settings_note_ = session_->carriedOverSettingsNote();
  if (!settings_note_.isEmpty())
    statusBar()->showMessage(settings_note_);
  else
    statusBar()->clearMessage();  // another sequence's message
}

void MainWindow::renewSettingsNote() {
  // A re-fusion with other settings makes the note shown at the sequence's
  // opening wrong: it is said again for the settings now in use (or goes).
  if (settings_note_.isEmpty() || statusBar()->currentMessage() != settings_note_) return;
  settings_note_ = session_->carriedOverSettingsNote();
  if (!settings_note_.isEmpty())
    statusBar()->showMessage(settings_note_);
  else
    statusBar()->clearMessage();
}

void MainWindow::onCurrentFrameChanged() {
  status_label_->setText(describeFrame(*controller_));
  timeline_->setCurrentFrame(controller_->currentFrame());
  if (controller_->currentFrame() < 0) {
    frame_images_->clear();
    scene_view_->clear();
    return;
  }
  const auto index = static_cast<size_t>(controller_->currentFrame());
  frame_images_->setSegmenterState(controller_->frameSegmenterName(),
                                   controller_->isSegmentingFrame(),
                                   controller_->frameSegmenterProblem());
  frame_images_->showFrame(controller_->sequence(), controller_->currentFrameData(),
                           controller_->currentLabels());
  scene_view_->showFrame(controller_->sequence(), index, controller_->currentFrameData(),
                         controller_->currentLabels());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  // A close asked for again while the questions below are open (or while a
  // fusion stops) waits for their answers.
  if (closing_) {
    event->ignore();
    return;
  }
  closing_ = true;
  const std::shared_ptr<void> done(nullptr, [this](void*) { closing_ = false; });
  const bool unsaved = controller_->hasUnsavedWork();  // commits a value being typed first
  // Each question is asked about what is true once the ones before it are
  // answered: a fusion may end while one of them is open. A map still being
  // fused is asked about with the rest of the work that closing stops; a map
  // whose fusion has ended, after that.
  const auto keepsMap = [this] {
    const MapWorker& worker = session_->worker();
    return !worker.isFusing() && worker.hasUnsavedMap() &&
           !confirmDiscardMap(tr("Closing the studio"));
  };
  if ((unsaved && !confirmDiscard(tr("Closing the studio"), /*ask_map=*/false)) ||
      !confirmStopWork() || keepsMap()) {
    event->ignore();
    return;
  }
  if (unsaved) autosave_->discard();  // the user chose to drop the boxes
  // A conversion under way stops after its current frame; the open that
  // waits for it then returns without touching the window.
  controller_->cancelConversion();
  if (remember_layout_) panel_layout_->save();
  event->accept();
}

void MainWindow::rememberLayout() {
  remember_layout_ = true;
  panel_layout_->restoreSaved();
  // The Evaluation panel's IU_3d mode is a preference like the layout: the
  // last one chosen comes back (an unknown stored value leaves the default).
  const QString stored = QSettings().value(kIouModeKey).toString();
  if (stored == QLatin1String("center"))
    session_->setIouMode(IouMode::Center);
  else if (stored == QLatin1String("exact"))
    session_->setIouMode(IouMode::Exact);
  connect(session_, &StudioSession::iouModeChanged, this, [this] {
    QSettings().setValue(kIouModeKey, session_->iouMode() == IouMode::Center ? "center" : "exact");
  });
  rememberViewOptions();
}

void MainWindow::rememberViewOptions() {
  QSettings settings;
  // Triggered, not only checked: the view follows as when the user chooses.
  // A stored value that is no true or false leaves the default.
  for (const auto& [action, key] : remembered_toggles_) {
    const QString stored = settings.value(key).toString();
    if ((stored == QLatin1String("true") && !action->isChecked()) ||
        (stored == QLatin1String("false") && action->isChecked())) {
      // Frame Points is off until a sequence opens; a disabled action ignores trigger().
      const bool enabled = action->isEnabled();
      action->setEnabled(true);
      action->trigger();
      action->setEnabled(enabled);
    }
    connect(action, &QAction::toggled, this,
            [key = key](bool checked) { QSettings().setValue(key, checked); });
  }
  const QString size_key = QString(kViewOptionsGroup) + "/pictureSize";
  bool number = false;
  const int size = settings.value(size_key).toInt(&number);
  if (number && size >= 1 && size <= static_cast<int>(picture_sizes_.size()))
    picture_sizes_[static_cast<size_t>(size - 1)]->trigger();
  for (size_t i = 0; i < picture_sizes_.size(); ++i)
    connect(picture_sizes_[i], &QAction::triggered, this,
            [size_key, i] { QSettings().setValue(size_key, static_cast<int>(i) + 1); });
  const QString fps_key = QString(kViewOptionsGroup) + "/playbackFps";
  QComboBox& speed = timeline_->speed();
  const int stored_fps = settings.value(fps_key).toInt(&number);
  if (number && speed.findData(stored_fps) >= 0) speed.setCurrentIndex(speed.findData(stored_fps));
  connect(&speed, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [fps_key, &speed] { QSettings().setValue(fps_key, speed.currentData().toInt()); });
}

}  // namespace lom::ui
