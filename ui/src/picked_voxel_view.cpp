#include "lom/ui/picked_voxel_view.hpp"

#include <algorithm>
#include <numeric>

#include "lom/ui/elision.hpp"
#include "lom/ui/map_snapshot.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

PickedVoxelView::PickedVoxelView(StudioSession& session, QWidget* parent)
    : QLabel(parent), session_(session) {
  setObjectName("pickedVoxel");
  setWordWrap(true);
  setAlignment(Qt::AlignTop | Qt::AlignLeft);
  // Its numbers can be selected and copied with the keyboard too (Tab reaches it).
  setTextInteractionFlags(Qt::TextSelectableByMouse | Qt::TextSelectableByKeyboard);
  setFocusPolicy(Qt::StrongFocus);
  const QString hint = tr("Click a voxel in the 3D view to see its probabilities.");
  setText(hint);
  // The voxel clicked is looked up again whenever the map changes (each
  // snapshot of a fusion, a threshold, Reset Map, a map opened), so that the
  // panel never shows the probabilities of a map that is gone; another
  // sequence forgets the point.
  connect(&session_.worker(), &MapWorker::snapshotChanged, this, [this] {
    if (const auto& point = session_.pickedPoint()) session_.worker().pick(*point);
  });
  connect(&session_, &StudioSession::pickedPointChanged, this, [this, hint] {
    if (session_.pickedPoint()) return;
    setText(hint);
    setToolTip({});
  });
  connect(&session_.worker(), &MapWorker::voxelPicked, this,
          [this](const Eigen::Vector3d& point, const VoxelState& voxel) {
            // Only the answer for the point picked now: one asked before
            // another sequence (or pick) replaced it describes another map.
            const auto& picked = session_.pickedPoint();
            if (!picked || *picked != point) return;
            const auto sequence = session_.sequence();
            const LabelSet labels = sequence ? sequence->labels : LabelSet{};
            const auto snapshot = session_.worker().snapshot();
            const bool has_frames = snapshot && snapshot->frames_fused > 0;
            setText(describe(point, voxel, labels, 32, has_frames));
            // Long names are shortened in the text: the tooltip tells them whole.
            const QString whole = describe(point, voxel, labels, -1, has_frames);
            setToolTip(whole == text() ? QString() : whole);
          });
}

QString PickedVoxelView::describe(const Eigen::Vector3d& point, const VoxelState& voxel,
                                  const LabelSet& labels, int max_name_characters,
                                  bool map_has_frames) {
  auto name = [&](int id) {
    if (!labels.contains(id)) return QString::number(id);
    const QString whole = QString::fromStdString(labels.at(id).name);
    return max_name_characters < 0 ? whole : shortName(whole, max_name_characters);
  };
  const int decimals = voxel.known ? coordinateDecimals(voxel.size) : 3;
  QString text = tr("Point (%1, %2, %3)\n")
                     .arg(point.x(), 0, 'f', decimals)
                     .arg(point.y(), 0, 'f', decimals)
                     .arg(point.z(), 0, 'f', decimals);
  // The voxel described: after a re-fusion at another resolution (or where
  // the tree has merged equal voxels) it is not the one first clicked.
  if (voxel.known && voxel.size > 0.0)
    text += tr("Voxel of %1 centred at (%2, %3, %4)\n")
                .arg(voxel.size < 1.0 ? tr("%1 cm").arg(voxel.size * 100.0, 0, 'g', 3)
                                      : tr("%1 m").arg(voxel.size, 0, 'g', 3))
                .arg(voxel.center.x(), 0, 'f', decimals)
                .arg(voxel.center.y(), 0, 'f', decimals)
                .arg(voxel.center.z(), 0, 'f', decimals);
  if (!voxel.known && !map_has_frames)
    return text + tr("No map yet: no frame is fused (Fusion ▸ Fuse Sequence, or File ▸ Open "
                     "Map…).");
  if (!voxel.known) return text + tr("Unknown voxel (never observed).");
  text += tr("%1: label %2 %3\n")
              .arg(voxel.occupied ? tr("Occupied") : tr("Free"))
              .arg(voxel.label)
              .arg(name(voxel.label));
  const std::vector<float>& p = voxel.probabilities;
  if (p.empty()) return text.trimmed();
  // Labels a voxel never saw evidence for share its lowest probability (most
  // often the clamping floor): one line for them all, not a few picked at
  // random among equals as if they were the runners-up.
  const float lowest = *std::min_element(p.begin(), p.end());
  auto at_lowest = [&](size_t id) { return p[id] <= lowest + 1e-6f; };
  std::vector<int> order;
  for (size_t id = 0; id < p.size(); ++id)
    if (!at_lowest(id)) order.push_back(static_cast<int>(id));
  const size_t lowest_count = p.size() - order.size();
  const size_t top = std::min<size_t>(5, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(top), order.end(),
                    [&](int a, int b) {  // ties by label id, as the argmax breaks them
                      const float pa = p[static_cast<size_t>(a)], pb = p[static_cast<size_t>(b)];
                      return pa > pb || (pa == pb && a < b);
                    });
  for (size_t i = 0; i < top; ++i)
    text += tr("  %1  %2 %3\n")
                .arg(p[static_cast<size_t>(order[i])], 0, 'f', 3)
                .arg(order[i])
                .arg(name(order[i]));
  if (order.size() > top)
    text += tr("  …  %1 more above %2\n").arg(order.size() - top).arg(lowest, 0, 'f', 3);
  if (lowest_count == 1) {
    const int id = static_cast<int>(
        std::find_if(p.begin(), p.end(), [&](float v) { return v <= lowest + 1e-6f; }) - p.begin());
    text += tr("  %1  %2 %3\n").arg(lowest, 0, 'f', 3).arg(id).arg(name(id));
  } else {
    text += lowest_count == p.size()
                ? tr("  %1  all %2 labels alike\n").arg(lowest, 0, 'f', 3).arg(lowest_count)
                : tr("  %1  %2 other labels\n").arg(lowest, 0, 'f', 3).arg(lowest_count);
  }
  return text.trimmed();
}

}  // namespace lom::ui
