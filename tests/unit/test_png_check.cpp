// Truncated and damaged PNG frames: refused with one error naming the file and
// the chunk, before libpng can print its own message on stderr.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "png_check.hpp"
#include "test_input_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::errorOf;
using lom::test::writeText;

struct Chunk {
  size_t at = 0;      // offset of the length field
  size_t length = 0;  // bytes of chunk data
  std::string type;
};

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The chunks of a well-formed PNG, walked independently of the code under test.
std::vector<Chunk> chunksOf(const std::string& png) {
  std::vector<Chunk> chunks;
  for (size_t at = 8; at + 12 <= png.size();) {
    size_t length = 0;
    for (int i = 0; i < 4; ++i) length = length << 8 | static_cast<unsigned char>(png[at + i]);
    chunks.push_back({at, length, png.substr(at + 4, 4)});
    at += length + 12;
  }
  return chunks;
}

// The number (from 1) of the first IDAT chunk.
size_t firstImageData(const std::vector<Chunk>& chunks) {
  for (size_t i = 0; i < chunks.size(); ++i)
    if (chunks[i].type == "IDAT") return i;
  ADD_FAILURE() << "no IDAT chunk";
  return 0;
}

// A 16-bit depth PNG written by the project's writer, with varied values so
// that the image data is more than a few bytes.
fs::path writeDepth(const lom::test::TempDir& dir) {
  lom::DepthImage depth{64, 48, std::vector<float>(64 * 48)};
  for (size_t i = 0; i < depth.metres.size(); ++i) depth.metres[i] = 0.5f + 0.001f * (i % 997);
  lom::writeDepthPng(dir / "depth.png", depth, 0.001);
  return dir / "depth.png";
}

lom::Problem depthErrorOf(const fs::path& path) {
  return errorOf([&] { (void)lom::readDepthImage(path, 0.001); });
}

TEST(PngCheckTest, PngFromTheProjectsWriterPasses) {
  lom::test::TempDir dir;
  const fs::path path = writeDepth(dir);
  const std::string png = readBytes(path);
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(png.data());
  ASSERT_TRUE(lom::hasPngSignature(bytes, png.size()));
  EXPECT_NO_THROW(lom::checkPngChunks(bytes, png.size(), path.string()));
  const lom::DepthImage depth = lom::readDepthImage(path, 0.001);
  ASSERT_EQ(depth.width, 64);
  ASSERT_EQ(depth.height, 48);
  EXPECT_NEAR(depth.at(5, 1), 0.5f + 0.001f * 69, 1e-6);
}

TEST(PngCheckTest, PngCutInsideImageDataNamesTheFileAndTheChunk) {
  lom::test::TempDir dir;
  const std::string png = readBytes(writeDepth(dir));
  const auto chunks = chunksOf(png);
  const size_t idat = firstImageData(chunks);
  ASSERT_GT(chunks[idat].length, 20u);
  const size_t cut = chunks[idat].at + 8 + chunks[idat].length / 2;
  writeText(dir / "cut.png", png.substr(0, cut));
  const lom::Problem problem = depthErrorOf(dir / "cut.png");
  EXPECT_EQ(problem.file, (dir / "cut.png").string());
  EXPECT_EQ(problem.field, "PNG data");
  EXPECT_EQ(problem.expected, "a complete PNG file");
  EXPECT_EQ(problem.found, "the PNG ends inside chunk " + std::to_string(idat + 1) +
                               " (IDAT), after " + std::to_string(cut) + " of at least " +
                               std::to_string(chunks[idat].at + chunks[idat].length + 12) +
                               " bytes");
}

TEST(PngCheckTest, FlippedByteInImageDataFailsTheCrcCheck) {
  lom::test::TempDir dir;
  std::string png = readBytes(writeDepth(dir));
  const auto chunks = chunksOf(png);
  const size_t idat = firstImageData(chunks);
  png[chunks[idat].at + 8 + chunks[idat].length / 2] ^= 0x10;
  writeText(dir / "flipped.png", png);
  const lom::Problem problem = errorOf([&] { (void)lom::readLabelImage(dir / "flipped.png"); });
  EXPECT_EQ(problem.file, (dir / "flipped.png").string());
  EXPECT_EQ(problem.field, "PNG data");
  EXPECT_EQ(problem.found, "chunk " + std::to_string(idat + 1) + " (IDAT) fails its CRC check");
}

TEST(PngCheckTest, PngWithoutIendIsRefused) {
  lom::test::TempDir dir;
  const std::string png = readBytes(writeDepth(dir));
  const auto chunks = chunksOf(png);
  ASSERT_EQ(chunks.back().type, "IEND");
  const std::string cut = png.substr(0, chunks.back().at);
  writeText(dir / "no-end.png", cut);
  const lom::Problem problem = errorOf([&] { (void)lom::readColorImage(dir / "no-end.png"); });
  EXPECT_EQ(problem.file, (dir / "no-end.png").string());
  EXPECT_EQ(problem.found, "the PNG ends after " + std::to_string(cut.size()) +
                               " bytes, after chunk " + std::to_string(chunks.size() - 1) + " (" +
                               chunks[chunks.size() - 2].type + "), without an IEND chunk");
}

TEST(PngCheckTest, ReadingATruncatedPngPrintsNothingOnStderr) {
  lom::test::TempDir dir;
  const std::string png = readBytes(writeDepth(dir));
  const auto chunks = chunksOf(png);
  const size_t idat = firstImageData(chunks);
  writeText(dir / "cut.png", png.substr(0, chunks[idat].at + 8 + chunks[idat].length / 2));
  testing::internal::CaptureStderr();
  const lom::Problem problem = depthErrorOf(dir / "cut.png");
  const std::string printed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed, "");
  EXPECT_EQ(problem.file, (dir / "cut.png").string());
}

// Chunks built by hand: the CRC of an empty IEND chunk is the well-known AE 42 60 82.
std::string chunk(const std::string& type, const std::string& data, std::uint32_t crc) {
  std::string bytes;
  for (int shift = 24; shift >= 0; shift -= 8)
    bytes += static_cast<char>((data.size() >> shift) & 0xff);
  bytes += type + data;
  for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((crc >> shift) & 0xff);
  return bytes;
}

std::string foundFor(const std::string& png) {
  return errorOf([&] {
           lom::checkPngChunks(reinterpret_cast<const std::uint8_t*>(png.data()), png.size(),
                               "hand.png");
         })
      .found;
}

TEST(PngCheckTest, StructureProblemsAreNamedPrecisely) {
  const std::string signature("\x89PNG\r\n\x1a\n", 8);
  const std::string iend = chunk("IEND", "", 0xAE426082u);
  EXPECT_EQ(foundFor(signature), "the PNG ends after 8 bytes, right after the signature");
  // The IEND chunk's CRC is right: only its place is wrong.
  EXPECT_EQ(foundFor(signature + iend), "chunk 1 (IEND) comes first instead of IHDR");
  EXPECT_EQ(foundFor(signature + chunk("IHDR", std::string(12, '\0'), 0)),
            "chunk 1 (IHDR) is 12 bytes long instead of 13");
  EXPECT_EQ(foundFor(signature + chunk("IHDR", std::string(13, '\0'), 0)),
            "chunk 1 (IHDR) fails its CRC check");
  EXPECT_EQ(foundFor(signature + chunk("IH#R", std::string(13, '\0'), 0)),
            "chunk 1 (at byte 8) has no valid type (four letters)");
  EXPECT_EQ(foundFor(signature + std::string("\0\0\0", 3)),
            "the PNG ends after 11 bytes, inside the length and type of chunk 1");
  EXPECT_EQ(foundFor(signature + chunk("IHDR", std::string(13, '\0'), 0).substr(0, 20)),
            "the PNG ends inside chunk 1 (IHDR), after 28 of at least 33 bytes");
}

TEST(PngCheckTest, PngWithoutImageDataIsRefused) {
  lom::test::TempDir dir;
  const std::string png = readBytes(writeDepth(dir));
  const auto chunks = chunksOf(png);
  // IHDR (and any chunk before the image data), then IEND.
  const size_t idat = firstImageData(chunks);
  const std::string no_data = png.substr(0, chunks[idat].at) + png.substr(chunks.back().at);
  EXPECT_EQ(foundFor(no_data),
            "no IDAT chunk (image data) before chunk " + std::to_string(idat + 1) + " (IEND)");
}

}  // namespace
