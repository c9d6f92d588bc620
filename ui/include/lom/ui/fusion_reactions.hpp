#pragma once
// Fusion > Fuse / Pause / Cancel / Reset Map.
#include <functional>

#include "lom/ui/reaction.hpp"

namespace lom::ui {

class StudioSession;

class FusionReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Kind { Fuse, Pause, Cancel, Reset };
  // `fuse`, when given, replaces session.fuse() for Kind::Fuse (the window
  // fuses with the settings its Fusion panel shows).
  FusionReaction(QAction* action, Kind kind, StudioSession& session,
                 std::function<void()> fuse = {});
  // The status bar's line from Cancel until the fusion has stopped.
  [[nodiscard]] static QString stoppingNote();

 protected:
  void onTriggered() override;

 private:
  void updateState();

  Kind kind_;
  StudioSession& session_;
  std::function<void()> fuse_;
};

}  // namespace lom::ui
