// The .npy reader is checked against files assembled byte by byte here, so
// it is not only tested against its own writer.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "lom/error.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

std::string npyBytes(const std::string& dict, const std::string& data, int major = 1) {
  const size_t prefix = 6 + 2 + (major == 1 ? 2 : 4);
  std::string header = dict;
  const size_t total = (prefix + header.size() + 1 + 63) / 64 * 64;
  header.append(total - prefix - header.size() - 1, ' ');
  header += '\n';
  std::string bytes = "\x93NUMPY";
  bytes += static_cast<char>(major);
  bytes += '\0';
  const size_t length_bytes = major == 1 ? 2 : 4;
  for (size_t i = 0; i < length_bytes; ++i)
    bytes += static_cast<char>((header.size() >> (8 * i)) & 0xff);
  return bytes + header + data;
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <class T>
std::string rawLittleEndian(const std::vector<T>& values) {
  std::string data(values.size() * sizeof(T), '\0');
  std::memcpy(data.data(), values.data(), data.size());
  return data;
}

template <class T>
std::string rawBigEndian(const std::vector<T>& values) {
  std::string data = rawLittleEndian(values);
  for (size_t i = 0; i < data.size(); i += sizeof(T))
    std::reverse(data.begin() + static_cast<std::ptrdiff_t>(i),
                 data.begin() + static_cast<std::ptrdiff_t>(i + sizeof(T)));
  return data;
}

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const lom::Error& e) {
    return e.what();
  }
  return "(no error)";
}

class NpyTest : public ::testing::Test {
 protected:
  lom::test::TempDir dir;
  fs::path file(const std::string& dict, const std::string& data, int major = 1) {
    const fs::path path = dir / "array.npy";
    writeBytes(path, npyBytes(dict, data, major));
    return path;
  }
};

TEST_F(NpyTest, ReadsLittleEndianFloat32) {
  const std::vector<float> values{0.5f, -1.25f, 3.0f, 1e-20f, 7.0f, 0.0f};
  const auto array = lom::readNpy(
      file("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", rawLittleEndian(values)));
  EXPECT_EQ(array.type, lom::NpyType::Float32);
  EXPECT_EQ(array.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(array.toFloat(true), values);
}

TEST_F(NpyTest, ReadsBigEndianFloat32) {
  const std::vector<float> values{0.5f, -1.25f, 3.0f, 123456.75f};
  const auto array = lom::readNpy(
      file("{'descr': '>f4', 'fortran_order': False, 'shape': (4,), }", rawBigEndian(values)));
  EXPECT_EQ(array.shape, (std::vector<size_t>{4}));
  EXPECT_EQ(array.toFloat(false), values);
}

TEST_F(NpyTest, ConvertsFloat16IncludingSubnormalsInfinityAndNan) {
  const std::vector<std::uint16_t> halves{0x3555, 0x3C00, 0x0001, 0x03FF, 0xC000,
                                          0x7C00, 0xFC00, 0x7E00, 0x8000, 0x7BFF};
  const auto values =
      lom::readNpy(file("{'descr': '<f2', 'fortran_order': False, 'shape': (10,), }",
                        rawLittleEndian(halves)))
          .toFloat(false);
  ASSERT_EQ(values.size(), halves.size());
  EXPECT_EQ(values[0], 0.333251953125f);
  EXPECT_EQ(values[1], 1.0f);
  EXPECT_EQ(values[2], std::ldexp(1.0f, -24));     // smallest subnormal
  EXPECT_EQ(values[3], std::ldexp(1023.0f, -24));  // largest subnormal
  EXPECT_EQ(values[4], -2.0f);
  EXPECT_EQ(values[5], std::numeric_limits<float>::infinity());
  EXPECT_EQ(values[6], -std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(values[7]));
  EXPECT_EQ(values[8], 0.0f);
  EXPECT_TRUE(std::signbit(values[8]));
  EXPECT_EQ(values[9], 65504.0f);  // largest finite half
}

TEST_F(NpyTest, ReadsBigEndianFloat16) {
  const std::vector<std::uint16_t> halves{0x3555, 0x3C00};
  const auto values = lom::readNpy(file("{'descr': '>f2', 'fortran_order': False, 'shape': (2,), }",
                                        rawBigEndian(halves)))
                          .toFloat(false);
  EXPECT_EQ(values, (std::vector<float>{0.333251953125f, 1.0f}));
}

TEST_F(NpyTest, ScalesUInt8ToUnitRange) {
  const std::vector<std::uint8_t> raw{0, 255, 51};
  const auto array = lom::readNpy(
      file("{'descr': '|u1', 'fortran_order': False, 'shape': (3,), }", rawLittleEndian(raw)));
  EXPECT_EQ(array.type, lom::NpyType::UInt8);
  const auto scaled = array.toFloat(true);
  EXPECT_FLOAT_EQ(scaled[0], 0.0f);
  EXPECT_FLOAT_EQ(scaled[1], 1.0f);
  EXPECT_FLOAT_EQ(scaled[2], 0.2f);
  EXPECT_EQ(array.toFloat(false)[2], 51.0f);
}

TEST_F(NpyTest, ScalesUInt16ToUnitRangeInBothByteOrders) {
  const std::vector<std::uint16_t> raw{0, 65535, 13107};
  for (const auto& [descr, data] : {std::pair{std::string("<u2"), rawLittleEndian(raw)},
                                    std::pair{std::string(">u2"), rawBigEndian(raw)}}) {
    const auto array = lom::readNpy(
        file("{'descr': '" + descr + "', 'fortran_order': False, 'shape': (3,), }", data));
    const auto scaled = array.toFloat(true);
    EXPECT_FLOAT_EQ(scaled[0], 0.0f) << descr;
    EXPECT_FLOAT_EQ(scaled[1], 1.0f) << descr;
    EXPECT_FLOAT_EQ(scaled[2], 0.2f) << descr;
    EXPECT_EQ(array.toFloat(false)[2], 13107.0f) << descr;
  }
}

TEST_F(NpyTest, ReadsFloat64) {
  const std::vector<double> values{0.25, -8.5};
  const auto array = lom::readNpy(
      file("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), }", rawLittleEndian(values)));
  EXPECT_EQ(array.type, lom::NpyType::Float64);
  EXPECT_EQ(array.toFloat(false), (std::vector<float>{0.25f, -8.5f}));
}

TEST_F(NpyTest, ConvertsFortranOrderToCOrder) {
  // value(i, j, k) = 100 i + 10 j + k, stored with i varying fastest.
  const size_t d0 = 2, d1 = 3, d2 = 4;
  std::vector<float> fortran;
  for (size_t k = 0; k < d2; ++k)
    for (size_t j = 0; j < d1; ++j)
      for (size_t i = 0; i < d0; ++i) fortran.push_back(static_cast<float>(100 * i + 10 * j + k));
  const auto values =
      lom::readNpy(file("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3, 4), }",
                        rawLittleEndian(fortran)))
          .toFloat(false);
  ASSERT_EQ(values.size(), d0 * d1 * d2);
  for (size_t i = 0; i < d0; ++i)
    for (size_t j = 0; j < d1; ++j)
      for (size_t k = 0; k < d2; ++k)
        EXPECT_EQ(values[(i * d1 + j) * d2 + k], static_cast<float>(100 * i + 10 * j + k))
            << i << "," << j << "," << k;
}

TEST_F(NpyTest, FortranOrderMatrixEqualsTransposedCOrderMatrix) {
  const std::vector<float> data{1, 2, 3, 4, 5, 6};
  const auto c = lom::readNpy(
      file("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 2), }", rawLittleEndian(data)));
  const auto f = lom::readNpy(
      file("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", rawLittleEndian(data)));
  const auto cv = c.toFloat(false), fv = f.toFloat(false);
  for (size_t r = 0; r < 2; ++r)
    for (size_t col = 0; col < 3; ++col) EXPECT_EQ(fv[r * 3 + col], cv[col * 2 + r]);
}

TEST_F(NpyTest, ReadsHeaderVersions2And3AndPython2Shapes) {
  const std::vector<float> values{1.0f, 2.0f};
  for (int major : {2, 3}) {
    const auto array =
        lom::readNpy(file("{'shape': (1L, 2L), 'fortran_order': False, 'descr': '<f4'}",
                          rawLittleEndian(values), major));
    EXPECT_EQ(array.shape, (std::vector<size_t>{1, 2})) << "version " << major;
    EXPECT_EQ(array.toFloat(false), values) << "version " << major;
  }
}

TEST_F(NpyTest, RejectsTruncatedData) {
  const std::vector<float> values{1.0f, 2.0f, 3.0f};
  const auto path =
      file("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }", rawLittleEndian(values));
  const std::string message = errorOf([&] { (void)lom::readNpy(path); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  EXPECT_NE(message.find("16 data bytes"), std::string::npos) << message;
}

TEST_F(NpyTest, RejectsUnsupportedDtypeNamingItAndTheSupportedOnes) {
  const auto path =
      file("{'descr': '<i4', 'fortran_order': False, 'shape': (1,), }", std::string(4, '\0'));
  const std::string message = errorOf([&] { (void)lom::readNpy(path); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("dtype"), std::string::npos) << message;
  EXPECT_NE(message.find("int32"), std::string::npos) << message;
  for (const char* supported : {"float32", "float16", "uint8", "uint16"})
    EXPECT_NE(message.find(supported), std::string::npos) << supported << " in " << message;
}

TEST_F(NpyTest, RejectsStructuredDtypeAndNonNpyFiles) {
  const auto structured =
      file("{'descr': [('a', '<f4'), ('b', '<i2')], 'fortran_order': False, 'shape': (1,), }",
           std::string(6, '\0'));
  const std::string message = errorOf([&] { (void)lom::readNpy(structured); });
  EXPECT_NE(message.find("structured"), std::string::npos) << message;

  const auto text = dir / "not.npy";
  writeBytes(text, "hello, this is not numpy");
  EXPECT_NE(errorOf([&] { (void)lom::readNpy(text); }).find("\\x93NUMPY"), std::string::npos);
  EXPECT_NE(errorOf([&] { (void)lom::readNpy(dir / "missing.npy"); }).find("no such file"),
            std::string::npos);
}

TEST_F(NpyTest, HeaderEntriesOfTheWrongKindAreQuotedAsWritten) {
  auto message = errorOf([&] {
    (void)lom::readNpy(file("{'descr': '|u1', 'fortran_order': 'False', 'shape': (3, 4), }",
                            std::string(12, '\0')));
  });
  EXPECT_NE(
      message.find("expected a 'fortran_order' entry of True or False, found the string 'False'"),
      std::string::npos)
      << message;
  message = errorOf([&] {
    (void)lom::readNpy(file("{'descr': '|u1', 'fortran_order': False, 'shape': (-3, 4, 12), }",
                            std::string(12, '\0')));
  });
  EXPECT_NE(message.find("a 'shape' entry with a tuple of non-negative integers, found "
                         "(-3, 4, 12)"),
            std::string::npos)
      << message;
  message = errorOf([&] {
    (void)lom::readNpy(file("{'descr': '|u1', 'fortran_order': False, }", std::string(12, '\0')));
  });
  EXPECT_NE(message.find("a 'shape' entry with a tuple of non-negative integers, found none"),
            std::string::npos)
      << message;
}

TEST_F(NpyTest, FileEndingAfterTheMagicIsTruncatedNotForeign) {
  const fs::path path = dir / "magic-only.npy";
  writeBytes(path, "\x93NUMPY");
  const std::string message = errorOf([&] { (void)lom::readNpy(path); });
  EXPECT_EQ(message.find("other leading bytes"), std::string::npos) << message;
  EXPECT_NE(message.find(path.string() + ": header: expected a format version and header length "
                                         "after \\x93NUMPY, found the file ends after 6 bytes "
                                         "(truncated file)"),
            std::string::npos)
      << message;
  writeBytes(path, std::string("\x93NUMPY\x01\x00\x10", 9));
  EXPECT_NE(errorOf([&] { (void)lom::readNpy(path); }).find("ends after 9 bytes"),
            std::string::npos);
  writeBytes(path, "\x93NUM");
  EXPECT_NE(errorOf([&] { (void)lom::readNpy(path); }).find("found a file of 4 bytes"),
            std::string::npos);
}

TEST_F(NpyTest, WriterProducesAlignedLittleEndianFilesThatReadBack) {
  const fs::path path = dir / "written.npy";
  const std::vector<float> values{1.5f, -2.0f, 0.125f, 9.0f, 10.0f, 11.0f};
  lom::writeNpyFloat32(path, {1, 2, 3}, values);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 10u);
  const size_t header_length = static_cast<unsigned char>(bytes[8]) |
                               (static_cast<size_t>(static_cast<unsigned char>(bytes[9])) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);
  EXPECT_NE(bytes.find("'descr': '<f4'"), std::string::npos);
  EXPECT_EQ(bytes.size(), 10 + header_length + values.size() * 4);

  const auto array = lom::readNpy(path);
  EXPECT_EQ(array.shape, (std::vector<size_t>{1, 2, 3}));
  EXPECT_EQ(array.toFloat(false), values);

  lom::NpyArray words;
  words.type = lom::NpyType::UInt16;
  words.shape = {2};
  words.bytes = {0x34, 0x12, 0xff, 0xff};
  lom::writeNpy(path, words);
  EXPECT_EQ(lom::readNpy(path).toFloat(false), (std::vector<float>{4660.0f, 65535.0f}));
}

TEST_F(NpyTest, ProbabilityImageScalesIntegersAndChecksChannelsAndRange) {
  const fs::path path = dir / "proba.npy";
  lom::NpyArray bytes;
  bytes.type = lom::NpyType::UInt8;
  bytes.shape = {1, 2, 2};
  bytes.bytes = {255, 0, 51, 204};
  lom::writeNpy(path, bytes);
  const auto proba = lom::readProbabilityImage(path, {0, 7}, 8);
  EXPECT_EQ(proba.width, 2);
  EXPECT_EQ(proba.height, 1);
  EXPECT_EQ(proba.channels, 2);
  EXPECT_EQ(proba.channel_labels, (std::vector<int>{0, 7}));
  EXPECT_FLOAT_EQ(proba.pixel(1, 0)[0], 0.2f);
  EXPECT_FLOAT_EQ(proba.pixel(1, 0)[1], 0.8f);
  // 8-bit images keep their codes for fast fusion; values are code / 255.
  EXPECT_EQ(proba.codes, (std::vector<std::uint8_t>{255, 0, 51, 204}));
  for (size_t i = 0; i < proba.codes.size(); ++i)
    EXPECT_EQ(proba.values[i], lom::probabilityOfCode(proba.codes[i]));

  const std::string channels = errorOf([&] {
    (void)lom::readProbabilityImage(path, {0, 1, 2}, 8);
  });
  EXPECT_NE(channels.find("3 channels"), std::string::npos) << channels;
  EXPECT_NE(channels.find("found 2 channels"), std::string::npos) << channels;

  lom::writeNpyFloat32(path, {1, 1, 2}, {0.5f, 0.25f});
  EXPECT_TRUE(lom::readProbabilityImage(path, {}, 2).codes.empty());  // only 8-bit images have codes
  lom::writeNpyFloat32(path, {1, 1, 2}, {0.5f, 1.5f});
  const std::string range = errorOf([&] { (void)lom::readProbabilityImage(path, {}, 2); });
  EXPECT_NE(range.find("[0, 1]"), std::string::npos) << range;
  EXPECT_NE(range.find("channel 1"), std::string::npos) << range;

  // The first value that is off is named, wherever it lies, NaN included;
  // values a rounding error outside [0, 1] are clamped instead.
  std::vector<float> values(3 * 4 * 2, 0.5f);
  values[(2 * 4 + 3) * 2 + 0] = -1e-7f;
  values[(2 * 4 + 3) * 2 + 1] = 1.0f + 1e-7f;
  lom::writeNpyFloat32(path, {3, 4, 2}, values);
  const auto clamped = lom::readProbabilityImage(path, {}, 2);
  EXPECT_EQ(clamped.pixel(3, 2)[0], 0.0f);
  EXPECT_EQ(clamped.pixel(3, 2)[1], 1.0f);
  values[(1 * 4 + 2) * 2 + 1] = std::nanf("");
  values[(2 * 4 + 1) * 2 + 0] = -0.5f;
  lom::writeNpyFloat32(path, {3, 4, 2}, values);
  const std::string nan = errorOf([&] { (void)lom::readProbabilityImage(path, {}, 2); });
  EXPECT_NE(nan.find("nan at pixel (u=2, v=1), channel 1"), std::string::npos) << nan;
}

}  // namespace

namespace {

TEST_F(NpyTest, NamesComplexAndOtherDtypesAsNumpyDoes) {
  const auto name = [&](const std::string& descr, size_t bytes) {
    const auto path = file("{'descr': '" + descr + "', 'fortran_order': False, 'shape': (1,), }",
                           std::string(bytes, '\0'));
    return errorOf([&] { (void)lom::readNpy(path); });
  };
  // NumPy names a number type by its total bits: '<c8' is complex64, '<c16' complex128.
  EXPECT_NE(name("<c8", 8).find("(complex64)"), std::string::npos) << name("<c8", 8);
  EXPECT_NE(name("<c16", 16).find("(complex128)"), std::string::npos) << name("<c16", 16);
  EXPECT_NE(name("<i8", 8).find("(int64)"), std::string::npos);
  EXPECT_NE(name("|i1", 1).find("(int8)"), std::string::npos);
  EXPECT_NE(name("<u4", 4).find("(uint32)"), std::string::npos);
  EXPECT_NE(name("|b1", 1).find("(bool)"), std::string::npos);
}

}  // namespace
