// The Boxes panel's numeric fields: a value still being typed counts as an
// edit for every decision about unsaved boxes, and editing one angle leaves
// the other two exactly as they were.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QSettings>
#include <QStandardItemModel>
#include <QTest>
#include <QWheelEvent>
#include <cmath>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/box_edit_actions.hpp"
#include "lom/ui/box_editor_panel.hpp"
#include "lom/ui/box_math.hpp"
#include "lom/ui/scene_view.hpp"

namespace lom::ui {
namespace {

using fixture::qPath;

class BoxEditorTest : public fixture::DemoWindowTest {
 protected:
  void SetUp() override {
    DemoWindowTest::SetUp();
    window_.session().setAutoFuse(false);  // the fields need no map
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
    ASSERT_GT(boxes().boxCount(), 0);
    boxes().select(0);
  }
  void TearDown() override { boxes().undoStack().setClean(); }
  AnnotationsModel& boxes() { return window_.session().annotations(); }

  // Types `text` into centre x without pressing Enter or leaving the field.
  void typeIntoCentreX(const QString& text) {
    window_.activateWindow();
    ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
    QDoubleSpinBox& field = window_.boxEditor().field(0);
    field.setFocus();
    ASSERT_TRUE(QTest::qWaitFor([&] { return field.hasFocus(); }, 5000));
    field.selectAll();
    QTest::keyClicks(QApplication::focusWidget(), text);
    ASSERT_FALSE(boxes().isDirty());  // not committed yet
  }
};

// One box per object: the selected box's label list offers only its own label
// and labels without a box; the others are shown disabled.
TEST_F(BoxEditorTest, LabelsOtherBoxesHaveCannotBeChosen) {
  ASSERT_GE(boxes().boxCount(), 2);
  QComboBox& labels = window_.boxEditor().boxLabel();
  auto* items = qobject_cast<QStandardItemModel*>(labels.model());
  ASSERT_NE(items, nullptr);
  auto enabled = [&](int label) {
    const int row = labels.findData(label);
    EXPECT_GE(row, 0) << label;
    return row >= 0 && items->item(row)->isEnabled();
  };
  const int own = boxes().box(0).label, other = boxes().box(1).label;
  EXPECT_TRUE(enabled(own));
  EXPECT_FALSE(enabled(other));
  int unboxed = -1;
  for (int row = 0; row < labels.count() && unboxed < 0; ++row)
    if (boxes().indexOfLabel(labels.itemData(row).toInt()) < 0)
      unboxed = labels.itemData(row).toInt();
  ASSERT_GT(unboxed, 0);
  EXPECT_TRUE(enabled(unboxed));

  // Another box selected: the list follows it.
  boxes().select(1);
  EXPECT_TRUE(enabled(other));
  EXPECT_FALSE(enabled(own));
  // Its label changed to a free one: the old label becomes free.
  labels.setCurrentIndex(labels.findData(unboxed));
  emit labels.activated(labels.currentIndex());  // as a choice with the mouse
  EXPECT_EQ(boxes().box(1).label, unboxed);
  EXPECT_TRUE(enabled(other));
  boxes().select(0);
  EXPECT_FALSE(enabled(unboxed));
  EXPECT_TRUE(enabled(other));
}

// Letters typed into a label drop-down search its labels by name; they are
// not the window's one-key box edits (W moves the box forward) there, and
// still are with the focus elsewhere.
TEST_F(BoxEditorTest, LettersTypedIntoALabelDropDownDoNotEditTheBox) {
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  const double x = boxes().box(0).box.center.x();
  for (QComboBox* labels :
       {&window_.boxEditor().boxLabel(), window_.findChild<QComboBox*>("newBoxLabel")}) {
    ASSERT_NE(labels, nullptr);
    labels->setFocus();
    ASSERT_TRUE(QTest::qWaitFor([&] { return labels->hasFocus(); }, 5000));
    QTest::keyClick(labels, Qt::Key_W);
    QTest::keyClick(labels, Qt::Key_B);
    EXPECT_EQ(boxes().box(0).box.center.x(), x) << labels->objectName().toStdString();
  }
  // They find a label by its name (the entries start with its number, which
  // Qt's own search by first letter matched instead).
  QComboBox& new_label = *window_.findChild<QComboBox*>("newBoxLabel");
  new_label.setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return new_label.hasFocus(); }, 5000));
  ASSERT_GE(new_label.count(), 2);
  const int wanted = new_label.count() - 1;  // the last entry: not the current one
  const QString entry = new_label.itemText(wanted);
  const QString prefix = entry.mid(entry.indexOf(' ') + 1).left(4);
  ASSERT_TRUE(prefix.at(0).isLetter()) << entry.toStdString();
  QTest::keyClicks(&new_label, prefix);
  const QString chosen = new_label.currentText();
  EXPECT_TRUE(chosen.mid(chosen.indexOf(' ') + 1).startsWith(prefix))
      << chosen.toStdString() << " for " << prefix.toStdString();
  EXPECT_NE(new_label.currentIndex(), 0);
  boxes().undoStack().setClean();  // a label chosen by typing into the box's list is an edit
  QWidget& list = *window_.findChild<QWidget*>("boxList");
  list.setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return list.hasFocus(); }, 5000));
  QTest::keyClick(&list, Qt::Key_W);
  EXPECT_TRUE(boxes().isDirty());
  EXPECT_GT(boxes().box(0).box.center.x(), x);
}

TEST_F(BoxEditorTest, ValueBeingTypedIsNotLostWhenTheWindowCloses) {
  typeIntoCentreX("0.777");
  test::DialogAnswerer answer("Cancel");
  EXPECT_FALSE(window_.close());
  EXPECT_EQ(answer.questions.size(), 1);
  EXPECT_TRUE(boxes().isDirty());
  EXPECT_NEAR(boxes().box(0).box.center.x(), 0.777, 1e-12);
}

TEST_F(BoxEditorTest, ValueBeingTypedIsSaved) {
  typeIntoCentreX("0.321");
  window_.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(boxes().isDirty());
  const Annotations saved = loadAnnotations(folder_ / "annotations.json");
  EXPECT_NEAR(saved.boxes.front().box.center.x(), 0.321, 1e-12);
}

TEST_F(BoxEditorTest, ValueBeingTypedCountsBeforeAnotherSequenceOpens) {
  typeIntoCentreX("0.555");
  test::DialogAnswerer answer("Cancel");
  EXPECT_FALSE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_EQ(answer.questions.size(), 1);
  EXPECT_NEAR(boxes().box(0).box.center.x(), 0.555, 1e-12);
}

// A box beyond a field's usual range is shown as it is (the range widens):
// clamped, the field showed another box, and its first step moved the box
// hundreds of metres.
TEST_F(BoxEditorTest, ValuesBeyondAFieldsRangeAreShownAsTheyAre) {
  GroundTruthBox box = boxes().box(0);
  box.box.center.x() = 1500.25;
  box.box.center.y() = -2000.5;
  box.box.size.x() = 150.0;
  boxes().setBox(0, box, "far away");
  QDoubleSpinBox& x = window_.boxEditor().field(0);
  EXPECT_DOUBLE_EQ(x.value(), 1500.25);
  EXPECT_DOUBLE_EQ(window_.boxEditor().field(1).value(), -2000.5);
  EXPECT_DOUBLE_EQ(window_.boxEditor().field(3).value(), 150.0);
  x.stepDown();
  EXPECT_NEAR(boxes().box(0).box.center.x(), 1500.245, 1e-9) << "one step, not a jump";
}

// At pitch +-90 degrees roll and yaw turn about the same axis: the angles
// shown must still rebuild the box, and a one-degree edit turn it by one
// degree (noise in the vanishing entries turned it by up to 150).
TEST_F(BoxEditorTest, AnglesAtAPitchOfNinetyDegreesStillDescribeTheBox) {
  for (const double pitch : {M_PI / 2, -M_PI / 2}) {
    const Eigen::Quaterniond standing(Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
    const Eigen::Vector3d angles = rollPitchYaw(standing);
    EXPECT_NEAR(std::abs(angles.y()), M_PI / 2, 1e-9);
    EXPECT_LT(fromRollPitchYaw(angles).angularDistance(standing), 1e-6);
    GroundTruthBox box = boxes().box(0);
    box.box.rotation = standing;
    boxes().setBox(0, box, "standing");
    QDoubleSpinBox& yaw = window_.boxEditor().field(8);
    yaw.setValue(yaw.value() + 1.0);
    EXPECT_NEAR(boxes().box(0).box.rotation.angularDistance(standing) * 180.0 / M_PI, 1.0, 0.06);
  }
}

TEST_F(BoxEditorTest, EditingOneAngleKeepsTheOthersAtFullPrecision) {
  GroundTruthBox box = boxes().box(0);
  const double roll = 0.01234;   // 0.707°: the field shows 0.7
  const double pitch = -0.2345;  // -13.436°: the field shows -13.4
  const double yaw = 0.3;
  box.box.rotation = fromRollPitchYaw({roll, pitch, yaw});
  boxes().setBox(0, box, "set rotation");
  QDoubleSpinBox& yaw_field = window_.boxEditor().field(8);
  yaw_field.setValue(yaw_field.value() + 1.0);
  const Eigen::Vector3d after = rollPitchYaw(boxes().box(0).box.rotation);
  EXPECT_NEAR(after.x(), roll, 1e-9);
  EXPECT_NEAR(after.y(), pitch, 1e-9);
  EXPECT_NEAR(after.z(), (std::round(yaw * 1800.0 / M_PI) / 10.0 + 1.0) * M_PI / 180.0, 1e-9);
}

TEST_F(BoxEditorTest, TheWheelChangesAFieldOnlyWhenItHasTheFocus) {
  auto wheel = [](QWidget& widget) {
    const QPoint centre = widget.rect().center();
    QWheelEvent event(centre, widget.mapToGlobal(centre), QPoint(), QPoint(0, -120), Qt::NoButton,
                      Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(&widget, &event);
  };
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  const GroundTruthBox before = boxes().box(0);
  // Scrolling the panel past the fields: the box stays as it was.
  window_.setFocus();
  QDoubleSpinBox& pitch = window_.boxEditor().field(7);
  ASSERT_FALSE(pitch.hasFocus());
  wheel(pitch);
  wheel(window_.boxEditor().field(0));
  EXPECT_EQ(boxes().box(0).box.rotation.coeffs(), before.box.rotation.coeffs());
  EXPECT_EQ(boxes().box(0).box.center, before.box.center);
  EXPECT_FALSE(boxes().isDirty());
  // A field the user clicked into takes the wheel as before.
  QDoubleSpinBox& x = window_.boxEditor().field(0);
  x.setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return x.hasFocus(); }, 5000));
  wheel(x);
  EXPECT_NE(boxes().box(0).box.center.x(), before.box.center.x());
}

TEST_F(BoxEditorTest, AClickOnTheHandlesThatMovesNothingIsNotAnEdit) {
  const GroundTruthBox before = boxes().box(0);
  const int steps = boxes().undoStack().count();
  // What the handles give back for a plain click: the same box up to rounding.
  OrientedBox clicked = before.box;
  clicked.size.x() = std::nextafter(clicked.size.x(), 1.0);
  clicked.rotation.z() = std::nextafter(clicked.rotation.z(), 1.0);
  emit window_.sceneView().boxEdited(clicked);
  EXPECT_EQ(boxes().undoStack().count(), steps);
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(boxes().box(0).box.size, before.box.size);
  // A drag that moved the box by a millimetre is one.
  OrientedBox dragged = before.box;
  dragged.center.x() += 0.001;
  emit window_.sceneView().boxEdited(dragged);
  EXPECT_EQ(boxes().undoStack().count(), steps + 1);
  EXPECT_NEAR(boxes().box(0).box.center.x(), before.box.center.x() + 0.001, 1e-12);
}

TEST_F(BoxEditorTest, CtrlZInAFieldUndoesTheBoxEdit) {
  const double before = boxes().box(0).box.center.x();
  typeIntoCentreX("0.4");
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Return);
  ASSERT_NEAR(boxes().box(0).box.center.x(), 0.4, 1e-12);
  QDoubleSpinBox& field = window_.boxEditor().field(0);
  ASSERT_TRUE(field.hasFocus());
  QTest::keyClick(&field, Qt::Key_Z, Qt::ControlModifier);
  EXPECT_EQ(boxes().box(0).box.center.x(), before);
  QTest::keyClick(&field, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  EXPECT_NEAR(boxes().box(0).box.center.x(), 0.4, 1e-12);
  // A value still being typed: Ctrl+Z takes back that value only (it took
  // back the 0.4 as well and dropped the typing).
  field.selectAll();
  QTest::keyClicks(&field, "0.45");
  ASSERT_NEAR(boxes().box(0).box.center.x(), 0.4, 1e-12) << "typed, not entered";
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier);
  EXPECT_NEAR(boxes().box(0).box.center.x(), 0.4, 1e-12);
  EXPECT_NEAR(window_.boxEditor().field(0).value(), 0.4, 1e-9);
}

// Ctrl+Z in a key-step field undoes box edits too, as in every field.
TEST_F(BoxEditorTest, CtrlZInAKeyStepFieldUndoesTheBoxEdit) {
  const double before = boxes().box(0).box.center.x();
  typeIntoCentreX("0.4");
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Return);
  ASSERT_NEAR(boxes().box(0).box.center.x(), 0.4, 1e-12);
  QDoubleSpinBox* step = nullptr;
  for (QDoubleSpinBox* box : window_.boxEditor().findChildren<QDoubleSpinBox*>())
    if (box->suffix() == " m" && box->maximum() == 1.0) step = box;  // Move or Resize
  ASSERT_NE(step, nullptr);
  step->setFocus();
  QApplication::processEvents();
  QTest::keyClick(step, Qt::Key_Z, Qt::ControlModifier);
  EXPECT_EQ(boxes().box(0).box.center.x(), before);
}

// A box fit arrives after it was asked for (it runs on the map's thread): the
// value being typed into another box's field is kept, and so is that box's
// selection.
TEST_F(BoxEditorTest, ABoxFitArrivingLaterKeepsTheValueBeingTypedAndTheSelection) {
  StudioSession& session = window_.session();
  session.fuse();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, fixture::kTimeoutMs));
  const int label = *visibleObjectLabels().begin();
  boxes().removeBox(boxes().indexOfLabel(label));
  boxes().undoStack().setClean();
  boxes().select(0);
  const int edited = boxes().box(0).label;
  const int count = boxes().boxCount();
  session.setSelectedLabel(label);
  typeIntoCentreX("0.123");
  window_.findAction("Add Box from Label Voxels")->trigger();
  ASSERT_EQ(boxes().boxCount(), count);  // not yet: the fit is on its way
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return boxes().boxCount() == count + 1; }, fixture::kTimeoutMs));
  EXPECT_GE(boxes().indexOfLabel(label), 0);
  const int index = boxes().indexOfLabel(edited);
  ASSERT_GE(index, 0);
  EXPECT_NEAR(boxes().box(index).box.center.x(), 0.123, 1e-9);
  EXPECT_EQ(boxes().selected(), index);
  EXPECT_NEAR(window_.boxEditor().field(0).value(), 0.123, 1e-9);
}

// Key steps from a settings file edited by hand: out of range, not finite or
// no number at all. The keys must step what the Key steps fields can show.
TEST(BoxStepsTest, StepsFromTheSettingsAreKeptInTheFieldsRanges) {
  QSettings settings;
  const auto restore = [&settings] { settings.remove("studio/boxSteps"); };
  restore();
  settings.setValue("studio/boxSteps/move", 5.0);
  settings.setValue("studio/boxSteps/turn", -30.0);
  settings.setValue("studio/boxSteps/resize", "nan");
  BoxSteps steps = BoxSteps::load();
  EXPECT_EQ(steps.move, BoxSteps::kMaxLength);
  EXPECT_EQ(steps.turn, BoxSteps::kMinTurn);
  EXPECT_EQ(steps.resize, BoxSteps{}.resize);
  settings.setValue("studio/boxSteps/move", "abc");
  settings.setValue("studio/boxSteps/turn", 200.0);
  settings.setValue("studio/boxSteps/resize", 0.0);
  steps = BoxSteps::load();
  EXPECT_EQ(steps.move, BoxSteps{}.move);
  EXPECT_EQ(steps.turn, BoxSteps::kMaxTurn);
  EXPECT_EQ(steps.resize, BoxSteps::kMinLength);
  settings.setValue("studio/boxSteps/move", 0.02);  // in range: as stored
  EXPECT_EQ(BoxSteps::load().move, 0.02);
  restore();
}

}  // namespace
}  // namespace lom::ui
