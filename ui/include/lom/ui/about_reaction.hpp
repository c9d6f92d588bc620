#pragma once
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

// The studio's version string ("0.1.0").
[[nodiscard]] QString studioVersion();

// Help > About LabelOctoMap Studio.
class AboutReaction : public Reaction {
  Q_OBJECT

 public:
  AboutReaction(QAction* action, QWidget* dialog_parent);

 protected:
  void onTriggered() override;

 private:
  QWidget* dialog_parent_;
};

}  // namespace lom::ui
