#pragma once
// File > Save Boxes / Save Boxes As… / Open Boxes… / Import YAML Boxes….
// A boxes file that could not be read is never overwritten unasked: saving to
// it asks first, naming the file and why it could not be read, and offers to
// save under another name instead.
#include <QString>

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
  // Saves the boxes to `path` as Save Boxes does once the file is known: an
  // unreadable boxes file is only replaced after the user confirms (or they
  // choose another name). Errors go to the reporter.
  void saveTo(QString path);

 protected:
  void onTriggered() override;

 private:
  // Confirms saving to `path`; may replace it by another name the user picks.
  // False cancels the save.
  bool confirmTarget(QString& path);
  // Reports and returns true when `path` names a file of the open sequence.
  bool refuseSequenceFile(const QString& path);

  Kind kind_;
  StudioSession& session_;
  QWidget* parent_;
  const ErrorReporter& report_;
};

}  // namespace lom::ui
