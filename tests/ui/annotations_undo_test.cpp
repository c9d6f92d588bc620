// Undo of an added box brings back the selection of before the add (it moved
// to the box before the removed one: the last box, not the one the user had).
#include <gtest/gtest.h>

#include "lom/ui/annotations_model.hpp"

namespace lom::ui {
namespace {

GroundTruthBox boxOfLabel(int label) {
  GroundTruthBox box;
  box.label = label;
  box.name = "label " + std::to_string(label);
  box.box.center = Eigen::Vector3d(0.1 * label, 0.0, 0.0);
  box.box.size = Eigen::Vector3d(0.05, 0.05, 0.05);
  return box;
}

TEST(AnnotationsUndoTest, UndoOfAnAddSelectsTheBoxSelectedBefore) {
  AnnotationsModel model;
  Annotations start;
  for (int label : {4, 6, 13}) start.boxes.push_back(boxOfLabel(label));
  model.reset(start, {});
  model.select(0);
  model.addBox(boxOfLabel(19));
  EXPECT_EQ(model.selected(), 3);  // the new box
  model.undoStack().undo();
  EXPECT_EQ(model.boxCount(), 3);
  EXPECT_EQ(model.selected(), 0);
  model.undoStack().redo();
  EXPECT_EQ(model.selected(), 3);

  // Several adds as one step (Add Boxes for All Labels), nothing selected before.
  model.select(-1);
  model.undoStack().beginMacro("Add boxes");
  model.addBox(boxOfLabel(20));
  model.addBox(boxOfLabel(21));
  model.undoStack().endMacro();
  model.undoStack().undo();
  EXPECT_EQ(model.boxCount(), 4);
  EXPECT_EQ(model.selected(), -1);
}

}  // namespace
}  // namespace lom::ui
