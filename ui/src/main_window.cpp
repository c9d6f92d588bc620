#include "lom/ui/main_window.hpp"

#include <QAction>
#include <QCloseEvent>
#include <QIcon>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QSplitter>
#include <QStatusBar>
#include <QStyle>
#include <QVBoxLayout>

#include "lom/ui/about_reaction.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/frame_step_reaction.hpp"
#include "lom/ui/open_sequence_reaction.hpp"
#include "lom/ui/recent_sequences_reaction.hpp"
#include "lom/ui/reset_camera_reaction.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/sequence_drop_handler.hpp"

// Resources compiled into a static library are only registered on request;
// Q_INIT_RESOURCE must be used outside any namespace.
static void registerStudioResources() { Q_INIT_RESOURCE(studio); }

namespace lom::ui {

namespace {

bool confirmDiscardUnsavedWork(QWidget* parent) {
  return QMessageBox::question(parent, QObject::tr("Discard unsaved work?"),
                               QObject::tr("The current work has unsaved changes. Discard them?"),
                               QMessageBox::Discard | QMessageBox::Cancel,
                               QMessageBox::Cancel) == QMessageBox::Discard;
}

QString describeFrame(const SequenceController& controller) {
  if (!controller.hasSequence()) return QObject::tr("No sequence open");
  const int index = controller.currentFrame();
  if (index < 0) return QObject::tr("%1 — no frames").arg(controller.sequenceName());
  const double stamp = controller.sequence().frames[static_cast<size_t>(index)].stamp;
  return QObject::tr("%1 — frame %2 of %3 (frames[%4], t = %5 s)")
      .arg(controller.sequenceName())
      .arg(index + 1)
      .arg(controller.frameCount())
      .arg(index)
      .arg(stamp, 0, 'f', 3);
}

}  // namespace

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent),
      report_error_(messageBoxErrorReporter(this)),
      controller_(new SequenceController(this)),
      frame_images_(new FrameImagesView),
      scene_view_(new SceneView),
      status_label_(new QLabel) {
  registerStudioResources();
  setWindowTitle(tr("LabelOctoMap Studio"));
  setWindowIcon(QIcon(":/icons/labeloctomap-studio.svg"));
  resize(1280, 800);

  const TimelineWidget::StepActions step_actions = createStepActions();
  timeline_ = new TimelineWidget(step_actions);
  timeline_->setObjectName("timeline");

  auto* views = new QSplitter(Qt::Horizontal);
  views->addWidget(frame_images_);
  views->addWidget(scene_view_);
  views->setStretchFactor(1, 1);
  views->setSizes({360, 920});
  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(0);
  layout->addWidget(views, 1);
  layout->addWidget(timeline_);
  setCentralWidget(central);

  status_label_->setObjectName("frameStatus");
  statusBar()->addWidget(status_label_, 1);
  status_label_->setText(describeFrame(*controller_));

  createMenus(step_actions);
  new SequenceDropHandler(this, *controller_);
  controller_->setDiscardGuard([this] { return confirmDiscardUnsavedWork(this); });

  connect(controller_, &SequenceController::errorOccurred, this,
          [this](const QString& title, const QString& message) { report_error_(title, message); });
  connect(controller_, &SequenceController::sequenceChanged, this, &MainWindow::onSequenceChanged);
  connect(controller_, &SequenceController::currentFrameChanged, this,
          &MainWindow::onCurrentFrameChanged);
  connect(timeline_, &TimelineWidget::frameRequested, controller_,
          &SequenceController::setCurrentFrame);
}

MainWindow::~MainWindow() = default;

TimelineWidget::StepActions MainWindow::createStepActions() {
  auto make = [this](const QString& text, QStyle::StandardPixmap icon, const QKeySequence& key,
                     FrameStepReaction::Step step) {
    auto* action = new QAction(style()->standardIcon(icon), text, this);
    action->setShortcut(key);
    new FrameStepReaction(action, step, *controller_);
    return action;
  };
  using Step = FrameStepReaction::Step;
  return {make(tr("&First Frame"), QStyle::SP_MediaSkipBackward, Qt::Key_Home, Step::First),
          make(tr("&Previous Frame"), QStyle::SP_MediaSeekBackward, Qt::Key_PageUp, Step::Previous),
          make(tr("&Next Frame"), QStyle::SP_MediaSeekForward, Qt::Key_PageDown, Step::Next),
          make(tr("&Last Frame"), QStyle::SP_MediaSkipForward, Qt::Key_End, Step::Last)};
}

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
  file->addSeparator();
  auto* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  view->addActions(
      {step_actions.first, step_actions.previous, step_actions.next, step_actions.last});
  view->addSeparator();
  new ResetCameraReaction(view->addAction(tr("&Reset Camera")), *scene_view_);

  QMenu* help = menuBar()->addMenu(tr("&Help"));
  new AboutReaction(help->addAction(tr("&About LabelOctoMap Studio")), this);
}

QString MainWindow::statusText() const { return status_label_->text(); }

void MainWindow::onSequenceChanged() {
  setWindowTitle(tr("%1 — LabelOctoMap Studio").arg(controller_->sequenceName()));
  timeline_->setFrameCount(controller_->frameCount());
  scene_view_->showSequence(controller_->sequence());
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
  frame_images_->showFrame(controller_->sequence(), controller_->currentFrameData(),
                           controller_->currentLabels());
  scene_view_->showFrame(controller_->sequence(), index, controller_->currentFrameData(),
                         controller_->currentLabels());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (controller_->hasUnsavedWork() && !confirmDiscardUnsavedWork(this)) {
    event->ignore();
    return;
  }
  event->accept();
}

}  // namespace lom::ui
