#pragma once
// Export ▸ Mesh / Point Cloud / Octree: writes the fused map like
// `labeloctomap export`, on the map worker so the window stays responsive.
#include "lom/export.hpp"
#include "lom/ui/error_reporter.hpp"
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class StudioSession;

class ExportMapReaction : public Reaction {
  Q_OBJECT

 public:
  ExportMapReaction(QAction* action, ExportOptions options, StudioSession& session,
                    QWidget* parent, const ErrorReporter& report);
  // Exports to `path` without asking; the result arrives through finished().
  // While fusion runs the export waits for it to end, which queued() says.
  // False when refused at once (a file of the sequence): then no finished().
  bool exportTo(const QString& path);
  // exportTo, waiting for the result with the window's events still running;
  // true when written.
  [[nodiscard]] bool exportToAndWait(const QString& path);
  // The same after asking where (the file dialog of the menu item).
  [[nodiscard]] bool exportAndWait();
  // When `only_shown` is checked, exports leave out the labels hidden in the
  // 3D view (Export > Only Labels Shown).
  void setOnlyShownAction(const QAction* only_shown) { only_shown_ = only_shown; }

 signals:
  void queued(const QString& message);
  void finished(const QString& message, bool ok);

 protected:
  void onTriggered() override;

 private:
  [[nodiscard]] QString askPath() const;

  ExportOptions options_;
  const QAction* only_shown_ = nullptr;
  StudioSession& session_;
  QWidget* parent_;
  const ErrorReporter& report_;
};

}  // namespace lom::ui
