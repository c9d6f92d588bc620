#pragma once
// What the last click in the 3D view hit: the voxel's label and the top five
// of its probability vector.
#include <QLabel>

#include "lom/label_map.hpp"

namespace lom::ui {

class StudioSession;

class PickedVoxelView : public QLabel {
  Q_OBJECT

 public:
  explicit PickedVoxelView(StudioSession& session, QWidget* parent = nullptr);
  // The text for one voxel, e.g. "label 3 crayola_24_ct, p = 0.91" and the top 5 lines;
  // names longer than `max_name_characters` are shortened with "…" (-1: never).
  // Without `map_has_frames` (reset, or a fusion that has fused no frame yet)
  // an unknown voxel is said to be so because there is no map.
  [[nodiscard]] static QString describe(const Eigen::Vector3d& point, const VoxelState& voxel,
                                        const LabelSet& labels, int max_name_characters = 32,
                                        bool map_has_frames = true);

 private:
  StudioSession& session_;
};

}  // namespace lom::ui
