// labeloctomap import stopped by Ctrl-C (SIGINT) or SIGTERM halfway: like a
// cancel, it removes what it wrote and exits with 128 + the signal number.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

#include "lom/images.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 400;
constexpr double kTimeoutSeconds = 300.0;  // only reached when something is wrong

// A frames-layout recording of kFrames posed 640 x 480 depth images: long enough
// to import that it is still running when the test stops it. The frames share
// one depth file through hard links, so writing the recording is quick.
void writeLongRecording(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "camera-intrinsics.txt") << "520 0 319.5\n0 520 239.5\n0 0 1\n";
  DepthImage depth;
  depth.width = 640;
  depth.height = 480;
  depth.metres.resize(static_cast<size_t>(depth.width) * depth.height);
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u)
      depth.metres[static_cast<size_t>(v) * depth.width + u] =
          1.0f + 0.001f * static_cast<float>((u * 7 + v * 13) % 97);
  const fs::path first = dir / "frame-000000.depth.png";
  writeDepthPng(first, depth, 0.001);
  for (int n = 0; n < kFrames; ++n) {
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06d", n);
    if (n > 0) fs::create_hard_link(first, dir / (std::string(base) + ".depth.png"));
    std::ofstream(dir / (std::string(base) + ".pose.txt"))
        << "1 0 0 " << 0.001 * n << "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  }
}

// Whether a depth file was written under `out` (in its depth/ folder, or in
// the hidden folder where --overwrite stages the new frames).
bool wroteADepthFile(const fs::path& out) {
  std::error_code ec;
  if (fs::is_directory(out / "depth", ec) && !fs::is_empty(out / "depth", ec) &&
      !fs::exists(out / "sequence.json", ec))
    return true;
  for (const auto& entry : fs::directory_iterator(out, ec))
    if (entry.path().filename().string().rfind(".labeloctomap-import-", 0) == 0 &&
        fs::is_directory(entry.path() / "depth", ec) && !fs::is_empty(entry.path() / "depth", ec))
      return true;
  return false;
}

// Waits until the import has written its first depth file, so that the signal
// comes while the output folder holds a part of the sequence.
bool waitForFirstFrame(test::CliProcess& process, const fs::path& out) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(kTimeoutSeconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (wroteADepthFile(out)) return true;
    if (!process.running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

class CliImportSignalTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    writeLongRecording(source());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path source() { return dir_->path() / "recording"; }

  // Imports into `out`, sends `signal` once the first frame is written; returns
  // how the import ended, with its stderr.
  static std::pair<test::CliExit, std::string> importStoppedBy(int signal, const fs::path& out,
                                                               bool overwrite = false) {
    std::vector<std::string> words{"import", "frames",     source().string(),
                                   "--out",  out.string(), "--bilateral",
                                   "2",      "--quiet"};
    if (overwrite) words.push_back("--overwrite");
    test::CliProcess process(words);
    if (!waitForFirstFrame(process, out)) {
      ADD_FAILURE() << "the import ended or wrote nothing before it could be stopped\n"
                    << process.err();
      return {};
    }
    process.sendSignal(signal);
    const auto ended = process.wait(kTimeoutSeconds);
    if (!ended) {
      ADD_FAILURE() << "the import did not stop after the signal";
      return {};
    }
    return {*ended, process.err()};
  }

  inline static test::TempDir* dir_ = nullptr;
};

TEST_F(CliImportSignalTest, CtrlCRemovesTheNewOutputFolderAndExits130) {
  const fs::path out = dir_->path() / "seq-int";
  const auto [ended, err] = importStoppedBy(SIGINT, out);
  EXPECT_TRUE(ended.exited) << "killed by signal " << ended.signal;
  EXPECT_EQ(ended.exit_code, 130) << err;
  EXPECT_NE(err.find("labeloctomap import: interrupted by SIGINT"), std::string::npos) << err;
  EXPECT_NE(err.find("nothing was kept"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out)) << "the folder did not exist before the import";
}

TEST_F(CliImportSignalTest, SigtermKeepsOnlyWhatTheFolderHeldBeforeAndExits143) {
  const fs::path out = dir_->path() / "seq-term";
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "recorded on Tuesday\n";
  const auto [ended, err] = importStoppedBy(SIGTERM, out);
  EXPECT_TRUE(ended.exited) << "killed by signal " << ended.signal;
  EXPECT_EQ(ended.exit_code, 143) << err;
  EXPECT_NE(err.find("interrupted by SIGTERM"), std::string::npos) << err;
  std::vector<std::string> left;
  for (const auto& entry : fs::recursive_directory_iterator(out))
    left.push_back(fs::relative(entry.path(), out).string());
  EXPECT_EQ(left, std::vector<std::string>{"notes.txt"});

  // The folder takes a new import as if nothing had happened.
  const auto again = test::runCli("import frames '" + source().string() + "' --out '" +
                                  out.string() + "' --max-frames 2 --quiet");
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

// An interrupted --overwrite leaves the sequence it was replacing as it was.
TEST_F(CliImportSignalTest, AnInterruptedOverwriteKeepsTheOldSequence) {
  const fs::path out = dir_->path() / "seq-kept";
  auto r = test::runCli("import frames '" + source().string() + "' --out '" + out.string() +
                        "' --max-frames 2 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Boxes that load: validate below reads them.
  std::ofstream(out / "annotations.json")
      << R"({"format": "labeloctomap-annotations", "version": 1, "boxes": []})";
  const auto listing = [&] {
    std::vector<std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(out))
      files.push_back(fs::relative(entry.path(), out).string() + " " +
                      (entry.is_regular_file() ? std::to_string(entry.file_size()) : "dir"));
    std::sort(files.begin(), files.end());
    return files;
  };
  const std::vector<std::string> before = listing();
  const std::string json = test::slurp(out / "sequence.json");

  const auto [ended, err] = importStoppedBy(SIGINT, out, true);
  EXPECT_TRUE(ended.exited) << "killed by signal " << ended.signal;
  EXPECT_EQ(ended.exit_code, 130) << err;
  EXPECT_NE(err.find("a sequence it held before is as it was"), std::string::npos) << err;
  EXPECT_EQ(listing(), before);
  EXPECT_EQ(test::slurp(out / "sequence.json"), json);
  r = test::runCli("validate '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;

  // Not interrupted, it replaces the frames and keeps the boxes.
  r = test::runCli("import frames '" + source().string() + "' --out '" + out.string() +
                   "' --max-frames 3 --overwrite --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lom::loadSequence(out).frames.size(), 3u);
  EXPECT_TRUE(fs::exists(out / "annotations.json"));
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_NE(entry.path().filename().string().rfind(".labeloctomap", 0), 0u)
        << "left behind: " << entry.path();
}

}  // namespace
}  // namespace lom
