// Writes a synthetic scene as a sequence folder with annotations.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <vector>

#include "json_text.hpp"
#include "lom/annotations.hpp"
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

bool sameBoxes(const Annotations& a, const Annotations& b) {
  if (a.boxes.size() != b.boxes.size()) return false;
  for (size_t i = 0; i < a.boxes.size(); ++i) {
    const GroundTruthBox &x = a.boxes[i], &y = b.boxes[i];
    constexpr double kWritten = 1e-9;  // what a round trip through the JSON text keeps
    if (x.label != y.label || x.name != y.name || !x.box.center.isApprox(y.box.center, kWritten) ||
        !x.box.size.isApprox(y.box.size, kWritten) ||
        !x.box.rotation.coeffs().isApprox(y.box.rotation.coeffs(), kWritten))
      return false;
  }
  return true;
}

// The annotations.json of an earlier synth output is replaced only when it
// still holds the boxes that run wrote (its options are in synth.json): boxes
// edited since, e.g. in the studio, are the user's work.
void checkBoxesUnedited(const fs::path& out) {
  std::error_code ec;
  const fs::path boxes = out / "annotations.json";
  if (!fs::exists(boxes, ec)) return;
  const std::string keep = "; move annotations.json away to keep it, or choose another folder";
  std::optional<Annotations> written;
  try {
    const nlohmann::json marker = json_text::parseFile(out / kMarkerFile, "synth.json");
    SynthOptions earlier;
    earlier.seed = marker.at("seed").get<std::uint64_t>();
    earlier.objects = marker.at("objects").get<int>();
    earlier.frames = marker.at("frames").get<int>();
    earlier.views = marker.at("views").get<int>();
    earlier.width = marker.at("width").get<int>();
    earlier.height = marker.at("height").get<int>();
    written = synthAnnotations(makeSynthLayout(earlier));
  } catch (const std::exception&) {
    failFolder(out, "an earlier synth output whose synth.json says which boxes it wrote",
               "a synth.json that cannot be read, beside an annotations.json" + keep);
  }
  std::optional<Annotations> present;
  try {
    present = loadAnnotations(boxes);
  } catch (const std::exception&) {
  }
  if (!present || !sameBoxes(*present, *written))
    failFolder(out, "an earlier synth output whose annotations.json holds the boxes synth wrote",
               "an annotations.json with other boxes (edited since, e.g. in the studio)" + keep);
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
      checkBoxesUnedited(out);
      const std::regex frame_file(R"(\d{6}\.(png|npy))");
      fs::remove(out / "sequence.json", ec);
      // The boxes the earlier run wrote (checked above): a run that fails
      // leaves none of another seed's beside its own synth.json.
      fs::remove(out / "annotations.json", ec);
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
  // (A symbolic link leading nowhere is there: never removed below.)
  const bool existed = fs::symlink_status(out, ec).type() != fs::file_type::not_found;
  const bool fresh = !existed || (fs::is_directory(out, ec) && fs::is_empty(out, ec));
  // What a run stopped by a signal (Ctrl-C) leaves is what one that fails
  // leaves: the new folders it made, or the new or empty folder's new
  // entries, are recorded until the scene is complete.
  // The folder made for the scene goes with everything in it; the parents
  // made for it only while empty (`a/../scene` makes `a` too, which does
  // not hold the scene). Each is named as it resolves once made (`a/..` is
  // the folder holding `a`): one that exists already is the user's, however
  // it is named.
  std::vector<fs::path> missing;
  if (!existed)
    for (const fs::path& folder : missingFolders(out)) {
      const fs::path real = fs::weakly_canonical(folder, ec);
      if (!ec && !fs::exists(real, ec)) missing.push_back(real);
    }
  const fs::path scene = existed ? out : fs::weakly_canonical(out, ec);
  std::vector<PendingOutput> pending;
  if (!existed) {
    pending.emplace_back(scene, PendingOutput::Kind::Tree);
    for (const fs::path& folder : missing)
      pending.emplace_back(folder, PendingOutput::Kind::EmptyFolder);
  } else if (fresh) {
    for (const char* folder : kFrameFolders)
      pending.emplace_back(out / folder, PendingOutput::Kind::Tree);
    for (const char* file : {kMarkerFile, "annotations.json"})
      pending.emplace_back(out / file, PendingOutput::Kind::File);
  }
  try {
    return writeScene(layout, options, out);
  } catch (...) {
    // A run that fails (a full disk) takes away what it wrote into a new or
    // empty folder; an earlier output it was replacing stays marked by
    // synth.json, without sequence.json, so that the next run replaces it.
    if (!existed) {
      fs::remove_all(scene, ec);
      for (const fs::path& folder : missing) fs::remove(folder, ec);  // innermost first; if empty
    } else if (fresh) {
      std::vector<fs::path> written;
      for (const auto& entry : fs::directory_iterator(out, ec)) written.push_back(entry.path());
      for (const auto& path : written) fs::remove_all(path, ec);
    }
    throw;
  }
}

}  // namespace lom
