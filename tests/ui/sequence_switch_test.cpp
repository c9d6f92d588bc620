// Opening one sequence after another: nothing of the first one's view, map
// or files is taken for the second's.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QStatusBar>
#include <QTest>
#include <QTimer>
#include <QUrl>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_drop_handler.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;
using fixture::qPath;

class SequenceSwitchTest : public fixture::DemoWindowTest {
 protected:
  lom::test::TinySequence writeTiny() {
    return lom::test::writeTinySequence(temp_.path() / "tiny_shelf");
  }
  // The files the file dialogs opened by `action` propose (left unanswered).
  std::string proposedBy(const char* action) {
    QAction* found = window_.findAction(action);
    EXPECT_NE(found, nullptr) << action;
    if (found == nullptr) return {};
    test::DialogAnswerer answer("Cancel");
    found->trigger();
    return answer.proposed_files.join('|').toStdString();
  }
  // The folder the Export report… dialog proposes (left unanswered).
  std::string proposedReportFolder() {
    QString proposed;
    QTimer answer;
    answer.setInterval(20);
    QObject::connect(&answer, &QTimer::timeout, [&] {
      for (QWidget* widget : QApplication::topLevelWidgets())
        if (auto* dialog = qobject_cast<QFileDialog*>(widget); dialog && dialog->isVisible()) {
          const QStringList selected = dialog->selectedFiles();
          proposed = selected.isEmpty() ? QString() : selected.front();
          QMetaObject::invokeMethod(dialog, "reject", Qt::QueuedConnection);
        }
    });
    answer.start();
    auto& button = const_cast<QPushButton&>(window_.evaluationPanel().exportButton());
    emit button.clicked();  // whether or not there are scores to export yet
    return proposed.toStdString();
  }
  // The box of the open sequence's cameras, as VTK bounds.
  void cameraBounds(double bounds[6]) {
    const Sequence& sequence = window_.controller().sequence();
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis] = std::numeric_limits<double>::infinity();
      bounds[2 * axis + 1] = -std::numeric_limits<double>::infinity();
    }
    for (const FrameRecord& frame : sequence.frames)
      for (int axis = 0; axis < 3; ++axis) {
        const double x = frame.T_world_camera.translation()[axis];
        bounds[2 * axis] = std::min(bounds[2 * axis], x);
        bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], x);
      }
  }
};

// The first sequence's map stays until the map worker has dropped it, after
// the next sequence's first frame is shown: that frame's framing (Reset
// Camera's) is of the next sequence alone, not of both scenes.
TEST_F(SequenceSwitchTest, TheNextSequenceIsFramedWithoutThePreviousMap) {
  openAndFuse();
  SceneView& scene = window_.sceneView();
  ASSERT_GT(scene.voxelCount(), 0u);
  // Another scene, 20 m from the first one's map.
  const lom::test::TinySequence tiny = writeTiny();
  Sequence far = loadSequence(tiny.folder);
  for (FrameRecord& frame : far.frames)
    frame.T_world_camera.pretranslate(Eigen::Vector3d(20.0, 0.0, 0.0));
  saveSequence(far, tiny.folder);

  window_.session().setAutoFuse(false);
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny.folder)));
  settle();  // the map's reset arrives from the worker
  EXPECT_EQ(scene.voxelCount(), 0u) << "the previous map is gone";
  double cameras[6];
  cameraBounds(cameras);
  const double framed = scene.boxExtentInView(cameras);
  // As Reset Camera frames the new sequence by itself.
  scene.resetCamera();
  const double alone = scene.boxExtentInView(cameras);
  ASSERT_GT(alone, 0.05);
  // Framed with the old map too, the new scene is a speck off to one side.
  EXPECT_GT(framed, 0.8 * alone);
  EXPECT_LT(framed, 1.25 * alone);
}

// Settings of one sequence fuse the next one too (sequences are compared at
// one setting), and the status bar says so when they are not the start-up ones.
TEST_F(SequenceSwitchTest, SettingsCarriedOverToTheNextSequenceAreNamed) {
  window_.session().setAutoFuse(false);
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_EQ(window_.statusBar()->currentMessage(), QString()) << "the start-up settings";
  FusionOptions options = window_.session().fusionOptions();
  options.map.resolution = 0.04;
  options.map.max_range = 10.0;
  window_.session().setFusionOptions(options);

  const lom::test::TinySequence tiny = writeTiny();
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny.folder)));
  EXPECT_DOUBLE_EQ(window_.session().fusionOptions().map.resolution, 0.04) << "carried over";
  const QString note = window_.statusBar()->currentMessage();
  EXPECT_TRUE(note.contains("4.0 cm voxels") && note.contains("up to 10.0 m") &&
              note.contains("Fusion panel"))
      << note.toStdString();

  // Back at the start-up settings, nothing is said.
  window_.session().setFusionOptions(FusionOptions{});
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_EQ(window_.statusBar()->currentMessage(), QString());
}

// A value typed in the Fusion panel but not applied is the user's setting for
// what is fused next: the next sequence is fused with it and the note says so;
// a re-fusion with other values renews the note.
TEST_F(SequenceSwitchTest, UnappliedFusionSettingsFuseTheNextSequence) {
  StudioSession& session = window_.session();
  session.setAutoFuse(false);  // no map: nothing to ask about before the switch
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  FusionPanel& panel = window_.fusionPanel();
  panel.resolutionBox().setValue(0.02);  // typed, not applied
  ASSERT_TRUE(panel.hasPendingChanges());

  const auto fused = [&] {
    return QTest::qWaitFor(
        [&] {
          const auto snapshot = session.worker().snapshot();
          return !session.worker().isFusing() && snapshot && snapshot->frames_fused > 0;
        },
        fixture::kTimeoutMs);
  };
  session.setAutoFuse(true);
  const lom::test::TinySequence tiny = writeTiny();
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny.folder)));
  ASSERT_TRUE(fused());
  EXPECT_DOUBLE_EQ(session.fusionOptions().map.resolution, 0.02);
  EXPECT_DOUBLE_EQ(session.worker().snapshot()->resolution, 0.02) << "fused with it";
  EXPECT_NEAR(panel.resolutionBox().value(), 0.02, 1e-9);
  EXPECT_FALSE(panel.hasPendingChanges());
  QString note = window_.statusBar()->currentMessage();
  EXPECT_TRUE(note.contains("2.0 cm voxels")) << note.toStdString();

  // Re-fused at 4 cm: the note names the settings now in use.
  panel.resolutionBox().setValue(0.04);
  panel.refuseButton().click();
  ASSERT_TRUE(fused());
  EXPECT_DOUBLE_EQ(session.worker().snapshot()->resolution, 0.04);
  note = window_.statusBar()->currentMessage();
  EXPECT_TRUE(note.contains("4.0 cm voxels")) << note.toStdString();
  EXPECT_FALSE(note.contains("2.0 cm")) << note.toStdString();
}

// Save Map…, the exports, the screenshots and Export report… propose names
// of the open sequence beside it: another sequence's files are not offered
// for replacing.
TEST_F(SequenceSwitchTest, OutputsAreProposedBesideTheSequenceUnderItsName) {
  window_.session().setAutoFuse(false);
  const lom::test::TinySequence tiny = writeTiny();
  const fs::path outputs = temp_.path();
  for (const auto& [folder, name] :
       {std::pair{folder_, QString("demo_shelf")}, std::pair{tiny.folder, QString("tiny_shelf")}}) {
    SCOPED_TRACE(name.toStdString());
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder)));
    // A map to save or export.
    window_.session().fuse();
    ASSERT_TRUE(QTest::qWaitFor(
        [&] {
          const auto map = window_.session().worker().snapshot();
          return !window_.session().worker().isFusing() && map && !map->empty();
        },
        fixture::kTimeoutMs));
    settle();
    const QDir beside(qPath(outputs));
    EXPECT_EQ(proposedBy("Save Map…"), beside.filePath(name + ".ot").toStdString());
    EXPECT_EQ(proposedBy("Voxel Mesh (PLY)…"), beside.filePath(name + ".ply").toStdString());
    // A colour octree may not replace the map saved as NAME.ot.
    EXPECT_EQ(proposedBy("Colour Octree (OT)…"),
              beside.filePath(name + "-colour.ot").toStdString());
    EXPECT_EQ(proposedBy("Save Screenshot…"), beside.filePath(name + ".png").toStdString());
    EXPECT_EQ(proposedBy("Save 3D View…"), beside.filePath(name + "-3d-view.png").toStdString());
    EXPECT_EQ(proposedReportFolder(), beside.filePath(name + "-report").toStdString());
    // Made for the dialog only: the report did not go there.
    EXPECT_FALSE(fs::exists(outputs / (name + "-report").toStdString()));
  }
}

// A sequence that cannot be opened is said so before the unsaved boxes are
// asked about: saving or discarding them would be for nothing.
TEST_F(SequenceSwitchTest, AVanishedSequenceIsReportedBeforeUnsavedWorkIsAskedAbout) {
  window_.session().setAutoFuse(false);
  const lom::test::TinySequence tiny = writeTiny();
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  GroundTruthBox box = truth_.boxes.front();
  box.box.center.x() += 0.05;
  window_.session().annotations().setBox(0, box, "Edit box");
  ASSERT_TRUE(window_.controller().hasUnsavedWork());
  int asked = 0;
  window_.controller().setDiscardGuard([&] {
    ++asked;
    return false;
  });
  const fs::path renamed = temp_.path() / "tiny_shelf_renamed";
  fs::rename(tiny.folder, renamed);
  EXPECT_FALSE(window_.controller().openSequence(qPath(tiny.folder)));
  EXPECT_EQ(asked, 0);
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_.front().contains("no such file or folder")) << errors_.front().toStdString();
  // Nor is a folder that holds no sequence, or a sequence.json that does not load.
  fs::create_directories(temp_.path() / "empty");
  EXPECT_FALSE(window_.controller().openSequence(qPath(temp_.path() / "empty")));
  std::ofstream(renamed / "sequence.json") << "{ not json";
  EXPECT_FALSE(window_.controller().openSequence(qPath(renamed)));
  EXPECT_EQ(asked, 0);
  EXPECT_EQ(errors_.size(), 3u);
  EXPECT_EQ(window_.controller().sequenceName(), "demo_shelf");
  // A sequence that opens is asked about, and Cancel keeps the open one.
  EXPECT_FALSE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_EQ(asked, 1);
  EXPECT_TRUE(window_.session().annotations().isDirty());
}

// Open Recent drops an entry whose sequence is gone once the open has said
// so; never silently, as after Cancel on the question about unsaved work.
TEST_F(SequenceSwitchTest, OpenRecentDropsAnEntryOnlyWithTheReport) {
  window_.session().setAutoFuse(false);
  const lom::test::TinySequence tiny = writeTiny();
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny.folder)));
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  GroundTruthBox box = truth_.boxes.front();
  box.box.center.x() += 0.05;
  window_.session().annotations().setBox(0, box, "Edit box");
  QMenu* recent = nullptr;
  for (QMenu* menu : window_.findChildren<QMenu*>())
    if (menu->title().remove('&') == "Open Recent") recent = menu;
  ASSERT_NE(recent, nullptr);
  const auto trigger = [&](const fs::path& sequence) {
    emit recent->aboutToShow();
    for (QAction* action : recent->actions())
      if (action->text().contains(QDir::toNativeSeparators(qPath(sequence)) + ")")) {
        action->trigger();
        return true;
      }
    return false;
  };
  const auto listed = [&](const fs::path& sequence) {
    return window_.recentSequences().paths().contains(qPath(sequence));
  };
  ASSERT_TRUE(listed(tiny.folder));

  // Renamed while the question is up, and the open cancelled: kept.
  const fs::path renamed = temp_.path() / "tiny_renamed";
  window_.controller().setDiscardGuard([&] {
    fs::rename(tiny.folder, renamed);
    return false;
  });
  ASSERT_TRUE(trigger(tiny.folder));
  EXPECT_TRUE(errors_.empty());
  EXPECT_TRUE(listed(tiny.folder)) << "nothing said, nothing dropped";

  // Gone: reported (before any question) and dropped.
  int asked = 0;
  window_.controller().setDiscardGuard([&] {
    ++asked;
    return false;
  });
  ASSERT_TRUE(trigger(tiny.folder));
  EXPECT_EQ(asked, 0);
  EXPECT_EQ(errors_.size(), 1u);
  EXPECT_FALSE(listed(tiny.folder));
  QSettings().remove("recentSequences");
}

// Drops that cannot open are refused: a folder of no layout the studio knows
// (the one that holds the sequences, say) is not taken for a sequence.
TEST_F(SequenceSwitchTest, ADroppedFolderThatHoldsNoSequenceIsRefused) {
  const auto dropped = [](const fs::path& path) {
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(qPath(path))});
    return SequenceDropHandler::droppedSequencePath(&mime);
  };
  EXPECT_EQ(dropped(folder_), qPath(folder_));
  EXPECT_EQ(dropped(temp_.path()), QString());
  fs::create_directories(temp_.path() / "frames");
  EXPECT_EQ(dropped(temp_.path() / "frames"), QString());
}

// The offer of unsaved boxes comes once the window shows the sequence they
// belong to, and names it.
TEST_F(SequenceSwitchTest, RecoveredBoxesAreOfferedOnceTheSequenceIsShown) {
  window_.session().setAutoFuse(false);
  const lom::test::TinySequence tiny = writeTiny();
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny.folder)));
  GroundTruthBox box;
  box.label = lom::test::kSquareLabel;
  box.name = "square_box";
  box.box.center = {0.1, 0.0, 0.6};
  box.box.size = {0.05, 0.05, 0.05};
  window_.session().annotations().addBox(box);
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(window_.autosave().currentRecoveryPath()));

  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  next.setWarningReporter([](const QString&, const QString&) {});
  next.session().setAutoFuse(false);
  next.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&next));
  ASSERT_TRUE(next.controller().openSequence(qPath(folder_)));
  QString status_when_asked;
  int frame_when_asked = -2;
  QTimer look;  // what the window shows while the question waits
  look.setInterval(10);
  QObject::connect(&look, &QTimer::timeout, [&] {
    for (QWidget* widget : QApplication::topLevelWidgets())
      if (widget->isVisible() && qobject_cast<QMessageBox*>(widget) &&
          status_when_asked.isEmpty()) {
        status_when_asked = next.statusText();
        frame_when_asked = next.controller().currentFrame();
      }
  });
  look.start();
  test::DialogAnswerer answer("Yes");
  ASSERT_TRUE(next.controller().openSequence(qPath(tiny.folder)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !answer.questions.isEmpty(); }, 10'000));
  look.stop();
  EXPECT_TRUE(answer.questions.front().contains("Boxes of tiny_shelf were not saved"))
      << answer.questions.front().toStdString();
  EXPECT_TRUE(status_when_asked.startsWith("tiny_shelf — frame 1 of"))
      << status_when_asked.toStdString();
  EXPECT_EQ(frame_when_asked, 0);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !next.autosave().isOfferPending(); }, 10'000));
  // Restored, still unsaved.
  EXPECT_EQ(next.session().annotations().boxCount(), 1);
  EXPECT_TRUE(next.session().annotations().isDirty());
  next.session().annotations().undoStack().setClean();
  next.autosave().discard();
}

}  // namespace
}  // namespace lom::ui
