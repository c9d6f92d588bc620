#include "lom/ui/reaction.hpp"

#include <QAction>

namespace lom::ui {

Reaction::Reaction(QAction* action) : QObject(action), action_(action) {
  connect(action, &QAction::triggered, this, [this] { onTriggered(); });
}

}  // namespace lom::ui
