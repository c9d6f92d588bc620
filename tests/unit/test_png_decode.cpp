// PNG frames are decoded through libpng with its messages captured: the same
// pixels as OpenCV's reader for every kind of PNG a camera or a dataset
// writes, and damaged image data becomes one error naming the file, with
// nothing printed on stderr.
#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <vector>

#include "lom/sequence.hpp"
#include "png_decode.hpp"
#include "png_direct.hpp"
#include "png_encode.hpp"
#include "test_input_helpers.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::errorOf;
using lom::test::writeText;

struct PngSpec {
  const char* name;
  int width, height, bit_depth, color_type;
  bool interlaced = false;
  bool transparency = false;  // a tRNS chunk
};

void appendBytes(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), size);
}

// A PNG written with libpng's own writer, samples varying over the image.
std::string writePng(const PngSpec& spec) {
  std::string bytes;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    ADD_FAILURE() << "libpng could not write " << spec.name;
    return {};
  }
  png_set_write_fn(png, &bytes, appendBytes, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(spec.width),
               static_cast<png_uint_32>(spec.height), spec.bit_depth, spec.color_type,
               spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette;
  if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < (1 << spec.bit_depth); ++i)
      palette.push_back({static_cast<png_byte>(i * 37), static_cast<png_byte>(255 - i * 11),
                         static_cast<png_byte>(i * 5)});
    png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  }
  png_byte alpha[4] = {0, 80, 160, 255};
  png_color_16 colour_key{};
  colour_key.red = colour_key.green = colour_key.blue = colour_key.gray = 1;
  if (spec.transparency)
    png_set_tRNS(png, info, alpha, spec.color_type == PNG_COLOR_TYPE_PALETTE ? 4 : 0, &colour_key);
  png_write_info(png, info);
  const int samples = (spec.color_type & PNG_COLOR_MASK_PALETTE) ? 1
                      : (spec.color_type & PNG_COLOR_MASK_COLOR) ? 3
                                                                 : 1;
  const int channels = samples + ((spec.color_type & PNG_COLOR_MASK_ALPHA) ? 1 : 0);
  const size_t row_bytes = (static_cast<size_t>(spec.width) * channels * spec.bit_depth + 7) / 8;
  std::vector<std::vector<png_byte>> rows(static_cast<size_t>(spec.height),
                                          std::vector<png_byte>(row_bytes));
  std::vector<png_bytep> row_pointers;
  for (size_t v = 0; v < rows.size(); ++v) {
    for (size_t i = 0; i < row_bytes; ++i)
      rows[v][i] = static_cast<png_byte>((v * 31 + i * 7) ^ (i >> 3));
    row_pointers.push_back(rows[v].data());
  }
  png_write_image(png, row_pointers.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return bytes;
}

cv::Mat decodedByOpenCv(const std::string& png) {
  const std::vector<std::uint8_t> buffer(png.begin(), png.end());
  return cv::imdecode(buffer, cv::IMREAD_UNCHANGED);
}

cv::Mat decodedHere(const std::string& png) {
  return lom::decodePng(reinterpret_cast<const std::uint8_t*>(png.data()), png.size(), "x.png");
}

TEST(PngDecodeTest, GivesOpenCvsPixelsForEveryKindOfPng) {
  const PngSpec specs[] = {
      {"grey 8-bit", 13, 7, 8, PNG_COLOR_TYPE_GRAY},
      {"grey 16-bit (depth)", 13, 7, 16, PNG_COLOR_TYPE_GRAY},
      {"grey 1-bit", 13, 7, 1, PNG_COLOR_TYPE_GRAY},
      {"grey 2-bit", 13, 7, 2, PNG_COLOR_TYPE_GRAY},
      {"grey 4-bit", 13, 7, 4, PNG_COLOR_TYPE_GRAY},
      {"grey with a colour key", 13, 7, 8, PNG_COLOR_TYPE_GRAY, false, true},
      {"grey and alpha", 13, 7, 8, PNG_COLOR_TYPE_GRAY_ALPHA},
      {"grey and alpha 16-bit", 13, 7, 16, PNG_COLOR_TYPE_GRAY_ALPHA},
      {"RGB", 13, 7, 8, PNG_COLOR_TYPE_RGB},
      {"RGB 16-bit", 13, 7, 16, PNG_COLOR_TYPE_RGB},
      {"RGB with a colour key", 13, 7, 8, PNG_COLOR_TYPE_RGB, false, true},
      {"RGBA", 13, 7, 8, PNG_COLOR_TYPE_RGB_ALPHA},
      {"RGBA 16-bit", 13, 7, 16, PNG_COLOR_TYPE_RGB_ALPHA},
      {"palette 8-bit", 13, 7, 8, PNG_COLOR_TYPE_PALETTE},
      {"palette 2-bit", 13, 7, 2, PNG_COLOR_TYPE_PALETTE},
      {"palette with transparency", 13, 7, 4, PNG_COLOR_TYPE_PALETTE, false, true},
      {"interlaced RGB", 13, 7, 8, PNG_COLOR_TYPE_RGB, true},
      {"interlaced grey 16-bit", 13, 7, 16, PNG_COLOR_TYPE_GRAY, true},
  };
  for (const PngSpec& spec : specs) {
    SCOPED_TRACE(spec.name);
    const std::string png = writePng(spec);
    const cv::Mat expected = decodedByOpenCv(png);
    ASSERT_FALSE(expected.empty());
    const cv::Mat decoded = decodedHere(png);
    ASSERT_EQ(decoded.type(), expected.type());
    ASSERT_EQ(decoded.size(), expected.size());
    EXPECT_EQ(cv::norm(decoded, expected, cv::NORM_INF), 0.0);
  }
}

// The numbers a palette or low-bit grey PNG stores, as writePng wrote them.
int storedSample(const PngSpec& spec, int u, int v) {
  const size_t bit = static_cast<size_t>(u) * static_cast<size_t>(spec.bit_depth);
  const size_t i = bit / 8;
  const auto byte = static_cast<png_byte>((static_cast<size_t>(v) * 31 + i * 7) ^ (i >> 3));
  const int shift = 8 - spec.bit_depth - static_cast<int>(bit % 8);
  return (byte >> shift) & ((1 << spec.bit_depth) - 1);
}

// Label images need the stored numbers: a palette PNG's indices (PASCAL VOC's
// label format) and a 4-bit grey's values unscaled (OpenCV makes 3 into 51).
TEST(PngDecodeTest, IndicesAreTheStoredNumbersOfPaletteAndLowBitGreys) {
  const PngSpec specs[] = {
      {"palette 8-bit", 13, 7, 8, PNG_COLOR_TYPE_PALETTE},
      {"palette 2-bit", 13, 7, 2, PNG_COLOR_TYPE_PALETTE},
      {"palette with transparency", 13, 7, 4, PNG_COLOR_TYPE_PALETTE, false, true},
      {"interlaced palette", 13, 7, 4, PNG_COLOR_TYPE_PALETTE, true},
      {"grey 1-bit", 13, 7, 1, PNG_COLOR_TYPE_GRAY},
      {"grey 2-bit", 13, 7, 2, PNG_COLOR_TYPE_GRAY},
      {"grey 4-bit", 13, 7, 4, PNG_COLOR_TYPE_GRAY},
  };
  for (const PngSpec& spec : specs) {
    SCOPED_TRACE(spec.name);
    const std::string png = writePng(spec);
    const cv::Mat decoded = lom::decodePng(reinterpret_cast<const std::uint8_t*>(png.data()),
                                           png.size(), "x.png", lom::PngSamples::Indices);
    ASSERT_EQ(decoded.type(), CV_8UC1);
    ASSERT_EQ(decoded.size(), cv::Size(spec.width, spec.height));
    int differing = 0;
    for (int v = 0; v < spec.height; ++v)
      for (int u = 0; u < spec.width; ++u)
        differing += decoded.at<std::uint8_t>(v, u) != storedSample(spec, u, v);
    EXPECT_EQ(differing, 0);
  }
  // Other kinds read as OpenCV reads them.
  const PngSpec grey{"grey 16-bit", 13, 7, 16, PNG_COLOR_TYPE_GRAY};
  const std::string png = writePng(grey);
  const cv::Mat indices = lom::decodePng(reinterpret_cast<const std::uint8_t*>(png.data()),
                                         png.size(), "x.png", lom::PngSamples::Indices);
  EXPECT_EQ(cv::norm(indices, decodedByOpenCv(png), cv::NORM_INF), 0.0);
  // A label image file of 4-bit greys holds the ids themselves.
  lom::test::TempDir dir;
  const PngSpec four{"labels", 13, 7, 4, PNG_COLOR_TYPE_GRAY};
  writeText(dir / "label.png", writePng(four));
  const lom::LabelImage label = lom::readLabelImage(dir / "label.png");
  ASSERT_EQ(label.width, 13);
  for (int v = 0; v < 7; ++v)
    for (int u = 0; u < 13; ++u)
      ASSERT_EQ(label.at(u, v), storedSample(four, u, v)) << u << "," << v;
}

// The programs write PNGs with libpng (OpenCV's encoder is in imgcodecs, which
// they no longer link): OpenCV reads every kind they write back to the same
// samples, channel order included, and so does the decoder here.
TEST(PngEncodeTest, OpenCvReadsBackTheSamplesOfEveryKindWritten) {
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3, CV_16UC4}) {
    SCOPED_TRACE("OpenCV type " + std::to_string(type));
    cv::Mat image(7, 13, type);
    cv::randu(image, cv::Scalar::all(0),
              cv::Scalar::all(CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256));
    const std::vector<std::uint8_t> png = lom::encodePng(image, "test.png");
    const cv::Mat by_opencv = cv::imdecode(png, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(by_opencv.type(), type);
    EXPECT_EQ(cv::norm(by_opencv, image, cv::NORM_INF), 0.0);
    const cv::Mat here = lom::decodePng(png.data(), png.size(), "test.png");
    ASSERT_EQ(here.type(), type);
    EXPECT_EQ(cv::norm(here, image, cv::NORM_INF), 0.0);
  }
  // A view into a larger image (rows not contiguous) is written as the view.
  cv::Mat big(20, 30, CV_8UC3);
  cv::randu(big, cv::Scalar::all(0), cv::Scalar::all(256));
  const cv::Mat view = big(cv::Rect(3, 4, 11, 9));
  const std::vector<std::uint8_t> png = lom::encodePng(view, "view.png");
  EXPECT_EQ(cv::norm(cv::imdecode(png, cv::IMREAD_UNCHANGED), view, cv::NORM_INF), 0.0);
  // What PNG cannot hold is an error naming the file, not a file.
  const lom::Problem floats =
      errorOf([] { (void)lom::encodePng(cv::Mat(3, 3, CV_32FC1), "f.png"); });
  EXPECT_EQ(floats.file, "f.png");
  EXPECT_EQ(floats.field, "output");
  EXPECT_NE(floats.expected.find("8 or 16 bits"), std::string::npos);
  EXPECT_THROW((void)lom::encodePng(cv::Mat(3, 3, CV_8UC2), "two.png"), lom::Error);
}

std::string chunk(const std::string& type, const std::string& data) {
  std::string bytes;
  for (int shift = 24; shift >= 0; shift -= 8)
    bytes += static_cast<char>((data.size() >> shift) & 0xff);
  bytes += type + data;
  const std::string crc_input = type + data;
  const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(crc_input.data()),
                          static_cast<uInt>(crc_input.size()));
  for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((crc >> shift) & 0xff);
  return bytes;
}

// An 8-bit grey PNG built by hand from `rows` (each starting with its filter
// byte) and compressed here, with every chunk's CRC right: only the image
// data itself can be wrong. `keep` cuts the compressed stream.
std::string handMadePng(int width, int height, const std::string& rows,
                        size_t keep = std::string::npos) {
  std::string header;
  for (const int value : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8)
      header += static_cast<char>((value >> shift) & 0xff);
  header += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit grey, not interlaced
  std::vector<Bytef> compressed(compressBound(static_cast<uLong>(rows.size())));
  uLongf size = static_cast<uLongf>(compressed.size());
  EXPECT_EQ(compress(compressed.data(), &size, reinterpret_cast<const Bytef*>(rows.data()),
                     static_cast<uLong>(rows.size())),
            Z_OK);
  const std::string data(reinterpret_cast<const char*>(compressed.data()),
                         std::min<size_t>(size, keep));
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", header) + chunk("IDAT", data) +
         chunk("IEND", "");
}

// The predictor of PNG filter type 4, written as the specification gives it.
int paethPredictor(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  if (pb <= pc) return b;
  return c;
}

// `raw` (rows of `row_bytes` samples, big-endian) filtered as a PNG encoder
// would, row v with filter type filter_of(v); each row starts with its type.
template <class FilterOf>
std::string filterRows(const std::vector<std::uint8_t>& raw, size_t row_bytes, int bpp,
                       FilterOf filter_of) {
  std::string rows;
  const size_t height = raw.size() / row_bytes;
  for (size_t v = 0; v < height; ++v) {
    const int filter = filter_of(v);
    rows += static_cast<char>(filter);
    for (size_t i = 0; i < row_bytes; ++i) {
      const int x = raw[v * row_bytes + i];
      const int a = i >= static_cast<size_t>(bpp) ? raw[v * row_bytes + i - bpp] : 0;
      const int b = v > 0 ? raw[(v - 1) * row_bytes + i] : 0;
      const int c = v > 0 && i >= static_cast<size_t>(bpp) ? raw[(v - 1) * row_bytes + i - bpp] : 0;
      const int predicted = filter == 1   ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? paethPredictor(a, b, c)
                                          : 0;
      rows += static_cast<char>((x - predicted) & 0xff);
    }
  }
  return rows;
}

// A PNG built from already filtered rows, the compressed stream split over
// IDAT chunks of `chunk_bytes`.
std::string pngOfRows(int width, int height, int bit_depth, int colour_type,
                      const std::string& rows, size_t chunk_bytes) {
  std::string header;
  for (const int value : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8)
      header += static_cast<char>((value >> shift) & 0xff);
  header += static_cast<char>(bit_depth);
  header += static_cast<char>(colour_type);
  header += std::string(3, '\0');  // standard compression and filtering, not interlaced
  std::vector<Bytef> compressed(compressBound(static_cast<uLong>(rows.size())));
  uLongf size = static_cast<uLongf>(compressed.size());
  EXPECT_EQ(compress(compressed.data(), &size, reinterpret_cast<const Bytef*>(rows.data()),
                     static_cast<uLong>(rows.size())),
            Z_OK);
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", header);
  for (size_t at = 0; at < size; at += chunk_bytes)
    png += chunk("IDAT", std::string(reinterpret_cast<const char*>(compressed.data()) + at,
                                     std::min<size_t>(chunk_bytes, size - at)));
  return png + chunk("IEND", "");
}

// Grey, RGB and RGBA PNGs of 8 and 16 bits, what cameras and this program
// write, are inflated and unfiltered without libpng: every filter type, on
// the first row (nothing above it) and on later ones, gives the samples
// OpenCV reads.
TEST(PngDecodeTest, DecodesCommonKindsDirectlyWithEveryFilter) {
  struct Kind {
    const char* name;
    int bit_depth, colour_type, channels;
  };
  const Kind kinds[] = {{"grey", 8, 0, 1}, {"grey 16-bit", 16, 0, 1},
                        {"RGB", 8, 2, 3},  {"RGB 16-bit", 16, 2, 3},
                        {"RGBA", 8, 6, 4}, {"RGBA 16-bit", 16, 6, 4}};
  cv::RNG random(7);
  for (const Kind& kind : kinds)
    for (const int width : {1, 2, 37})
      for (int first_filter = 0; first_filter < 5; ++first_filter) {
        SCOPED_TRACE(std::string(kind.name) + ", width " + std::to_string(width) +
                     ", first row's filter " + std::to_string(first_filter));
        const int height = 11, bpp = kind.channels * kind.bit_depth / 8;
        const size_t row_bytes = static_cast<size_t>(width * bpp);
        std::vector<std::uint8_t> raw(row_bytes * height);
        for (size_t i = 0; i < raw.size(); ++i)  // smooth rows and noise, so predictors matter
          raw[i] = static_cast<std::uint8_t>(i % 3 == 0 ? random.uniform(0, 256) : (i * 5) / 7);
        const std::string rows = filterRows(raw, row_bytes, bpp, [&](size_t v) {
          return static_cast<int>((v + static_cast<size_t>(first_filter)) % 5);
        });
        const std::string png =
            pngOfRows(width, height, kind.bit_depth, kind.colour_type, rows, 50);
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(png.data());
        ASSERT_TRUE(lom::isDirectPng(bytes, png.size()));
        const cv::Mat expected = decodedByOpenCv(png);
        ASSERT_FALSE(expected.empty());
        const std::optional<cv::Mat> direct = lom::decodePngDirectly(bytes, png.size());
        ASSERT_TRUE(direct.has_value());
        ASSERT_EQ(direct->type(), expected.type());
        ASSERT_EQ(direct->size(), expected.size());
        EXPECT_EQ(cv::norm(*direct, expected, cv::NORM_INF), 0.0);
      }
}

// Every other kind, and data the direct route cannot decode whole, goes to
// libpng (which decodes the kinds as OpenCV does, above, and names what is
// wrong with damaged data, below).
TEST(PngDecodeTest, OtherKindsAndOddDataAreLeftToLibpng) {
  const PngSpec others[] = {
      {"grey 4-bit", 13, 7, 4, PNG_COLOR_TYPE_GRAY},
      {"grey with a colour key", 13, 7, 8, PNG_COLOR_TYPE_GRAY, false, true},
      {"grey and alpha", 13, 7, 8, PNG_COLOR_TYPE_GRAY_ALPHA},
      {"RGB with a colour key", 13, 7, 8, PNG_COLOR_TYPE_RGB, false, true},
      {"palette 8-bit", 13, 7, 8, PNG_COLOR_TYPE_PALETTE},
      {"interlaced grey 16-bit", 13, 7, 16, PNG_COLOR_TYPE_GRAY, true},
  };
  for (const PngSpec& spec : others) {
    SCOPED_TRACE(spec.name);
    const std::string png = writePng(spec);
    EXPECT_FALSE(lom::isDirectPng(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()));
  }
  const PngSpec depth{"grey 16-bit (depth)", 13, 7, 16, PNG_COLOR_TYPE_GRAY};
  EXPECT_TRUE(lom::isDirectPng(reinterpret_cast<const std::uint8_t*>(writePng(depth).data()),
                               writePng(depth).size()));

  const int width = 40, height = 30;
  std::string rows;
  for (int v = 0; v < height; ++v)
    rows += std::string(1, '\0') + std::string(width, static_cast<char>(v * 5));
  std::string bad_filter = rows;
  bad_filter[static_cast<size_t>(5 * (width + 1))] = 9;
  std::string extra_row = rows + std::string(1, '\0') + std::string(width, 'x');
  const std::string odd[] = {
      handMadePng(width, height, bad_filter),  // an unknown filter type
      handMadePng(width, height, rows, 20),    // the stream stops early
      handMadePng(width, height, extra_row),   // more data than the image's rows
  };
  for (const std::string& png : odd) {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(png.data());
    ASSERT_TRUE(lom::isDirectPng(bytes, png.size()));
    EXPECT_FALSE(lom::decodePngDirectly(bytes, png.size()).has_value());
  }
  // libpng decodes the image with data to spare (and its warning is dropped).
  testing::internal::CaptureStderr();
  const cv::Mat spare = decodedHere(odd[2]);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  ASSERT_EQ(spare.rows, height);
  EXPECT_EQ(spare.at<std::uint8_t>(29, 3), static_cast<std::uint8_t>(29 * 5));
}

// The depth and colour frames of the recordings take the direct route and
// give the samples OpenCV reads (their encoders chose Paeth, Up, Sub and no
// filter row by row).
TEST(PngDecodeTest, RecordedFramesDecodeDirectlyAsOpenCvReadsThem) {
  LOM_REQUIRE_SHARED_DATA("");
  size_t decoded = 0;
  for (const auto& entry : fs::recursive_directory_iterator(lom::test::sharedDataDir())) {
    if (entry.path().extension() != ".png") continue;
    SCOPED_TRACE(entry.path().string());
    const std::string png = lom::test::slurp(entry.path());
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(png.data());
    ASSERT_TRUE(lom::isDirectPng(bytes, png.size()));
    const std::optional<cv::Mat> direct = lom::decodePngDirectly(bytes, png.size());
    ASSERT_TRUE(direct.has_value());
    const cv::Mat expected = decodedByOpenCv(png);
    ASSERT_EQ(direct->type(), expected.type());
    ASSERT_EQ(direct->size(), expected.size());
    EXPECT_EQ(cv::norm(*direct, expected, cv::NORM_INF), 0.0);
    ++decoded;
  }
  if (decoded == 0) GTEST_SKIP() << "no PNG frames in " << lom::test::sharedDataDir();
}

TEST(PngDecodeTest, DamagedImageDataIsOneErrorWithLibpngsReasonAndNothingPrinted) {
  lom::test::TempDir dir;
  const int width = 40, height = 30;
  std::string rows;
  for (int v = 0; v < height; ++v)
    rows += std::string(1, '\0') + std::string(width, static_cast<char>(v * 5));
  writeText(dir / "good.png", handMadePng(width, height, rows));
  EXPECT_EQ(lom::readLabelImage(dir / "good.png").ids[static_cast<size_t>(3 * width)], 15);

  std::string bad_filter = rows;
  bad_filter[static_cast<size_t>(5 * (width + 1))] = 9;  // row 5's filter: only 0 to 4 exist
  writeText(dir / "filter.png", handMadePng(width, height, bad_filter));
  writeText(dir / "short.png", handMadePng(width, height, rows, 20));  // the stream stops early
  for (const char* name : {"filter.png", "short.png"}) {
    SCOPED_TRACE(name);
    testing::internal::CaptureStderr();
    const lom::Problem problem = errorOf([&] { (void)lom::readLabelImage(dir / name); });
    const std::string printed = testing::internal::GetCapturedStderr();
    EXPECT_EQ(printed, "");
    EXPECT_EQ(problem.file, (dir / name).string());
    EXPECT_EQ(problem.field, "PNG data");
    EXPECT_NE(problem.found.find("libpng stopped: "), std::string::npos) << problem.found;
  }
  EXPECT_NE(errorOf([&] { (void)lom::readLabelImage(dir / "filter.png"); }).found.find("filter"),
            std::string::npos);

  // PNG data in a bag has had no header check: billions of declared pixels are refused
  // before anything is allocated.
  const std::string huge = handMadePng(20000, 20000, rows);
  const lom::Problem problem = errorOf([&] { (void)decodedHere(huge); });
  EXPECT_NE(problem.found.find("more than 134217728"), std::string::npos) << problem.found;
}

}  // namespace
