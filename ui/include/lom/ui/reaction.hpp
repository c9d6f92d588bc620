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

}  // namespace lom::ui
