// Writes a synthetic scene as a sequence folder with annotations.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/npy.hpp"
#include "synth_internal.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMarkerFile = "synth.json";
constexpr const char* kFrameFolders[] = {"depth", "color", "label", "proba"};
constexpr double kSecondsPerFrame = 0.2;

[[noreturn]] void failFolder(const fs::path& out, const std::string& expected,
                             const std::string& found) {
  throw Error(out.string(), "output folder", expected, found);
}

// The folder may be new, empty, or an earlier synth output (marked by
// synth.json), whose sequence.json and frame files are removed first so that
// an interrupted run never leaves a sequence that mixes old and new frames.
void prepareFolder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) failFolder(out, "a folder", "a file");
    const bool earlier_output = fs::exists(out / kMarkerFile, ec);
    if (!earlier_output && !fs::is_empty(out, ec))
      failFolder(out, "a new or empty folder, or an earlier synth output (holding synth.json)",
                 "a non-empty folder without synth.json; not overwriting it");
    if (earlier_output) {
      const std::regex frame_file(R"(\d{6}\.(png|npy))");
      fs::remove(out / "sequence.json", ec);
      for (const char* folder : kFrameFolders) {
        if (!fs::is_directory(out / folder, ec)) continue;
        for (const auto& entry : fs::directory_iterator(out / folder, ec))
          if (std::regex_match(entry.path().filename().string(), frame_file))
            fs::remove(entry.path(), ec);
      }
    }
  }
  for (const char* folder : kFrameFolders) {
    fs::create_directories(out / folder, ec);
    if (ec) failFolder(out, "a folder that can be created and written", ec.message());
  }
}

void writeMarker(const SynthOptions& options, const fs::path& out) {
  const nlohmann::json marker = {
      {"format", "labeloctomap-synth"}, {"version", 1},
      {"seed", options.seed},           {"objects", options.objects},
      {"frames", options.frames},       {"views", options.views},
      {"width", options.width},         {"height", options.height},
      {"noise", options.noise},         {"segmenter_mistakes", options.segmenter_mistakes},
  };
  writeTextFileAtomically(out / kMarkerFile, marker.dump(2) + "\n");
}

std::string frameName(size_t index, const char* folder, const char* extension) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu", index);
  return std::string(folder) + "/" + name + extension;
}

void writeProbabilities(const fs::path& path, const ProbabilityImage& proba) {
  NpyArray array;
  array.type = NpyType::UInt8;
  array.shape = {static_cast<size_t>(proba.height), static_cast<size_t>(proba.width),
                 static_cast<size_t>(proba.channels)};
  array.bytes.resize(proba.values.size());
  for (size_t i = 0; i < proba.values.size(); ++i)
    array.bytes[i] = static_cast<std::uint8_t>(std::lround(proba.values[i] * 255.0f));
  writeNpy(path, array);
}

FrameRecord writeFrame(const SynthLayout& layout, const SynthOptions& options, size_t index,
                       const fs::path& out) {
  const SynthFrame frame = renderSynthFrame(layout, options, index);
  FrameRecord record;
  record.stamp = kSecondsPerFrame * static_cast<double>(index);
  record.T_world_camera = layout.T_world_camera[index];
  record.view = layout.view[index];
  record.depth = frameName(index, "depth", ".png");
  writeDepthPng(out / record.depth, frame.depth, layout.camera.depth_scale);
  if (options.write_color) {
    record.color = frameName(index, "color", ".png");
    writeColorPng(out / record.color, frame.color);
  }
  if (options.write_label) {
    record.label = frameName(index, "label", ".png");
    writeLabelPng(out / record.label, frame.label);
  }
  record.proba = frameName(index, "proba", ".npy");
  record.proba_labels = layout.proba_labels;
  writeProbabilities(out / record.proba, frame.proba);
  return record;
}

SynthScene writeScene(const SynthLayout& layout, const SynthOptions& options,
                      const fs::path& out) {
  prepareFolder(out);
  writeMarker(options, out);

  SynthScene scene;
  Sequence& sequence = scene.sequence;
  sequence.root = out;
  sequence.frame_id = "world";
  sequence.labels = apc2016Labels();
  sequence.camera = layout.camera;
  for (size_t i = 0; i < layout.T_world_camera.size(); ++i)
    sequence.frames.push_back(writeFrame(layout, options, i, out));

  scene.annotations = synthAnnotations(layout);
  saveAnnotations(scene.annotations, out / "annotations.json");
  saveSequence(sequence, out);  // last: only a complete scene is a valid sequence
  return scene;
}

}  // namespace

SynthScene writeSyntheticScene(const SynthOptions& options, const fs::path& out) {
  const SynthLayout layout = makeSynthLayout(options);
  std::error_code ec;
  const bool existed = fs::exists(out, ec);
  const bool fresh = !existed || (fs::is_directory(out, ec) && fs::is_empty(out, ec));
  try {
    return writeScene(layout, options, out);
  } catch (...) {
    // A run that fails (a full disk) takes away what it wrote into a new or
    // empty folder; an earlier output it was replacing stays marked by
    // synth.json, without sequence.json, so that the next run replaces it.
    if (fresh && !existed) {
      fs::remove_all(out, ec);
    } else if (fresh) {
      std::vector<fs::path> written;
      for (const auto& entry : fs::directory_iterator(out, ec)) written.push_back(entry.path());
      for (const auto& path : written) fs::remove_all(path, ec);
    }
    throw;
  }
}

}  // namespace lom
