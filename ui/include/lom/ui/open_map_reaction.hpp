#pragma once
#include <QString>
#include <functional>

#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class StudioSession;

// File > Open Map…: a map fused earlier (.ot) for the open sequence, shown,
// boxed, scored and exported instead of fusing the sequence again.
class OpenMapReaction : public Reaction {
  Q_OBJECT

 public:
  OpenMapReaction(QAction* action, StudioSession& session, QWidget* dialog_parent);
  // Replaces the file dialog (tests): returns the chosen file, or empty.
  void setChooser(std::function<QString(const QString& start_folder)> chooser) {
    chooser_ = std::move(chooser);
  }

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();

  StudioSession& session_;
  QWidget* dialog_parent_;
  std::function<QString(const QString&)> chooser_;
};

}  // namespace lom::ui
