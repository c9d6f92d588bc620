// The images of a frame that fusion reads.
#include "lom/fusion.hpp"
#include "lom/segmenter.hpp"

namespace lom {

FrameParts fusionPartsOf(const Sequence& sequence, size_t index, const Segmenter* segmenter) {
  const FrameRecord& record = sequence.frames.at(index);
  FrameParts parts{false, false, false, false};
  if (segmenterRunsOn(sequence, index, segmenter))
    parts.color = true;
  else if (!record.proba.empty())
    parts.proba = true;
  else
    parts.label = true;  // makeEvidence says so when there is none either
  return parts;
}

FrameData loadFusionFrame(const Sequence& sequence, size_t index, const Segmenter* segmenter) {
  FrameData frame = loadFrame(sequence, index, fusionPartsOf(sequence, index, segmenter));
  addSegmenterProbabilities(sequence, index, segmenter, frame);
  return frame;
}

}  // namespace lom
