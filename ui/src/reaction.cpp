#include "lom/ui/reaction.hpp"

#include <QAction>

namespace lom::ui {

Reaction::Reaction(QAction* action) : QObject(action), action_(action) {
  connect(action, &QAction::triggered, this, [this] { onTriggered(); });
}

SceneToggleReaction::SceneToggleReaction(QAction* action, StudioSession& session, SceneView& scene)
    : Reaction(action), session_(session), scene_(scene) {
  action->setCheckable(true);
}

}  // namespace lom::ui
