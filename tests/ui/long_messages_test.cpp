// Messages that list many things stay on the screen: the boxes with unknown
// labels are listed up to ten, and a dialog shows the beginning of a long
// message with the whole of it under Show Details.
#include <gtest/gtest.h>

#include <QApplication>
#include <QMessageBox>
#include <QScreen>
#include <QTimer>

#include "lom/annotations.hpp"
#include "lom/labels.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/error_reporter.hpp"

namespace {

using lom::ui::shortMessage;

lom::Annotations boxesWithLabels(int count, int first_label) {
  lom::Annotations annotations;
  for (int i = 0; i < count; ++i) {
    lom::GroundTruthBox box;
    box.label = first_label + i % 50;
    box.box.size = Eigen::Vector3d(0.1, 0.1, 0.1);
    annotations.boxes.push_back(box);
  }
  return annotations;
}

TEST(LongMessages, BoxesWithUnknownLabelsAreListedUpToTen) {
  const lom::LabelSet labels = lom::apc2016Labels();  // 0..39
  const QString few = lom::ui::unknownLabelsMessage(boxesWithLabels(3, 40), labels, "b.json");
  EXPECT_EQ(few.count("is not a label of the sequence"), 3) << few.toStdString();
  EXPECT_FALSE(few.contains("more boxes")) << few.toStdString();

  lom::Annotations many = boxesWithLabels(300, 40);
  many.boxes[0].label = 3;  // one known
  const QString message = lom::ui::unknownLabelsMessage(many, labels, "b.json");
  EXPECT_EQ(message.count("is not a label of the sequence"), 10) << message.toStdString();
  EXPECT_TRUE(
      message.contains("b.json: boxes[1]: label 41 is not a label of the sequence (0 to "
                       "39)"))
      << message.toStdString();
  EXPECT_TRUE(
      message.contains("… and 289 more boxes; in all 299 of the 300 boxes have labels the "
                       "sequence does not have (40, 41, 42, 43, 44, 45, 46, 47, 48, 49, "
                       "…)"))
      << message.toStdString();
  EXPECT_TRUE(message.endsWith("change their label or delete them.")) << message.toStdString();
  EXPECT_LE(message.count('\n'), 13);
}

TEST(LongMessages, ALongMessageShowsItsBeginningAndItsAdvice) {
  EXPECT_FALSE(shortMessage("one line").shortened);
  EXPECT_EQ(shortMessage("one line").text, "one line");
  QStringList lines;
  for (int i = 0; i < 300; ++i) lines << QString("f.json: boxes[%1]: something is wrong").arg(i);
  const QString message = lines.join('\n') + "\n\nFix the file and open it again.";
  const auto shown = shortMessage(message);
  EXPECT_TRUE(shown.shortened);
  EXPECT_LE(shown.text.count('\n'), 16) << shown.text.toStdString();
  EXPECT_TRUE(shown.text.startsWith("f.json: boxes[0]: something is wrong\n"));
  EXPECT_TRUE(shown.text.contains("(290 more lines: Show Details… holds the whole message)"))
      << shown.text.toStdString();
  EXPECT_TRUE(shown.text.endsWith("\n\nFix the file and open it again."))
      << shown.text.toStdString();
  // One very long line is cut at a word.
  const QString sentence = QString("box ").repeated(2000) + "end";
  const auto cut = shortMessage(sentence);
  EXPECT_TRUE(cut.shortened);
  EXPECT_LT(cut.text.size(), 1500);
  EXPECT_TRUE(cut.text.contains("box …\n\n(cut short: Show Details… holds the whole message)"))
      << cut.text.toStdString();
}

TEST(LongMessages, TheDialogFitsTheScreenAndHoldsTheWholeMessageInItsDetails) {
  QStringList lines;
  for (int i = 0; i < 300; ++i) lines << QString("f.json: boxes[%1]: label 99 is unknown").arg(i);
  const QString message = lines.join('\n');
  QString detailed;
  int height = 0;
  QTimer::singleShot(50, [&] {
    for (QWidget* widget : QApplication::topLevelWidgets())
      if (auto* box = qobject_cast<QMessageBox*>(widget); box && box->isVisible()) {
        detailed = box->detailedText();
        height = box->sizeHint().height();
        box->accept();
      }
  });
  lom::ui::messageBoxErrorReporter(nullptr)("Many problems", message);
  EXPECT_EQ(detailed, message);
  ASSERT_GT(height, 0);
  EXPECT_LT(height, QApplication::primaryScreen()->availableGeometry().height());
}

}  // namespace
