// JPEG frames are decoded through libjpeg with its messages captured: the same
// pixels as OpenCV's reader for the kinds of JPEG cameras and datasets write,
// and damaged image data (which libjpeg would decode anyway, with a line on
// stderr and made-up pixels) becomes one error naming the file.
#include <gtest/gtest.h>

#include <cstdio>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <cstdint>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "jpeg_decode.hpp"
#include "lom/sequence.hpp"
#include "test_input_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::errorOf;
using lom::test::writeText;

struct JpegSpec {
  const char* name;
  int width, height, components;
  J_COLOR_SPACE input;         // the samples handed to libjpeg
  J_COLOR_SPACE stored;        // the colour space written in the file
  bool progressive = false;
  int restart_rows = 0;        // restart markers every so many MCU rows (0: none)
};

// A JPEG written with libjpeg's own encoder, samples varying over the image.
std::string writeJpeg(const JpegSpec& spec) {
  jpeg_compress_struct info{};
  jpeg_error_mgr errors{};
  info.err = jpeg_std_error(&errors);
  jpeg_create_compress(&info);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&info, &buffer, &size);
  info.image_width = static_cast<JDIMENSION>(spec.width);
  info.image_height = static_cast<JDIMENSION>(spec.height);
  info.input_components = spec.components;
  info.in_color_space = spec.input;
  jpeg_set_defaults(&info);
  jpeg_set_colorspace(&info, spec.stored);
  jpeg_set_quality(&info, 90, TRUE);
  if (spec.progressive) jpeg_simple_progression(&info);
  info.restart_in_rows = spec.restart_rows;
  jpeg_start_compress(&info, TRUE);
  std::vector<JSAMPLE> row(static_cast<size_t>(spec.width) * spec.components);
  while (info.next_scanline < info.image_height) {
    const size_t v = info.next_scanline;
    for (size_t i = 0; i < row.size(); ++i)
      row[i] = static_cast<JSAMPLE>((v * 29 + i * 13) ^ (i * v >> 2));
    JSAMPROW pointer = row.data();
    jpeg_write_scanlines(&info, &pointer, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::string bytes(reinterpret_cast<const char*>(buffer), size);
  std::free(buffer);
  return bytes;
}

cv::Mat decodedByOpenCv(const std::string& jpeg) {
  const std::vector<std::uint8_t> buffer(jpeg.begin(), jpeg.end());
  return cv::imdecode(buffer, cv::IMREAD_UNCHANGED);
}

cv::Mat decodedHere(const std::string& jpeg) {
  return lom::decodeJpeg(reinterpret_cast<const std::uint8_t*>(jpeg.data()), jpeg.size(),
                         "x.jpg");
}

const JpegSpec kColour{"YCbCr colour", 37, 21, 3, JCS_RGB, JCS_YCbCr};

TEST(JpegDecodeTest, GivesOpenCvsPixelsForEveryKindOfJpeg) {
  const JpegSpec specs[] = {
      kColour,
      {"grey", 37, 21, 1, JCS_GRAYSCALE, JCS_GRAYSCALE},
      {"RGB stored as RGB", 37, 21, 3, JCS_RGB, JCS_RGB},
      {"CMYK", 37, 21, 4, JCS_CMYK, JCS_CMYK},
      {"YCCK", 37, 21, 4, JCS_CMYK, JCS_YCCK},
      {"progressive colour", 37, 21, 3, JCS_RGB, JCS_YCbCr, true},
      {"colour with restart markers", 64, 48, 3, JCS_RGB, JCS_YCbCr, false, 1},
      {"one pixel", 1, 1, 3, JCS_RGB, JCS_YCbCr},
  };
  for (const JpegSpec& spec : specs) {
    SCOPED_TRACE(spec.name);
    const std::string jpeg = writeJpeg(spec);
    const cv::Mat expected = decodedByOpenCv(jpeg);
    ASSERT_FALSE(expected.empty());
    const cv::Mat decoded = decodedHere(jpeg);
    ASSERT_EQ(decoded.type(), expected.type());
    ASSERT_EQ(decoded.size(), expected.size());
    EXPECT_EQ(cv::norm(decoded, expected, cv::NORM_INF), 0.0);
  }
}

TEST(JpegDecodeTest, DamagedImageDataIsOneErrorWithLibjpegsReasonAndNothingPrinted) {
  lom::test::TempDir dir;
  const std::string good = writeJpeg({"colour", 64, 48, 3, JCS_RGB, JCS_YCbCr});
  writeText(dir / "good.jpg", good);
  const lom::ColorImage colour = lom::readColorImage(dir / "good.jpg");
  const cv::Mat expected = decodedByOpenCv(good);
  EXPECT_EQ(colour.rgb[0], expected.at<cv::Vec3b>(0, 0)[2]);  // RGB against OpenCV's BGR

  struct Damage {
    const char* name;
    std::string bytes;
    const char* reason;
  };
  std::string junk = good;  // bytes left over before the end-of-image marker
  junk.insert(junk.size() - 2, "\x12\x34\x56");
  std::string header = good.substr(0, 40);  // cut inside the headers: no image at all
  const Damage damages[] = {
      {"cut.jpg", good.substr(0, good.size() / 2), "Premature end of JPEG file"},
      {"junk.jpg", junk, "extraneous bytes before marker 0xd9"},
      {"header.jpg", header, "libjpeg stopped: "},
  };
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.name);
    writeText(dir / damage.name, damage.bytes);
    testing::internal::CaptureStderr();
    const lom::Problem problem = errorOf([&] { (void)lom::readColorImage(dir / damage.name); });
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(problem.file, (dir / damage.name).string());
    EXPECT_EQ(problem.field, "JPEG data");
    EXPECT_EQ(problem.expected, "a JPEG whose image data can be decoded");
    EXPECT_NE(problem.found.find("libjpeg stopped: "), std::string::npos) << problem.found;
    EXPECT_NE(problem.found.find(damage.reason), std::string::npos) << problem.found;
  }
}

TEST(JpegDecodeTest, HarmlessWarningsAreDroppedAndTheImageIsRead) {
  std::string jpeg = writeJpeg(kColour);
  // The JFIF segment's major version (after SOI, APP0, its length and "JFIF\0"):
  // libjpeg warns about an unknown revision and decodes as usual.
  ASSERT_EQ(jpeg.compare(6, 5, std::string("JFIF\0", 5)), 0);
  const cv::Mat expected = decodedHere(jpeg);
  jpeg[11] = 2;
  testing::internal::CaptureStderr();
  const cv::Mat decoded = decodedHere(jpeg);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  ASSERT_EQ(decoded.size(), expected.size());
  EXPECT_EQ(cv::norm(decoded, expected, cv::NORM_INF), 0.0);
}

TEST(JpegDecodeTest, HugeDeclaredImagesAreRefusedBeforeDecoding) {
  std::string jpeg = writeJpeg(kColour);
  // The frame header (SOF0): marker, length, precision, then height and width.
  const size_t sof = jpeg.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  for (const size_t at : {sof + 5, sof + 7}) {  // 20000 = 0x4e20
    jpeg[at] = '\x4e';
    jpeg[at + 1] = '\x20';
  }
  const lom::Problem problem = errorOf([&] { (void)decodedHere(jpeg); });
  EXPECT_NE(problem.found.find("more than 134217728"), std::string::npos) << problem.found;
  EXPECT_FALSE(lom::hasJpegSignature(reinterpret_cast<const std::uint8_t*>("\x89PNG"), 4));
}

}  // namespace
