#pragma once
// --segmenter MODEL.onnx: run a segmentation network on the colour image of
// every frame without a proba, or with one made from its label image (fuse, score, segment).
// docs/segmenter.md.
#include <memory>

#include "args.hpp"
#include "lom/segmenter.hpp"

namespace lom::cli {

// The option's name, for Args::expectOnly.
inline constexpr const char* kSegmenterOption = "segmenter";

// Loads the model named by --segmenter (and MODEL.json beside it) now, so that a
// bad model fails before any fusion; nullptr when the option is absent. Cache
// warnings are printed to stderr as notes.
[[nodiscard]] std::shared_ptr<const Segmenter> segmenterFromArgs(const Args& args);

// Same, as the non-const object `segment` needs; `required` makes --segmenter mandatory.
[[nodiscard]] std::shared_ptr<Segmenter> loadSegmenterOption(const Args& args, bool required);

// One line describing what the segmenter did, e.g.
// "segmenter net.onnx: 4 network runs, 2 outputs from the cache".
[[nodiscard]] std::string segmenterSummary(const Segmenter& segmenter);

}  // namespace lom::cli
