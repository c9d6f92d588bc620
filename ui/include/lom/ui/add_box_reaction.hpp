#pragma once
// Annotate > Add Box: for the selected label, either fitted to that label's
// voxels (the same oriented-box fit as the evaluation) or with a default size
// at the last clicked point.
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class StudioSession;

class AddBoxReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Mode { FitLabelVoxels, AtPickedPoint };
  static constexpr double kDefaultSize = 0.1;  // metres

  AddBoxReaction(QAction* action, Mode mode, StudioSession& session);

 signals:
  void failed(const QString& title, const QString& message);

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();

  Mode mode_;
  StudioSession& session_;
};

}  // namespace lom::ui
