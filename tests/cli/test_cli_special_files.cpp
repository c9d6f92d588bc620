// Devices and FIFOs given where a command reads a file (a model, a label list,
// a batch list): refused at once, saying what they are. Read as files they would
// never end (/dev/zero) or block forever (a FIFO nobody writes), so every run
// here is killed after a generous time and given a memory limit.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "lom/images.hpp"
#include "lom/sequence.hpp"
#include "onnx_model_builder.hpp"
#include "test_input_helpers.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::TempDir;

std::string shellQuoted(const fs::path& path) { return "'" + path.string() + "'"; }

// Killed well before a test runner's own timeout; 4 GB of address space is far
// beyond what these small inputs need and far below a device read without end.
constexpr lom::test::CliLimits kLimits{4L * 1024 * 1024, 0, 120};

lom::test::CliResult run(const std::string& args) { return lom::test::runCli(args, kLimits); }

class CliSpecialFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    (void)lom::test::writeColourWallSequence(dir_ / "seq", 2);
    ASSERT_EQ(::mkfifo((dir_ / "model.onnx").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir_ / "labels.txt").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir_ / "list.txt").c_str(), 0600), 0);
  }
  // A frames-layout recording of two posed frames, for import.
  fs::path writeFramesSource() const {
    const fs::path src = dir_ / "frames";
    fs::create_directories(src);
    std::ofstream(src / "camera-intrinsics.txt") << "20 0 7.5\n0 20 5.5\n0 0 1\n";
    lom::DepthImage depth;
    depth.width = 16;
    depth.height = 12;
    depth.metres.assign(16 * 12, 1.0f);
    for (int n = 0; n < 2; ++n) {
      const std::string base = "frame-00000" + std::to_string(n);
      lom::writeDepthPng(src / (base + ".depth.png"), depth, 0.001);
      std::ofstream(src / (base + ".pose.txt")) << "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
    }
    return src;
  }
  TempDir dir_;
};

void expectRefused(const lom::test::CliResult& r, const std::string& file,
                   const std::string& what) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
}

TEST_F(CliSpecialFilesTest, SegmenterModelThatIsADeviceOrAFifoIsRefused) {
  const std::string seq = shellQuoted(dir_ / "seq");
  const std::string fifo = (dir_ / "model.onnx").string();
  for (const std::string& model : {std::string("/dev/zero"), fifo}) {
    const std::string kind = model == fifo ? "a named pipe (FIFO), not a regular file"
                                           : "a character device, not a regular file";
    SCOPED_TRACE(model);
    auto r = run("fuse " + seq + " --out " + shellQuoted(dir_ / "m.ot") + " --segmenter " +
                 shellQuoted(model));
    expectRefused(r, model + ": model: expected a readable ONNX model file", kind);
    r = run("segment " + seq + " --segmenter " + shellQuoted(model));
    expectRefused(r, model + ": model", kind);
    r = run("score " + seq + " --annotations " + shellQuoted(dir_ / "seq" / "sequence.json") +
            " --out " + shellQuoted(dir_ / "r") + " --segmenter " + shellQuoted(model));
    expectRefused(r, model + ": model", kind);
  }
  EXPECT_FALSE(fs::exists(dir_ / "m.ot"));
  EXPECT_FALSE(fs::exists(dir_ / "r"));
}

TEST_F(CliSpecialFilesTest, SegmenterConfigurationThatIsAFifoIsRefused) {
  lom::test::writeModel(dir_ / "net.onnx",
                        lom::test::buildConvModel(lom::test::colourChannelModel()));
  ASSERT_EQ(::mkfifo((dir_ / "net.json").c_str(), 0600), 0);
  const auto r = run("segment " + shellQuoted(dir_ / "seq") + " --segmenter " +
                     shellQuoted(dir_ / "net.onnx"));
  expectRefused(r, (dir_ / "net.json").string(), "a named pipe (FIFO), not a regular file");
}

TEST_F(CliSpecialFilesTest, ImportLabelListThatIsADeviceOrAFifoIsRefused) {
  const fs::path src = writeFramesSource();
  const std::string fifo = (dir_ / "labels.txt").string();
  for (const std::string& labels : {std::string("/dev/zero"), fifo}) {
    SCOPED_TRACE(labels);
    const auto r = run("import frames " + shellQuoted(src) + " --out " +
                       shellQuoted(dir_ / "imported") + " --labels " + shellQuoted(labels));
    expectRefused(r, labels + ": --labels: expected a label list file",
                  labels == fifo ? "a named pipe (FIFO), not a regular file"
                                 : "a character device, not a regular file");
  }
  EXPECT_FALSE(fs::exists(dir_ / "imported"));
}

TEST_F(CliSpecialFilesTest, BatchListThatIsADeviceOrAFifoSaysSo) {
  auto r = run("score --batch /dev/zero --out " + shellQuoted(dir_ / "r"));
  expectRefused(r, "/dev/zero", "expected an existing batch list file, found a character device");
  r = run("score --batch " + shellQuoted(dir_ / "list.txt") + " --out " + shellQuoted(dir_ / "r"));
  expectRefused(r, "list.txt", "found a named pipe (FIFO), not a regular file");
  EXPECT_FALSE(fs::exists(dir_ / "r"));
}

// OpenCV's imgcodecs needs 139 libraries; loading them made every start of
// the program take 0.2 s instead of 0.05 s. It is loaded only for an image
// that is neither PNG nor JPEG, and such an image is still read.
TEST(CliStartTest, ImageCodecsAreLoadedOnlyForOtherImageFormats) {
  std::string libraries;
  FILE* ldd = popen((std::string("ldd '") + LOM_CLI_PATH + "' 2>&1").c_str(), "r");
  ASSERT_NE(ldd, nullptr);
  char line[512];
  while (fgets(line, sizeof(line), ldd)) libraries += line;
  pclose(ldd);
  ASSERT_NE(libraries.find("libopencv_core"), std::string::npos) << libraries;
  EXPECT_EQ(libraries.find("libopencv_imgcodecs"), std::string::npos) << libraries;

  lom::test::TempDir dir;
  lom::Sequence written = lom::test::writeSequence(dir.path());
  lom::test::writeText(dir / "labels.pgm", "P5 4 3 255\n" + std::string(12, '\x01'));
  written.frames[0].label = "labels.pgm";
  lom::saveSequence(written, dir.path());
  const auto r = lom::test::runCli("validate '" + written.root.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

}  // namespace
