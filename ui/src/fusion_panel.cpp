#include "lom/ui/fusion_panel.hpp"

#include <QCoreApplication>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPointer>
#include <QPushButton>
#include <QSignalBlocker>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "lom/frame_range.hpp"
#include "lom/fusion.hpp"
#include "lom/segmenter.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/pending_edits.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/wheel_guard.hpp"

namespace lom::ui {

namespace {

QDoubleSpinBox* makeBox(double low, double high, double step, int decimals, const QString& suffix) {
  auto* box = new QDoubleSpinBox;
  box->setRange(low, high);
  box->setSingleStep(step);
  box->setDecimals(decimals);
  box->setSuffix(suffix);
  box->setKeyboardTracking(false);
  return box;
}

std::optional<std::vector<int>> parseCandidates(const QString& text, bool* ok) {
  *ok = true;
  const QStringList words = text.split(QRegExp("[,\\s]+"), Qt::SkipEmptyParts);
  if (words.isEmpty()) return std::nullopt;
  std::vector<int> ids;
  for (const QString& word : words) {
    bool number = false;
    const int id = word.toInt(&number);
    if (!number || id < 0) {
      *ok = false;
      return std::nullopt;
    }
    ids.push_back(id);
  }
  return ids;
}

QString candidatesText(const std::optional<std::vector<int>>& candidates) {
  if (!candidates) return {};
  QStringList words;
  for (int id : *candidates) words << QString::number(id);
  return words.join(' ');
}

QString segmenterText(const std::shared_ptr<const Segmenter>& segmenter) {
  return segmenter ? QString::fromStdString(segmenter->modelPath().filename().string()) : QString();
}

}  // namespace

FusionPanel::FusionPanel(StudioSession& session, QWidget* parent)
    : QWidget(parent),
      session_(session),
      // The command line's limits (docs/fusion.md): voxels from 2 mm to 1 m,
      // rays of at most 1000 voxels (checked with the resolution in onEdited),
      // a miss that lowers occupancy, a threshold inside the clamping bounds.
      // Decimals enough for the values maps are fused with (0.0025 m voxels,
      // a 0.125 threshold); a map's value with more shows in the box's tooltip.
      resolution_(makeBox(kMinFusionResolution, kMaxFusionResolution, 0.005, 4, " m")),
      max_range_(makeBox(0.0, kMaxFusionVoxelsPerRay * kMaxFusionResolution, 0.1, 3, " m")),
      p_miss_(makeBox(0.001, 0.499, 0.05, 3, "")),
      threshold_(
          makeBox(MapParameters{}.clamp_min + 0.001, MapParameters{}.clamp_max, 0.05, 3, "")),
      candidates_(new QLineEdit),
      frames_(new QLineEdit),
      segmenter_path_(new QLineEdit),
      note_(new QLabel),
      refuse_(new QPushButton(tr("Re-fuse"))),
      extend_range_(new QPushButton) {
  setObjectName("fusionPanel");
  threshold_->setObjectName("thresholdBox");
  resolution_->setObjectName("resolutionBox");
  refuse_->setObjectName("refuseButton");
  max_range_->setSpecialValueText(tr("unlimited"));
  candidates_->setPlaceholderText(tr("all labels (e.g. 0 3 7)"));
  frames_->setObjectName("framesEdit");
  frames_->setPlaceholderText(tr("all frames (e.g. 0:20)"));
  frames_->setToolTip(
      tr("Frames A:B fuses frames A to B-1, as `labeloctomap fuse --frames A:B`; "
         "A: fuses from A to the end, :B the first B."));
  note_->setWordWrap(true);
  // Two-line notes (the depth-range one) keep their height in a crowded dock.
  note_->setSizePolicy(QSizePolicy::Preferred, QSizePolicy::MinimumExpanding);
  // Notes and the depth-range Re-fuse come first: in a short dock they are in
  // view with the first fields, the ones the depth-range note is about. They
  // sit outside the form, whose hidden rows would keep their spacing.
  auto* column = new QVBoxLayout(this);
  column->addWidget(note_);
  column->addWidget(extend_range_);
  auto* form = new QFormLayout;
  column->addLayout(form);
  form->addRow(tr("Resolution"), resolution_);
  form->addRow(tr("Max range"), max_range_);
  form->addRow(tr("p_miss"), p_miss_);
  form->addRow(tr("Threshold"), threshold_);
  form->addRow(tr("Candidates"), candidates_);
  form->addRow(tr("Frames"), frames_);
  segmenter_path_->setReadOnly(true);
  segmenter_path_->setAccessibleName(tr("Segmenter model"));  // its label names the row
  // Short enough for a narrow dock; the tooltip says what the model is for.
  segmenter_path_->setPlaceholderText(tr("none"));
  segmenter_path_->setToolTip(
      tr("A segmentation network (.onnx) that computes each frame's label probabilities. "
         "Without one, frames need probability images."));
  auto* choose = new QPushButton(tr("Choose…"));
  auto* clear = new QPushButton(tr("Clear"));
  auto* segmenter_row = new QHBoxLayout;
  segmenter_row->addWidget(segmenter_path_, 1);
  segmenter_row->addWidget(choose);
  segmenter_row->addWidget(clear);
  form->addRow(tr("Segmenter"), segmenter_row);
  connect(choose, &QPushButton::clicked, this, &FusionPanel::chooseSegmenter);
  connect(clear, &QPushButton::clicked, this, [this] { setSegmenterModel({}); });
  clear->setObjectName("clearSegmenterButton");
  // Nothing to clear without a model.
  connect(segmenter_path_, &QLineEdit::textChanged, clear,
          [clear](const QString& text) { clear->setEnabled(!text.isEmpty()); });
  clear->setEnabled(!segmenter_path_->text().isEmpty());
  column->addWidget(refuse_);
  extend_range_->setObjectName("extendRangeButton");
  extend_range_->hide();
  connect(extend_range_, &QPushButton::clicked, this, [this] {
    max_range_->setValue(suggested_range_);
    resolution_->setValue(suggested_resolution_);
    refuse();
  });
  connect(&session_.worker(), &MapWorker::depthRangesMeasured, this, &FusionPanel::showDepthRanges);
  connect(&session_.worker(), &MapWorker::stateChanged, this, [this](MapWorker::State state) {
    if (state == MapWorker::State::Idle) return;
    range_note_.clear();  // a new fusion: its own depths will tell
    extend_range_->hide();
    onEdited();
  });

  loadFromSession();
  // Nothing to fuse until a sequence is open.
  setEnabled(session_.sequence() != nullptr);
  // Settings typed but not applied are the user's choice for what is fused
  // next: the next sequence is fused with them (the status bar says so, as for
  // any setting carried over), not with the ones they were meant to replace.
  // Candidates name labels of one scene and go with it, as frames do.
  connect(&session_.controller(), &SequenceController::sequenceAboutToChange, this, [this] {
    if (!hasPendingChanges() || !session_.sequence()) return;
    onEdited();
    if (!refuse_->isEnabled()) return;  // not valid: the next sequence's values replace them
    FusionOptions options = effectiveOptions();
    options.candidates = session_.fusionOptions().candidates;
    options.first_frame = session_.fusionOptions().first_frame;  // frames of this sequence
    options.last_frame = session_.fusionOptions().last_frame;
    session_.setFusionOptions(options);
  });
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, [this] {
    setEnabled(session_.sequence() != nullptr);
    const std::shared_ptr<const Segmenter> previous = segmenter_;
    segmenter_note_.clear();
    // The session has dropped a segmenter whose channels do not fit the new
    // labels (StudioSession::onSequenceChanged): say why.
    if (previous && !session_.fusionOptions().segmenter && session_.sequence()) {
      try {
        previous->checkFits(session_.sequence()->labels);
      } catch (const std::exception& error) {
        segmenter_note_ = tr("Segmenter %1 removed: it does not fit this sequence's labels: %2")
                              .arg(segmenterText(previous), QString::fromStdString(error.what()));
      }
    }
    loadFromSession();  // the candidates of the previous sequence are gone
  });
  // A map read from a file brings its own parameters (edits not yet applied
  // are of the map it replaced).
  connect(&session_, &StudioSession::mapOpened, this, &FusionPanel::loadFromSession);
  // A fusion that kept the map before it: the boxes keep the values typed,
  // which differ from that map's again (Re-fuse tries them once more).
  connect(&session_, &StudioSession::previousMapKept, this, [this] {
    const MapParameters& map = session_.fusionOptions().map;
    auto shown = [](const QDoubleSpinBox* box, double value) {
      const double rounded = QString::number(value, 'f', box->decimals()).toDouble();
      return std::clamp(rounded, box->minimum(), box->maximum());
    };
    shown_ = {shown(resolution_, map.resolution), shown(max_range_, std::max(0.0, map.max_range)),
              shown(p_miss_, map.p_miss)};
    // The values typed for it are still the user's (Re-fuse applies them).
    const auto differs = [](const QDoubleSpinBox* box, double value) {
      return !qFuzzyCompare(1.0 + box->value(), 1.0 + value);
    };
    edited_ = {differs(resolution_, map.resolution),
               differs(max_range_, std::max(0.0, map.max_range)), differs(p_miss_, map.p_miss)};
    onEdited();
  });
  connect(threshold_, qOverload<double>(&QDoubleSpinBox::valueChanged), this, [this](double value) {
    threshold_->setToolTip(QString());
    session_.setOccupancyThreshold(value);
  });
  // A value committed in a box (Enter, leaving it, a step) is the user's,
  // applied on Re-fuse even where it equals the map's value as the box shows it.
  const auto track = [this](QDoubleSpinBox* box, bool Edited::*flag) {
    connect(box, qOverload<double>(&QDoubleSpinBox::valueChanged), this, [this, box, flag] {
      edited_.*flag = true;
      box->setToolTip(QString());
      onEdited();
    });
  };
  track(resolution_, &Edited::resolution);
  track(max_range_, &Edited::max_range);
  track(p_miss_, &Edited::p_miss);
  connect(candidates_, &QLineEdit::textChanged, this, &FusionPanel::onEdited);
  connect(frames_, &QLineEdit::textChanged, this, &FusionPanel::onEdited);
  connect(refuse_, &QPushButton::clicked, this, &FusionPanel::refuse);
  guardWheel(*this);
}

void FusionPanel::loadFromSession() {
  const FusionOptions& options = session_.fusionOptions();
  const QSignalBlocker b1(resolution_), b2(max_range_), b3(p_miss_), b4(threshold_),
      b5(candidates_), b6(frames_);
  frames_->setText(
      QString::fromStdString(frameRangeText({options.first_frame, options.last_frame})));
  resolution_->setValue(options.map.resolution);
  max_range_->setValue(std::max(0.0, options.map.max_range));
  p_miss_->setValue(options.map.p_miss);
  threshold_->setValue(options.map.occupancy_threshold);
  // A value the box rounds (or clamps) is the map's all the same: the tooltip
  // says which, and Re-fuse keeps it unless the box is edited.
  const auto exact = [this](QDoubleSpinBox* box, double value, const QString& unit) {
    box->setToolTip(qFuzzyCompare(1.0 + box->value(), 1.0 + value)
                        ? QString()
                        : tr("The map's value: %1%2").arg(value, 0, 'g', 10).arg(unit));
  };
  exact(resolution_, options.map.resolution, QStringLiteral(" m"));
  exact(max_range_, std::max(0.0, options.map.max_range), QStringLiteral(" m"));
  exact(p_miss_, options.map.p_miss, QString());
  exact(threshold_, options.map.occupancy_threshold, QString());
  rememberShown();
  candidates_->setText(candidatesText(options.candidates));
  segmenter_ = options.segmenter;
  segmenter_path_->setText(segmenterText(segmenter_));
  onEdited();
}

bool FusionPanel::setSegmenterModel(const QString& model_path) {
  if (model_path.isEmpty()) {
    segmenter_.reset();
  } else {
    try {
      SegmenterOptions options;
      // Problems that do not stop segmentation (an unwritable cache folder)
      // come from the fusion worker: shown in the note, in the GUI thread.
      options.warn = [panel = QPointer<FusionPanel>(this)](const std::string& message) {
        QMetaObject::invokeMethod(
            QCoreApplication::instance(),
            [panel, text = QString::fromStdString(message)] {
              if (panel) panel->showSegmenterWarning(text);
            },
            Qt::QueuedConnection);
      };
      auto loaded = Segmenter::load(model_path.toStdString(), std::move(options));
      // Its channels must fit the labels of the open sequence (names and ids,
      // and the channel count, from one run on a small image): else Re-fuse
      // would drop the map and fail.
      if (const auto sequence = session_.sequence()) loaded->checkFits(sequence->labels);
      segmenter_ = std::move(loaded);
    } catch (const std::exception& error) {
      segmenter_note_ = tr("Segmenter: %1").arg(QString::fromStdString(error.what()));
      setNote(segmenter_note_);
      return false;
    }
  }
  segmenter_note_.clear();
  segmenter_path_->setText(segmenterText(segmenter_));
  onEdited();
  return true;
}

void FusionPanel::showSegmenterWarning(const QString& text) {
  segmenter_note_ = tr("Segmenter: %1").arg(text);
  onEdited();
}

void FusionPanel::chooseSegmenter() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Segmentation Network"), QString(),
                                                    tr("ONNX models (*.onnx)"));
  if (!path.isEmpty()) setSegmenterModel(path);
}

QString FusionPanel::noteText() const { return note_->text(); }

void FusionPanel::setNote(const QString& text) {
  note_->setText(text);
  note_->setVisible(!text.isEmpty());  // no empty row above the fields
}

void FusionPanel::rememberShown() {
  // What the boxes show, rounded to their decimals: a box still showing it
  // stands for the map's exact value (effectiveOptions).
  shown_ = {resolution_->value(), max_range_->value(), p_miss_->value()};
  edited_ = {};
}

FusionOptions FusionPanel::effectiveOptions() const {
  FusionOptions options = session_.fusionOptions();
  // A box the user left as loaded keeps the map's value, even one with more
  // decimals than the box shows (a map fused by `labeloctomap fuse --p-miss
  // 0.495`): re-fusing must not round the settings nobody changed.
  auto edited = [](const QDoubleSpinBox* box, double shown, bool committed) {
    return committed || !qFuzzyCompare(1.0 + box->value(), 1.0 + shown);
  };
  if (edited(resolution_, shown_.resolution, edited_.resolution))
    options.map.resolution = resolution_->value();
  if (edited(max_range_, shown_.max_range, edited_.max_range))
    options.map.max_range = max_range_->value();
  if (edited(p_miss_, shown_.p_miss, edited_.p_miss)) options.map.p_miss = p_miss_->value();
  bool ok = true;
  options.candidates = parseCandidates(candidates_->text(), &ok);
  if (const std::optional<FrameRange> frames = parseFrameRange(frames_->text().toStdString())) {
    options.first_frame = frames->first;
    options.last_frame = frames->end;
  }
  options.segmenter = segmenter_;
  return options;
}

bool FusionPanel::hasPendingChanges() const {
  const FusionOptions& current = session_.fusionOptions();
  const FusionOptions wanted = effectiveOptions();
  return wanted.map.resolution != current.map.resolution ||
         wanted.map.max_range != current.map.max_range || wanted.map.p_miss != current.map.p_miss ||
         wanted.candidates != current.candidates || wanted.segmenter != current.segmenter ||
         wanted.first_frame != current.first_frame || wanted.last_frame != current.last_frame;
}

void FusionPanel::onEdited() {
  bool ok = true;
  const auto candidates = parseCandidates(candidates_->text(), &ok);
  // The command line's checks: candidates are labels of the sequence, and rays
  // are not too long, which bounds the memory a frame needs.
  const std::optional<CandidateProblem> unknown =
      ok && session_.sequence() ? checkCandidates(candidates, session_.sequence()->labels)
                                : std::nullopt;
  const FusionOptions wanted = effectiveOptions();
  const std::optional<RayLengthProblem> too_long =
      checkRayLength(wanted.map.max_range, wanted.map.resolution);
  const bool pending = hasPendingChanges();
  const std::optional<FrameRange> frames = parseFrameRange(frames_->text().toStdString());
  const bool frames_ok = frames.has_value();
  const size_t frame_count = session_.sequence() ? session_.sequence()->frames.size() : 0;
  const bool past_end = frames_ok && session_.sequence() && frames->first >= frame_count;
  refuse_->setEnabled(pending && ok && !unknown && !too_long && frames_ok && !past_end);
  QString note;
  if (!frames_ok)
    note = tr("Frames: A:B fuses frames A to B-1 (B after A); A: to the end, :B the first B.");
  else if (past_end)
    note = frame_count == 1 ? tr("Frames: the sequence has 1 frame (0).")
                            : tr("Frames: the sequence has %1 frames (0 to %2).")
                                  .arg(static_cast<qulonglong>(frame_count))
                                  .arg(static_cast<qulonglong>(frame_count) - 1);
  else if (unknown)
    note = tr("Candidates: %1 is not a label of the sequence (0 to %2).")
               .arg(unknown->label)
               .arg(unknown->label_count - 1);
  else if (!ok)
    note = tr("Candidates: label ids separated by spaces.");
  else if (too_long)
    note = tr("Max range / resolution makes rays %1 voxels long; at most %2: choose a coarser "
              "resolution or a shorter max range.")
               .arg(too_long->voxels, 0, 'f', 0)
               .arg(too_long->limit, 0, 'f', 0);
  else if (candidates && std::find(candidates->begin(), candidates->end(), 0) == candidates->end())
    // As `labeloctomap fuse` notes: renormalised over objects only, every pixel becomes one.
    note = (pending ? tr("Changed: re-fuse to apply. ") : QString()) +
           tr("The candidates leave out 0, the background: background pixels are fused (and "
              "projected) as objects.");
  else
    note = pending ? tr("Changed: re-fuse to apply.") : range_note_;
  // What became of the segmenter (refused, removed, its cache) comes first,
  // whatever else is said.
  QStringList notes;
  for (const QString& part : {segmenter_note_, note})
    if (!part.isEmpty()) notes << part;
  setNote(notes.join(' '));
}

void FusionPanel::showDepthRanges(const FrameStats& totals, double max_range) {
  range_note_.clear();
  extend_range_->hide();
  // As `labeloctomap fuse` warns: when max range took most of the depths, the
  // map holds little of what the camera saw.
  if (mostDepthsBeyondMaxRange(totals, max_range)) {
    suggested_range_ =
        std::min(max_range_->maximum(), std::ceil(totals.farthest_range * 10.0) / 10.0);
    suggested_resolution_ = suggestedResolutionForRange(suggested_range_, resolution_->value());
    // One decimal, as `labeloctomap fuse` prints it (99.8 %, not 99 %).
    const double percent = 100.0 * static_cast<double>(totals.beyond_range_pixels) /
                           static_cast<double>(measuredPixels(totals));
    range_note_ = tr("%1% of the depths lay beyond the max range of %2 m and mapped nothing "
                     "(the farthest lies %3 m from the camera).")
                      .arg(percent, 0, 'f', 1)
                      .arg(max_range, 0, 'f', 2)
                      .arg(totals.farthest_range, 0, 'f', 1);
    if (suggested_range_ > max_range) {
      extend_range_->setText(suggested_resolution_ > resolution_->value() + 1e-9
                                 ? tr("Re-fuse up to %1 m, %2 cm voxels")
                                       .arg(suggested_range_, 0, 'f', 1)
                                       .arg(suggested_resolution_ * 100.0, 0, 'f', 1)
                                 : tr("Re-fuse up to %1 m").arg(suggested_range_, 0, 'f', 1));
      extend_range_->show();
    }
  } else if (totals.valid_pixels == 0 && totals.outside_map_pixels > 0) {
    // As `labeloctomap fuse` refuses: the depths were measured, but the map cannot hold them.
    range_note_ =
        tr("Every measured depth lay outside the map's extent (%1): nothing could be mapped.")
            .arg(
                QString::fromStdString(describeMapExtent(session_.fusionOptions().map.resolution)));
  } else if (totals.valid_pixels == 0 && totals.seconds > 0.0) {
    // As `labeloctomap fuse` refuses: frames were fused and none had a depth.
    range_note_ =
        tr("No frame fused had a valid depth (every depth pixel was 0, no "
           "measurement, or invalid): nothing could be mapped.");
  }
  // As `labeloctomap fuse` warns: the map left those depths out.
  if (totals.valid_pixels > 0 && totals.outside_map_pixels > 0)
    range_note_ += (range_note_.isEmpty() ? QString() : QStringLiteral(" ")) +
                   tr("%1 measured depths lay outside the map's extent (%2) and were left out; "
                      "coarser voxels extend it.")
                       .arg(totals.outside_map_pixels)
                       .arg(QString::fromStdString(
                           describeMapExtent(session_.fusionOptions().map.resolution)));
  onEdited();
}

bool FusionPanel::fuseWithShownSettings() {
  commitPendingEdits();  // a value still being typed is one the panel shows
  onEdited();
  if (!hasPendingChanges()) {
    session_.fuse();
    return true;
  }
  if (!refuse_->isEnabled()) return false;  // the note names the field
  refuse();
  return true;
}

void FusionPanel::refuse() {
  onEdited();
  if (!refuse_->isEnabled()) return;  // a field the note names is not valid
  bool ok = true;
  parseCandidates(candidates_->text(), &ok);
  if (!ok) return;
  session_.setFusionOptions(effectiveOptions());
  rememberShown();  // the new map's
  session_.fuse();
  onEdited();
}

}  // namespace lom::ui
