#include "segmenter_option.hpp"

#include <iostream>

namespace lom::cli {

std::shared_ptr<Segmenter> loadSegmenterOption(const Args& args, bool required) {
  const auto model = args.option(kSegmenterOption);
  if (!model) {
    if (required) throw UsageError(std::string("missing option --") + kSegmenterOption);
    return nullptr;
  }
  if (model->empty())
    throw UsageError(std::string("option --") + kSegmenterOption +
                     " expects the path of an ONNX model (MODEL.onnx)");
  SegmenterOptions options;
  options.warn = [](const std::string& message) { std::cerr << "note: " << message << "\n"; };
  return Segmenter::load(*model, options);
}

std::shared_ptr<const Segmenter> segmenterFromArgs(const Args& args) {
  return loadSegmenterOption(args, false);
}

std::string segmenterSummary(const Segmenter& segmenter) {
  const SegmenterStats stats = segmenter.stats();
  const size_t cached = stats.memory_hits + stats.disk_hits;
  return "segmenter " + segmenter.modelPath().filename().string() + ": " +
         std::to_string(stats.inferences) +
         (stats.inferences == 1 ? " network run, " : " network runs, ") + std::to_string(cached) +
         (cached == 1 ? " output" : " outputs") + " from the cache";
}

}  // namespace lom::cli
