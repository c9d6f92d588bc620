// Reading and writing the frame images of a sequence. This is the only file
// that talks to OpenCV's image codecs.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags only
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

#include "file_checks.hpp"
#include "image_header.hpp"
#include "jpeg_decode.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "other_images.hpp"
#include "png_check.hpp"
#include "png_decode.hpp"
#include "png_encode.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

// Softmax outputs stored as float16 can overshoot [0, 1] by a rounding step.
constexpr float kProbabilityTolerance = 1e-3f;

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string describeMat(const cv::Mat& mat) {
  const int depth = mat.depth();
  const std::string bits = depth == CV_8U    ? "8-bit"
                           : depth == CV_16U ? "16-bit"
                           : depth == CV_16S ? "16-bit signed"
                           : depth == CV_32F ? "32-bit float"
                           : depth == CV_32S ? "32-bit signed"
                           : depth == CV_64F ? "64-bit float"
                                             : "other bit depth";
  const int channels = mat.channels();
  return bits + ", " + std::to_string(channels) + (channels == 1 ? " channel" : " channels");
}

bool isSpace(int c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// One decimal number of a PNM header, after white space and '#' comments.
std::optional<std::uint64_t> pnmNumber(std::istream& in) {
  int c = in.get();
  while (c != EOF && (isSpace(c) || c == '#')) {
    if (c == '#')
      while (c != EOF && c != '\n' && c != '\r') c = in.get();
    c = in.get();
  }
  if (c == EOF || c < '0' || c > '9') return std::nullopt;
  std::uint64_t value = 0;
  for (int digits = 0; c != EOF && c >= '0' && c <= '9'; c = in.get(), ++digits) {
    if (digits >= 12) return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return value;
}

// The whole file when it is a PNG or a JPEG, nullopt for other formats
// (OpenCV reads those from the path as before). PNGs and JPEGs are decoded
// here, with their libraries' messages captured, from these bytes, so the
// file is read once.
std::optional<std::vector<std::uint8_t>> pngOrJpegFileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;  // OpenCV reports a file it cannot open
  const std::streamoff size = in.tellg();
  std::vector<std::uint8_t> bytes(8);
  in.seekg(0);
  if (size < 8 || !in.read(reinterpret_cast<char*>(bytes.data()), 8) ||
      (!hasPngSignature(bytes.data(), bytes.size()) && !hasJpegSignature(bytes.data(), 8)))
    return std::nullopt;
  // Kept as for cv::imdecode, which takes at most INT_MAX bytes; no camera image comes near.
  if (size > std::numeric_limits<int>::max())
    throw Error(path.string(), "file size",
                std::string("a ") + (hasJpegSignature(bytes.data(), 8) ? "JPEG" : "PNG") +
                    " file of less than 2 GiB",
                std::to_string(size) + " bytes");
  bytes.resize(static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()) + 8, size - 8);
  // A file that shrank while being read is reported as truncated by the decoder.
  bytes.resize(8 + static_cast<size_t>(in.gcount()));
  return bytes;
}

cv::Mat readImage(const fs::path& path, PngSamples samples = PngSamples::AsOpenCv) {
  const std::string file = path.string();
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(file, "", "an existing image file", why);
  // A few kilobytes of PNG can declare billions of pixels: refuse before decoding.
  const auto size = readImageHeaderSize(path);
  if (size &&
      (size->width == 0 || size->height == 0 || size->width > kMaxImagePixels / size->height))
    throw Error(file, "image size",
                "an image of at most " + std::to_string(kMaxImagePixels) + " pixels",
                std::to_string(size->width) + " x " + std::to_string(size->height) +
                    " pixels (declared in the " + size->format + " header)");
  // OpenCV prints to the terminal about a truncated PNM before it fails: say it here instead.
  if (size && size->complete_file_bytes > 0) {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (!ec && bytes < size->complete_file_bytes)
      throw Error(file, "image data",
                  std::to_string(size->width) + " x " + std::to_string(size->height) +
                      " pixels of " + size->format + " data (" +
                      std::to_string(size->complete_file_bytes) + " bytes with the header)",
                  "a file truncated after " + std::to_string(bytes) + " bytes");
  }
  if (const auto bytes = pngOrJpegFileBytes(path))
    return hasJpegSignature(bytes->data(), bytes->size())
               ? decodeJpeg(bytes->data(), bytes->size(), file)
               : decodePng(bytes->data(), bytes->size(), file, samples);
  // Say what is wrong with an empty file or a .png / .jpg that holds other
  // data, rather than that no decoder took it.
  std::error_code ec;
  if (fs::file_size(path, ec) == 0 && !ec)
    throw Error(file, "", "a readable image", "an empty file (0 bytes)");
  const std::string ext = lowerExtension(path);
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    return readOtherImage(file, cv::IMREAD_UNCHANGED);
  try {
    return readOtherImage(file, cv::IMREAD_UNCHANGED);  // misnamed, in a format OpenCV knows
  } catch (const Error&) {
    std::ifstream in(path, std::ios::binary);
    unsigned char first[8] = {};
    in.read(reinterpret_cast<char*>(first), sizeof first);
    std::string shown;
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%s%02x", i ? " " : "", first[i]);
      shown += hex;
    }
    throw Error(file, "",
                ext == ".png" ? "PNG data (as its name says)" : "JPEG data (as its name says)",
                "a file of other data (it starts with the bytes " + shown + ")");
  }
}

std::string typeName(NpyType type) {
  switch (type) {
    case NpyType::Float32:
      return "float32";
    case NpyType::Float16:
      return "float16";
    case NpyType::Float64:
      return "float64";
    case NpyType::UInt8:
      return "uint8";
    case NpyType::UInt16:
      return "uint16";
  }
  return "unknown";
}

std::string shapeText(const std::vector<size_t>& shape) {
  std::string text;
  for (size_t i = 0; i < shape.size(); ++i) text += (i ? " x " : "") + std::to_string(shape[i]);
  return shape.empty() ? "a scalar" : text;
}

DepthImage readDepthNpy(const fs::path& path) {
  const std::string file = path.string();
  const char* const depth_types =
      "float32 depths in metres ('<f4'/'>f4'; float16 and float64 also accepted)";
  NpyArray array;
  try {
    array = readNpy(path);
  } catch (const Error& e) {
    // readNpy lists the dtypes of every .npy it reads, uint8 and uint16
    // among them, which depths refuse below: name only what a depth takes.
    if (e.problem().field != "dtype") throw;
    Problem problem = e.problem();
    problem.expected = depth_types;
    throw Error(problem);
  }
  const bool single_channel = array.shape.size() == 3 && array.shape[2] == 1;
  if (array.shape.size() != 2 && !single_channel)
    throw Error(file, "shape", "a 2-D array H x W of depths in metres", shapeText(array.shape));
  if (array.type == NpyType::UInt8 || array.type == NpyType::UInt16)
    throw Error(file, "dtype", depth_types,
                typeName(array.type) + " (store integer depths as a 16-bit PNG with depth_scale)");
  DepthImage depth;
  depth.height = static_cast<int>(array.shape[0]);
  depth.width = static_cast<int>(array.shape[1]);
  depth.metres = array.toFloat(false);
  for (float& z : depth.metres)
    if (!std::isfinite(z) || z < 0.0f) z = 0.0f;
  return depth;
}

void writeMatPng(const fs::path& path, const cv::Mat& mat) {
  if (lowerExtension(path) != ".png")
    throw Error(path.string(), "output path", "a file name ending in .png",
                "'" + path.extension().string() + "'");
  // Encoded in memory and written by the atomic writer: libpng writing to the
  // file itself would print "libpng error: Write Error" on a full disk.
  const std::vector<std::uint8_t> png = encodePng(mat, path.string());
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

void checkPixelCount(const fs::path& path, int width, int height, size_t values, size_t per_pixel) {
  if (width <= 0 || height <= 0 ||
      values != static_cast<size_t>(width) * static_cast<size_t>(height) * per_pixel)
    throw Error(path.string(), "image",
                "width x height x " + std::to_string(per_pixel) + " values for a " +
                    std::to_string(width) + " x " + std::to_string(height) + " image",
                std::to_string(values) + " values");
}

}  // namespace

namespace {

// JPEG: the frame header (SOF0 to SOF15, not DHT, JPG or DAC) after the start
// of image; other segments are skipped by their length, until the scan starts.
std::optional<ImageHeaderSize> jpegSize(std::istream& in) {
  for (int segments = 0; segments < 1024; ++segments) {
    int c = in.get();
    if (c != 0xff) return std::nullopt;
    while (c == 0xff) c = in.get();                               // fill bytes
    if (c == EOF || c == 0xda || c == 0xd9) return std::nullopt;  // scan or end: no frame header
    if (c == 0x01 || (c >= 0xd0 && c <= 0xd7)) continue;          // markers without a segment
    unsigned char segment[7] = {};
    in.read(reinterpret_cast<char*>(segment), 2);
    if (!in) return std::nullopt;
    const unsigned length = (unsigned{segment[0]} << 8) | segment[1];
    if (length < 2) return std::nullopt;
    if (c >= 0xc0 && c <= 0xcf && c != 0xc4 && c != 0xc8 && c != 0xcc) {
      in.read(reinterpret_cast<char*>(segment) + 2, 5);  // precision, height, width
      if (!in) return std::nullopt;
      return ImageHeaderSize{(std::uint64_t{segment[5]} << 8) | segment[6],
                             (std::uint64_t{segment[3]} << 8) | segment[4], "JPEG"};
    }
    in.seekg(length - 2, std::ios::cur);
    if (!in) return std::nullopt;
  }
  return std::nullopt;
}

// TIFF: the first image's ImageWidth (256) and ImageLength (257) tags.
std::optional<ImageHeaderSize> tiffSize(std::istream& in, bool little_endian) {
  const auto number = [&](const unsigned char* bytes, int size) {
    std::uint64_t value = 0;
    for (int i = 0; i < size; ++i)
      value |= std::uint64_t{bytes[little_endian ? i : size - 1 - i]} << (8 * i);
    return value;
  };
  unsigned char head[6] = {};
  in.read(reinterpret_cast<char*>(head), 6);  // 42, then the first directory's offset
  if (!in || number(head, 2) != 42) return std::nullopt;
  in.seekg(static_cast<std::streamoff>(number(head + 2, 4)));
  unsigned char count_bytes[2] = {};
  in.read(reinterpret_cast<char*>(count_bytes), 2);
  if (!in) return std::nullopt;
  std::optional<std::uint64_t> width, height;
  for (std::uint64_t i = 0, count = number(count_bytes, 2); i < count && !(width && height); ++i) {
    unsigned char entry[12] = {};
    in.read(reinterpret_cast<char*>(entry), 12);
    if (!in) return std::nullopt;
    const std::uint64_t tag = number(entry, 2), type = number(entry + 2, 2);
    if (tag != 256 && tag != 257) continue;
    if (type != 3 && type != 4) return std::nullopt;  // SHORT or LONG only
    (tag == 256 ? width : height) = number(entry + 8, type == 3 ? 2 : 4);
  }
  if (!width || !height) return std::nullopt;
  return ImageHeaderSize{*width, *height, "TIFF"};
}

}  // namespace

std::optional<ImageHeaderSize> readImageHeaderSize(const fs::path& path) {
  // Never open a named pipe or a device here: opening a pipe waits for a writer.
  if (!notARegularFile(path).empty()) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  unsigned char head[24] = {};
  in.read(reinterpret_cast<char*>(head), 2);
  if (!in) return std::nullopt;
  if (head[0] == 0x89 && head[1] == 'P') {
    // PNG: signature, then the IHDR chunk (length, "IHDR", width, height big-endian).
    in.read(reinterpret_cast<char*>(head) + 2, 22);
    static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!in || std::memcmp(head, kSignature, 8) != 0 || std::memcmp(head + 12, "IHDR", 4) != 0)
      return std::nullopt;
    const auto big = [&](int at) {
      return (std::uint64_t{head[at]} << 24) | (std::uint64_t{head[at + 1]} << 16) |
             (std::uint64_t{head[at + 2]} << 8) | std::uint64_t{head[at + 3]};
    };
    return ImageHeaderSize{big(16), big(20), "PNG"};
  }
  if (head[0] == 'P' && head[1] >= '1' && head[1] <= '6') {
    // PNM: "P5", then width and height as decimal text between white space and comments.
    const char* format = (head[1] == '1' || head[1] == '4')   ? "PBM"
                         : (head[1] == '2' || head[1] == '5') ? "PGM"
                                                              : "PPM";
    const auto width = pnmNumber(in);
    const auto height = width ? pnmNumber(in) : std::nullopt;
    if (!width || !height) return std::nullopt;
    ImageHeaderSize size{*width, *height, format};
    if (head[1] == '5' || head[1] == '6') {
      // The maximum value, one white-space character, then the samples: two
      // bytes each above 255, three per pixel for PPM.
      const auto max_value = pnmNumber(in);
      const auto data_start = in.tellg();
      if (max_value && *max_value > 0 && data_start >= 0 && *width <= kMaxImagePixels &&
          *height <= kMaxImagePixels)
        size.complete_file_bytes =
            static_cast<std::uint64_t>(data_start) +
            *width * *height * (head[1] == '6' ? 3 : 1) * (*max_value > 255 ? 2 : 1);
    }
    return size;
  }
  if (head[0] == 0xff && head[1] == 0xd8) return jpegSize(in);
  if ((head[0] == 'I' && head[1] == 'I') || (head[0] == 'M' && head[1] == 'M'))
    return tiffSize(in, head[0] == 'I');
  if (head[0] == 'B' && head[1] == 'M') {
    // BMP: the info header's width and height (little-endian, height negative when top-down).
    unsigned char info[24] = {};
    in.read(reinterpret_cast<char*>(info), sizeof(info));
    if (!in) return std::nullopt;
    const auto little = [&](int at) {
      return static_cast<std::int32_t>(
          std::uint32_t{info[at]} | (std::uint32_t{info[at + 1]} << 8) |
          (std::uint32_t{info[at + 2]} << 16) | (std::uint32_t{info[at + 3]} << 24));
    };
    // File header (14 bytes, 2 read), then the info header's size, width, height.
    const std::int64_t width = little(16), height = little(20);
    return ImageHeaderSize{static_cast<std::uint64_t>(width < 0 ? -width : width),
                           static_cast<std::uint64_t>(height < 0 ? -height : height), "BMP"};
  }
  return std::nullopt;
}

DepthImage readDepthImage(const fs::path& path, double depth_scale) {
  if (lowerExtension(path) == ".npy") return readDepthNpy(path);
  const cv::Mat mat = readImage(path);
  if (mat.channels() != 1 || mat.depth() != CV_16U)
    throw Error(path.string(), "bit depth",
                "a 16-bit single-channel image (depth in units of depth_scale)", describeMat(mat));
  DepthImage depth;
  depth.width = mat.cols;
  depth.height = mat.rows;
  depth.metres.resize(static_cast<size_t>(mat.cols) * static_cast<size_t>(mat.rows));
  for (int v = 0; v < mat.rows; ++v) {
    const auto* row = mat.ptr<std::uint16_t>(v);
    float* out = depth.metres.data() + static_cast<size_t>(v) * static_cast<size_t>(mat.cols);
    for (int u = 0; u < mat.cols; ++u) out[u] = static_cast<float>(row[u] * depth_scale);
  }
  return depth;
}

ColorImage readColorImage(const fs::path& path) {
  const cv::Mat mat = readImage(path);
  if (mat.depth() != CV_8U)
    throw Error(path.string(), "bit depth", "an 8-bit RGB image", describeMat(mat));
  cv::Mat rgb;
  switch (mat.channels()) {
    case 1:
      cv::cvtColor(mat, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(mat, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(mat, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      throw Error(path.string(), "channels", "an 8-bit RGB image (3 channels)", describeMat(mat));
  }
  ColorImage color;
  color.width = rgb.cols;
  color.height = rgb.rows;
  color.rgb.resize(static_cast<size_t>(rgb.cols) * static_cast<size_t>(rgb.rows) * 3);
  for (int v = 0; v < rgb.rows; ++v)
    std::copy_n(rgb.ptr<std::uint8_t>(v), static_cast<size_t>(rgb.cols) * 3,
                color.rgb.data() + static_cast<size_t>(v) * static_cast<size_t>(rgb.cols) * 3);
  return color;
}

LabelImage readLabelImage(const fs::path& path) {
  // Palette PNGs (PASCAL VOC's label format) give their indices, low-bit
  // greys their stored values: the label ids.
  const cv::Mat mat = readImage(path, PngSamples::Indices);
  if (mat.channels() != 1)
    throw Error(path.string(), "channels", "a single-channel 8- or 16-bit image of label ids",
                describeMat(mat) + " (a colour image?)");
  if (mat.depth() != CV_8U && mat.depth() != CV_16U)
    throw Error(path.string(), "bit depth", "a single-channel 8- or 16-bit image of label ids",
                describeMat(mat));
  cv::Mat ids;
  mat.convertTo(ids, CV_16U);
  LabelImage label;
  label.width = ids.cols;
  label.height = ids.rows;
  label.ids.resize(static_cast<size_t>(ids.cols) * static_cast<size_t>(ids.rows));
  for (int v = 0; v < ids.rows; ++v)
    std::copy_n(ids.ptr<std::uint16_t>(v), ids.cols,
                label.ids.data() + static_cast<size_t>(v) * static_cast<size_t>(ids.cols));
  return label;
}

ProbabilityImage readProbabilityImage(const fs::path& path, const std::vector<int>& channel_labels,
                                      int num_labels, bool floats_of_codes) {
  const std::string file = path.string();
  std::set<int> seen;
  for (size_t i = 0; i < channel_labels.size(); ++i) {
    const std::string field = "proba_labels[" + std::to_string(i) + "]";
    if (channel_labels[i] < 0 || channel_labels[i] >= num_labels)
      throw Error(file, field, "a label id from 0 to " + std::to_string(num_labels - 1),
                  std::to_string(channel_labels[i]));
    if (!seen.insert(channel_labels[i]).second)
      throw Error(file, field, "each label id once", std::to_string(channel_labels[i]) + " again");
  }
  NpyArray array = readNpy(path);
  if (array.shape.size() != 3)
    throw Error(file, "shape", "a 3-D array H x W x C of probabilities", shapeText(array.shape));
  const size_t expected_channels =
      channel_labels.empty() ? static_cast<size_t>(std::max(num_labels, 0)) : channel_labels.size();
  if (array.shape[2] != expected_channels)
    throw Error(
        file, "channels",
        std::to_string(expected_channels) +
            (channel_labels.empty() ? " channels (one per label, as proba_labels is absent)"
                                    : " channels (one per entry of proba_labels)"),
        std::to_string(array.shape[2]) + " channels (shape " + shapeText(array.shape) + ")");

  ProbabilityImage proba;
  proba.height = static_cast<int>(array.shape[0]);
  proba.width = static_cast<int>(array.shape[1]);
  proba.channels = static_cast<int>(array.shape[2]);
  proba.channel_labels = channel_labels;
  if (proba.channel_labels.empty())
    for (int id = 0; id < num_labels; ++id) proba.channel_labels.push_back(id);
  if (array.type == NpyType::UInt8) {  // codes / 255: always probabilities
    if (floats_of_codes) proba.values = array.toFloat(true);
    proba.codes = std::move(array.bytes);  // C order, like values
    return proba;
  }
  proba.values = array.toFloat(true);
  // Checked in one pass without branches, then searched only when one is off.
  bool all_probabilities = true;
  for (const float p : proba.values)
    all_probabilities &= p >= -kProbabilityTolerance && p <= 1.0f + kProbabilityTolerance;
  if (!all_probabilities) {
    for (size_t i = 0; i < proba.values.size(); ++i) {
      const float p = proba.values[i];
      if (p >= -kProbabilityTolerance && p <= 1.0f + kProbabilityTolerance) continue;
      const size_t pixel = i / static_cast<size_t>(proba.channels);
      throw Error(file, "values", "probabilities in [0, 1]",
                  std::to_string(p) +
                      " at pixel (u=" + std::to_string(pixel % static_cast<size_t>(proba.width)) +
                      ", v=" + std::to_string(pixel / static_cast<size_t>(proba.width)) +
                      "), channel " + std::to_string(i % static_cast<size_t>(proba.channels)));
    }
  }
  for (float& p : proba.values) p = std::clamp(p, 0.0f, 1.0f);
  return proba;
}

void writeDepthPng(const fs::path& path, const DepthImage& depth, double depth_scale) {
  checkPixelCount(path, depth.width, depth.height, depth.metres.size(), 1);
  if (!(depth_scale > 0.0) || !std::isfinite(depth_scale))
    throw Error(path.string(), "depth_scale", "a positive number", std::to_string(depth_scale));
  cv::Mat mat(depth.height, depth.width, CV_16UC1);
  for (int v = 0; v < depth.height; ++v) {
    auto* row = mat.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth.width; ++u) {
      const float z = depth.at(u, v);
      const double units = std::isfinite(z) && z > 0.0f ? std::round(z / depth_scale) : 0.0;
      if (units > 65535.0)
        throw Error(
            path.string(), "depth",
            "depths up to " + std::to_string(65535.0 * depth_scale) + " m (65535 * depth_scale)",
            std::to_string(z) + " m at pixel (u=" + std::to_string(u) + ", v=" + std::to_string(v) +
                ")");
      row[u] = static_cast<std::uint16_t>(units);
    }
  }
  writeMatPng(path, mat);
}

void writeColorPng(const fs::path& path, const ColorImage& color) {
  checkPixelCount(path, color.width, color.height, color.rgb.size(), 3);
  const cv::Mat rgb(color.height, color.width, CV_8UC3,
                    const_cast<std::uint8_t*>(color.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  writeMatPng(path, bgr);
}

void writeLabelPng(const fs::path& path, const LabelImage& label) {
  checkPixelCount(path, label.width, label.height, label.ids.size(), 1);
  const cv::Mat ids(label.height, label.width, CV_16UC1,
                    const_cast<std::uint16_t*>(label.ids.data()));
  // 8 bits whenever they suffice: smaller files that any image viewer shows.
  const bool fits_8_bit =
      label.ids.empty() || *std::max_element(label.ids.begin(), label.ids.end()) < 256;
  if (!fits_8_bit) {
    writeMatPng(path, ids);
    return;
  }
  cv::Mat narrow;
  ids.convertTo(narrow, CV_8U);
  writeMatPng(path, narrow);
}

}  // namespace lom
