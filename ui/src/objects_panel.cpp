#include "lom/ui/objects_panel.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMainWindow>
#include <QMessageBox>
#include <QPointer>
#include <QPushButton>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QSplitter>
#include <QStatusBar>
#include <QTableWidget>
#include <QVBoxLayout>
#include <cmath>
#include <memory>

#include "label_search.hpp"
#include "lom/label_map.hpp"
#include "lom/ui/elision.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/save_file_dialog.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "number_item.hpp"

namespace lom::ui {

namespace {

QTableWidgetItem* textItem(const QString& text) {
  auto* item = new QTableWidgetItem(text);
  item->setToolTip(text);  // the table elides long names
  return item;
}

QString objectTitle(const ObjectInstance& object) {
  return QStringLiteral("%1 %2").arg(QString::fromStdString(object.id()),
                                     QString::fromStdString(object.name));
}

// The height of a table's header and `rows` rows.
int rowsHeight(const QTableWidget& table, int rows) {
  return table.horizontalHeader()->sizeHint().height() +
         rows * table.verticalHeader()->defaultSectionSize() + 2 * table.frameWidth();
}

void setupTable(QTableWidget* table) {
  table->verticalHeader()->hide();
  table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table->setSelectionBehavior(QAbstractItemView::SelectRows);
  table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
}

}  // namespace

ObjectsPanel::ObjectsPanel(StudioSession& session, QWidget* parent)
    : QWidget(parent),
      session_(session),
      table_(new QTableWidget(0, Columns)),
      show_boxes_(new QCheckBox(tr("Show boxes"))),
      target_(new ElidingComboBox),
      refresh_(new QPushButton(tr("Refresh"))),
      plan_button_(new QPushButton(tr("Plan pick"))),
      save_plan_button_(new QPushButton(tr("Save Plan…"))),
      steps_(new QTableWidget(0, StepColumns)),
      status_(new QLabel) {
  setObjectName("objectsPanel");
  table_->setObjectName("objectsTable");
  steps_->setObjectName("pickStepsTable");
  table_->setTabKeyNavigation(false);  // Tab goes on to the next field; arrows move rows
  steps_->setTabKeyNavigation(false);
  target_->setObjectName("pickTargetCombo");
  table_->setAccessibleName(tr("Objects"));
  steps_->setAccessibleName(tr("Pick steps"));
  show_boxes_->setObjectName("showObjectBoxes");
  plan_button_->setObjectName("planPickButton");
  save_plan_button_->setObjectName("savePlanButton");
  save_plan_button_->setToolTip(
      tr("Write the plan shown to a plan.json file, as labeloctomap plan --out writes it"));
  save_plan_button_->setEnabled(false);
  refresh_->setObjectName("refreshObjectsButton");
  status_->setObjectName("objectsStatus");
  table_->setHorizontalHeaderLabels({tr("Label"), tr("Object"), tr("Voxels"), tr("Mean p")});
  // Not the Map Labels count: stray voxels of the label are not the object.
  table_->horizontalHeaderItem(Voxels)->setToolTip(
      tr("Voxels of the object's cluster; the label's stray voxels elsewhere are not counted "
         "(Map Labels counts them all)"));
  setupTable(table_);
  table_->horizontalHeader()->setSectionResizeMode(Name, QHeaderView::Stretch);
  table_->setSortingEnabled(true);
  table_->sortByColumn(Label, Qt::AscendingOrder);  // as the Evaluation panel lists objects
  steps_->setHorizontalHeaderLabels({tr("Step"), tr("Action"), tr("Object")});
  setupTable(steps_);
  steps_->horizontalHeader()->setSectionResizeMode(Object, QHeaderView::Stretch);
  show_boxes_->setChecked(true);
  status_->setWordWrap(true);
  plan_button_->setEnabled(false);
  target_->setToolTip(
      tr("The object to pick: the objects in front of it along the mean "
         "viewing direction of the frames fused are removed first."));
  searchLabelsByName(*target_);

  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  auto* top = new QHBoxLayout;
  top->addWidget(show_boxes_);
  top->addStretch(1);
  top->addWidget(refresh_);
  layout->addLayout(top);
  // Right under Refresh: what it is doing, and what the table shows, stay in
  // sight however tall the table and the steps are.
  layout->addWidget(status_);
  // The objects above, the plan below, in a splitter: each keeps a few rows in
  // sight however short the panel (the steps table shrank to its header).
  auto* plan_part = new QWidget;
  auto* plan_layout = new QVBoxLayout(plan_part);
  plan_layout->setContentsMargins(0, 0, 0, 0);
  auto* plan_row = new QHBoxLayout;
  auto* target_label = new QLabel(tr("&Target:"));
  target_label->setBuddy(target_);  // its name to a screen reader, Alt+T to it
  plan_row->addWidget(target_label);
  plan_row->addWidget(target_, 1);
  plan_row->addWidget(plan_button_);
  plan_layout->addLayout(plan_row);
  plan_layout->addWidget(steps_, 1);
  // Under the steps it saves (beside Plan pick it widened the dock past a
  // small screen's room).
  auto* save_row = new QHBoxLayout;
  save_row->addStretch(1);
  save_row->addWidget(save_plan_button_);
  plan_layout->addLayout(save_row);
  for (QTableWidget* table : {table_, steps_}) table->setMinimumHeight(rowsHeight(*table, 3));
  auto* splitter = new QSplitter(Qt::Vertical);
  splitter->setObjectName("objectsSplitter");
  splitter->setChildrenCollapsible(false);
  splitter->addWidget(table_);
  splitter->addWidget(plan_part);
  splitter->setStretchFactor(0, 2);
  splitter->setStretchFactor(1, 1);
  layout->addWidget(splitter, 1);

  MapWorker& worker = session_.worker();
  connect(&worker, &MapWorker::fusionFinished, this, [this](bool) { refresh(); });
  // The session starts fusing the new sequence before this runs: then the
  // panel says so, as for any fusion.
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, [this] {
    clearObjects(session_.worker().isFusing()
                     ? tr("Fusing: the objects are listed when fusion finishes.")
                     : tr("Fuse the sequence to extract its objects."));
  });
  // The objects (and a plan made from them) belong to one map: a new fusion
  // or Reset Map drops them, a re-thresholded map is extracted again.
  connect(&worker, &MapWorker::stateChanged, this, [this](MapWorker::State state) {
    if (state == MapWorker::State::Fusing)
      clearObjects(tr("Fusing: the objects are listed when fusion finishes."));
  });
  connect(&worker, &MapWorker::snapshotChanged, this, [this] {
    if (session_.worker().isFusing()) return;  // fusionFinished refreshes
    const auto snapshot = session_.worker().snapshot();
    if (!snapshot || snapshot->frames_fused == 0)
      clearObjects(tr("The map is empty: fuse the sequence to list its objects."));
    else
      refresh();
  });
  // Refresh extracts the objects of a map that has voxels, once fusion is done.
  auto update_refresh = [this] {
    const auto snapshot = session_.worker().snapshot();
    refresh_->setEnabled(session_.sequence() && !session_.worker().isFusing() && snapshot &&
                         !snapshot->empty());
  };
  connect(&worker, &MapWorker::snapshotChanged, this, update_refresh);
  connect(&worker, &MapWorker::stateChanged, this, update_refresh);
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, update_refresh);
  update_refresh();
  connect(refresh_, &QPushButton::clicked, this, &ObjectsPanel::refresh);
  connect(plan_button_, &QPushButton::clicked, this, &ObjectsPanel::planPick);
  connect(save_plan_button_, &QPushButton::clicked, this, &ObjectsPanel::savePlan);
  // What a saved plan names as its map: the file, for a map opened from one.
  connect(&worker, &MapWorker::fusionStarted, this, [this] { map_source_.clear(); });
  connect(&worker, &MapWorker::mapAdopted, this,
          [this](const QString& source) { map_source_ = source; });
  connect(&worker, &MapWorker::mapReset, this, [this] { map_source_.clear(); });
  connect(&worker, &MapWorker::previousMapKept, this,
          [this](const QString& source) { map_source_ = source; });
  // A plan on show is of the target chosen: another choice plans again (the
  // objects are at hand, so it is quick), rather than leave the steps of the
  // previous target under the new name.
  connect(target_, qOverload<int>(&QComboBox::currentIndexChanged), this, [this](int index) {
    if (plan_ && index >= 0) planPick();
  });
  connect(show_boxes_, &QCheckBox::toggled, this, [this] { emitBoxes(); });
  showMessage(tr("Open a sequence and fuse it to list its objects."));
}

QString ObjectsPanel::statusText() const { return status_->text(); }

std::vector<int> ObjectsPanel::listedLabels() const {
  std::vector<int> labels;
  for (int row = 0; row < table_->rowCount(); ++row)
    if (const QTableWidgetItem* item = table_->item(row, Label))
      labels.push_back(item->data(Qt::DisplayRole).toInt());
  return labels;
}

void ObjectsPanel::refresh() {
  if (!session_.sequence()) return;
  MapWorker* worker = &session_.worker();  // outlives its thread's jobs
  if (worker->isFusing()) return;          // fusionFinished asks again
  const unsigned generation = ++generation_;
  ++busy_;
  showMessage(tr("Extracting objects…"));
  QPointer<ObjectsPanel> self(this);
  worker->withMap([self, worker, generation](const LabelMap* map) {
    auto objects = std::make_shared<std::vector<ObjectInstance>>();
    auto error = std::make_shared<QString>();
    auto approach = std::make_shared<std::optional<Eigen::Vector3d>>();
    if (map) {
      try {
        *objects = extractObjects(*map);
        *approach = map->meanViewingDirection();
      } catch (const std::exception& e) {
        *error = QString::fromStdString(e.what());
      }
    }
    QMetaObject::invokeMethod(
        worker,
        [self, objects, error, approach, generation] {
          if (!self) return;
          --self->busy_;
          if (generation != self->generation_) return;  // superseded
          if (!error->isEmpty()) return self->showMessage(*error);
          self->map_approach_ = *approach;
          self->showObjects(std::move(*objects));
        },
        Qt::QueuedConnection);
  });
}

void ObjectsPanel::clearObjects(const QString& message) {
  ++generation_;  // an extraction under way is of the old map
  objects_.clear();
  map_approach_.reset();
  clearPlan();  // before the target list empties (a plan on show would plan again)
  table_->setRowCount(0);
  target_->clear();
  plan_button_->setEnabled(false);
  clearPlan();
  emitBoxes();
  showMessage(message);
}

void ObjectsPanel::showObjects(std::vector<ObjectInstance> objects) {
  objects_ = std::move(objects);
  clearPlan();
  table_->setSortingEnabled(false);
  table_->setRowCount(static_cast<int>(objects_.size()));
  const int previous_target = target_->currentData().isValid() ? target_->currentData().toInt() : -1;
  const QSignalBlocker quiet(target_);  // no plan to redo while the list fills
  target_->clear();
  for (int row = 0; row < table_->rowCount(); ++row) {
    const ObjectInstance& object = objects_[static_cast<size_t>(row)];
    table_->setItem(row, Label, countItem(static_cast<size_t>(object.label)));
    table_->setItem(row, Name, textItem(QString::fromStdString(object.name)));
    table_->setItem(row, Voxels, countItem(object.voxelCount()));
    table_->setItem(
        row, MeanProbability,
        new NumberItem(object.mean_probability, QString::number(object.mean_probability, 'f', 3)));
    if (object.instance == 0) target_->addItem(objectTitle(object), object.label);
  }
  table_->setSortingEnabled(true);
  const int keep = target_->findData(previous_target);
  if (keep >= 0) target_->setCurrentIndex(keep);
  plan_button_->setEnabled(target_->count() > 0);
  // A recording of geometry only (its one label the background) never has any.
  const auto sequence = session_.sequence();
  const bool background_only = sequence && sequence->labels.size() < 2;
  showMessage(background_only
                  ? tr("No objects: the sequence's only label is the background (0); import "
                       "the recording with object labels (--labels) to list objects.")
              : objects_.empty()     ? tr("The map has no objects yet.")
              : objects_.size() == 1 ? tr("1 object in the map.")
                                     : tr("%1 objects in the map.").arg(objects_.size()));
  emitBoxes();
  emit objectsShown();
}

void ObjectsPanel::planPick() {
  const auto sequence = session_.sequence();
  if (!sequence || objects_.empty() || target_->currentIndex() < 0) return;
  if (session_.worker().isFusing()) return;  // the objects are of the previous map
  const int target = target_->currentData().toInt();
  try {
    // As `labeloctomap plan` plans the same map: along the cameras it was
    // fused from (some of the frames, maybe); a map that records none is
    // viewed as the whole sequence is.
    PlanOptions options;
    options.approach = map_approach_ ? *map_approach_ : meanViewingDirection(*sequence);
    options.approach_source = map_approach_ ? ApproachSource::MapCameras : ApproachSource::Sequence;
    const auto snapshot = session_.worker().snapshot();
    const double resolution = snapshot && snapshot->resolution > 0 ? snapshot->resolution : 0.01;
    PickPlan plan =
        lom::planPick(objects_, sequence->labels, target, *options.approach, options, resolution);
    // The objects are of the map as the studio reads it (maybe re-thresholded).
    plan.occupancy_threshold = session_.fusionOptions().map.occupancy_threshold;
    showPlan(std::move(plan));
  } catch (const std::exception& e) {
    clearPlan();
    showMessage(QString::fromStdString(e.what()));
  }
}

void ObjectsPanel::savePlan() {
  if (!plan_) return;
  QString start = session_.controller().proposedOutput(QStringLiteral("-plan.json"));
  if (start.isEmpty()) start = QStringLiteral("plan.json");
  const QString path = plan_file_chooser_ ? plan_file_chooser_(start)
                                          : askSaveFileName(this, tr("Save Plan"), start,
                                                            tr("Plans (*.json)"), {"json"});
  if (path.isEmpty()) return;
  const QString error = savePlanTo(path);
  if (!error.isEmpty()) {
    QMessageBox::warning(this, tr("Save Plan"), error);
    return;
  }
  // Said where it went, also in the status bar: the panel may have scrolled
  // its own status line out of sight to show the steps.
  const QString saved = tr("Plan saved to %1.").arg(QDir::toNativeSeparators(path));
  showMessage(saved);
  if (auto* main = qobject_cast<QMainWindow*>(window()))
    main->statusBar()->showMessage(saved, 8000);
}

QString ObjectsPanel::savePlanTo(const QString& path) {
  if (!plan_) return tr("There is no plan to save: choose a target and press Plan pick.");
  if (const QString input = session_.controller().sequenceFileAt(path); !input.isEmpty())
    return tr("%1 is a file of the sequence (%2): a plan never replaces it. Choose another name.")
        .arg(QDir::toNativeSeparators(path), input);
  try {
    writePlanJson(*plan_, path.toStdString(), map_source_.toStdString());
  } catch (const std::exception& error) {
    return tr("The plan was not saved: %1").arg(QString::fromStdString(error.what()));
  }
  return {};
}

void ObjectsPanel::showPlan(PickPlan plan) {
  plan_ = std::move(plan);
  save_plan_button_->setEnabled(true);
  steps_->setRowCount(static_cast<int>(plan_->steps.size()));
  for (int row = 0; row < steps_->rowCount(); ++row) {
    const PlanStep& step = plan_->steps[static_cast<size_t>(row)];
    steps_->setItem(row, Step, countItem(static_cast<size_t>(row + 1)));
    steps_->setItem(row, Action, textItem(QString::fromLatin1(stepActionName(step.action))));
    const QString object =
        step.object < plan_->objects.size() ? objectTitle(plan_->objects[step.object]) : QString();
    steps_->setItem(row, Object, textItem(object));
  }
  const QString target = shortName(QString::fromStdString(plan_->target_name));
  const size_t occluders = plan_->occluders.size();
  const Eigen::Vector3d& approach = plan_->approach;
  const QString direction = QStringLiteral("(%1, %2, %3)")
                                .arg(approach.x(), 0, 'f', 2)
                                .arg(approach.y(), 0, 'f', 2)
                                .arg(approach.z(), 0, 'f', 2);
  showMessage((occluders == 0 ? tr("Pick %1: nothing to remove first.").arg(target)
               : occluders == 1
                   ? tr("Pick %1: 1 occluder to remove first.").arg(target)
                   : tr("Pick %1: %2 occluders to remove first.").arg(target).arg(occluders)) +
              " " +
              (plan_->approach_source == ApproachSource::MapCameras
                   ? tr("Approach %1: the mean viewing direction of the frames fused.")
                   : tr("Approach %1: the mean viewing direction of the sequence's frames."))
                  .arg(direction));
  // The steps in sight: the panel scrolls inside its dock when the dock is short.
  for (QWidget* up = parentWidget(); up != nullptr; up = up->parentWidget())
    if (auto* area = qobject_cast<QScrollArea*>(up)) {
      area->ensureWidgetVisible(steps_, 0, 0);
      break;
    }
  emit pickPlanChanged(&*plan_);
  emit planShown();
}

void ObjectsPanel::clearPlan() {
  const bool had_plan = plan_.has_value();
  plan_.reset();
  save_plan_button_->setEnabled(false);
  steps_->setRowCount(0);
  if (had_plan) emit pickPlanChanged(nullptr);
}

void ObjectsPanel::emitBoxes() {
  emit objectBoxesChanged(show_boxes_->isChecked() ? objects_ : std::vector<ObjectInstance>{});
}

void ObjectsPanel::showMessage(const QString& message) { status_->setText(message); }

}  // namespace lom::ui
