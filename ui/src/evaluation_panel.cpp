#include "lom/ui/evaluation_panel.hpp"

#include <QComboBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QFontMetrics>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMainWindow>
#include <QMessageBox>
#include <QPushButton>
#include <QScrollBar>
#include <QStatusBar>
#include <QStringList>
#include <QStyleOptionHeader>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <optional>
#include <utility>

#include "lom/report.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/score_chart.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "number_item.hpp"

namespace lom::ui {

namespace {

static_assert(EvaluationPanel::kValueRole == kNumberValueRole,
              "number cells keep their value there");

// The index into the report's objects of a row (on its Label cell).
constexpr int kObjectRole = Qt::UserRole + 2;

// The boxes that can be scored: an object label of the sequence, each label
// once (the first box of a label). The command line refuses such files; the
// studio keeps the boxes for editing and scores the others. `left_out` names
// the boxes left out, for the summary.
Annotations scorableBoxes(const Annotations& all, const LabelSet& labels, QString& left_out) {
  const std::vector<UnscorableBox> unscorable = unscorableBoxes(all, labels.size());
  std::vector<bool> left(all.boxes.size(), false);
  QStringList problems;
  for (const UnscorableBox& box : unscorable) {
    left[box.index] = true;
    problems << (box.boxed_before
                     ? EvaluationPanel::tr("boxes[%1] (label %2 is already boxed)")
                     : EvaluationPanel::tr(
                           "boxes[%1] (label %2 is not an object label of the sequence)"))
                    .arg(box.index)
                    .arg(box.label);
  }
  Annotations scorable = all;
  scorable.boxes.clear();
  for (size_t i = 0; i < all.boxes.size(); ++i)
    if (!left[i]) scorable.boxes.push_back(all.boxes[i]);
  left_out = problems.isEmpty() ? QString()
                                : EvaluationPanel::tr("Not scored: %1.").arg(problems.join("; "));
  return scorable;
}

// A header that makes room for the sort arrow in the sorted column only:
// QHeaderView widens every column by an arrow's width, which in a narrow dock
// pushes the scores out of view.
class CompactHeader : public QHeaderView {
 public:
  explicit CompactHeader(QWidget* parent) : QHeaderView(Qt::Horizontal, parent) {
    setSectionsClickable(true);
    setHighlightSections(true);
    connect(this, &QHeaderView::sortIndicatorChanged, this, [this] { resizeSections(); });
  }

 protected:
  [[nodiscard]] QSize sectionSizeFromContents(int logical) const override {
    const QSize size = QHeaderView::sectionSizeFromContents(logical);
    if (!isSortIndicatorShown() || logical == sortIndicatorSection()) return size;
    QStyleOptionHeader option;
    initStyleOption(&option);
    option.section = logical;
    option.text = model()->headerData(logical, orientation()).toString();
    option.sortIndicator = QStyleOptionHeader::None;
    // Measured in bold, as Qt measures its own size: the header of the
    // selected row's columns is drawn bold (highlighted sections).
    QFont bold = font();
    bold.setBold(true);
    option.fontMetrics = QFontMetrics(bold);
    const QSize bare = style()->sizeFromContents(QStyle::CT_HeaderSection, &option, QSize(), this);
    return {std::min(size.width(), bare.width()), size.height()};
  }
};

// Asks for the height of its rows (3 to 8 of them) instead of Qt's fixed 192
// px: the dock's layout sizes the panel from its widgets' size hints, and the
// extra height pushed the score chart below the fold at common window sizes.
class ScoreTable : public QTableWidget {
 public:
  ScoreTable(int rows, int columns) : QTableWidget(rows, columns) {
    setTabKeyNavigation(false);  // Tab goes on to the next field; arrows move rows
  }

  [[nodiscard]] QSize sizeHint() const override {
    const int rows = std::clamp(rowCount(), 3, 8);
    const int height = horizontalHeader()->sizeHint().height() +
                       rows * verticalHeader()->defaultSectionSize() + 2 * frameWidth() +
                       (horizontalScrollBar()->isVisible() ? horizontalScrollBar()->height() : 0);
    return {QTableWidget::sizeHint().width(), height};
  }
};

QTableWidgetItem* scoreItem(double value) {
  // Shown in percent with one decimal.
  return new NumberItem(value, QString::number(value * 100.0, 'f', 1));
}

// What LabelOctoMap's IU_3d is made of (report.md's volumes table), in cm³.
QString volumesTip(const IouVolumes& v) {
  auto cm3 = [](double cubic_metres) {
    return QString::number(std::max(cubic_metres, 0.0) * 1e6, 'f', 1);
  };
  return QObject::tr(
             "IU_3d of LabelOctoMap: %1 cm³ of its voxels inside the box, %2 cm³ outside, "
             "%3 cm³ of the box (%4 cm³) without voxels. View ▸ Show Score Breakdown "
             "(Ctrl+E) shows which voxels.")
      .arg(cm3(v.true_positive), cm3(v.falsePositive()), cm3(v.falseNegative()),
           cm3(v.ground_truth));
}

// The view whose projection scored highest (the first of equals), as a frame
// index; none without views.
std::optional<size_t> bestView(const ObjectScore& object, const std::vector<size_t>& views) {
  const size_t n = std::min(object.per_view.size(), views.size());
  if (n == 0) return std::nullopt;
  const auto best =
      std::max_element(object.per_view.begin(), object.per_view.begin() + static_cast<long>(n));
  return views[static_cast<size_t>(best - object.per_view.begin())];
}

// Each view's projection IU_3d, for the projection cells' tooltips. Frames
// are numbered as the timeline numbers them (from 1), the best one also by
// its index in sequence.json, as the reports give views.
QString viewsTip(const ObjectScore& object, const std::vector<size_t>& views) {
  const std::optional<size_t> best = bestView(object, views);
  if (!best) return {};
  QStringList each;
  for (size_t i = 0; i < std::min(object.per_view.size(), views.size()); ++i)
    each << QString("%1: %2").arg(views[i] + 1).arg(object.per_view[i] * 100.0, 0, 'f', 1);
  return QObject::tr(
             "Projection IU_3d of each view (frame: %): %1. Best: frame %2 (frames[%3]). "
             "Double-click to show that frame.")
      .arg(each.join(", "))
      .arg(*best + 1)
      .arg(*best);
}

}  // namespace

EvaluationPanel::EvaluationPanel(StudioSession& session, QWidget* parent)
    : QWidget(parent),
      session_(session),
      table_(new ScoreTable(0, Columns)),
      summary_(new QLabel),
      warnings_(new QLabel),
      chart_(new ScoreChart),
      export_(new QPushButton(tr("Export report…"))),
      iou_mode_(new QComboBox),
      debounce_(new QTimer(this)) {
  setObjectName("evaluationPanel");
  table_->setObjectName("evaluationTable");
  table_->setAccessibleName(tr("Scores"));
  summary_->setObjectName("evaluationSummary");
  warnings_->setObjectName("evaluationWarnings");
  table_->setHorizontalHeader(new CompactHeader(table_));
  // Short headers keep the scores in view in a narrow dock; the full wording
  // is in each header's tooltip.
  const std::pair<QString, QString> headers[Columns] = {
      {tr("Label"), tr("Label id")},
      {tr("Object"), tr("Object name")},
      {tr("Voxels"), tr("LabelOctoMap voxels of the label")},
      {tr("Mean"), tr("IU_3d of Projection (Mean), %")},
      {tr("Max"), tr("IU_3d of Projection (Max), %")},
      {tr("LOM"), tr("IU_3d of LabelOctoMap, %")},
      {tr("Box"), tr("Box IU of LabelOctoMap, %")}};
  for (int column = 0; column < Columns; ++column) {
    auto* header = new QTableWidgetItem(headers[column].first);
    header->setToolTip(headers[column].second);
    table_->setHorizontalHeaderItem(column, header);
  }
  table_->verticalHeader()->hide();
  table_->verticalHeader()->setDefaultSectionSize(table_->fontMetrics().height() + 4);
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setWordWrap(false);
  table_->setTextElideMode(Qt::ElideRight);
  // The numbers take the width they need; the object name takes what is left
  // (elided, in full in its tooltip), so the scores never scroll out of view.
  QHeaderView* columns = table_->horizontalHeader();
  columns->setSectionResizeMode(QHeaderView::ResizeToContents);
  columns->setSectionResizeMode(Name, QHeaderView::Stretch);
  columns->setMinimumSectionSize(24);
  // Ascending label by default, as the report lists the objects. The chart
  // follows the table's order, whatever column the user sorts by, so that
  // the n-th group of bars is always the n-th row (see syncChart).
  columns->setSortIndicator(Label, Qt::AscendingOrder);
  table_->setSortingEnabled(true);
  connect(table_->model(), &QAbstractItemModel::layoutChanged, this, &EvaluationPanel::syncChart);
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  connect(table_, &QTableWidget::itemSelectionChanged, this, &EvaluationPanel::selectBoxOfRow);
  connect(table_, &QTableWidget::cellDoubleClicked, this, &EvaluationPanel::showBestView);
  connect(&session_.annotations(), &AnnotationsModel::selectionChanged, this,
          &EvaluationPanel::selectRowOfBox);
  summary_->setWordWrap(true);
  summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  // What `labeloctomap score` warns about, for these scores too (boxes named
  // after another label, labels left out of the candidates, a map that does
  // not fit the depths): in the report's own words, hidden when there is none.
  warnings_->setWordWrap(true);
  warnings_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  // Orange that reads (at least 4.5:1) on the panel's background, light or dark.
  QPalette warning_colours = warnings_->palette();
  warning_colours.setColor(QPalette::WindowText,
                           palette().color(QPalette::Window).lightness() >= 128
                               ? QColor(0x8a, 0x45, 0x00)
                               : QColor(0xff, 0xb8, 0x6b));
  warnings_->setPalette(warning_colours);
  warnings_->hide();
  export_->setEnabled(false);
  iou_mode_->setObjectName("evaluationIouMode");
  iou_mode_->addItem(tr("Exact volumes"), static_cast<int>(IouMode::Exact));
  iou_mode_->addItem(tr("Voxel centres"), static_cast<int>(IouMode::Center));
  iou_mode_->setCurrentIndex(iou_mode_->findData(static_cast<int>(session_.iouMode())));
  iou_mode_->setToolTip(
      tr("How IU_3d counts a voxel in a box: by the exact volume of the voxel inside it, or "
         "whole when its centre is inside (labeloctomap score --iou exact|center)"));
  connect(iou_mode_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int index) {
    session_.setIouMode(static_cast<IouMode>(iou_mode_->itemData(index).toInt()));
  });

  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  layout->setSpacing(4);
  // As tall as its rows (ScoreTable), never shorter; the chart takes what is left.
  table_->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Minimum);
  layout->addWidget(table_);
  // The button sits beside the summary, above the chart: in a short window
  // (a 1366x768 laptop) the chart gives way and the button stays in view.
  // The IU_3d mode under it: how the scores were counted, beside them.
  auto* summary_row = new QHBoxLayout;
  summary_row->addWidget(summary_, 1);
  auto* buttons = new QVBoxLayout;
  buttons->addWidget(export_);
  buttons->addWidget(iou_mode_);
  buttons->addStretch(1);
  summary_row->addLayout(buttons);
  layout->addLayout(summary_row);
  layout->addWidget(warnings_);
  layout->addWidget(chart_, 1);

  debounce_->setSingleShot(true);
  debounce_->setInterval(300);
  connect(debounce_, &QTimer::timeout, this, &EvaluationPanel::evaluateNow);
  MapWorker& worker = session_.worker();
  connect(&session_.annotations(), &AnnotationsModel::boxesChanged, this,
          &EvaluationPanel::requestUpdate);
  connect(&worker, &MapWorker::fusionFinished, this, &EvaluationPanel::requestUpdate);
  connect(&session_, &StudioSession::iouModeChanged, this, [this] {
    const int index = iou_mode_->findData(static_cast<int>(session_.iouMode()));
    if (index != iou_mode_->currentIndex()) iou_mode_->setCurrentIndex(index);
    requestUpdate();
  });
  connect(&worker, &MapWorker::snapshotChanged, this, [this] {
    if (!session_.worker().isFusing()) requestUpdate();  // re-thresholded or reset
  });
  // A report belongs to one map and one set of boxes: once either changes it
  // cannot be exported until it is recomputed.
  // So is the evaluation of the earlier map still on its way.
  connect(&worker, &MapWorker::stateChanged, this, [this](MapWorker::State state) {
    if (state == MapWorker::State::Fusing)
      clearReport(tr("Fusing: the map is scored when fusion finishes."));
    else if (state == MapWorker::State::Paused)
      clearReport(tr("Fusion paused: the map is scored when fusion finishes."));
  });
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          [this] { clearReport(tr("Fuse the sequence to score the map.")); });
  connect(&worker, &MapWorker::evaluationFinished, this, &EvaluationPanel::show);
  connect(&worker, &MapWorker::evaluationFailed, this,
          [this](const QString& message) { clearReport(message); });
  connect(export_, &QPushButton::clicked, this, [this] {
    // The folder dialog proposes NAME-report beside the sequence (or the
    // converted recording, not in the import cache): each sequence's report
    // has a folder of its own, as `score --batch` gives it, and one
    // sequence's export does not offer to replace another's. A folder dialog
    // chooses only folders that exist, so it is made for the dialog, and
    // taken away again (when still empty) unless the report goes there.
    const QString proposed = session_.controller().proposedOutput(QStringLiteral("-report"));
    const bool made = !QFileInfo::exists(proposed) && QDir().mkdir(proposed);
    QFileDialog dialog(this, tr("Export Report To"));
    dialog.setFileMode(QFileDialog::Directory);
    dialog.setOption(QFileDialog::ShowDirsOnly);
    if (QFileInfo(proposed).isDir()) {
      dialog.setDirectory(QFileInfo(proposed).absolutePath());
      dialog.selectFile(proposed);
    } else {
      dialog.setDirectory(session_.controller().outputFolder());
    }
    const QStringList chosen =
        dialog.exec() == QDialog::Accepted ? dialog.selectedFiles() : QStringList();
    const QString dir = chosen.isEmpty() ? QString() : chosen.front();
    const bool exported = !dir.isEmpty() && exportReportTo(dir);
    if (made && !(exported && QFileInfo(dir) == QFileInfo(proposed))) QDir().rmdir(proposed);
  });
  showMessage(tr("Open a sequence, fuse it and add boxes to score the map."));
}

int EvaluationPanel::heightForWidth(int width) const {
  return layout()->minimumHeightForWidth(width);
}

bool EvaluationPanel::isBusy() const {
  return debounce_->isActive() || session_.worker().isEvaluating();
}

void EvaluationPanel::requestUpdate() {
  // The scores shown are out of date until the new ones arrive, and say so.
  stale_ = true;
  export_->setEnabled(false);
  const QString updating = tr("Updating the scores…");
  if (report_ && !summary_->text().startsWith(updating))
    summary_->setText(updating + " " + summary_->text());
  debounce_->start();
}

void EvaluationPanel::clearReport(const QString& message) {
  report_.reset();
  stale_ = true;
  awaiting_ = false;  // results of evaluations asked for before are dropped
  syncing_selection_ = true;
  table_->setRowCount(0);
  syncing_selection_ = false;
  table_->updateGeometry();  // its height follows its rows
  chart_->setObjects({});
  export_->setEnabled(false);
  showMessage(message);
}

void EvaluationPanel::evaluateNow() {
  const auto sequence = session_.sequence();
  if (!sequence) return;
  if (session_.worker().isFusing()) return;  // fusionFinished asks again
  const Annotations& boxes = session_.annotations().annotations();
  if (boxes.boxes.empty()) {
    clearReport(sequence->labels.size() > 1
                    ? tr("No boxes: add one (Annotate menu) to score the map.")
                    : tr("This sequence has only the background label: it has no objects to "
                         "box or score."));
    return;
  }
  if (!session_.worker().snapshot() || session_.worker().snapshot()->frames_fused == 0) {
    clearReport(tr("Fuse the sequence to score the map."));
    return;
  }
  Annotations annotations = scorableBoxes(boxes, sequence->labels, left_out_);
  if (annotations.boxes.empty()) {
    clearReport(tr("No box can be scored. %1").arg(left_out_));
    return;
  }
  EvaluationOptions options;
  options.fusion = session_.fusionOptions();
  options.iou_mode = session_.iouMode();
  // Warnings about the boxes name their file, as `score` names it.
  const AnnotationsModel& model = session_.annotations();
  annotations_file_ = QDir::toNativeSeparators(model.path()).toStdString();
  if (model.isDirty() || annotations_file_.empty())
    annotations_file_ += annotations_file_.empty() ? "the boxes in the studio (not saved)"
                                                   : " (with edits not saved)";
  options.annotations_file = annotations_file_;
  annotations.frame_id = sequence->frame_id;
  // A fusion cancelled or stopped part way fused only the first frames: the
  // baselines project the views among those, as `score --frames` does.
  const size_t first = std::min(options.fusion.first_frame, sequence->frames.size());
  const size_t last = std::min(options.fusion.last_frame, sequence->frames.size());
  const size_t fused = session_.worker().snapshot()->frames_fused;
  partial_.clear();
  if (first + fused < last) {
    options.fusion.last_frame = first + fused;
    partial_ = tr("Partial map (%1 of %2 frames fused): the baselines use the views among them.")
                   .arg(fused)
                   .arg(last - first);
  }
  summary_->setText(tr("Scoring…"));
  awaiting_ = true;
  session_.worker().evaluate(sequence, annotations, options);
}

void EvaluationPanel::show(const EvaluationReport& scored) {
  if (!awaiting_) return;  // asked for before the map or sequence changed
  // The scores' box numbers are those of the boxes scored (some may be left
  // out): the name warnings number the boxes as the file does.
  EvaluationReport report = scored;
  if (const auto sequence = session_.sequence()) {
    for (const std::string& warning : scored.box_name_warnings) {
      const auto said = std::find(report.warnings.begin(), report.warnings.end(), warning);
      if (said != report.warnings.end()) report.warnings.erase(said);
    }
    report.box_name_warnings =
        boxNameWarnings(session_.annotations().annotations(), sequence->labels, annotations_file_,
                        (sequence->root / "sequence.json").string());
    report.warnings.insert(report.warnings.begin(), report.box_name_warnings.begin(),
                           report.box_name_warnings.end());
  }
  report_ = report;
  // Boxes changed again while scoring: newer scores are on their way.
  stale_ = debounce_->isActive() || session_.worker().isEvaluating();
  // Rebuilding the rows moves the table's selection to whatever row lands
  // under it: that is no choice of the user's, and must not select a box
  // (selectRowOfBox below puts the selection back on the selected box's row).
  syncing_selection_ = true;
  table_->setSortingEnabled(false);
  table_->setRowCount(static_cast<int>(report.objects.size()));
  table_->updateGeometry();  // its height follows its rows
  for (int row = 0; row < table_->rowCount(); ++row) {
    const ObjectScore& object = report.objects[static_cast<size_t>(row)];
    QTableWidgetItem* label = new NumberItem(object.label, QString::number(object.label));
    label->setData(kObjectRole, row);
    table_->setItem(row, Label, label);
    auto* name = new QTableWidgetItem(QString::fromStdString(object.name));
    name->setToolTip(name->text());
    table_->setItem(row, Name, name);
    table_->setItem(row, Voxels, countItem(object.voxels));
    const QString views = viewsTip(object, report.views);
    for (const auto& [column, value] : {std::pair{ProjectionMean, object.iou_3d.projection_mean},
                                        std::pair{ProjectionMax, object.iou_3d.projection_max}}) {
      QTableWidgetItem* item = scoreItem(value);
      item->setToolTip(views);
      table_->setItem(row, column, item);
    }
    QTableWidgetItem* labeloctomap = scoreItem(object.iou_3d.labeloctomap);
    labeloctomap->setToolTip(volumesTip(object.labeloctomap_volumes));
    table_->setItem(row, LabelOctoMap, labeloctomap);
    table_->setItem(row, BoxIou, scoreItem(object.box_iou.labeloctomap));
  }
  table_->setSortingEnabled(true);
  syncing_selection_ = false;
  const ScoreSummary& s = report.summary;
  const QString over =
      s.objects == 1 ? tr("Mean over 1 object") : tr("Mean over %1 objects").arg(s.objects);
  summary_->setText(tr("%1 — Proj. mean %2, Proj. max %3, LabelOctoMap %4, box IU %5; "
                       "LabelOctoMap beats Proj. max on %6 of %7.")
                        .arg(over)
                        .arg(s.iou_3d.projection_mean * 100.0, 0, 'f', 1)
                        .arg(s.iou_3d.projection_max * 100.0, 0, 'f', 1)
                        .arg(s.iou_3d.labeloctomap * 100.0, 0, 'f', 1)
                        .arg(s.box_iou.labeloctomap * 100.0, 0, 'f', 1)
                        .arg(s.labeloctomap_beats_projection_max)
                        .arg(s.objects) +
                    (left_out_.isEmpty() ? QString() : " " + left_out_) +
                    (partial_.isEmpty() ? QString() : " " + partial_));
  QStringList warnings;
  for (const std::string& warning : report.warnings)
    warnings << tr("Warning: %1").arg(QString::fromStdString(warning));
  warnings_->setText(warnings.join("\n"));
  warnings_->setVisible(!warnings.isEmpty());
  syncChart();
  selectRowOfBox();
  export_->setEnabled(!stale_);
  emit reportShown();
}

void EvaluationPanel::syncChart() {
  std::vector<ObjectScore> objects;
  if (report_) {
    objects.reserve(static_cast<size_t>(table_->rowCount()));
    for (int row = 0; row < table_->rowCount(); ++row) {
      const QTableWidgetItem* label = table_->item(row, Label);
      if (!label) continue;
      const int index = label->data(kObjectRole).toInt();
      if (index >= 0 && static_cast<size_t>(index) < report_->objects.size())
        objects.push_back(report_->objects[static_cast<size_t>(index)]);
    }
  }
  chart_->setObjects(std::move(objects));
}

void EvaluationPanel::showBestView(int row, int column) {
  if (!report_ || (column != ProjectionMean && column != ProjectionMax)) return;
  const QTableWidgetItem* label = table_->item(row, Label);
  if (!label) return;
  const int index = label->data(kObjectRole).toInt();
  if (index < 0 || static_cast<size_t>(index) >= report_->objects.size()) return;
  if (const auto frame = bestView(report_->objects[static_cast<size_t>(index)], report_->views))
    session_.controller().setCurrentFrame(static_cast<int>(*frame));
}

void EvaluationPanel::selectBoxOfRow() {
  if (syncing_selection_) return;
  const QList<QTableWidgetItem*> selected = table_->selectedItems();
  if (selected.isEmpty()) return;  // a box stays selected when the table loses its selection
  const QTableWidgetItem* label = table_->item(selected.front()->row(), Label);
  if (!label) return;
  AnnotationsModel& boxes = session_.annotations();
  const int index = boxes.indexOfLabel(label->text().toInt());
  if (index >= 0) boxes.select(index);
}

void EvaluationPanel::selectRowOfBox() {
  const AnnotationsModel& boxes = session_.annotations();
  const int selected = boxes.selected();
  const QString label = selected >= 0 ? QString::number(boxes.box(selected).label) : QString();
  syncing_selection_ = true;
  table_->clearSelection();
  if (const int row = rowOfLabel(label); row >= 0) {
    table_->selectRow(row);
    table_->scrollToItem(table_->item(row, Label));
  }
  syncing_selection_ = false;
}

int EvaluationPanel::boxAfterIfFocused(int box) const {
  const AnnotationsModel& boxes = session_.annotations();
  if (!table_->hasFocus() || box < 0 || box >= boxes.boxCount()) return -1;
  const int row = rowOfLabel(QString::number(boxes.box(box).label));
  if (row < 0) return -1;
  const int next = row + 1 < table_->rowCount() ? row + 1 : row - 1;
  const QTableWidgetItem* item = next >= 0 ? table_->item(next, Label) : nullptr;
  return item ? boxes.indexOfLabel(item->text().toInt()) : -1;
}

int EvaluationPanel::rowOfLabel(const QString& label) const {
  for (int row = 0; row < table_->rowCount() && !label.isEmpty(); ++row)
    if (const QTableWidgetItem* item = table_->item(row, Label); item && item->text() == label)
      return row;
  return -1;
}

void EvaluationPanel::showMessage(const QString& message) {
  summary_->setText(message);
  // The warnings were about scores no longer shown.
  warnings_->clear();
  warnings_->hide();
}

QString EvaluationPanel::warningsText() const { return warnings_->text(); }

QString EvaluationPanel::summaryText() const { return summary_->text(); }

bool EvaluationPanel::exportReportTo(const QString& dir) {
  QStringList existing;
  for (const char* name : {"report.json", "report.csv", "report.md", "report.svg"}) {
    const QString path = QDir(dir).filePath(name);
    if (const QString own = session_.controller().sequenceFileAt(path); !own.isEmpty()) {
      QMessageBox::warning(this, tr("Export report"),
                           tr("%1 is a file of the sequence (%2): the report never replaces it. "
                              "Choose another folder.")
                               .arg(path, own));
      return false;
    }
    if (QFileInfo::exists(path)) existing << name;
  }
  if (!existing.isEmpty()) {
    QMessageBox question(QMessageBox::Question, tr("Replace the report?"),
                         tr("%1 already holds %2. Exporting the report replaces %3.")
                             .arg(QDir::toNativeSeparators(dir), existing.join(", "),
                                  existing.size() == 1 ? tr("it") : tr("them")),
                         QMessageBox::Cancel, this);
    QPushButton* replace = question.addButton(tr("Replace"), QMessageBox::AcceptRole);
    question.setDefaultButton(QMessageBox::Cancel);
    question.exec();
    if (question.clickedButton() != replace) return false;
  }
  const QString error = exportReport(dir);
  if (!error.isEmpty()) {
    QMessageBox::warning(this, tr("Export report"), error);
    return false;
  }
  // Said where it went, as the map exports say what they wrote.
  if (auto* main = qobject_cast<QMainWindow*>(window()))
    main->statusBar()->showMessage(tr("Wrote the report (report.json, .csv, .md, .svg) to %1.")
                                       .arg(QDir::toNativeSeparators(dir)),
                                   8000);
  return true;
}

QString EvaluationPanel::exportReport(const QString& dir) const {
  if (!report_) return tr("Nothing to export yet.");
  if (stale_)
    return tr(
        "The scores shown are out of date (the boxes or the map changed): wait for the "
        "new scores, then export.");
  // Named as the window names the sequence: a converted recording by its own
  // name, not by its cache folder's (which carries a hash and is removed
  // after 30 days).
  EvaluationReport named = *report_;
  const QString name = session_.controller().sequenceName();
  if (!name.isEmpty()) named.sequence = name.toStdString();
  // What the panel says beside the scores belongs in the report too: boxes
  // left out of the means, and a map fused from only the first frames.
  for (const QString& note : {left_out_, partial_})
    if (!note.isEmpty()) named.warnings.push_back(note.toStdString());
  try {
    writeReport(named, std::filesystem::path(dir.toStdString()));
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  return {};
}

}  // namespace lom::ui
