// labeloctomap synth: writes a synthetic shelf-bin sequence with annotations.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>

#include "args.hpp"
#include "commands.hpp"
#include "lom/synth.hpp"
#include "output_paths.hpp"

namespace lom::cli {

namespace {

int boundedInteger(const Args& args, const std::string& name, long fallback, long low, long high,
                   const std::string& range_text) {
  const long value = args.integer(name, fallback);
  if (value < low || value > high)
    throw UsageError("option --" + name + " must be " + range_text + ", got " +
                     std::to_string(value));
  return static_cast<int>(value);
}

std::uint64_t parseSeed(const Args& args) {
  const auto text = args.option("seed");
  if (!text) return SynthOptions{}.seed;
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text->c_str(), &end, 10);
  const bool digits =
      !text->empty() &&
      std::all_of(text->begin(), text->end(), [](unsigned char c) { return std::isdigit(c); });
  if (!digits || *end != '\0' || errno == ERANGE)
    throw UsageError("option --seed expects a non-negative integer below 2^64, got '" + *text +
                     "'");
  return value;
}

std::string range(long low, long high) {
  return "between " + std::to_string(low) + " and " + std::to_string(high);
}

}  // namespace

int runSynth(const Words& words) {
  const Args args(words, {"no-noise", "perfect-segmenter"});
  args.expectOnly({"out", "seed", "objects", "frames", "views", "width", "height", "no-noise",
                   "perfect-segmenter"},
                  0);
  const std::string out = args.required("out");
  checkOutputFolder(out, "out", "the scene", {});
  checkHoldsNoFramesOfSequencesAbove(out, "out", "synth");
  SynthOptions options;
  options.seed = parseSeed(args);
  options.objects = boundedInteger(args, "objects", options.objects, 1, kSynthMaxObjects,
                                   range(1, kSynthMaxObjects));
  options.frames = boundedInteger(args, "frames", options.frames, kSynthMinViews, kSynthMaxFrames,
                                  range(kSynthMinViews, kSynthMaxFrames));
  options.views = boundedInteger(args, "views", options.views, kSynthMinViews, options.frames,
                                 range(kSynthMinViews, options.frames) + " (--frames)");
  options.width = boundedInteger(args, "width", options.width, kSynthMinWidth, kSynthMaxImageSide,
                                 range(kSynthMinWidth, kSynthMaxImageSide));
  options.height = boundedInteger(args, "height", options.height, kSynthMinHeight,
                                  kSynthMaxImageSide, range(kSynthMinHeight, kSynthMaxImageSide));
  options.noise = !args.flag("no-noise");
  options.segmenter_mistakes = !args.flag("perfect-segmenter");

  const auto start = std::chrono::steady_clock::now();
  const SynthScene scene = writeSyntheticScene(options, out);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  int views = 0;
  for (const auto& frame : scene.sequence.frames) views += frame.view ? 1 : 0;
  std::cout << "wrote " << out << " (seed " << options.seed << ", " << seconds << " s)\n"
            << "  sequence.json: " << scene.sequence.frames.size() << " frames (" << views
            << " views), " << options.width << "x" << options.height << ", "
            << scene.sequence.labels.size() << " labels\n"
            << "  annotations.json: " << scene.annotations.boxes.size() << " objects\n";
  for (const auto& box : scene.annotations.boxes)
    std::cout << "    " << box.label << " " << box.name << "\n";
  std::cout << "  frame files: depth/, color/, label/ (.png), proba/ (.npy, "
            << scene.sequence.frames.front().proba_labels.size() << " channels)\n";
  return 0;
}

}  // namespace lom::cli
