#include "lom/ui/add_box_reaction.hpp"

#include <QAction>
#include <QMetaObject>
#include <QPointer>
#include <QStringList>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "lom/box_fit.hpp"
#include "lom/fusion.hpp"
#include "lom/level_plane.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/pending_edits.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

namespace {

// From the worker's thread: the fit failed; said in the GUI thread.
void sayFitFailed(const QPointer<AddBoxReaction>& self, MapWorker* worker,
                  const std::exception& error) {
  const QString message = QString::fromStdString(error.what());
  QMetaObject::invokeMethod(
      worker,
      [self, message] {
        if (self) self->fitFailed(message);
      },
      Qt::QueuedConnection);
}

// "1 box", "3 boxes".
QString count(size_t n, const QString& one, const QString& many) {
  return QString::number(n) + " " + (n == 1 ? one : many);
}

// The box of a label's voxels: fitted to their largest cluster (none without
// voxels), level with the scene, as the evaluation fits it.
std::optional<OrientedBox> fittedBox(const std::vector<VoxelKey>& voxels, double resolution,
                                     const SceneLevel& level, AddBoxReaction::FitShare& share) {
  std::vector<std::vector<VoxelKey>> clusters = voxelClusters(voxels, 2.0);
  share = {};
  if (clusters.empty()) return std::nullopt;
  share.fitted = clusters.front().size();
  share.label = voxels.size();
  share.other_clusters = clusters.size() - 1;
  return fitOrientedBox(clusters.front(), resolution, level.up, level.plane);
}

// The cameras' mean up of the sequence's poses: the evaluation's stand-in for
// the up of a map that records no camera (sceneLevelOf), here too so that the
// studio fits the box the score judges.
std::optional<Eigen::Vector3d> sequenceUp(const std::shared_ptr<const Sequence>& sequence) {
  return sequence ? camerasUpOf(*sequence) : std::nullopt;
}

// "fitted to 120 of 200 voxels of mug; 80 more in 2 other clusters left out",
// or empty when the fit left out at most kLeftOutShare of the label's voxels.
QString leftOutText(const QString& name, const AddBoxReaction::FitShare& share) {
  const size_t left_out = share.label - share.fitted;
  if (static_cast<double>(left_out) <=
      AddBoxReaction::kLeftOutShare * static_cast<double>(share.label))
    return {};
  return AddBoxReaction::tr("fitted to %1 of %2 voxels of %3; %4 more in %5 left out")
      .arg(share.fitted)
      .arg(share.label)
      .arg(name)
      .arg(left_out)
      .arg(share.other_clusters == 1
               ? AddBoxReaction::tr("another cluster")
               : AddBoxReaction::tr("%1 other clusters").arg(share.other_clusters));
}

}  // namespace

AddBoxReaction::AddBoxReaction(QAction* action, Mode mode, StudioSession& session)
    : Reaction(action), mode_(mode), session_(session) {
  connect(&session_, &StudioSession::selectedLabelChanged, this, &AddBoxReaction::updateEnabled);
  connect(&session_, &StudioSession::pickedPointChanged, this, &AddBoxReaction::updateEnabled);
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &AddBoxReaction::updateEnabled);
  updateEnabled();
}

void AddBoxReaction::updateEnabled() {
  if (mode_ == Mode::FitAllLabels) {
    // A sequence of the background label alone has no object to box.
    action()->setEnabled(session_.sequence() && session_.sequence()->labels.size() > 1);
    return;
  }
  const bool label = session_.sequence() && session_.selectedLabel() > 0;
  action()->setEnabled(label && (mode_ == Mode::FitLabelVoxels || session_.pickedPoint()));
}

bool AddBoxReaction::selectExistingBox(int label) {
  // One box per object: a label that has one gets it selected instead.
  AnnotationsModel& model = session_.annotations();
  const int i = model.indexOfLabel(label);
  if (i < 0) return false;
  model.select(i);
  emit failed(tr("Label already boxed"),
              tr("%1 has a box already (selected now): edit or delete it.")
                  .arg(QString::fromStdString(model.box(i).name)));
  return true;
}

void AddBoxReaction::onTriggered() {
  if (mode_ == Mode::FitAllLabels) return fitAllLabels();
  const auto sequence = session_.sequence();
  const int label = session_.selectedLabel();
  if (!sequence || !sequence->labels.contains(label)) return;
  if (selectExistingBox(label)) return;
  GroundTruthBox box;
  box.label = label;
  box.name = sequence->labels.at(label).name;
  if (mode_ == Mode::AtPickedPoint) {
    if (!session_.pickedPoint()) return;
    box.box.center = *session_.pickedPoint();
    box.box.size = Eigen::Vector3d::Constant(kDefaultSize);
    box.box.rotation = levelRotation(mapUp());
    session_.annotations().addBox(box);
    return;
  }
  QPointer<AddBoxReaction> self(this);
  MapWorker* worker = &session_.worker();  // outlives its thread's jobs
  const unsigned generation = session_.mapGeneration();
  const int asked_with = selectedBoxLabel();
  const QString name = QString::fromStdString(box.name);
  if (worker->isFusing())
    emit status(tr("Box for %1: fitted to the voxels fused so far; if there are none yet, when "
                   "fusion finishes.")
                    .arg(name));
  worker->withCurrentMap(
      [self, worker, box, generation, asked_with, sequence_up = sequenceUp(sequence)](
          const LabelMap* map, bool final) mutable {
        std::optional<OrientedBox> fitted_box;
        FitShare share;
        try {
          if (map) {
            const std::vector<VoxelKey> voxels = map->voxelsOfLabel(box.label);
            if (!voxels.empty())
              fitted_box = fittedBox(voxels, map->parameters().resolution,
                                     sceneLevelOf(*map, sequence_up), share);
          }
        } catch (const std::exception& error) {  // leaves standing for too many voxels
          sayFitFailed(self, worker, error);
          return true;
        }
        if (!fitted_box && !final) return false;  // fusion may still bring some
        if (fitted_box) box.box = *fitted_box;
        const bool fitted = fitted_box.has_value();
        QMetaObject::invokeMethod(
            worker,
            [self, box, fitted, share, generation, asked_with] {
              if (self) self->addFitted(box, fitted, share, generation, asked_with);
            },
            Qt::QueuedConnection);
        return true;
      },
      tr("box fit for %1").arg(name));
}

Eigen::Vector3d AddBoxReaction::mapUp() const {
  // The map's up (its cameras' mean up, levelled by its largest plane), as
  // Look from Above and Colour by Height use it; +z before there is one.
  const auto snapshot = session_.worker().snapshot();
  if (snapshot && snapshot->up && snapshot->up->allFinite() && snapshot->up->norm() > 1e-9)
    return *snapshot->up;
  return Eigen::Vector3d::UnitZ();
}

int AddBoxReaction::selectedBoxLabel() const {
  const AnnotationsModel& model = session_.annotations();
  return model.selected() >= 0 ? model.box(model.selected()).label : -1;
}

void AddBoxReaction::addArrived(const std::vector<GroundTruthBox>& boxes, int asked_with,
                                bool one_step) {
  // Adding rebuilds the Boxes panel, whose fields then show the boxes' values
  // over what is being typed.
  const bool editing = commitPendingEdits();
  AnnotationsModel& model = session_.annotations();
  const int kept = selectedBoxLabel();
  if (!one_step) {
    for (const GroundTruthBox& box : boxes) model.addBox(box);
  } else {
    // One undo step for the lot.
    model.undoStack().beginMacro(
        tr("Add %1 from label voxels").arg(count(boxes.size(), tr("box"), tr("boxes"))));
    for (const GroundTruthBox& box : boxes) model.addBox(box);
    model.undoStack().endMacro();
  }
  if (kept >= 0 && (editing || kept != asked_with)) model.select(model.indexOfLabel(kept));
}

void AddBoxReaction::addFitted(const GroundTruthBox& box, bool fitted, const FitShare& share,
                               unsigned generation, int asked_with) {
  const QString name = QString::fromStdString(box.name);
  emit status(QString());
  if (generation != session_.mapGeneration()) {
    emit status(tr("Box for %1 dropped: it was fitted to a map that has since been replaced "
                   "(another sequence, a new fusion or Reset Map). Press B again.")
                    .arg(name));
    return;
  }
  if (!fitted) {
    // Fused already: fusing again would not help (the frames gave the label
    // no evidence, e.g. a recording imported without label images).
    const auto snapshot = session_.worker().snapshot();
    const auto sequence = session_.sequence();
    const bool fused = snapshot && sequence && !session_.worker().isFusing() &&
                       snapshot->frames_fused >= sequence->frames.size();
    emit failed(tr("No voxels to fit"),
                fused ? tr("The fused map has no voxels of %1: its frames gave that label no "
                           "evidence. Click a point in the 3D view and add a box there (Add Box "
                           "at Clicked Point).")
                            .arg(name)
                      : tr("The map has no voxels of %1. Fuse the sequence first, or click a "
                           "point in the 3D view and add a box there.")
                            .arg(name));
    return;
  }
  // The label may have got a box while the fit waited (B pressed twice, or a
  // box added by hand).
  if (selectExistingBox(box.label)) return;
  addArrived({box}, asked_with, false);
  // An object split into clusters (seen in parts, or two objects of one
  // label) gets a box around one part only: said, so that it is checked.
  const QString left_out = leftOutText(name, share);
  if (!left_out.isEmpty()) emit status(tr("Box %1.").arg(left_out));
}

void AddBoxReaction::fitFailed(const QString& message) {
  emit status(QString());
  emit failed(tr("Cannot fit a box"), message);
}

void AddBoxReaction::fitAllLabels() {
  if (!session_.sequence()) return;
  QPointer<AddBoxReaction> self(this);
  MapWorker* worker = &session_.worker();  // outlives its thread's jobs
  const unsigned generation = session_.mapGeneration();
  const LabelSet labels = session_.sequence()->labels;
  const int asked_with = selectedBoxLabel();
  if (worker->isFusing()) emit status(tr("Boxes for every label: when fusion finishes."));
  worker->withCurrentMap(
      [self, worker, labels, generation, asked_with, sequence_up = sequenceUp(session_.sequence())](
          const LabelMap* map, bool final) {
        // Labels keep appearing while frames are fused: fit once all are in.
        if (!final) return false;
        std::vector<GroundTruthBox> boxes;
        std::vector<FitShare> shares;
        try {
          if (map) {
            std::set<int> objects;  // the background's voxels are never boxed: not expanded
            for (int label = 1; label < map->numLabels(); ++label)
              if (labels.contains(label)) objects.insert(label);
            const std::map<int, std::vector<VoxelKey>> by_label = map->voxelsByLabel(objects);
            // Levelled once for every box: it gathers the whole map.
            const SceneLevel level =
                by_label.empty() ? SceneLevel{} : sceneLevelOf(*map, sequence_up);
            for (const auto& [label, keys] : by_label) {
              GroundTruthBox box;
              box.label = label;
              box.name = labels.at(label).name;
              FitShare share;
              // keys: never empty here
              box.box = *fittedBox(keys, map->parameters().resolution, level, share);
              boxes.push_back(std::move(box));
              shares.push_back(share);
            }
          }
        } catch (const std::exception& error) {  // leaves standing for too many voxels
          sayFitFailed(self, worker, error);
          return true;
        }
        QMetaObject::invokeMethod(
            worker,
            [self, boxes, shares, generation, asked_with] {
              if (self) self->addAllFitted(boxes, shares, generation, asked_with);
            },
            Qt::QueuedConnection);
        return true;
      },
      tr("box fits for every label"));
}

void AddBoxReaction::addAllFitted(const std::vector<GroundTruthBox>& boxes,
                                  const std::vector<FitShare>& shares, unsigned generation,
                                  int asked_with) {
  emit status(QString());
  if (generation != session_.mapGeneration()) {
    emit status(
        tr("Boxes for every label dropped: they were fitted to a map that has since been "
           "replaced (another sequence, a new fusion or Reset Map). Ask again."));
    return;
  }
  AnnotationsModel& model = session_.annotations();
  std::vector<GroundTruthBox> added;
  QStringList left_out;  // of the boxes added
  size_t already = 0;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const GroundTruthBox& box = boxes[i];
    if (model.indexOfLabel(box.label) >= 0) {
      ++already;
      continue;
    }
    added.push_back(box);
    if (i < shares.size()) {
      const QString text = leftOutText(QString::fromStdString(box.name), shares[i]);
      if (!text.isEmpty()) left_out << text;
    }
  }
  if (added.empty()) {
    emit failed(tr("No boxes to add"), !boxes.empty()
                                           ? tr("Every object label of the map has a box already.")
                                       : session_.worker().snapshot()->frames_fused == 0
                                           ? tr("The map is empty: fuse the sequence first.")
                                           : tr("The map has no voxels of any object label."));
    return;
  }
  addArrived(added, asked_with, true);
  QString message =
      tr("Added %1 fitted to label voxels").arg(count(added.size(), tr("box"), tr("boxes")));
  if (already)
    message +=
        tr("; %1 kept").arg(count(already, tr("label boxed already"), tr("labels boxed already")));
  // Objects split into clusters got a box around one part only: said, so
  // that those boxes are checked.
  if (!left_out.isEmpty()) message += tr("; boxes %1").arg(left_out.join(tr("; ")));
  emit status(message + ".");
}

}  // namespace lom::ui
