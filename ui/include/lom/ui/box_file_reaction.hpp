#pragma once
// File > Save Boxes / Save Boxes As… / Open Boxes… / Import YAML Boxes….
#include "lom/ui/error_reporter.hpp"
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class StudioSession;

class BoxFileReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Kind { Save, SaveAs, Open, ImportYaml };
  BoxFileReaction(QAction* action, Kind kind, StudioSession& session, QWidget* parent,
                  const ErrorReporter& report);

 protected:
  void onTriggered() override;

 private:
  Kind kind_;
  StudioSession& session_;
  QWidget* parent_;
  const ErrorReporter& report_;
};

}  // namespace lom::ui
