#pragma once
// The playback buttons' icons (play, pause, first, previous, next, last),
// drawn in the palette's button text colour: Qt's own media icons are dark
// whatever the palette, and vanish on a dark desktop theme.
#include <QIcon>
#include <QPalette>

namespace lom::ui {

enum class MediaIcon { Play, Pause, First, Previous, Next, Last };

// Normal in `palette`'s ButtonText colour, Disabled in its disabled one.
[[nodiscard]] QIcon mediaIcon(MediaIcon kind, const QPalette& palette);

}  // namespace lom::ui
