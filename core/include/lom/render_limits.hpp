#pragma once
// The largest picture `render` and the studio's screenshots draw, checked by
// the command line whether or not the build can render.

namespace lom::render {

// Each side at most 16384 pixels and 2^27 pixels in all (16384 x 8192;
// Mesa's offscreen buffers under Xvfb read back black beyond).
inline constexpr int kMaxRenderSide = 16384;
inline constexpr long long kMaxRenderPixels = 1LL << 27;

}  // namespace lom::render
