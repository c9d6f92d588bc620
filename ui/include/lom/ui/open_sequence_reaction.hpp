#pragma once
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class RecentSequences;
class SequenceController;

// File > Open Sequence… (picks a sequence.json) and File > Open Folder…
class OpenSequenceReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Pick { SequenceJson, Folder };

  OpenSequenceReaction(QAction* action, Pick pick, SequenceController& controller,
                       const RecentSequences& recent, QWidget* dialog_parent);

 protected:
  void onTriggered() override;

 private:
  [[nodiscard]] QString startFolder() const;

  Pick pick_;
  SequenceController& controller_;
  const RecentSequences& recent_;
  QWidget* dialog_parent_;
};

}  // namespace lom::ui
