#pragma once
// View > Show Score Breakdown: colours the selected box's
// label's voxels by how IU_3d counts them against that box (inside, partly,
// outside) and says how many there are of each; with no box selected, every
// box's. Follows the box while it is edited, another box being selected and
// the map growing.
#include <QString>
#include <vector>

#include "lom/score_breakdown.hpp"
#include "lom/ui/reaction.hpp"

namespace lom::ui {

// One line for the status bar: the counts, their colours and the IU_3d they make.
[[nodiscard]] QString describeScoreBreakdown(const ScoreBreakdown& breakdown, const QString& name);
// The same for every box at once (no box selected): the counts summed.
[[nodiscard]] QString describeScoreBreakdowns(const std::vector<ScoreBreakdown>& breakdowns);

class ScoreBreakdownReaction : public SceneToggleReaction {
  Q_OBJECT

 public:
  ScoreBreakdownReaction(QAction* action, StudioSession& session, SceneView& scene);

 protected:
  void onTriggered() override;

 private:
  void refresh();
  void showBreakdowns();  // refresh's work once the breakdown is on
};

}  // namespace lom::ui
