// A map fused in the studio is work: closing the window, opening another
// sequence, opening a map file or Reset Map ask before they drop it, until it
// is saved (File ▸ Save Map…, the map's own .ot that Open Map… reads back).
// A map opened from a file is saved work;
// fusing again replaces the map without asking (the same sequence, the
// settings the Fusion panel shows).
#include <gtest/gtest.h>

#include <QAbstractButton>
#include <QAction>
#include <QApplication>
#include <QMessageBox>
#include <QTest>
#include <QTimer>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <thread>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/fusion.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/export_map_reaction.hpp"
#include "lom/ui/open_map_reaction.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class UnsavedMapTest : public fixture::DemoWindowTest {
 protected:
  void SetUp() override {
    DemoWindowTest::SetUp();
    window_.setMapDiscardQuestion({});  // the window's own question
  }
  StudioSession& session() { return window_.session(); }
  // Exports the map with the Export menu's item `item`; true when written.
  bool exportWith(const QString& item, const std::filesystem::path& path) {
    auto* exporter = window_.findAction(item)->findChild<ExportMapReaction*>();
    EXPECT_NE(exporter, nullptr);
    return exporter && exporter->exportToAndWait(qPath(path));
  }
  void openMapFile(const std::filesystem::path& path) {
    auto* reaction = window_.findAction("Open Map…")->findChild<OpenMapReaction*>();
    ASSERT_NE(reaction, nullptr);
    reaction->setChooser([path](const QString&) { return qPath(path); });
    window_.findAction("Open Map…")->trigger();
    ASSERT_TRUE(QTest::qWaitFor(
        [&] { return !session().isOpeningMap() && !session().worker().isFusing(); }, kTimeoutMs));
    QTest::qWait(50);
  }
  [[nodiscard]] size_t framesShown() { return session().worker().snapshot()->frames_fused; }
  // The next fusion holds after its second frame until `release` (or the
  // end of the test).
  struct Hold {
    std::atomic<size_t> reached{0};
    std::atomic<bool> release{false};
  };
  std::shared_ptr<Hold> heldAtSecondFrame() {
    auto hold = std::make_shared<Hold>();
    session().worker().setFrameFusedHook([hold](size_t frames) {
      hold->reached = frames;
      while (frames == 2 && !hold->release)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    hold_ = hold;
    return hold;
  }
  // While `timer` runs, every 20 ms: `answer` is called once for each message
  // box shown with a text not asked before, which `asked` records.
  static void answerNewQuestions(QTimer& timer, QStringList& asked,
                                 std::function<void(QMessageBox&)> answer) {
    timer.setInterval(20);
    QObject::connect(&timer, &QTimer::timeout, [&asked, answer = std::move(answer)] {
      for (QWidget* widget : QApplication::topLevelWidgets()) {
        auto* box = qobject_cast<QMessageBox*>(widget);
        if (!box || !box->isVisible() || asked.contains(box->text())) continue;
        asked << box->text();
        answer(*box);
      }
    });
    timer.start();
  }
  void TearDown() override {
    if (hold_) hold_->release = true;
    session().worker().setFrameFusedHook({});
    DemoWindowTest::TearDown();
  }

 private:
  std::shared_ptr<Hold> hold_;
};

TEST_F(UnsavedMapTest, ClosingAfterAFusionAsksAndCancelKeepsTheWindow) {
  openAndFuse();
  EXPECT_TRUE(session().worker().hasUnsavedMap());
  {
    test::DialogAnswerer answer("Cancel");
    EXPECT_FALSE(window_.close());
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(
        answer.questions.front().contains("has not been saved. Closing the studio discards it"))
        << answer.questions.front().toStdString();
  }
  EXPECT_EQ(framesShown(), static_cast<size_t>(fixture::smallDemo().frames));
  // Save Map… writes the whole map (Only Labels Shown or not) where the file
  // dialog says, and the window closes; a cancelled dialog keeps it open.
  window_.findAction("Only Labels Shown")->setChecked(true);
  const int hidden = *visibleObjectLabels().begin();
  session().setHiddenLabels({hidden});
  {
    test::DialogAnswerer answer("Save Map");
    EXPECT_FALSE(window_.close());
    EXPECT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(session().worker().hasUnsavedMap());
  }
  const auto saved = temp_.path() / "kept.ot";
  test::DialogAnswerer answer("Save Map", qPath(saved));
  EXPECT_TRUE(window_.close());
  EXPECT_EQ(answer.questions.size(), 1) << answer.questions.join("\n").toStdString();
  ASSERT_TRUE(std::filesystem::exists(saved));
  const LabelMap kept = LabelMap::load(saved);
  EXPECT_GT(kept.occupiedCountPerLabel().count(hidden), 0u);  // hidden, and saved all the same
}

TEST_F(UnsavedMapTest, ReplacingTheMapAsksFirstAndCancelKeepsIt) {
  openAndFuse();
  const unsigned generation = session().mapGeneration();
  const auto file = temp_.path() / "other.ot";
  fuseSequence(loadSequence(folder_), FusionOptions{}).save(file);
  {  // Reset Map, Open Map… and another sequence, each cancelled.
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Reset Map")->trigger();
    openMapFile(file);
    EXPECT_FALSE(window_.controller().openSequence(qPath(folder_)));
    ASSERT_EQ(answer.questions.size(), 3);
    EXPECT_TRUE(answer.questions[0].contains("Reset Map discards it"));
    EXPECT_TRUE(answer.questions[1].contains("Opening other.ot discards it"));
    EXPECT_TRUE(answer.questions[2].contains("Opening another sequence discards it"));
  }
  EXPECT_EQ(session().mapGeneration(), generation);
  EXPECT_EQ(framesShown(), static_cast<size_t>(fixture::smallDemo().frames));
  EXPECT_TRUE(session().worker().hasUnsavedMap());

  // Discarded: Reset Map empties it, and an empty map is nothing to lose.
  {
    test::DialogAnswerer answer("Discard Map");
    window_.findAction("Reset Map")->trigger();
    EXPECT_EQ(answer.questions.size(), 1);
  }
  ASSERT_TRUE(QTest::qWaitFor([&] { return framesShown() == 0; }, kTimeoutMs));
  EXPECT_FALSE(session().worker().hasUnsavedMap());

  // A map opened from its file is saved work: closing asks nothing.
  openMapFile(file);
  EXPECT_TRUE(errors_.empty());
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  test::DialogAnswerer answer("Cancel");
  EXPECT_TRUE(window_.close());
  EXPECT_TRUE(answer.questions.isEmpty());
}

TEST_F(UnsavedMapTest, SaveMapWritesTheMapThatOpenMapReadsBack) {
  openAndFuse();
  // Exports are not the map: a mesh, a colour octree (for octovis).
  ASSERT_TRUE(exportWith("Voxel Mesh (PLY)…", temp_.path() / "map.ply"));
  ASSERT_TRUE(exportWith("Colour Octree (OT)…", temp_.path() / "colour.ot"));
  EXPECT_TRUE(session().worker().hasUnsavedMap());
  QApplication::processEvents();
  EXPECT_TRUE(window_.isWindowModified()) << "the title marks the unsaved map";
  EXPECT_FALSE(session().annotations().isDirty());
  // Save Map… writes every label, whatever the 3D view hides.
  window_.findAction("Only Labels Shown")->setChecked(true);
  const int hidden = *visibleObjectLabels().begin();
  session().setHiddenLabels({hidden});
  ASSERT_TRUE(exportWith("Save Map…", temp_.path() / "map.ot"));
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  QApplication::processEvents();
  EXPECT_FALSE(window_.isWindowModified());
  // Re-thresholded, the map is no longer the one saved (a .ot keeps its
  // threshold); the same threshold again changes nothing.
  const double threshold = session().fusionOptions().map.occupancy_threshold;
  session().setOccupancyThreshold(threshold);
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  session().setOccupancyThreshold(threshold + 0.1);
  EXPECT_TRUE(session().worker().hasUnsavedMap());
  ASSERT_TRUE(exportWith("Save Map…", temp_.path() / "map.ot"));
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  EXPECT_NEAR(LabelMap::load(temp_.path() / "map.ot").parameters().occupancy_threshold,
              threshold + 0.1, 1e-9);
  const LabelMap saved = LabelMap::load(temp_.path() / "map.ot");
  EXPECT_GT(saved.occupiedCountPerLabel().count(hidden), 0u);
  openMapFile(temp_.path() / "map.ot");
  EXPECT_TRUE(errors_.empty());
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  // Fusing again makes a new map to save; it replaces the saved one unasked.
  {
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Fuse Sequence")->trigger();
    waitForFusion();
    EXPECT_TRUE(answer.questions.isEmpty());
  }
  EXPECT_TRUE(session().worker().hasUnsavedMap());
  EXPECT_TRUE(window_.isWindowModified());
  test::DialogAnswerer answer("Discard Map");
  EXPECT_TRUE(window_.close());
  EXPECT_EQ(answer.questions.size(), 1);
}

// A fusion that fused nothing (its first frame unreadable) leaves nothing to lose.
TEST_F(UnsavedMapTest, AFusionThatFusedNothingIsNotAsked) {
  const Sequence sequence = loadSequence(folder_);
  std::ofstream(sequence.pathOf(sequence.frames.front().depth), std::ios::trunc) << "not a PNG";
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session().worker().isFusing(); }, kTimeoutMs));
  QTest::qWait(50);
  EXPECT_FALSE(errors_.empty());
  EXPECT_FALSE(session().worker().hasUnsavedMap());
  test::DialogAnswerer answer("Cancel");
  EXPECT_TRUE(window_.close());
  EXPECT_TRUE(answer.questions.isEmpty()) << answer.questions.join('\n').toStdString();
}

// A fusion that ends while the close question about it is open leaves a
// whole map: the question says the work has finished, and the map is asked
// about before the window closes (closing dropped it).
TEST_F(UnsavedMapTest, AFusionThatEndsWhileClosingIsAskedIsAskedAboutItsMap) {
  auto held = heldAtSecondFrame();
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return held->reached == 2; }, kTimeoutMs));
  QStringList asked;
  bool closing_answered = false;
  QTimer answerer;
  answerNewQuestions(answerer, asked, [&](QMessageBox& box) {
    if (box.text().contains("Closing the studio now stops")) {
      held->release = true;  // the fusion ends while the question is open
    } else if (box.text().contains("has finished") && !closing_answered) {
      for (QAbstractButton* button : box.buttons())
        if (button->text().remove('&') == "Close") {
          closing_answered = true;
          QMetaObject::invokeMethod(button, "click", Qt::QueuedConnection);
        }
    } else {
      QMetaObject::invokeMethod(&box, "reject", Qt::QueuedConnection);  // Cancel
    }
  });
  EXPECT_FALSE(window_.close());
  ASSERT_EQ(asked.size(), 3) << asked.join("\n").toStdString();
  EXPECT_TRUE(asked[0].contains("fusion of")) << asked[0].toStdString();
  EXPECT_TRUE(asked[1].startsWith("The work in progress has finished")) << asked[1].toStdString();
  EXPECT_TRUE(closing_answered);
  EXPECT_TRUE(asked[2].contains("has not been saved. Closing the studio discards it"))
      << asked[2].toStdString();
  EXPECT_EQ(framesShown(), static_cast<size_t>(fixture::smallDemo().frames));
  EXPECT_TRUE(session().worker().hasUnsavedMap());
}

// Reset Map asked while fusing, the fusion ending while the question is open:
// the question becomes the one about a whole map, and offers to save it.
TEST_F(UnsavedMapTest, TheMapQuestionOffersSaveOnceTheFusionEndsWhileItIsOpen) {
  session().worker().setSnapshotInterval(0);  // the first frame's map is shown
  auto held = heldAtSecondFrame();
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return held->reached == 2; }, kTimeoutMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return session().worker().hasUnsavedMap(); }, kTimeoutMs));
  QStringList asked;
  QStringList buttons_at_end;
  QTimer answerer;
  answerNewQuestions(answerer, asked, [&](QMessageBox& box) {
    if (box.text().contains("being fused from")) {
      held->release = true;
    } else {
      for (QAbstractButton* button : box.buttons()) buttons_at_end << button->text().remove('&');
      QMetaObject::invokeMethod(&box, "reject", Qt::QueuedConnection);  // Cancel
    }
  });
  window_.findAction("Reset Map")->trigger();
  ASSERT_EQ(asked.size(), 2) << asked.join("\n").toStdString();
  EXPECT_TRUE(asked[1].contains("fused from")) << asked[1].toStdString();
  EXPECT_FALSE(asked[1].contains("being fused")) << asked[1].toStdString();
  EXPECT_FALSE(asked[1].contains("once fusion ends")) << asked[1].toStdString();
  EXPECT_TRUE(buttons_at_end.contains("Save Map…")) << buttons_at_end.join(", ").toStdString();
  EXPECT_TRUE(session().worker().hasUnsavedMap());  // Cancel kept it
  EXPECT_EQ(framesShown(), static_cast<size_t>(fixture::smallDemo().frames));
}

// Reset Map while fusing: the status says "not fused", not where the fusion
// it stopped had got to (the stopped fusion's end came after the reset).
TEST_F(UnsavedMapTest, ResetMapWhileFusingLeavesTheStatusNotFused) {
  auto held = heldAtSecondFrame();
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return held->reached == 2; }, kTimeoutMs));
  {
    test::DialogAnswerer answer("Discard Map");  // if asked
    window_.findAction("Reset Map")->trigger();
  }
  held->release = true;
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session().worker().isFusing() && framesShown() == 0; },
                              kTimeoutMs));
  QTest::qWait(200);
  EXPECT_TRUE(window_.fusionStatusText().startsWith("not fused"))
      << window_.fusionStatusText().toStdString();
  EXPECT_FALSE(window_.fusionStatusText().contains("stopped"))
      << window_.fusionStatusText().toStdString();
}

}  // namespace
// An export other than Save Map… never replaces a labelled map: a colour
// octree written over the map opened (or saved) left a file Open Map cannot
// read, and the studio still took the map for saved.
TEST_F(UnsavedMapTest, ExportsNeverReplaceALabelledMap) {
  openAndFuse();
  const auto saved = temp_.path() / "saved.ot";
  ASSERT_TRUE(exportWith("Save Map…", saved));
  const std::string before = lom::test::slurp(saved);
  errors_.clear();
  EXPECT_FALSE(exportWith("Colour Octree (OT)…", saved));
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_.front().contains("holds a labelled map")) << errors_.front().toStdString();
  EXPECT_TRUE(errors_.front().contains("Save Map")) << errors_.front().toStdString();
  EXPECT_EQ(lom::test::slurp(saved), before);
  // Save Map… over it stays possible; so does a colour octree over a colour octree.
  errors_.clear();
  EXPECT_TRUE(exportWith("Save Map…", saved));
  ASSERT_TRUE(exportWith("Colour Octree (OT)…", temp_.path() / "colour.ot"));
  EXPECT_TRUE(exportWith("Colour Octree (OT)…", temp_.path() / "colour.ot"));
  EXPECT_TRUE(errors_.empty());
  // The map opened from that file is protected alike.
  openMapFile(saved);
  errors_.clear();
  EXPECT_FALSE(exportWith("Colour Octree (OT)…", saved));
  EXPECT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(LabelMap::isMapFile(saved));
}

}  // namespace lom::ui
