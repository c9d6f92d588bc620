#pragma once
// The studio window: creates the controller, views, menus and reactions and
// wires them together. Behaviour lives in those classes, not here.
#include <QMainWindow>

#include "lom/ui/error_reporter.hpp"
#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/timeline_widget.hpp"

class QLabel;

namespace lom::ui {

class FrameImagesView;
class SceneView;
class SequenceController;

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  [[nodiscard]] SequenceController& controller() { return *controller_; }
  [[nodiscard]] FrameImagesView& frameImages() { return *frame_images_; }
  [[nodiscard]] SceneView& sceneView() { return *scene_view_; }
  [[nodiscard]] TimelineWidget& timeline() { return *timeline_; }
  [[nodiscard]] RecentSequences& recentSequences() { return recent_; }
  [[nodiscard]] QString statusText() const;

  // Replaces the message box used for errors (tests, screenshot mode).
  void setErrorReporter(ErrorReporter reporter) { report_error_ = std::move(reporter); }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  [[nodiscard]] TimelineWidget::StepActions createStepActions();
  void createMenus(const TimelineWidget::StepActions& step_actions);
  void onSequenceChanged();
  void onCurrentFrameChanged();

  RecentSequences recent_;
  ErrorReporter report_error_;
  SequenceController* controller_;
  FrameImagesView* frame_images_;
  SceneView* scene_view_;
  TimelineWidget* timeline_;
  QLabel* status_label_;
};

}  // namespace lom::ui
