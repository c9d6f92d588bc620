#pragma once
// The synthetic shelf-bin scene behind `labeloctomap-studio --demo`.
#include <QString>

#include "lom/synth.hpp"

namespace lom::ui {

// The cache folder the demo is written to (created on demand).
[[nodiscard]] QString defaultDemoFolder();

// Writes the scene into `folder` unless a previous run left it there already,
// and returns the folder. Throws lom::Error when it cannot be written.
QString prepareDemoScene(const QString& folder, const SynthOptions& options = {});

}  // namespace lom::ui
