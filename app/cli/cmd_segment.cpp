// labeloctomap segment: run a segmentation network on the colour images of a
// sequence and write its probability images into the sequence (docs/segmenter.md).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "args.hpp"
#include "commands.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/npy.hpp"
#include "lom/segmenter.hpp"
#include "lom/sequence.hpp"
#include "output_paths.hpp"
#include "segmenter_option.hpp"

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

NpyType parseDtype(const std::string& text) {
  if (text == "float32") return NpyType::Float32;
  if (text == "float16") return NpyType::Float16;
  if (text == "uint8") return NpyType::UInt8;
  throw UsageError("option --dtype expects float32, float16 or uint8, got '" + text + "'");
}

const char* dtypeName(NpyType type) {
  return type == NpyType::Float16 ? "float16" : type == NpyType::UInt8 ? "uint8" : "float32";
}

std::string frameList(const std::vector<size_t>& frames) {
  std::ostringstream text;
  for (size_t i = 0; i < frames.size() && i < 8; ++i) text << (i ? ", " : "") << frames[i];
  if (frames.size() > 8) text << ", ... (" << frames.size() << " frames)";
  return text.str();
}

std::string probaFileName(size_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.npy", frame);
  return name;
}

// The probability images of `frames` go to `folder`: it must be a folder (or absent), and
// no image may land on a folder, a device, or a file of the sequence other than the
// proba image it replaces (--all).
void checkOutputs(const Sequence& sequence, const std::vector<size_t>& frames,
                  const fs::path& folder) {
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    throw UsageError("--out-dir " + folder.string() +
                     " is an existing file; expected a folder for the probability images "
                     "(created when missing)");
  // A folder to create under an existing file cannot be made: said before any work.
  if (const auto file = fileInPlaceOfFolder(folder.parent_path()))
    throw UsageError("--out-dir " + folder.string() + " lies under " + file->string() +
                     ", an existing file; expected a folder for the probability images "
                     "(created when missing)");
  if (!fs::is_directory(folder, ec)) return;  // nothing can be in the way yet
  struct Named {
    size_t frame;
    const char* field;
  };
  std::map<fs::path, Named> named;  // canonical path of every file the sequence names
  for (size_t j = 0; j < sequence.frames.size(); ++j) {
    const FrameRecord& frame = sequence.frames[j];
    const std::pair<const std::string*, const char*> fields[] = {{&frame.depth, "depth"},
                                                                 {&frame.color, "color"},
                                                                 {&frame.proba, "proba"},
                                                                 {&frame.label, "label"}};
    for (const auto& [name, field] : fields) {
      if (name->empty()) continue;
      const fs::path path = fs::canonical(sequence.pathOf(*name), ec);
      if (!ec) named.emplace(path, Named{j, field});
    }
  }
  CommandInputs none;
  for (const size_t i : frames) {
    const fs::path target = folder / probaFileName(i);
    checkOutputInFolder(target, "out-dir", none);
    const fs::path path = fs::canonical(target, ec);
    if (ec) continue;  // not there yet
    const auto found = named.find(path);
    if (found == named.end()) {
      // Nor a file of another sequence (its frames, its sequence.json, its boxes).
      checkNotASequenceFile(target, "out-dir");
      continue;
    }
    const auto& [frame, field] = found->second;
    if (frame == i && std::string(field) == "proba") continue;  // replaced on purpose
    throw UsageError("--out-dir: writing " + target.string() + " for frame " + std::to_string(i) +
                     " would overwrite frames[" + std::to_string(frame) + "]." + field + " of " +
                     (sequence.root / "sequence.json").string() + "; choose another --out-dir");
  }
}

bool allLabelsInOrder(const std::vector<int>& channel_labels, int num_labels) {
  if (static_cast<int>(channel_labels.size()) != num_labels) return false;
  for (int k = 0; k < num_labels; ++k)
    if (channel_labels[static_cast<size_t>(k)] != k) return false;
  return true;
}

}  // namespace

int runSegment(const Words& words) {
  const Args args(words, {"all", "quiet"});
  args.expectOnly({kSegmenterOption, "all", "dtype", "out-dir", "quiet"}, 1);
  const std::string sequence_path = args.positional(0, "SEQ (a sequence folder)");
  if (!args.option(kSegmenterOption))
    throw UsageError(std::string("missing option --") + kSegmenterOption);
  const NpyType dtype = parseDtype(args.option("dtype").value_or("float32"));

  Sequence sequence = loadSequence(sequence_path);
  const std::shared_ptr<Segmenter> segmenter = loadSegmenterOption(args, true);
  segmenter->checkLabels(sequence.labels);
  const fs::path out_dir =
      args.option("out-dir").value_or("proba-" + segmenter->modelPath().stem().string());
  if (out_dir.empty()) throw UsageError("option --out-dir expects a folder name");

  // Frames to segment: those without a proba, or whose proba an import made from
  // their own label image (no segmenter's output either); every frame with --all.
  std::vector<size_t> frames, without_color;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const FrameRecord& frame = sequence.frames[i];
    if (!args.flag("all") && !frame.proba.empty() && !frame.proba_from_label) continue;
    frames.push_back(i);
    if (sequence.frames[i].color.empty()) without_color.push_back(i);
  }
  if (frames.empty()) {
    std::cout << "nothing to do: every frame of " << sequence_path
              << " has a proba image (--all replaces them)\n";
    return 0;
  }
  if (!without_color.empty()) {
    bool any_color = false;
    for (const auto& frame : sequence.frames) any_color = any_color || !frame.color.empty();
    throw Error((sequence.root / "sequence.json").string(),
                "frames[" + std::to_string(without_color.front()) + "].color",
                "a colour image in every frame to segment (the network runs on colour images)",
                any_color ? "none in frames " + frameList(without_color)
                          : "a sequence without colour images");
  }

  const fs::path folder = out_dir.is_absolute() ? out_dir : sequence.root / out_dir;
  checkOutputs(sequence, frames, folder);
  // Before the network runs on every frame: both places must take files.
  checkFolderWritable(folder, folder, "--out-dir");
  checkFolderWritable(folderWrittenFor(sequence.root / "sequence.json"),
                      sequence.root / "sequence.json", "output");
  auto makeFolder = [&] {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (!fs::is_directory(folder))
      throw Error(folder.string(), "--out-dir", "a folder that can be created",
                  ec ? ec.message() : "not a folder");
  };

  // The images are staged beside their targets and renamed into place only
  // once every frame is segmented: a failure half-way (an unreadable colour
  // image, a full disk) leaves the sequence's images, those --all would
  // replace included, and sequence.json as they were, and removes the output
  // folder again if this run created it.
  NewFolders new_folders(folder);
  StagedFiles staged;
  const bool show_progress = !args.flag("quiet") && ::isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  for (size_t n = 0; n < frames.size(); ++n) {
    const size_t i = frames[n];
    FrameRecord& record = sequence.frames[i];
    // Only the colour image is read; one of another size than the frame's
    // camera is refused, as fuse --segmenter and validate refuse it.
    const std::string field = "frames[" + std::to_string(i) + "].color";
    const fs::path color_file = sequence.pathOf(record.color);
    ColorImage color;
    try {
      color = readColorImage(color_file);
    } catch (const Error& e) {
      Problem p = e.problem();
      p.field = field;
      throw Error(p);
    }
    const CameraIntrinsics& camera = sequence.cameraOf(i);
    if (color.width != camera.width || color.height != camera.height)
      throw Error(color_file.string(), field + " (image size)",
                  std::to_string(camera.width) + " x " + std::to_string(camera.height) +
                      " pixels (the frame's camera width x height)",
                  std::to_string(color.width) + " x " + std::to_string(color.height));
    const ProbabilityImage proba = segmentFrame(sequence, i, color, *segmenter);
    if (n == 0) makeFolder();  // only once the network has produced something
    const std::string name = probaFileName(i);
    staged.addPath(folder / name,
                   [&](const fs::path& path) { writeProbabilityNpy(path, proba, dtype); });
    record.proba = (out_dir / name).generic_string();
    record.proba_from_label = false;  // the network's output is independent of the label image
    record.proba_labels = allLabelsInOrder(proba.channel_labels, sequence.labels.size())
                              ? std::vector<int>{}
                              : proba.channel_labels;
    if (show_progress) {
      std::fprintf(stderr, "\rsegmented %zu/%zu frames", n + 1, frames.size());
      std::fflush(stderr);
    }
  }
  if (show_progress) std::fprintf(stderr, "\n");
  // sequence.json is staged too, last, so that it is renamed only after every
  // probability image it names is in place, and a sequence.json that cannot be
  // written leaves the old images (and the old file) as they were.
  const std::string json = sequenceJsonText(sequence, sequence.root);
  staged.add(
      sequence.root / "sequence.json", [&](std::ostream& out) { out << json; }, false);
  staged.commit();
  new_folders.keep();

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "segmented " << frames.size() << (frames.size() == 1 ? " frame" : " frames")
            << " of " << sequence_path << " in " << std::fixed << std::setprecision(2) << seconds
            << " s\n"
            << segmenterSummary(*segmenter) << "\n"
            << "wrote " << frames.size() << " " << dtypeName(dtype) << " probability images to "
            << folder.string() << " and updated " << (sequence.root / "sequence.json").string()
            << "\n";
  return 0;
}

}  // namespace lom::cli
