#pragma once
// A studio window with a small synthetic demo scene written for the test:
// the fixture shared by the GUI tests that fuse a scene.
#include <gtest/gtest.h>

#include <QApplication>
#include <QDockWidget>
#include <QString>
#include <QTest>
#include <filesystem>
#include <set>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/synth.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "test_support.hpp"

namespace lom::ui::fixture {

inline constexpr int kTimeoutMs = 120'000;

inline SynthOptions smallDemo() {
  SynthOptions options;
  options.objects = 4;
  options.frames = 6;
  options.views = 3;
  options.width = 160;
  options.height = 120;
  return options;
}

inline QString qPath(const std::filesystem::path& path) {
  return QString::fromStdString(path.string());
}

class DemoWindowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = temp_.path() / "demo_shelf";
    prepareDemoScene(qPath(folder_), smallDemo());
    truth_ = loadAnnotations(folder_ / "annotations.json");
    window_.setErrorReporter([this](const QString& title, const QString& message) {
      errors_.push_back(title + ": " + message);
    });
    window_.setRecoveryOffer([](const QString&) { return false; });
    // Maps fused here are dropped without the question (unsaved_map_test.cpp asks it).
    window_.setMapDiscardQuestion([](const QString&) { return true; });
    window_.resize(1280, 860);
    window_.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window_));
  }

  // Opens the demo and waits until every frame is fused.
  void openAndFuse() {
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
    waitForFusion();
  }
  void waitForFusion() {
    StudioSession& session = window_.session();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
    // The last snapshot arrives through the event loop (a loaded machine may
    // take a while to deliver it).
    const auto all_fused = [&] {
      const auto snapshot = session.worker().snapshot();
      return snapshot && snapshot->frames_fused == static_cast<size_t>(smallDemo().frames);
    };
    ASSERT_TRUE(QTest::qWaitFor(all_fused, kTimeoutMs));
    QTest::qWait(20);
    ASSERT_EQ(session.worker().snapshot()->frames_fused, static_cast<size_t>(smallDemo().frames));
  }
  static void settle() {
    QApplication::processEvents();
    QTest::qWait(100);  // posted layout requests and resizes
  }
  // One of the window's panels, by its object name.
  QDockWidget& dock(const char* name) {
    auto* widget = window_.findChild<QDockWidget*>(name);
    EXPECT_NE(widget, nullptr) << name;
    return *widget;
  }
  // Object labels that have depth (the transparent bottle has none).
  [[nodiscard]] std::set<int> visibleObjectLabels() const {
    std::set<int> labels;
    for (const auto& box : truth_.boxes)
      if (box.label != kSynthTransparentLabel) labels.insert(box.label);
    return labels;
  }

  lom::test::TempDir temp_;
  std::filesystem::path folder_;
  Annotations truth_;
  MainWindow window_;
  std::vector<QString> errors_;
};

}  // namespace lom::ui::fixture
