#pragma once
// A menu or toolbar action's behaviour lives in a small reaction object owned
// by its QAction, so the main window only wires actions to reactions.
#include <QObject>

class QAction;

namespace lom::ui {

class Reaction : public QObject {
  Q_OBJECT

 public:
  explicit Reaction(QAction* action);
  [[nodiscard]] QAction* action() const { return action_; }

 protected:
  virtual void onTriggered() = 0;

 private:
  QAction* action_;
};

class SceneView;
class StudioSession;

// A View menu toggle that draws on the 3D view and says in the status bar
// what it shows (the score breakdown, measuring).
class SceneToggleReaction : public Reaction {
  Q_OBJECT

 public:
  SceneToggleReaction(QAction* action, StudioSession& session, SceneView& scene);

 signals:
  // What the toggle shows now, or what to do next; empty when it is switched off.
  void status(const QString& message);

 protected:
  StudioSession& session_;
  SceneView& scene_;
};

}  // namespace lom::ui
