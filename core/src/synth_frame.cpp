// One synthetic frame: ray casting, then the sensor and the segmenter.
#include "synth_internal.hpp"

namespace lom {

SynthFrame renderSynthFrame(const SynthLayout& layout, const SynthOptions& options, size_t index) {
  const synth::SurfaceImage surface = synth::castRays(layout, index);
  SynthFrame frame;
  synth::Rng depth_rng(synth::streamSeed(options.seed, synth::Stream::Depth, index));
  frame.depth = synth::senseDepth(surface, layout.camera.depth_scale, options.noise, depth_rng);
  synth::Rng color_rng(synth::streamSeed(options.seed, synth::Stream::Color, index));
  frame.color = synth::shadeColor(surface, color_rng);
  frame.label.width = surface.width;
  frame.label.height = surface.height;
  frame.label.ids = surface.label;
  // Index 0 of the segmenter stream chose the channels (makeSynthLayout).
  synth::Rng segmenter_rng(synth::streamSeed(options.seed, synth::Stream::Segmenter, index + 1));
  frame.proba = synth::simulateSegmenter(frame.label, layout.proba_labels,
                                         options.segmenter_mistakes, segmenter_rng);
  return frame;
}

}  // namespace lom
