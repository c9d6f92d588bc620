#pragma once
// Help > Keyboard Shortcuts: every action and button of the window that has a
// shortcut.
#include <memory>

#include "lom/ui/reaction.hpp"

class QDialog;
class QWidget;

namespace lom::ui {

class ShortcutsHelpReaction : public Reaction {
  Q_OBJECT

 public:
  ShortcutsHelpReaction(QAction* action, QWidget* window);
  // The rows the dialog shows: "shortcut\taction text".
  [[nodiscard]] QStringList rows() const;
  // The dialog (not shown): a table of the rows, wide enough for both columns
  // within the screen.
  [[nodiscard]] std::unique_ptr<QDialog> createDialog() const;

 protected:
  void onTriggered() override;

 private:
  QWidget* window_;
};

}  // namespace lom::ui
