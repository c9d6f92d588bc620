// Scenes of the Princeton Shelf & Tote benchmark (Amazon Picking Challenge 2016):
// cam.info.txt, bit-rotated depth, ground-truth segm/ and the segmenter's masks/.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "import_internal.hpp"

namespace lom::import_detail {

namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string trim(const std::string& text, const std::string& characters) {
  const auto first = text.find_first_not_of(characters);
  if (first == std::string::npos) return {};
  const auto last = text.find_last_not_of(characters);
  return text.substr(first, last - first + 1);
}

// The list after "# Objects:": ["a", "b"], ['a', 'b'] or [a, b].
std::vector<std::string> parseObjects(const std::string& line, const fs::path& file, int number) {
  const auto open = line.find('[');
  const auto close = line.rfind(']');
  if (open == std::string::npos || close == std::string::npos || close < open)
    throw Error(file.string(), "line " + std::to_string(number) + " (# Objects)",
                "a list such as [\"crayola_24_ct\", \"expo_dry_erase_board_eraser\"]",
                "'" + line + "'");
  std::vector<std::string> names;
  const std::string inner = line.substr(open + 1, close - open - 1);
  size_t start = 0;
  while (start <= inner.size()) {
    const auto comma = inner.find(',', start);
    const std::string item =
        trim(inner.substr(start, comma == std::string::npos ? std::string::npos : comma - start),
             " \t\"'");
    if (!item.empty()) names.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return names;
}

std::string frameName(long number) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "frame-%06ld", number);
  return buffer;
}

// Stored value v holds the depth rotated by 3 bits: metres = rotl13(v) / 10000.
std::uint16_t unrotateApcDepth(std::uint16_t v) {
  return static_cast<std::uint16_t>(((v << 13) | (v >> 3)) & 0xFFFF);
}

}  // namespace

void importApcShelf(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  const fs::path info = source / "cam.info.txt";
  std::optional<std::vector<std::string>> objects;
  for (const auto& [number, line] : readLines(info)) {
    const std::string text = trim(line, " \t");
    if (text.empty() || text[0] != '#') continue;
    const std::string body = trim(text.substr(1), " \t");
    if (body.rfind("Objects:", 0) == 0) objects = parseObjects(body, info, number);
  }
  if (!objects)
    throw Error(info.string(), "# Objects", "a line '# Objects: [\"name\", ...]' listing the scene's objects",
                "no such line");
  const std::vector<double> numbers = readNumbers(info);
  if (numbers.size() < 50 + 16 || (numbers.size() - 50) % 16 != 0)
    throw Error(info.string(), "matrices",
                "colour intrinsics 3x3, depth intrinsics 3x3, depth-to-colour 4x4, bin-to-world "
                "4x4, then one 4x4 camera-to-world per frame (50 + 16 N numbers)",
                std::to_string(numbers.size()) + " numbers");
  const size_t pose_count = (numbers.size() - 50) / 16;

  const LabelSet labels = apc2016Labels();
  std::vector<int> object_ids;
  for (const auto& name : *objects) {
    const auto id = labels.findByName(name);
    if (!id || *id == 0)
      throw Error(info.string(), "# Objects", "names of the 39 APC 2016 objects",
                  "'" + name + "'");
    object_ids.push_back(*id);
  }
  std::sort(object_ids.begin(), object_ids.end());
  object_ids.erase(std::unique(object_ids.begin(), object_ids.end()), object_ids.end());
  std::vector<int> channel_labels{0};
  channel_labels.insert(channel_labels.end(), object_ids.begin(), object_ids.end());

  // Depth is registered to the colour image, so the colour camera is the camera.
  const std::vector<double> color_k(numbers.begin(), numbers.begin() + 9);
  writer.setCamera(chooseCamera(intrinsicsFromNumbers(color_k, info.string()),
                                "the colour intrinsics of cam.info.txt", options, writer, source,
                                ""));
  const double scale = options.depth_scale.value_or(1e-4);
  writer.setDepthScale(scale);
  writer.setLabels(labels);

  const auto depth_files = numberedFiles(source, "frame-", ".depth.png");
  if (depth_files.empty())
    throw Error(source.string(), "frames", "frame-NNNNNN.depth.png files", "none");
  if (depth_files.size() != pose_count)
    writer.note("cam.info.txt has " + std::to_string(pose_count) + " camera poses for " +
                std::to_string(depth_files.size()) + " depth images (frame-N uses pose N)");

  writer.setFound(depth_files.size());
  // Which frames lack which object's mask (a segmenter's gap or a broken
  // export): named at the end, a few each.
  std::map<int, std::vector<std::string>> without_mask;  // object id -> frames
  std::vector<std::string> one_hot;                      // frames with segm only

  const auto selected = selectFrames(depth_files.size(), options);
  writer.setTotal(selected.size());
  for (size_t index : selected) {
    const auto& depth_file = depth_files[index];
    const std::string name = frameName(depth_file.number);
    // Its colour, segm and mask files are named as its depth image is.
    const std::string stem = numberedStem(depth_file, ".depth.png");
    if (depth_file.number < 0 || static_cast<size_t>(depth_file.number) >= pose_count) {
      if (!writer.skip(name, "no camera pose for it in cam.info.txt (" +
                                 std::to_string(pose_count) + " poses)"))
        return;
      continue;
    }
    SourceFrame frame;
    frame.name = name;
    frame.pose = matrixFromRowMajor(numbers.data() + 50 + 16 * depth_file.number);
    std::optional<std::string> error;
    try {
      frame.depth = readRaw16(depth_file.path);
      for (float& z : frame.depth.metres)
        z = static_cast<float>(unrotateApcDepth(static_cast<std::uint16_t>(z)) * scale);
      const fs::path color = source / (stem + ".color.png");
      if (isFile(color)) frame.color = readColorOrLeaveOut(color, writer);

      // Ground truth: value / 6 is the label id.
      const fs::path segm = source / "segm" / (stem + ".segm.png");
      if (isFile(segm)) {
        LabelImage label = readLabelImage(segm);
        size_t bad = 0;
        for (auto& value : label.ids) {
          const int id = value / 6;
          if (value % 6 != 0 || id >= labels.size()) {
            ++bad;
            value = 0;
          } else {
            value = static_cast<std::uint16_t>(id);
          }
        }
        if (bad)
          writer.note("segm images with values that are not 6 x a label id: those pixels set "
                      "to background");
        frame.label = std::move(label);
      }

      // The segmenter's masks: probability of each scene object; background is the rest.
      std::vector<std::optional<DepthImage>> masks;
      size_t found = 0;
      for (int id : object_ids) {
        const fs::path mask = source / "masks" / (stem + "." + labels.at(id).name + ".mask.png");
        if (!isFile(mask)) {
          masks.emplace_back();
          without_mask[id].push_back(name);
          continue;
        }
        DepthImage values = readRaw16(mask);
        for (float& p : values.metres) p /= 65535.0f;
        masks.emplace_back(std::move(values));
        ++found;
      }
      if (found) {
        int width = 0, height = 0;
        for (const auto& m : masks)
          if (m) {
            if (width == 0) {
              width = m->width;
              height = m->height;
            } else if (m->width != width || m->height != height) {
              throw Error((source / "masks").string(), name,
                          "masks of one size for all objects of a frame",
                          std::to_string(m->width) + " x " + std::to_string(m->height) + " and " +
                              std::to_string(width) + " x " + std::to_string(height));
            }
          }
        ProbabilityImage proba;
        proba.width = width;
        proba.height = height;
        proba.channels = static_cast<int>(channel_labels.size());
        proba.channel_labels = channel_labels;
        const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
        const size_t k = channel_labels.size();
        proba.values.assign(pixels * k, 0.0f);
        for (size_t i = 0; i < pixels; ++i) {
          float* p = proba.values.data() + i * k;
          float sum = 0.0f;
          for (size_t o = 0; o < masks.size(); ++o) {
            const float value = masks[o] ? std::clamp(masks[o]->metres[i], 0.0f, 1.0f) : 0.0f;
            p[o + 1] = value;
            sum += value;
          }
          p[0] = std::max(0.0f, 1.0f - sum);
          const float total = p[0] + sum;
          for (size_t c = 0; c < k; ++c) p[c] /= total;  // total >= 1
        }
        frame.proba = std::move(proba);
      } else if (frame.label) {
        one_hot.push_back(name);
      } else {
        throw Error((source / "masks").string(), name,
                    "masks/" + stem + ".<object>.mask.png or segm/" + stem + ".segm.png",
                    "neither");
      }
    } catch (const Error& e) {
      error = e.what();
    }
    if (error) {
      // A skipped frame is reported as such, not among the frames without masks.
      for (auto& [id, frames] : without_mask)
        if (!frames.empty() && frames.back() == name) frames.pop_back();
      if (!one_hot.empty() && one_hot.back() == name) one_hot.pop_back();
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!writer.add(std::move(frame))) return;
  }
  const auto listed = [](const std::vector<std::string>& frames) {
    constexpr size_t kListed = 5;
    std::string text;
    for (size_t i = 0; i < std::min(frames.size(), kListed); ++i)
      text += (i ? ", " : "") + frames[i];
    if (frames.size() > kListed)
      text += " and " + std::to_string(frames.size() - kListed) + " more";
    return text;
  };
  // A frame without any mask has none of these: its segm labels stand in.
  for (auto& [id, frames] : without_mask) {
    frames.erase(std::remove_if(frames.begin(), frames.end(),
                                [&](const std::string& frame) {
                                  return std::find(one_hot.begin(), one_hot.end(), frame) !=
                                         one_hot.end();
                                }),
                 frames.end());
    if (!frames.empty())
      writer.note("no mask of " + labels.at(id).name + " in " + listed(frames) +
                  ": it gets probability 0 there");
  }
  if (!one_hot.empty())
    writer.note("no masks at all in " + listed(one_hot) +
                ": their segm labels became one-hot probabilities");
}

}  // namespace lom::import_detail
