// The window's layout: it fits a laptop's 1366x768 screen, long label names
// are elided (told whole in tooltips) instead of widening the docks, and the
// heat map's caption says what it shows.
#include <gtest/gtest.h>

#include <QApplication>
#include <QColor>
#include <QDockWidget>
#include <QFontMetrics>
#include <QMenu>
#include <QMenuBar>
#include <QPushButton>
#include <QStatusBar>
#include <QTableWidget>
#include <QTest>
#include <filesystem>
#include <functional>
#include <map>

#include "demo_window_fixture.hpp"
#include "lom/fusion.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/box_editor_panel.hpp"
#include "lom/ui/colour_bar.hpp"
#include "lom/ui/elision.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/label_legend.hpp"
#include "lom/ui/map_legend_panel.hpp"
#include "lom/ui/objects_panel.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/score_chart.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

// A 1366x768 laptop screen less a desktop panel and the window's title bar.
constexpr int kLaptopWindowHeight = 700;
constexpr int kLaptopWidth = 1366;
constexpr int kLongNameLength = 170;

// `name` lengthened to kLongNameLength characters with words joined by '_'
// (one unbreakable word, as in many datasets).
std::string longName(const std::string& name) {
  std::string result = name;
  while (result.size() < kLongNameLength) result += "_with_a_very_long_description";
  return result.substr(0, kLongNameLength);
}

class WindowLayoutTest : public fixture::DemoWindowTest {
 protected:
  void expectFitsALaptop(const char* when) {
    settle();
    EXPECT_LE(window_.minimumSizeHint().height(), kLaptopWindowHeight) << when;
    EXPECT_LE(window_.minimumSize().height(), kLaptopWindowHeight) << when;
    EXPECT_LE(window_.minimumSizeHint().width(), kLaptopWidth) << when;
    // At that height the timeline and the status bar are inside the window.
    window_.resize(kLaptopWidth - 100, kLaptopWindowHeight);
    settle();
    EXPECT_EQ(window_.height(), kLaptopWindowHeight) << when;
    const QRect timeline(window_.timeline().mapTo(&window_, QPoint(0, 0)),
                         window_.timeline().size());
    EXPECT_LE(timeline.bottom(), window_.statusBar()->geometry().top()) << when;
    EXPECT_LE(window_.statusBar()->geometry().bottom(), window_.height()) << when;
    EXPECT_GE(window_.sceneView().height(), 240) << when;
  }
  // A copy of the demo whose labels are named with kLongNameLength characters.
  std::filesystem::path writeLongNamedCopy() {
    const auto copy = temp_.path() / "long_names";
    std::filesystem::copy(folder_, copy, std::filesystem::copy_options::recursive);
    Sequence sequence = loadSequence(copy);
    std::vector<LabelInfo> labels = sequence.labels.all();
    for (LabelInfo& label : labels)
      if (label.id != 0) label.name = longName(label.name);
    sequence.labels = LabelSet(std::move(labels));
    saveSequence(sequence, copy);
    return copy;
  }
};

TEST_F(WindowLayoutTest, FitsALaptopScreen) {
  // A window opened on such a screen starts inside it.
  const QSize initial = initialWindowSize({kLaptopWidth, 768 - 28});
  EXPECT_LE(initial.width(), kLaptopWidth);
  EXPECT_LE(initial.height(), 768 - 28);
  EXPECT_EQ(initialWindowSize({1920, 1080}), QSize(1280, 1000));

  openAndFuse();
  expectFitsALaptop("with the demo fused");

  // The scores' Export button is in view without scrolling the dock, and the
  // chart keeps some height.
  EvaluationPanel& evaluation = window_.evaluationPanel();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !evaluation.isBusy() && evaluation.canExport(); },
                              fixture::kTimeoutMs))
      << evaluation.summaryText().toStdString();
  settle();
  const QPushButton& export_button = evaluation.exportButton();
  EXPECT_TRUE(export_button.isEnabled());
  EXPECT_EQ(export_button.visibleRegion().boundingRect(), export_button.rect());
  EXPECT_GE(evaluation.chart().visibleRegion().boundingRect().height(), 60);
  const QTableWidget& table = evaluation.table();
  ASSERT_GT(table.rowCount(), 0);
  const int last_row_bottom =
      table.rowViewportPosition(table.rowCount() - 1) + table.rowHeight(table.rowCount() - 1);
  EXPECT_LE(last_row_bottom, table.viewport()->height());

  // The Fusion panel's depth-range note (two lines) and its Re-fuse button,
  // scrolled into view in the short window.
  window_.resize(kLaptopWidth - 100, kLaptopWindowHeight);
  FusionOptions options = window_.session().fusionOptions();
  options.map.max_range = 0.1;  // the demo's depths lie beyond
  window_.session().setFusionOptions(options);
  window_.session().fuse();
  waitForFusion();
  FusionPanel& panel = window_.fusionPanel();
  ASSERT_FALSE(panel.extendRangeButton().isHidden()) << panel.noteText().toStdString();
  ASSERT_FALSE(panel.noteText().isEmpty());
  settle();
  EXPECT_FALSE(panel.extendRangeButton().visibleRegion().isEmpty());
  // With the field the note is about.
  const auto* resolution = panel.findChild<QWidget*>("resolutionBox");
  ASSERT_NE(resolution, nullptr);
  EXPECT_EQ(resolution->visibleRegion().boundingRect(), resolution->rect());
  expectFitsALaptop("with the Fusion panel's range note");
  EXPECT_TRUE(errors_.empty());
}

TEST_F(WindowLayoutTest, LongLabelNamesAreElidedWithoutWideningTheDocks) {
  openAndFuse();
  window_.session().setSelectedLabel(*visibleObjectLabels().begin());
  settle();
  const int dock_width = dock("mapLegendDock").width();
  const int scene_width = window_.sceneView().width();
  const int legend_width = window_.frameImages().labelLegend().width();

  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(window_.controller().openSequence(fixture::qPath(writeLongNamedCopy())));
  waitForFusion();
  window_.session().setSelectedLabel(*visibleObjectLabels().begin());
  settle();

  EXPECT_EQ(dock("mapLegendDock").width(), dock_width);
  EXPECT_EQ(dock("boxesDock").width(), dock_width);
  EXPECT_LT(dock("mapLegendDock").minimumSizeHint().width(), 400);
  EXPECT_EQ(window_.sceneView().width(), scene_width);

  // The frame's legend: every name elided within the legend, told whole in a tooltip.
  const LabelLegend& legend = window_.frameImages().labelLegend();
  EXPECT_EQ(legend.width(), legend_width);
  const auto& entries = legend.entries();
  const std::vector<QString> shown = legend.shownNames();
  ASSERT_FALSE(entries.empty());
  ASSERT_EQ(shown.size(), entries.size());
  for (size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(entries[i].name.size(), kLongNameLength);
    EXPECT_TRUE(shown[i].endsWith(QStringLiteral("…"))) << shown[i].toStdString();
    EXPECT_TRUE(entries[i].name.startsWith(shown[i].chopped(1))) << shown[i].toStdString();
    EXPECT_LE(legend.fontMetrics().horizontalAdvance(shown[i]), legend.width());
  }
  const QPoint first_entry(legend.fontMetrics().ascent() + 8, legend.fontMetrics().height() / 2);
  EXPECT_EQ(legend.toolTipAt(first_entry).toStdString(), entries[0].name.toStdString());
  EXPECT_TRUE(legend.toolTipAt({legend.width() - 1, legend.height() - 1}).isEmpty());

  // The map legend's table elides its names and tells them in tooltips.
  auto* table = window_.mapLegend().findChild<QTableWidget*>("mapLegendTable");
  ASSERT_NE(table, nullptr);
  ASSERT_GT(table->rowCount(), 1);
  EXPECT_EQ(table->item(1, 0)->toolTip().size(), kLongNameLength);
  EXPECT_LE(table->columnViewportPosition(1) + table->columnWidth(1), table->viewport()->width());

  // The label choosers show the chosen name elided, and whole in their tooltips.
  for (const QComboBox* combo :
       {static_cast<const QComboBox*>(&window_.boxEditor().newBoxLabel()),
        static_cast<const QComboBox*>(&window_.objectsPanel().targetCombo())}) {
    const auto* eliding = qobject_cast<const ElidingComboBox*>(combo);
    ASSERT_NE(eliding, nullptr) << combo->objectName().toStdString();
    ASSERT_GE(eliding->currentIndex(), 0) << combo->objectName().toStdString();
    EXPECT_TRUE(eliding->shownText().endsWith(QStringLiteral("…")))
        << eliding->shownText().toStdString();
    EXPECT_EQ(eliding->elidedToolTip().toStdString(), eliding->currentText().toStdString());
    EXPECT_LT(eliding->minimumSizeHint().width(), 300);
  }

  // The heat map's caption too.
  const ImagePane& heat = window_.frameImages().heatPane();
  EXPECT_TRUE(heat.caption().startsWith("Probability of ")) << heat.caption().toStdString();
  EXPECT_EQ(heat.caption().size(), QString("Probability of ").size() + kLongNameLength);
  EXPECT_TRUE(heat.shownCaption().endsWith(QStringLiteral("…")));
  EXPECT_LE(heat.fontMetrics().horizontalAdvance(heat.shownCaption()), heat.width());
  EXPECT_EQ(heat.captionToolTip().toStdString(), heat.caption().toStdString());
  EXPECT_TRUE(errors_.empty());
}

TEST_F(WindowLayoutTest, HeatMapCaptionSaysWhatItShows) {
  const ImagePane& heat = window_.frameImages().heatPane();
  EXPECT_EQ(heat.caption().toStdString(), "Probability");  // nothing open

  openAndFuse();
  window_.frameImages().setHeatLabel(-1);
  EXPECT_EQ(heat.caption().toStdString(), "Probability (choose a label)");
  const int label = *visibleObjectLabels().begin();
  window_.session().setSelectedLabel(label);
  const QString name =
      QString::fromStdString(window_.controller().sequence().labels.at(label).name);
  EXPECT_EQ(heat.caption().toStdString(), "Probability of " + name.toStdString());
  // Elided or not, depending on the pane's width: the tooltip tells what is cut.
  EXPECT_EQ(heat.captionToolTip().isEmpty(), heat.shownCaption() == heat.caption());
  EXPECT_FALSE(heat.image().isNull());
  // Its scale, 0 to 1, under it (no unit), and only with a heat map.
  const auto* scale = window_.findChild<ColourBar*>("heatLegend");
  ASSERT_NE(scale, nullptr);
  ASSERT_TRUE(scale->range().has_value());
  EXPECT_EQ(*scale->range(), std::make_pair(0.0, 1.0));
  EXPECT_TRUE(scale->shownTexts().isEmpty() || scale->shownTexts().front() == "0.00")
      << scale->shownTexts().join(' ').toStdString();
  window_.frameImages().setHeatLabel(-1);
  EXPECT_FALSE(scale->range().has_value());
  window_.session().setSelectedLabel(label);
  window_.frameImages().setHeatLabel(label);
  EXPECT_TRUE(scale->range().has_value());

  // A recording without probability images (the tiny sequence has label images only).
  const test::TinySequence tiny = test::writeTinySequence(temp_.path() / "tiny");
  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(window_.controller().openSequence(fixture::qPath(tiny.folder)));
  EXPECT_EQ(heat.caption().toStdString(), "Probability: none");
  EXPECT_EQ(heat.shownCaption(), heat.caption());  // short enough for the narrowest pane
  EXPECT_TRUE(heat.image().isNull());
  EXPECT_FALSE(scale->range().has_value());
  EXPECT_TRUE(errors_.empty());
}

// The colour bars' numbers never run into each other in a narrow dock: the
// caption goes first, then the numbers; the colours stay.
TEST(ColourBarTest, TextsThatWouldOverlapAreLeftOut) {
  ColourBar bar([](double t) { return QColor::fromRgbF(t, 0.0, 1.0 - t); }, "depth");
  bar.setRange(std::make_pair(0.24, 0.86));
  bar.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&bar));
  const QFontMetrics metrics = bar.fontMetrics();
  auto widthOf = [&](const QStringList& texts) {
    int sum = 0;
    for (const QString& text : texts) sum += metrics.horizontalAdvance(text);
    return sum;
  };
  bar.resize(400, 34);
  EXPECT_EQ(bar.shownTexts(), QStringList({"0.24 m", "depth", "0.86 m"}));
  int widest_without_caption = 0;
  for (int width = 400; width >= 10; width -= 2) {
    bar.resize(width, 34);
    const QStringList texts = bar.shownTexts();
    EXPECT_LE(widthOf(texts), width - 8) << width;  // side by side, they fit the bar
    if (texts.size() == 2) {
      EXPECT_EQ(texts, QStringList({"0.24 m", "0.86 m"})) << width;
      widest_without_caption = std::max(widest_without_caption, width);
    }
    if (texts.size() == 3) {  // the caption centred, clear of the ends
      const int ends =
          std::max(metrics.horizontalAdvance(texts[0]), metrics.horizontalAdvance(texts[2]));
      EXPECT_LT(2 * ends + metrics.horizontalAdvance(texts[1]), width - 8) << width;
    }
  }
  EXPECT_GT(widest_without_caption, 0);  // the caption went first
  bar.resize(12, 34);
  EXPECT_TRUE(bar.shownTexts().isEmpty());
  bar.setRange(std::nullopt);
  bar.resize(400, 34);
  EXPECT_TRUE(bar.shownTexts().isEmpty());

  // A quantity without a unit (probability).
  ColourBar probability([](double t) { return QColor::fromRgbF(t, t, t); }, "probability", nullptr,
                        QString());
  probability.setRange(std::make_pair(0.0, 1.0));
  probability.resize(400, 34);
  EXPECT_EQ(probability.shownTexts(), QStringList({"0.00", "probability", "1.00"}));
}

// Within each menu an access key (the underlined letter) opens one item:
// two items with the same letter make the key cycle between them instead.
// Save Boxes As… has its shortcut on every desktop (Qt's SaveAs key is unset
// on some).
TEST_F(WindowLayoutTest, MenuAccessKeysAreUniqueAndSaveAsHasItsShortcut) {
  std::function<void(QMenu*)> check = [&](QMenu* menu) {
    std::map<QChar, QString> seen;
    for (QAction* action : menu->actions()) {
      const QString text = action->text();
      const int amp = text.indexOf('&');
      if (amp >= 0 && amp + 1 < text.size() && text[amp + 1] != '&') {
        const QChar key = text[amp + 1].toLower();
        EXPECT_EQ(seen.count(key), 0u)
            << menu->title().toStdString() << ": '" << text.toStdString() << "' and '"
            << seen[key].toStdString() << "' share the access key " << QString(key).toStdString();
        seen[key] = text;
      }
      if (action->menu()) check(action->menu());
    }
  };
  size_t menus = 0;
  for (QAction* action : window_.menuBar()->actions())
    if (action->menu()) {
      check(action->menu());
      ++menus;
    }
  EXPECT_GE(menus, 5u);
  EXPECT_EQ(window_.findAction("Save Boxes As…")->shortcut(), QKeySequence("Ctrl+Shift+S"));
  // Redo answers Ctrl+Y as well as the platform's key.
  bool redo_with_ctrl_y = false;
  for (QAction* action : window_.findChildren<QAction*>())
    if (action->shortcuts().contains(QKeySequence::keyBindings(QKeySequence::Redo).value(0)))
      redo_with_ctrl_y = action->shortcuts().contains(QKeySequence("Ctrl+Y"));
  EXPECT_TRUE(redo_with_ctrl_y);
}

// Every item of the Export menu, and the Annotate items that are not one-key
// box edits, can be chosen from the keyboard with an access key.
TEST_F(WindowLayoutTest, ExportAndAnnotateItemsHaveAccessKeys) {
  const auto hasAccessKey = [](const QAction* action) {
    const int amp = action->text().indexOf('&');
    return amp >= 0 && amp + 1 < action->text().size() && action->text()[amp + 1] != '&';
  };
  for (QAction* menu_action : window_.menuBar()->actions()) {
    const QString title = menu_action->text().remove('&');
    if (title != "Export" || !menu_action->menu()) continue;
    for (QAction* action : menu_action->menu()->actions()) {
      if (!action->isSeparator()) {
        EXPECT_TRUE(hasAccessKey(action)) << action->text().toStdString();
      }
    }
  }
  for (const char* item :
       {"Add Box from Label Voxels", "Add Box at Clicked Point", "Add Boxes for All Labels",
        "Next Box", "Previous Box", "Delete Box", "Tighten Box to the Voxels Inside"}) {
    const QAction* action = window_.findAction(item);
    ASSERT_NE(action, nullptr) << item;
    EXPECT_TRUE(hasAccessKey(action)) << item;
  }
}

}  // namespace
}  // namespace lom::ui
