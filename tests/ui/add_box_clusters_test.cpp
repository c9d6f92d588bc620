// A box fitted to a label's voxels encloses their largest cluster only: when
// the label's other clusters hold a noticeable share of its voxels (an object
// seen in parts, or two objects of one label), the status bar says how many
// were left out, for Add Box from Label Voxels and Add Boxes for All Labels.
#include <gtest/gtest.h>

#include <QAction>
#include <QStatusBar>
#include <QTest>

#include "demo_window_fixture.hpp"
#include "lom/box_fit.hpp"
#include "lom/fusion.hpp"
#include "lom/objects.hpp"
#include "lom/ui/annotations_model.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class AddBoxClustersTest : public fixture::DemoWindowTest {
 protected:
  void SetUp() override {
    DemoWindowTest::SetUp();
    window_.session().setAutoFuse(false);
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
    // The demo fused, and a second part of one object's label placed beside
    // the bin: the label's voxels in two clusters, the smaller a third of the
    // larger's size or so.
    LabelMap map = fuseSequence(loadSequence(folder_), FusionOptions{});
    label_ = *visibleObjectLabels().begin();
    const size_t before = map.voxelsOfLabel(label_).size();
    ASSERT_GT(before, 30u);
    const auto bounds = map.bounds();
    ASSERT_TRUE(bounds.has_value());
    OrientedBox part;
    const double edge = map.parameters().resolution;
    const int side = std::max(2, static_cast<int>(std::cbrt(before / 3.0)));
    part.size = Eigen::Vector3d::Constant(side * edge);
    part.center = bounds->second + Eigen::Vector3d::Constant(0.1 + 0.5 * side * edge);
    ASSERT_GT(rasterizeBox(map, part, label_), 0u);
    const std::vector<VoxelKey> voxels = map.voxelsOfLabel(label_);
    const auto clusters = voxelClusters(voxels, 2.0);
    ASSERT_GE(clusters.size(), 2u);
    label_voxels_ = voxels.size();
    fitted_voxels_ = clusters.front().size();
    other_clusters_ = clusters.size() - 1;
    ASSERT_GT(label_voxels_ - fitted_voxels_, label_voxels_ / 20);
    name_ = QString::fromStdString(truth_.find(label_)->name);
    const auto path = temp_.path() / "two_parts.ot";
    map.save(path);
    window_.session().openMap(qPath(path));
    ASSERT_TRUE(QTest::qWaitFor(
        [&] { return !window_.session().isOpeningMap() && !window_.session().worker().isFusing(); },
        kTimeoutMs));
    QTest::qWait(50);
    ASSERT_TRUE(errors_.empty()) << errors_.front().toStdString();
    // The label gets its box anew.
    AnnotationsModel& model = window_.session().annotations();
    if (model.indexOfLabel(label_) >= 0) model.removeBox(model.indexOfLabel(label_));
  }
  void TearDown() override { window_.session().annotations().undoStack().setClean(); }

  // What the status bar says of the label's box.
  [[nodiscard]] QString expectedNote() const {
    return QString("fitted to %1 of %2 voxels of %3; %4 more in %5 left out")
        .arg(fitted_voxels_)
        .arg(label_voxels_)
        .arg(name_)
        .arg(label_voxels_ - fitted_voxels_)
        .arg(other_clusters_ == 1 ? QString("another cluster")
                                  : QString("%1 other clusters").arg(other_clusters_));
  }
  bool waitForBox() {
    return QTest::qWaitFor(
        [&] { return window_.session().annotations().indexOfLabel(label_) >= 0; }, kTimeoutMs);
  }

  int label_ = -1;
  size_t label_voxels_ = 0, fitted_voxels_ = 0, other_clusters_ = 0;
  QString name_;
};

TEST_F(AddBoxClustersTest, ABoxFittedToPartOfItsLabelSaysHowMuchWasLeftOut) {
  window_.session().setSelectedLabel(label_);
  window_.findAction("Add Box from Label Voxels")->trigger();
  ASSERT_TRUE(waitForBox());
  QTest::qWait(20);
  const QString message = window_.statusBar()->currentMessage();
  EXPECT_TRUE(message.contains(expectedNote())) << message.toStdString();
  EXPECT_TRUE(errors_.empty());
}

TEST_F(AddBoxClustersTest, BoxesForAllLabelsSayWhichWereFittedToPartOfTheirLabel) {
  window_.findAction("Add Boxes for All Labels")->trigger();
  ASSERT_TRUE(waitForBox());
  QTest::qWait(20);
  const QString message = window_.statusBar()->currentMessage();
  EXPECT_TRUE(message.startsWith("Added 1 box fitted to label voxels")) << message.toStdString();
  EXPECT_TRUE(message.contains(expectedNote())) << message.toStdString();
  EXPECT_TRUE(errors_.empty());
}

}  // namespace
}  // namespace lom::ui
