#pragma once
// Annotate > Add Box: for the selected label, either fitted to that label's
// voxels (the same oriented-box fit as the evaluation) or with a default size
// at the last clicked point. The fit runs on the map worker once fusion has
// ended; the box is added only if its label still has no box and the map it
// was fitted to is still the session's (not another sequence's or a reset one).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class StudioSession;

class AddBoxReaction : public Reaction {
  Q_OBJECT

 public:
  // FitLabelVoxels: the selected label's box, fitted to its largest cluster
  // of voxels (to what is fused so far during a fusion), level with the map's
  // up (fitOrientedBox of lom/box_fit.hpp, as `score` fits it). AtPickedPoint: a
  // cube at the clicked point. FitAllLabels: a fitted box for every object
  // label of the map that has none yet, in one undo step, once the fusion
  // running (if any) has finished.
  enum class Mode { FitLabelVoxels, AtPickedPoint, FitAllLabels };
  static constexpr double kDefaultSize = 0.1;  // metres
  // A fit that leaves out more than this share of its label's voxels (in
  // clusters other than the one boxed) says so in the status bar.
  static constexpr double kLeftOutShare = 0.05;

  // How much of a label's voxels a box was fitted to.
  struct FitShare {
    size_t fitted = 0;          // voxels of the cluster boxed (the largest)
    size_t label = 0;           // voxels of the label
    size_t other_clusters = 0;  // clusters left out
  };

  AddBoxReaction(QAction* action, Mode mode, StudioSession& session);
  // The map could not give a label's voxels (leaves standing for more voxels
  // than a fit may expand): said, nothing added.
  void fitFailed(const QString& message);

 signals:
  void failed(const QString& title, const QString& message);
  // Progress worth a status-bar line ("queued until fusion finishes"); an
  // empty message clears it.
  void status(const QString& message);

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();
  // Selects the label's box and says so; false when the label has none.
  bool selectExistingBox(int label);
  // The label of the selected box (-1 for none).
  [[nodiscard]] int selectedBoxLabel() const;
  // The up of the map shown (+z before there is one): new boxes stand along it.
  [[nodiscard]] Eigen::Vector3d mapUp() const;
  // A fit arrives after it was asked for: the value being typed into a box
  // field is committed first, and a box the user has turned to since
  // (`asked_with` is selectedBoxLabel() when asked) or is editing stays selected.
  // `one_step`: the boxes are added in one undo step.
  void addArrived(const std::vector<GroundTruthBox>& boxes, int asked_with, bool one_step);
  // Fitted boxes also say when they leave out more than kLeftOutShare of
  // their label's voxels (`share`, `shares`: one per box).
  void addFitted(const GroundTruthBox& box, bool fitted, const FitShare& share, unsigned generation,
                 int asked_with);
  void fitAllLabels();
  void addAllFitted(const std::vector<GroundTruthBox>& boxes, const std::vector<FitShare>& shares,
                    unsigned generation, int asked_with);

  Mode mode_;
  StudioSession& session_;
};

}  // namespace lom::ui
