#include "lom/ui/box_editor_panel.hpp"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QKeyEvent>
#include <QLabel>
#include <QListWidget>
#include <QSignalBlocker>
#include <QStandardItemModel>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "label_search.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/box_edit_actions.hpp"
#include "lom/ui/box_math.hpp"
#include "lom/ui/elision.hpp"
#include "lom/ui/frame_labels.hpp"
#include "lom/ui/pending_edits.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/wheel_guard.hpp"

namespace lom::ui {

namespace {

// Ctrl+Z / Ctrl+Shift+Z in a field undo and redo box edits, as everywhere in
// the window: the field's own text undo would otherwise take the keys, and a
// value entered with Enter could not be undone until the focus left it.
// A value still being typed is entered first, so that Undo takes back that
// value (it took back the edit before it and dropped the typing); Redo leaves
// it (entering it would end the redo history).
std::optional<bool> leaveUndoToTheWindow(const QKeyEvent& key) {
  if (key.matches(QKeySequence::Undo)) {
    commitPendingEdits();
    return false;
  }
  if (key.matches(QKeySequence::Redo)) return false;
  return std::nullopt;
}

QDoubleSpinBox* makeField(double low, double high, int decimals, double step,
                          const QString& suffix) {
  auto* box = new QDoubleSpinBox;
  box->setRange(low, high);
  box->setDecimals(decimals);
  box->setSingleStep(step);
  box->setSuffix(suffix);
  box->setKeyboardTracking(false);
  return box;
}

QIcon swatch(const QColor& color) {
  QPixmap pixmap(12, 12);
  pixmap.fill(color);
  return QIcon(pixmap);
}

constexpr double kDegrees = 180.0 / M_PI;

}  // namespace

BoxEditorPanel::BoxEditorPanel(StudioSession& session, BoxSteps& steps, QWidget* parent)
    : QWidget(parent),
      session_(session),
      steps_(steps),
      list_(new QListWidget),
      box_label_(new ElidingComboBox),
      new_label_(new ElidingComboBox) {
  setObjectName("boxEditor");
  list_->setObjectName("boxList");
  list_->setAccessibleName(tr("Boxes"));
  new_label_->setObjectName("newBoxLabel");
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  auto* new_form = new QFormLayout;
  new_form->addRow(tr("New box label"), new_label_);
  layout->addLayout(new_form);
  layout->addWidget(list_, 1);

  // One column per quantity and one row per axis (roll, pitch and yaw turn
  // about x, y and z): three fields side by side under short headings keep
  // the panel narrow enough for a 1024-pixel-wide screen.
  auto* grid = new QGridLayout;
  const QString columns[3] = {tr("Centre (m)"), tr("Size (m)"), tr("Roll/Pitch/Yaw")};
  const QString axes[3] = {QStringLiteral("x"), QStringLiteral("y"), QStringLiteral("z")};
  const QString tips[9] = {tr("Centre x, m"),
                           tr("Centre y, m"),
                           tr("Centre z, m"),
                           tr("Length (size along x), m"),
                           tr("Width (size along y), m"),
                           tr("Height (size along z), m"),
                           tr("Roll (about x), degrees"),
                           tr("Pitch (about y), degrees"),
                           tr("Yaw (about z), degrees")};
  for (int column = 0; column < 3; ++column) {
    grid->addWidget(new QLabel(columns[column]), 0, 1 + column, Qt::AlignLeft | Qt::AlignBottom);
    grid->addWidget(new QLabel(axes[column]), 1 + column, 0);
  }
  for (int i = 0; i < 9; ++i) {
    const bool angle = i >= 6;
    fields_[static_cast<size_t>(i)] = angle ? makeField(-180.0, 180.0, 1, 1.0, QStringLiteral("°"))
                                            : (i >= 3 ? makeField(0.002, 100.0, 3, 0.005, "")
                                                      : makeField(-1000, 1000, 3, 0.005, ""));
    fields_[static_cast<size_t>(i)]->setObjectName(QString("boxField%1").arg(i));
    fields_[static_cast<size_t>(i)]->setToolTip(tips[i]);
    fields_[static_cast<size_t>(i)]->setAccessibleName(tips[i]);  // the grid's headings are apart
    grid->addWidget(fields_[static_cast<size_t>(i)], 1 + i % 3, 1 + i / 3);
    connect(fields_[static_cast<size_t>(i)], qOverload<double>(&QDoubleSpinBox::valueChanged), this,
            &BoxEditorPanel::onFieldEdited);
  }
  auto* form = new QFormLayout;
  form->addRow(tr("Label"), box_label_);
  layout->addLayout(form);
  layout->addLayout(grid);

  auto* steps_box = new QGroupBox(tr("Key steps"));
  auto* steps_form = new QFormLayout(steps_box);
  auto* move = makeField(BoxSteps::kMinLength, BoxSteps::kMaxLength, 3, 0.005, " m");
  auto* turn = makeField(BoxSteps::kMinTurn, BoxSteps::kMaxTurn, 1, 1.0, QStringLiteral("°"));
  auto* resize = makeField(BoxSteps::kMinLength, BoxSteps::kMaxLength, 3, 0.005, " m");
  move->setValue(steps_.move);
  turn->setValue(steps_.turn);
  resize->setValue(steps_.resize);
  steps_form->addRow(tr("Move"), move);
  steps_form->addRow(tr("Rotate"), turn);
  steps_form->addRow(tr("Resize"), resize);
  layout->addWidget(steps_box);
  auto remember = [this, move, turn, resize] {
    steps_.move = move->value();
    steps_.turn = turn->value();
    steps_.resize = resize->value();
    steps_.save();
  };
  for (QDoubleSpinBox* box : {move, turn, resize})
    connect(box, qOverload<double>(&QDoubleSpinBox::valueChanged), this, remember);

  AnnotationsModel& model = session_.annotations();
  connect(&model, &AnnotationsModel::boxesChanged, this, &BoxEditorPanel::rebuildList);
  connect(&model, &AnnotationsModel::selectionChanged, this, &BoxEditorPanel::showSelected);
  connect(list_, &QListWidget::currentRowChanged, this, [this](int row) {
    if (!updating_) session_.annotations().select(row);
  });
  connect(box_label_, qOverload<int>(&QComboBox::activated), this,
          &BoxEditorPanel::onBoxLabelChosen);
  connect(new_label_, qOverload<int>(&QComboBox::currentIndexChanged), this, [this](int index) {
    if (!updating_) session_.setSelectedLabel(new_label_->itemData(index).toInt());
  });
  connect(&session_, &StudioSession::selectedLabelChanged, this, [this](int label) {
    const QSignalBlocker block(new_label_);
    new_label_->setCurrentIndex(new_label_->findData(label));
  });
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &BoxEditorPanel::rebuildLabels);
  rebuildList();
  guardWheel(*this);
  auto* undo_keys = new ShortcutKeys(this, leaveUndoToTheWindow);
  for (QDoubleSpinBox* field : fields_) field->installEventFilter(undo_keys);
  // The key steps too: Undo there undoes box edits, as in every field.
  for (QDoubleSpinBox* step : steps_box->findChildren<QDoubleSpinBox*>())
    step->installEventFilter(undo_keys);
  searchLabelsByName(*box_label_);
  searchLabelsByName(*new_label_);
}

void BoxEditorPanel::rebuildLabels() {
  updating_ = true;
  box_label_->clear();
  new_label_->clear();
  if (const auto sequence = session_.sequence()) {
    for (const LabelInfo& info : sequence->labels.all()) {
      if (info.id == 0) continue;  // the background is never boxed
      const QString text = QString("%1 %2").arg(info.id).arg(QString::fromStdString(info.name));
      const QIcon icon = swatch(labelColor(sequence->labels, info.id));
      box_label_->addItem(icon, text, info.id);
      new_label_->addItem(icon, text, info.id);
    }
  }
  new_label_->setCurrentIndex(new_label_->findData(session_.selectedLabel()));
  updating_ = false;
  showSelected();
}

void BoxEditorPanel::rebuildList() {
  updating_ = true;
  const AnnotationsModel& model = session_.annotations();
  list_->clear();
  const auto sequence = session_.sequence();
  for (int i = 0; i < model.boxCount(); ++i) {
    const GroundTruthBox& box = model.box(i);
    // Named by the sequence's label, as the scores name it; a boxes file that
    // calls it otherwise (drawn for another label numbering?) is said so.
    QString name = QString::fromStdString(box.name);
    QString tip;
    if (sequence && sequence->labels.contains(box.label)) {
      const QString label_name = QString::fromStdString(sequence->labels.at(box.label).name);
      if (!box.name.empty() && name != label_name)
        tip = tr("Label %1 is %2 in the sequence; the boxes file names this box %3.")
                  .arg(box.label)
                  .arg(label_name, name);
      name = tip.isEmpty() ? label_name : label_name + " (" + tr("file: %1").arg(name) + ")";
    }
    auto* item = new QListWidgetItem(QString("%1  %2").arg(box.label).arg(name));
    item->setToolTip(tip.isEmpty() ? item->text() : item->text() + "\n" + tip);  // elided names
    if (sequence) item->setIcon(swatch(labelColor(sequence->labels, box.label)));
    list_->addItem(item);
  }
  updating_ = false;
  showSelected();
}

void BoxEditorPanel::showSelected() {
  updating_ = true;
  const AnnotationsModel& model = session_.annotations();
  const int index = model.selected();
  list_->setCurrentRow(index);
  const bool has = index >= 0;
  for (QDoubleSpinBox* field : fields_) field->setEnabled(has);
  box_label_->setEnabled(has);
  if (has) {
    const GroundTruthBox& box = model.box(index);
    const Eigen::Vector3d angles = rollPitchYaw(box.box.rotation) * kDegrees;
    // A centre or size beyond a field's range widens the range: clamped, the
    // field would show another box, and its first step would move the box
    // there (a size keeps its smallest value above zero).
    const auto show = [](QDoubleSpinBox* field, double value, bool may_lower) {
      if (value > field->maximum()) field->setMaximum(value);
      if (may_lower && value < field->minimum()) field->setMinimum(value);
      field->setValue(value);
    };
    for (int i = 0; i < 3; ++i) {
      show(fields_[static_cast<size_t>(i)], box.box.center[i], true);
      show(fields_[static_cast<size_t>(i + 3)], box.box.size[i], false);
      show(fields_[static_cast<size_t>(i + 6)], angles[i], false);
    }
    box_label_->setCurrentIndex(box_label_->findData(box.label));
  }
  // One box per object: the labels other boxes have are shown but cannot be
  // chosen (choosing one used to snap back without a word).
  if (auto* items = qobject_cast<QStandardItemModel*>(box_label_->model()))
    for (int row = 0; row < items->rowCount(); ++row) {
      const int other = model.indexOfLabel(box_label_->itemData(row).toInt());
      QStandardItem* item = items->item(row);
      item->setEnabled(other < 0 || other == index);
      item->setToolTip(other < 0 || other == index ? QString() : tr("Has a box already"));
    }
  updating_ = false;
}

void BoxEditorPanel::onFieldEdited() {
  AnnotationsModel& model = session_.annotations();
  if (updating_ || model.selected() < 0) return;
  GroundTruthBox box = model.box(model.selected());
  // Only the edited value changes, so the others keep their full precision.
  const auto it = std::find(fields_.begin(), fields_.end(), sender());
  if (it == fields_.end()) return;
  const int i = static_cast<int>(it - fields_.begin());
  const double value = fields_[static_cast<size_t>(i)]->value();
  if (i < 3) {
    box.box.center[i] = value;
  } else if (i < 6) {
    box.box.size[i - 3] = value;
  } else {
    // The other two angles come from the box, not from their rounded fields.
    Eigen::Vector3d angles = rollPitchYaw(box.box.rotation);
    angles[i - 6] = value / kDegrees;
    box.box.rotation = fromRollPitchYaw(angles);
  }
  model.setBox(model.selected(), box, tr("Edit box"));
}

void BoxEditorPanel::onBoxLabelChosen(int combo_index) {
  AnnotationsModel& model = session_.annotations();
  const auto sequence = session_.sequence();
  if (updating_ || model.selected() < 0 || !sequence) return;
  GroundTruthBox box = model.box(model.selected());
  const int label = box_label_->itemData(combo_index).toInt();
  for (int i = 0; i < model.boxCount(); ++i)
    if (i != model.selected() && model.box(i).label == label) {
      showSelected();  // one box per object: keep the old label
      return;
    }
  box.label = label;
  box.name = sequence->labels.at(box.label).name;
  model.setBox(model.selected(), box, tr("Change box label"));
}

}  // namespace lom::ui
