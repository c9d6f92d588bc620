#pragma once
// Colours by height, for maps whose voxels carry no useful label (geometry
// imported without label images has the single label __background__, which
// would paint everything one colour and hide the shape).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "lom/labels.hpp"

namespace lom {

// How voxel surfaces are coloured in pictures and in the studio.
enum class VoxelColouring {
  Labels,  // each voxel in its label's colour
  Height,  // by height along the map's up direction (HeightColours)
};

// The background label's colour in shaded views of a map (the studio's 3D view
// and map legend, `labeloctomap render` without --flat): its palette colour is
// black in the VOC palette, which would hide all shading.
inline constexpr Rgb kShadedBackgroundColour{150, 150, 160};
// The one colour rule of shaded views: label 0 in kShadedBackgroundColour,
// another label coloured pure black in dark grey (96, 96, 96) so that its shape
// stays visible, every other label in its colour; magenta for an id `labels`
// does not have.
[[nodiscard]] Rgb shadedLabelColour(const LabelSet& labels, int id);

// A colour ramp from low (blue) through cyan, green and yellow to high (red);
// t is clamped to [0, 1].
[[nodiscard]] Rgb heightRampColour(double t);

// Heights along `up`, from `lowest` to `highest`, mapped onto the ramp.
class HeightColours {
 public:
  // `up` need not be unit length; a zero or non-finite up means +z.
  HeightColours(const Eigen::Vector3d& up, double lowest, double highest);
  // The range spanned by `points`: all of them below kPercentileMinimum points,
  // else from the 1st to the 99th percentile of their heights (heights
  // beyond get the end colours). The middle of the ramp for a flat or empty set.
  static constexpr size_t kPercentileMinimum = 200;
  [[nodiscard]] static HeightColours spanning(const std::vector<Eigen::Vector3d>& points,
                                              const Eigen::Vector3d& up);

  [[nodiscard]] double height(const Eigen::Vector3d& point) const { return up_.dot(point); }
  // Where `point` lies between lowest (0) and highest (1); 0.5 when they coincide.
  [[nodiscard]] double fraction(const Eigen::Vector3d& point) const;
  [[nodiscard]] Rgb colour(const Eigen::Vector3d& point) const {
    return heightRampColour(fraction(point));
  }
  [[nodiscard]] const Eigen::Vector3d& up() const { return up_; }
  // The heights the ramp's ends stand for (lowest blue, highest red).
  [[nodiscard]] double lowest() const { return lowest_; }
  [[nodiscard]] double highest() const { return highest_; }

 private:
  Eigen::Vector3d up_;
  double lowest_;
  double highest_;
};

}  // namespace lom
