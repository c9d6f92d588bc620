#pragma once
// Keyboard-first box editing, as in point-cloud labelling tools:
//   W/S move along the box's x, A/D along its y, E/Q up/down its z,
//   Z/X turn about its z, I/K grow/shrink x, O/L grow/shrink y,
//   Shift+I/Shift+K grow/shrink z, Tab/Shift+Tab next/previous box, Delete.
// Step sizes are adjustable and remembered in the settings.
#include <QObject>
#include <QString>
#include <vector>

#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class StudioSession;

struct BoxSteps {
  double move = 0.01;    // metres
  double turn = 5.0;     // degrees
  double resize = 0.01;  // metres

  static BoxSteps load();  // from QSettings "studio/boxSteps/*"
  void save() const;
};

class BoxEditReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Edit {
    MoveForward, MoveBack, MoveLeft, MoveRight, MoveUp, MoveDown,
    TurnLeft, TurnRight,
    GrowX, ShrinkX, GrowY, ShrinkY, GrowZ, ShrinkZ,
    Next, Previous, Delete,
  };
  BoxEditReaction(QAction* action, Edit edit, StudioSession& session, const BoxSteps& steps);

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();

  Edit edit_;
  StudioSession& session_;
  const BoxSteps& steps_;
};

// Creates the editing actions with their shortcuts. All but Tab/Shift+Tab act
// window-wide (text fields keep their letter keys); Tab/Shift+Tab act while
// the 3D view has the focus, so Tab still moves between fields elsewhere.
std::vector<QAction*> createBoxEditActions(QWidget& window, QWidget& scene, StudioSession& session,
                                           const BoxSteps& steps);

}  // namespace lom::ui
