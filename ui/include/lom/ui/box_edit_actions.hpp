#pragma once
// Keyboard-first box editing, as in point-cloud labelling tools:
//   W/S move along the box's x, A/D along its y, E/Q up/down its z,
//   Z/X turn about its z, I/K grow/shrink x, O/L grow/shrink y,
//   Shift+I/Shift+K grow/shrink z, Tab/Shift+Tab next/previous box, Delete,
//   T tighten the box onto the map's object voxels inside it.
// Step sizes are adjustable and remembered in the settings.
#include <QObject>
#include <QString>
#include <functional>
#include <optional>
#include <vector>

#include "lom/geometry.hpp"
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class StudioSession;

struct BoxSteps {
  double move = 0.01;    // metres
  double turn = 5.0;     // degrees
  double resize = 0.01;  // metres

  // The ranges the Key steps fields offer.
  static constexpr double kMinLength = 0.001, kMaxLength = 1.0;  // move, resize
  static constexpr double kMinTurn = 0.1, kMaxTurn = 90.0;
  // From QSettings "studio/boxSteps/*": a value out of its range (a settings
  // file edited by hand) is brought into it, one that is no number is the
  // default, so that the keys step what the fields show.
  static BoxSteps load();
  void save() const;
};

class BoxEditReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Edit {
    MoveForward,
    MoveBack,
    MoveLeft,
    MoveRight,
    MoveUp,
    MoveDown,
    TurnLeft,
    TurnRight,
    GrowX,
    ShrinkX,
    GrowY,
    ShrinkY,
    GrowZ,
    ShrinkZ,
    Next,
    Previous,
    Delete,
    Tighten,
  };
  // `report` gets a sentence for the status bar when an edit cannot be made.
  // `box_after` names the box a deleted box's row is followed by in the
  // focused view when that view lists the boxes in an order of its own (-1:
  // file order).
  BoxEditReaction(QAction* action, Edit edit, StudioSession& session, const BoxSteps& steps,
                  std::function<void(const QString&)> report,
                  std::function<int(int)> box_after = {});

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();
  // Tighten: the selected box shrunk onto the occupied voxels of any object
  // label (not the background) whose centres it holds (lom::tightenBox),
  // keeping its rotation.
  [[nodiscard]] std::optional<OrientedBox> tightened(const OrientedBox& box) const;

  Edit edit_;
  StudioSession& session_;
  const BoxSteps& steps_;
  std::function<void(const QString&)> report_;
  std::function<int(int)> box_after_;
};

// Creates the editing actions with their shortcuts. All but Tab/Shift+Tab act
// window-wide (text fields keep their letter keys); Tab/Shift+Tab act while
// the 3D view has the focus, so Tab still moves between fields elsewhere.
std::vector<QAction*> createBoxEditActions(QWidget& window, QWidget& scene, StudioSession& session,
                                           const BoxSteps& steps,
                                           const std::function<void(const QString&)>& report,
                                           const std::function<int(int)>& box_after = {});

// Tab and Shift+Tab select boxes in the 3D view, so Ctrl+Tab and
// Ctrl+Shift+Tab take the keyboard focus out of it, to the next or previous
// field of the window (as Qt's text editors do with Tab).
std::vector<QAction*> createLeaveViewActions(QWidget& window, QWidget& scene);

}  // namespace lom::ui
