#pragma once
// The studio window: creates the controller, views, menus and reactions and
// wires them together. Behaviour lives in those classes, not here.
#include <QMainWindow>
#include <functional>
#include <vector>

#include "lom/ui/box_edit_actions.hpp"
#include "lom/ui/error_reporter.hpp"
#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/timeline_widget.hpp"

class QLabel;
class QSplitter;

namespace lom::ui {

class BoxEditorPanel;
class EvaluationPanel;
class ExportMapReaction;
class BoxesAutosave;
class FrameImagesView;
class FusionPanel;
class FusionStatus;
class MapLegendPanel;
class ObjectsPanel;
class PanelLayout;
class SceneView;
class SequenceController;
class StudioSession;

// The size the window opens at on a screen whose available area (without
// panels and docks) is `available`: 1280x960 when it fits, less when not,
// leaving room for the window's title bar and borders.
[[nodiscard]] QSize initialWindowSize(const QSize& available);

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  [[nodiscard]] StudioSession& session() { return *session_; }
  [[nodiscard]] SequenceController& controller() { return *controller_; }
  [[nodiscard]] MapLegendPanel& mapLegend() { return *map_legend_; }
  [[nodiscard]] FusionPanel& fusionPanel() { return *fusion_panel_; }
  [[nodiscard]] QString fusionStatusText() const;
  [[nodiscard]] BoxEditorPanel& boxEditor() { return *box_editor_; }
  [[nodiscard]] EvaluationPanel& evaluationPanel() { return *evaluation_panel_; }
  [[nodiscard]] ObjectsPanel& objectsPanel() { return *objects_panel_; }
  [[nodiscard]] BoxesAutosave& autosave() { return *autosave_; }
  // Finds one of the window's actions by its text without '&' (tests, scripting).
  [[nodiscard]] QAction* findAction(const QString& text) const;
  [[nodiscard]] FrameImagesView& frameImages() { return *frame_images_; }
  [[nodiscard]] SceneView& sceneView() { return *scene_view_; }
  [[nodiscard]] TimelineWidget& timeline() { return *timeline_; }
  [[nodiscard]] RecentSequences& recentSequences() { return recent_; }
  [[nodiscard]] QString statusText() const;

  // Replaces the message box used for errors (tests, screenshot mode).
  void setErrorReporter(ErrorReporter reporter) { report_error_ = std::move(reporter); }
  // Replaces the message box used for warnings: what was opened is usable,
  // but something in it was left out (frames a conversion skipped, boxes of
  // unknown labels). The screenshot mode prints them and carries on.
  void setWarningReporter(ErrorReporter reporter) { report_warning_ = std::move(reporter); }
  // Replaces the question asked before restoring a recovery file (tests).
  void setRecoveryOffer(std::function<bool(const QString&)> offer);
  // Replaces the question asked before a map fused here and not saved is
  // dropped (confirmDiscardMap; argument: what replaces it; true drops it).
  // Empty: the question is a message box.
  void setMapDiscardQuestion(std::function<bool(const QString&)> ask) {
    map_discard_question_ = std::move(ask);
  }
  // Restores the window's size, position and panels from the last session
  // that remembered them, and saves them when the window closes; the
  // Evaluation panel's IU_3d mode likewise (saved when chosen). Off unless
  // called: screenshots and tests start from the default layout and leave the
  // saved one alone.
  void rememberLayout();
  static constexpr const char* kIouModeKey = "studio/evaluation/iouMode";
  // The View menu's display toggles (frame points, camera frustums, axes,
  // box outlines, opacity by probability), the 3D view picture size and the
  // playback speed are preferences too, kept under this group.
  static constexpr const char* kViewOptionsGroup = "studio/view";
  [[nodiscard]] PanelLayout& panelLayout() { return *panel_layout_; }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  [[nodiscard]] TimelineWidget::StepActions createStepActions();
  void createMenus(const TimelineWidget::StepActions& step_actions);
  void createDocks();
  void createAnnotateMenu();
  // Asks before unsaved boxes, and (with `ask_map`) a map fused here and not
  // saved, are dropped by `replaced_by`; true to go on.
  [[nodiscard]] bool confirmDiscard(const QString& replaced_by, bool ask_map = true);
  // Asks before the map fused here and not saved is dropped by `replaced_by`
  // (another sequence, a map file, Reset Map, closing); true to go on.
  [[nodiscard]] bool confirmDiscardMap(const QString& replaced_by);
  // Asks before closing drops a conversion, a running fusion or queued map
  // work (exports, box fits); true when there is none or the user agrees.
  // During a fusion it may also stop the fusion and keep the map so far
  // (true, the fusion stopped: the map is then asked about as a finished one).
  [[nodiscard]] bool confirmStopWork();
  // Conversion, fusion and queued map jobs running now, one line each.
  [[nodiscard]] QStringList workInProgress() const;
  // An export's queued and written messages in the status bar.
  void showProgressOf(ExportMapReaction* reaction);
  void connectScene();
  void updateTitle();
  // A reaction's message that lasts until the next one; empty clears it.
  void showStatusMessage(const QString& message);
  // Whether `message` fits the status bar beside its permanent widgets.
  [[nodiscard]] bool statusMessageFits(const QString& message) const;
  void onSequenceChanged();
  void renewSettingsNote();
  void onCurrentFrameChanged();
  // View actions that need a sequence, or anything in the scene (a sequence
  // or a map), are enabled only while there is one.
  void updateViewActions();
  // Part of rememberLayout: restores the View options and saves them when changed.
  void rememberViewOptions();

  RecentSequences recent_;
  ErrorReporter report_error_;
  ErrorReporter report_warning_;
  StudioSession* session_;
  SequenceController* controller_;
  MapLegendPanel* map_legend_ = nullptr;
  FusionPanel* fusion_panel_ = nullptr;
  FusionStatus* fusion_status_ = nullptr;
  BoxSteps steps_;
  BoxEditorPanel* box_editor_ = nullptr;
  EvaluationPanel* evaluation_panel_ = nullptr;
  ObjectsPanel* objects_panel_ = nullptr;
  PanelLayout* panel_layout_ = nullptr;
  bool remember_layout_ = false;
  // What rememberLayout restores and keeps: each action under its key.
  std::vector<std::pair<QAction*, QString>> remembered_toggles_;
  std::vector<QAction*> picture_sizes_;  // 1x to 4x
  bool closing_ = false;  // closeEvent is asking its questions
  QString settings_note_;  // the carried-over settings note shown when the sequence opened
  BoxesAutosave* autosave_ = nullptr;
  FrameImagesView* frame_images_;
  SceneView* scene_view_;
  QSplitter* views_ = nullptr;  // the frame images beside the 3D view
  TimelineWidget* timeline_;
  QLabel* status_label_;
  std::function<bool(const QString&)> map_discard_question_;
  ExportMapReaction* map_saver_ = nullptr;  // File ▸ Save Map…
  std::vector<QAction*> sequence_view_actions_;  // see updateViewActions
  std::vector<QAction*> scene_view_actions_;
};

}  // namespace lom::ui
