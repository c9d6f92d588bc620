#include "lom/ui/map_legend_panel.hpp"

#include <QEvent>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QPixmap>
#include <QPushButton>
#include <QSignalBlocker>
#include <QTableWidget>
#include <QVBoxLayout>
#include <functional>
#include <utility>

#include "lom/height_colours.hpp"
#include "lom/ui/colour_bar.hpp"
#include "lom/ui/frame_labels.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

namespace {
constexpr int kLabelRole = Qt::UserRole + 1;

// Runs `entering` when its table gets the keyboard focus, before the table
// itself makes its first row current (which would choose that label).
class FocusEntry : public QObject {
 public:
  FocusEntry(QObject* parent, std::function<void()> entering)
      : QObject(parent), entering_(std::move(entering)) {}
  bool eventFilter(QObject*, QEvent* event) override {
    if (event->type() == QEvent::FocusIn) entering_();
    return false;
  }

 private:
  std::function<void()> entering_;
};

QIcon swatch(const QColor& color) {
  QPixmap pixmap(14, 14);
  pixmap.fill(color);
  return QIcon(pixmap);
}
}  // namespace

MapLegendPanel::MapLegendPanel(StudioSession& session, QWidget* parent)
    : QWidget(parent),
      session_(session),
      table_(new QTableWidget(0, 2)),
      height_bar_(new ColourBar(
          [](double t) {
            const Rgb c = heightRampColour(t);
            return QColor(c[0], c[1], c[2]);
          },
          tr("height"))) {
  height_bar_->setObjectName("heightColourBar");
  height_bar_->hide();
  setObjectName("mapLegend");
  table_->setObjectName("mapLegendTable");
  table_->setAccessibleName(tr("Map labels"));
  table_->setTabKeyNavigation(false);  // Tab goes on to the next field; arrows move rows
  table_->setHorizontalHeaderLabels({tr("Label"), tr("Voxels")});
  table_->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
  table_->horizontalHeader()->setSectionResizeMode(1, QHeaderView::ResizeToContents);
  table_->verticalHeader()->hide();
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);

  auto* only = show_only_ = new QPushButton(tr("Show only"));
  only->setObjectName("showOnlyButton");
  auto* all = show_all_ = new QPushButton(tr("Show all"));
  only->setEnabled(false);  // until a map has labels to list
  all->setEnabled(false);
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(only);
  buttons->addWidget(all);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  layout->addWidget(height_bar_);
  layout->addWidget(table_, 1);
  layout->addLayout(buttons);

  connect(only, &QPushButton::clicked, this, [this] { showOnly(currentLabel()); });
  connect(all, &QPushButton::clicked, this, &MapLegendPanel::showAll);
  connect(table_, &QTableWidget::itemChanged, this, &MapLegendPanel::onItemChanged);
  connect(table_, &QTableWidget::itemDoubleClicked, this,
          [this](QTableWidgetItem* item) { showOnly(item->data(kLabelRole).toInt()); });
  connect(table_, &QTableWidget::currentCellChanged, this,
          [this] { emit currentLabelChanged(currentLabel()); });
  // Tabbing into the table chooses no label: the row it starts on is the
  // label chosen already (else the first), made current without a word, so
  // the frame images keep the label they show (the background's probability
  // instead, before). Arrows then move from there and choose as they go.
  table_->installEventFilter(new FocusEntry(table_, [this] {
    if (table_->currentRow() >= 0 || table_->rowCount() == 0) return;
    int row = 0;
    for (int r = 0; r < table_->rowCount(); ++r)
      if (table_->item(r, 0)->data(kLabelRole).toInt() == session_.selectedLabel()) row = r;
    const QSignalBlocker block(table_);
    table_->selectionModel()->setCurrentIndex(table_->model()->index(row, 0),
                                              QItemSelectionModel::NoUpdate);
  }));
  connect(&session_.worker(), &MapWorker::snapshotChanged, this, &MapLegendPanel::rebuild);
  connect(&session_, &StudioSession::hiddenLabelsChanged, this, &MapLegendPanel::rebuild);
}

std::vector<int> MapLegendPanel::listedLabels() const {
  std::vector<int> labels;
  for (int row = 0; row < table_->rowCount(); ++row)
    labels.push_back(table_->item(row, 0)->data(kLabelRole).toInt());
  return labels;
}

QString MapLegendPanel::nameOf(int row) const { return table_->item(row, 0)->text(); }

int MapLegendPanel::currentLabel() const {
  const int row = table_->currentRow();
  return row < 0 ? -1 : table_->item(row, 0)->data(kLabelRole).toInt();
}

void MapLegendPanel::rebuild() {
  const int keep = currentLabel();
  const QSignalBlocker block(table_);
  const auto snapshot = session_.worker().snapshot();
  const auto sequence = session_.sequence();
  table_->setRowCount(0);
  const bool listed = snapshot && sequence && !snapshot->counts.empty();
  show_only_->setEnabled(listed);
  show_all_->setEnabled(listed);
  if (!listed) return;
  int row = 0;
  table_->setRowCount(static_cast<int>(snapshot->counts.size()));
  for (const auto& [label, count] : snapshot->counts) {
    const QString name = sequence->labels.contains(label)
                             ? QString::fromStdString(sequence->labels.at(label).name)
                             : tr("label %1").arg(label);
    // The background is drawn grey in the 3D view (its palette colour is black).
    const Rgb shaded = shadedLabelColour(sequence->labels, label);  // as the 3D view draws it
    const QColor color(shaded[0], shaded[1], shaded[2]);
    auto* item = new QTableWidgetItem(swatch(color), name);
    item->setToolTip(name);  // the table elides long names
    item->setData(kLabelRole, label);
    item->setFlags(Qt::ItemIsEnabled | Qt::ItemIsSelectable | Qt::ItemIsUserCheckable);
    item->setCheckState(session_.hiddenLabels().count(label) ? Qt::Unchecked : Qt::Checked);
    auto* count_item = new QTableWidgetItem;
    count_item->setData(Qt::DisplayRole, static_cast<qulonglong>(count));
    count_item->setData(kLabelRole, label);
    count_item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
    table_->setItem(row, 0, item);
    table_->setItem(row, 1, count_item);
    if (label == keep) table_->setCurrentCell(row, 0);
    ++row;
  }
}

void MapLegendPanel::onItemChanged() {
  std::set<int> hidden = session_.hiddenLabels();
  for (int row = 0; row < table_->rowCount(); ++row) {
    const QTableWidgetItem* item = table_->item(row, 0);
    const int label = item->data(kLabelRole).toInt();
    if (item->checkState() == Qt::Checked)
      hidden.erase(label);
    else
      hidden.insert(label);
  }
  session_.setHiddenLabels(std::move(hidden));
}

void MapLegendPanel::showOnly(int label) {
  if (label < 0 || !session_.sequence()) return;
  std::set<int> hidden;
  for (const auto& info : session_.sequence()->labels.all())
    if (info.id != label) hidden.insert(info.id);
  session_.setHiddenLabels(std::move(hidden));
}

void MapLegendPanel::showAll() { session_.setHiddenLabels({}); }

void MapLegendPanel::showHeightColours(std::optional<std::pair<double, double>> range) {
  height_bar_->setRange(range);
  height_bar_->setVisible(range.has_value());
}

std::optional<std::pair<double, double>> MapLegendPanel::heightBarRange() const {
  return height_bar_->isHidden() ? std::nullopt : height_bar_->range();
}

}  // namespace lom::ui
