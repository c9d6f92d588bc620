// Frame files that are not what they claim: folders, pipes and devices given
// as files, NUL characters in paths, images whose headers declare sizes that
// would take gigabytes to decode. Each is reported naming the file and field.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "lom/annotations.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/labels.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "test_input_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using lom::test::errorOf;
using lom::test::writeSequence;
using lom::test::writeText;

TEST(FramePathTest, NulCharacterInAPathIsRefusedNamingTheField) {
  lom::test::TempDir dir;
  writeSequence(dir.path());
  Json json = Json::parse(std::ifstream(dir / "sequence.json"));
  json["frames"][0]["depth"] = std::string("depth/0.png\0.exr", 16);
  std::ofstream(dir / "sequence.json") << json.dump();
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.field, "frames[0].depth");
  EXPECT_NE(problem.found.find("NUL character"), std::string::npos) << problem.message();
  EXPECT_NE(problem.found.find("position 11"), std::string::npos) << problem.message();
}

TEST(FramePathTest, FramesThatAreNotRegularFilesSayWhatTheyAre) {
  lom::test::TempDir dir;
  lom::Sequence sequence = lom::loadSequence(writeSequence(dir.path()).root);
  fs::create_directories(dir / "folder.png");
  ASSERT_EQ(::mkfifo((dir / "pipe.png").c_str(), 0600), 0);
  const auto foundFor = [&](const std::string& depth) {
    sequence.frames[0].depth = depth;
    const auto problems = lom::validateSequence(sequence);
    EXPECT_EQ(problems.size(), 1u) << depth;
    return problems.empty() ? std::string() : problems[0].found;
  };
  EXPECT_EQ(foundFor("folder.png"), "a directory, not a file");
  EXPECT_EQ(foundFor("pipe.png"), "a named pipe (FIFO), not a regular file");  // no hang
  EXPECT_EQ(foundFor("/dev/zero"), "a character device, not a regular file");
  EXPECT_EQ(foundFor("missing.png"), "no such file");
  fs::create_symlink(dir / "gone.png", dir / "link.png");
  EXPECT_EQ(foundFor("link.png"), "no such file (a symbolic link to a missing target)");

  sequence.frames[0].depth = "depth/0.png";
  sequence.frames[0].label = "/dev/zero";
  sequence.frames[0].proba = "pipe.png";
  const auto problems = lom::validateSequence(sequence);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].found, "a named pipe (FIFO), not a regular file");
  EXPECT_EQ(problems[1].found, "a character device, not a regular file");

  EXPECT_EQ(errorOf([&] { (void)lom::loadSequence(dir / "pipe.png"); }).found,
            "a named pipe (FIFO), not a regular file");
  EXPECT_EQ(errorOf([&] { (void)lom::loadAnnotations(dir / "folder.png"); }).found,
            "a directory, not a file");
  EXPECT_EQ(errorOf([&] { (void)lom::readNpy("/dev/zero"); }).found,
            "a character device, not a regular file");
}

TEST(ListFileTest, LabelAndBatchListsThatAreNotRegularFilesSayWhatTheyAre) {
  lom::test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "pipe.txt").c_str(), 0600), 0);
  fs::create_directories(dir / "folder.txt");
  const std::string fifo = "a named pipe (FIFO), not a regular file";
  const std::string device = "a character device, not a regular file";
  EXPECT_EQ(errorOf([&] { (void)lom::readLabelList("/dev/zero"); }).found, device);
  EXPECT_EQ(errorOf([&] { (void)lom::readLabelList(dir / "pipe.txt"); }).found, fifo);  // no hang
  EXPECT_EQ(errorOf([&] { (void)lom::readLabelList(dir / "folder.txt"); }).found,
            "a directory, not a file");
  EXPECT_EQ(errorOf([&] { (void)lom::readBatchList("/dev/zero"); }).found, device);
  EXPECT_EQ(errorOf([&] { (void)lom::readBatchList(dir / "pipe.txt"); }).found, fifo);
  EXPECT_EQ(errorOf([&] { (void)lom::readBatchList(dir / "missing.txt"); }).found, "no such file");

  writeSequence(dir / "seq");
  writeText(dir / "list.txt", "seq /dev/zero\n");
  const lom::Problem problem = errorOf([&] { (void)lom::readBatchList(dir / "list.txt"); });
  EXPECT_EQ(problem.field, "line 1 (ANNOTATIONS_PATH)");
  EXPECT_EQ(problem.found, "/dev/zero: " + device);
}

TEST(ListFileTest, LabelListNamesTheLineOfABadName) {
  lom::test::TempDir dir;
  writeText(dir / "labels.txt", "# ids follow the lines\n__background__\r\n  mug \n\nbook\n");
  const lom::LabelSet labels = lom::readLabelList(dir / "labels.txt");
  ASSERT_EQ(labels.size(), 3);
  EXPECT_EQ(labels.at(1).name, "mug");
  EXPECT_EQ(labels.at(2).name, "book");
  EXPECT_EQ(labels.at(2).color, lom::vocColor(2));

  writeText(dir / "labels.txt", "__background__\nmug\nmug\n");
  lom::Problem problem = errorOf([&] { (void)lom::readLabelList(dir / "labels.txt"); });
  EXPECT_EQ(problem.file, (dir / "labels.txt").string());
  EXPECT_EQ(problem.field, "line 3");
  EXPECT_EQ(problem.found, "\"mug\" again (also line 2)");
  writeText(dir / "labels.txt", "__background__\n" + std::string(300, 'x') + "\n");
  problem = errorOf([&] { (void)lom::readLabelList(dir / "labels.txt"); });
  EXPECT_EQ(problem.field, "line 2");
  EXPECT_EQ(problem.found, "a name of 300 bytes");
  std::string many;
  for (int i = 0; i < 257; ++i) many += "label" + std::to_string(i) + "\n";
  writeText(dir / "labels.txt", many);
  problem = errorOf([&] { (void)lom::readLabelList(dir / "labels.txt"); });
  EXPECT_EQ(problem.field, "line 257");
  EXPECT_EQ(problem.found, "more than 256 names");
}

TEST(ListFileTest, AByteOrderMarkIsNotPartOfTheFirstLine) {
  lom::test::TempDir dir;
  writeText(dir / "labels.txt", "\xEF\xBB\xBF# my labels\r\n__background__\r\nbox\r\nbook\r\n");
  lom::LabelSet labels = lom::readLabelList(dir / "labels.txt");
  ASSERT_EQ(labels.size(), 3) << "the comment stays a comment";
  EXPECT_EQ(labels.at(0).name, "__background__");
  EXPECT_EQ(labels.at(2).name, "book");
  writeText(dir / "labels.txt", "\xEF\xBB\xBF__background__\nbox\n");
  labels = lom::readLabelList(dir / "labels.txt");
  EXPECT_EQ(labels.at(0).name, "__background__");
}

TEST(ImageFileTest, EmptyFilesAndMisnamedDataSayWhatTheyHold) {
  lom::test::TempDir dir;
  writeText(dir / "empty.png", "");
  lom::Problem problem = errorOf([&] { (void)lom::readDepthImage(dir / "empty.png", 0.001); });
  EXPECT_EQ(problem.file, (dir / "empty.png").string());
  EXPECT_EQ(problem.found, "an empty file (0 bytes)");
  writeText(dir / "text.png", "hello, not a picture");
  problem = errorOf([&] { (void)lom::readColorImage(dir / "text.png"); });
  EXPECT_EQ(problem.expected, "PNG data (as its name says)");
  EXPECT_EQ(problem.found,
            "a file of other data (it starts with the bytes 68 65 6c 6c 6f 2c 20 6e)");
  // Data of a format OpenCV knows, under another name, is still read.
  cv::Mat grey(4, 5, CV_8UC1, cv::Scalar(7));
  ASSERT_TRUE(cv::imwrite((dir / "grey.pgm").string(), grey));
  std::filesystem::rename(dir / "grey.pgm", dir / "grey.png");
  EXPECT_EQ(lom::readLabelImage(dir / "grey.png").width, 5);
}

// A PNG whose header declares width x height; only the signature and IHDR
// are real (a decoder would fail later, or allocate the whole image first).
std::string pngHeader(std::uint32_t width, std::uint32_t height) {
  std::string bytes("\x89PNG\r\n\x1a\n", 8);
  bytes += std::string("\0\0\0\x0d", 4) + "IHDR";
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((v >> shift) & 0xff);
  bytes += std::string("\x10\0\0\0", 4);  // 16-bit grey
  return bytes + std::string(4, '\0') + std::string(1000, '\0');
}

TEST(ImageHeaderTest, DepthPngOfTheWrongDeclaredSizeIsRefusedBeforeDecoding) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = lom::loadSequence(writeSequence(dir.path()).root);
  writeText(dir / "depth/0.png", pngHeader(30000, 30000));
  const auto problems = lom::validateSequence(sequence);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].file, (dir / "depth/0.png").string());
  EXPECT_EQ(problems[0].field, "frames[0].depth (image size)");
  EXPECT_EQ(problems[0].found, "30000 x 30000");
  EXPECT_NE(problems[0].expected.find("4 x 3"), std::string::npos);
}

TEST(ImageHeaderTest, PgmOfTheWrongDeclaredSizeIsRefusedBeforeDecoding) {
  lom::test::TempDir dir;
  lom::Sequence sequence = lom::loadSequence(writeSequence(dir.path()).root);
  writeText(dir / "depth/0.pgm", "P5\n# a comment\n40000 30000\n65535\n" + std::string(64, '\0'));
  sequence.frames[0].depth = "depth/0.pgm";
  const auto problems = lom::validateSequence(sequence);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].field, "frames[0].depth (image size)");
  EXPECT_EQ(problems[0].found, "40000 x 30000");
}

TEST(ImageHeaderTest, ReadersRefuseImagesDeclaringTooManyPixels) {
  lom::test::TempDir dir;
  writeText(dir / "huge.png", pngHeader(60000, 60000));
  const lom::Problem problem = errorOf([&] { (void)lom::readDepthImage(dir / "huge.png", 0.001); });
  EXPECT_EQ(problem.file, (dir / "huge.png").string());
  EXPECT_EQ(problem.field, "image size");
  EXPECT_EQ(problem.found, "60000 x 60000 pixels (declared in the PNG header)");
  writeText(dir / "huge.pgm", "P5 70000 70000 255\n");
  EXPECT_EQ(errorOf([&] { (void)lom::readLabelImage(dir / "huge.pgm"); }).found,
            "70000 x 70000 pixels (declared in the PGM header)");
}

TEST(ImageHeaderTest, TruncatedPgmAndPpmAreRefusedNamingTheirSize) {
  lom::test::TempDir dir;
  // 4 x 3 pixels of 16-bit depth need 24 bytes after the header; 10 are there.
  const std::string header = "P5\n# depth in mm\n4 3\n65535\n";
  writeText(dir / "depth.pgm", header + std::string(10, '\x01'));
  const lom::Problem problem =
      errorOf([&] { (void)lom::readDepthImage(dir / "depth.pgm", 0.001); });
  EXPECT_EQ(problem.file, (dir / "depth.pgm").string());
  EXPECT_EQ(problem.field, "image data");
  EXPECT_EQ(problem.expected, "4 x 3 pixels of PGM data (" + std::to_string(header.size() + 24) +
                                  " bytes with the header)");
  EXPECT_EQ(problem.found,
            "a file truncated after " + std::to_string(header.size() + 10) + " bytes");
  // Complete files still read: 8-bit grey and 8-bit colour.
  writeText(dir / "labels.pgm", "P5 4 3 255\n" + std::string(12, '\x02'));
  EXPECT_EQ(lom::readLabelImage(dir / "labels.pgm").ids.at(5), 2);
  writeText(dir / "colour.ppm", "P6 4 3 255\n" + std::string(35, '\x03'));
  EXPECT_EQ(errorOf([&] { (void)lom::readColorImage(dir / "colour.ppm"); }).found,
            "a file truncated after 46 bytes");
}

std::string bigEndian16(unsigned v) {
  return {static_cast<char>((v >> 8) & 0xff), static_cast<char>(v & 0xff)};
}

// A TIFF whose first directory declares width x height (SHORT or LONG tags).
std::string tiffHeader(bool little, std::uint32_t width, std::uint32_t height, bool longs) {
  const auto number = [&](std::uint32_t v, int size) {
    std::string bytes;
    for (int i = 0; i < size; ++i) {
      const int shift = 8 * (little ? i : size - 1 - i);
      bytes += static_cast<char>((v >> shift) & 0xff);
    }
    return bytes;
  };
  std::string bytes = little ? "II" : "MM";
  bytes += number(42, 2) + number(8, 4) + number(3, 2);
  bytes += number(254, 2) + number(4, 2) + number(1, 4) + number(0, 4);  // NewSubfileType
  for (const auto& [tag, value] : {std::pair{256u, width}, std::pair{257u, height}}) {
    bytes += number(tag, 2) + number(longs ? 4 : 3, 2) + number(1, 4);
    bytes += longs ? number(value, 4) : number(value, 2) + number(0, 2);
  }
  return bytes + number(0, 4) + std::string(100, '\0');
}

TEST(ImageHeaderTest, JpegTiffAndBmpDeclaringTooManyPixelsAreRefusedBeforeDecoding) {
  lom::test::TempDir dir;
  // JPEG: start of image, an APP0 segment to skip, then the frame header.
  writeText(dir / "huge.jpg", std::string("\xff\xd8\xff\xe0", 4) + bigEndian16(16) +
                                  std::string(14, 'J') + std::string("\xff\xc0", 2) +
                                  bigEndian16(17) + '\x08' + bigEndian16(50000) +
                                  bigEndian16(60000) + std::string(200, '\0'));
  EXPECT_EQ(errorOf([&] { (void)lom::readColorImage(dir / "huge.jpg"); }).found,
            "60000 x 50000 pixels (declared in the JPEG header)");
  for (const bool little : {true, false})
    for (const bool longs : {true, false}) {
      writeText(dir / "huge.tif", tiffHeader(little, 65000, 40000, longs));
      const lom::Problem problem = errorOf([&] { (void)lom::readColorImage(dir / "huge.tif"); });
      EXPECT_EQ(problem.field, "image size");
      EXPECT_EQ(problem.found, "65000 x 40000 pixels (declared in the TIFF header)")
          << little << longs;
    }
  std::string bmp = "BM" + std::string(12, '\0');  // file size, reserved, pixel offset
  for (const std::int32_t v : {40, 70000, -70000})
    for (int i = 0; i < 4; ++i)
      bmp += static_cast<char>((static_cast<std::uint32_t>(v) >> (8 * i)) & 0xff);
  writeText(dir / "huge.bmp", bmp + std::string(100, '\0'));
  EXPECT_EQ(errorOf([&] { (void)lom::readColorImage(dir / "huge.bmp"); }).found,
            "70000 x 70000 pixels (declared in the BMP header)");
}

TEST(ImageHeaderTest, RealJpegTiffAndBmpFilesStillRead) {
  lom::test::TempDir dir;
  cv::Mat bgr(3, 5, CV_8UC3, cv::Scalar(10, 20, 30));
  for (const char* name : {"c.jpg", "c.tif", "c.bmp", "c.png"}) {
    ASSERT_TRUE(cv::imwrite((dir / name).string(), bgr)) << name;
    const lom::ColorImage image = lom::readColorImage(dir / name);
    EXPECT_EQ(image.width, 5) << name;
    EXPECT_EQ(image.height, 3) << name;
  }
}

}  // namespace

namespace {

// A message quotes at most a few kilobytes of what it found (a megabyte-long
// line of a list was repeated whole), and says how long it was.
TEST(ErrorMessages, LongQuotedInputIsShortened) {
  const std::string line(1 << 20, 'A');
  const lom::Error error("list.txt", "line 1", "SEQ_PATH ANNOTATIONS_PATH [MAP.ot]", line);
  const std::string message = error.what();
  EXPECT_LT(message.size(), 4000u);
  EXPECT_NE(
      message.find("list.txt: line 1: expected SEQ_PATH ANNOTATIONS_PATH [MAP.ot], found AAA"),
      std::string::npos);
  EXPECT_NE(message.find("... (1048576 bytes in all)"), std::string::npos);
  // Not cut inside a character.
  const std::string accents(3000, 'a');
  const lom::Error cut("f", "", "x", accents + std::string(1000, '\xc3') + "\xa9" + accents);
  const std::string shown = cut.what();
  const size_t dots = shown.find("... (");
  ASSERT_NE(dots, std::string::npos);
  EXPECT_NE(static_cast<unsigned char>(shown[dots - 1]) & 0xC0, 0x80);
  // Short text as it is, UTF-8 included; bytes that are not UTF-8 become '?'.
  EXPECT_STREQ(lom::Error("f", "g", "h", "i").what(), "f: g: expected h, found i");
  EXPECT_STREQ(lom::Error("caf\xc3\xa9.bag", "topic", "h", "/cam\xff\xfe/depth").what(),
               "caf\xc3\xa9.bag: topic: expected h, found /cam?"
               "?/depth");
}

}  // namespace
