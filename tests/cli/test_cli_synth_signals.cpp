// labeloctomap synth stopped by Ctrl-C (SIGINT) or SIGTERM halfway: it leaves
// what a failed run leaves, no half-written scene (it left the frames written
// so far, without sequence.json, which validate refuses).
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

constexpr double kTimeoutSeconds = 300.0;  // only reached when something is wrong

// Runs synth into `out` with enough frames that it is still writing them when
// the signal comes, once its first depth image is there; returns how it ended.
std::optional<test::CliExit> synthStoppedBy(int signal, const fs::path& out) {
  test::CliProcess process(
      {"synth", "--out", out.string(), "--frames", "400", "--width", "320", "--height", "240"});
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(kTimeoutSeconds);
  std::error_code ec;
  while (!fs::exists(out / "depth" / "000000.png", ec)) {
    if (!process.running() || std::chrono::steady_clock::now() > deadline) {
      ADD_FAILURE() << "synth ended or wrote nothing before it could be stopped\n" << process.err();
      return std::nullopt;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  process.sendSignal(signal);
  return process.wait(kTimeoutSeconds);
}

TEST(CliSynthSignalTest, CtrlCRemovesTheFoldersItMade) {
  test::TempDir dir;
  const fs::path out = dir / "new" / "scene";
  const auto ended = synthStoppedBy(SIGINT, out);
  ASSERT_TRUE(ended) << "synth did not stop after the signal";
  // Ended by the signal itself, after the clean-up (a shell reports 130).
  EXPECT_FALSE(ended->exited);
  EXPECT_EQ(ended->signal, SIGINT);
  EXPECT_FALSE(fs::exists(dir / "new")) << "neither folder existed before";
}

// `made/../kept/scene`: the scene is in the user's empty folder `kept`, beside
// `made`, not in it. The scene and `made` go, `kept` stays (named
// `made/../kept`, it looked like a folder synth had made).
TEST(CliSynthSignalTest, CtrlCRemovesTheSceneAlsoBesideAFolderItMade) {
  test::TempDir dir;
  fs::create_directories(dir / "kept");
  const auto ended = synthStoppedBy(SIGINT, dir / "made" / ".." / "kept" / "scene");
  ASSERT_TRUE(ended) << "synth did not stop after the signal";
  EXPECT_EQ(ended->signal, SIGINT);
  EXPECT_FALSE(fs::exists(dir / "kept" / "scene")) << "the half-written scene was left";
  EXPECT_FALSE(fs::exists(dir / "made"));
  EXPECT_TRUE(fs::is_directory(dir / "kept"));
}

TEST(CliSynthSignalTest, SigtermEmptiesTheEmptyFolderItWasGiven) {
  test::TempDir dir;
  const fs::path out = dir / "scene";
  fs::create_directories(out);
  const auto ended = synthStoppedBy(SIGTERM, out);
  ASSERT_TRUE(ended) << "synth did not stop after the signal";
  EXPECT_EQ(ended->signal, SIGTERM);
  ASSERT_TRUE(fs::is_directory(out));
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(out)) left.push_back(entry.path().string());
  EXPECT_TRUE(left.empty()) << left.front();

  // The folder takes a new scene as if nothing had happened.
  const auto again = test::runCli("synth --out '" + out.string() +
                                  "' --frames 4 --views 3 --width 160 --height 120");
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

}  // namespace
}  // namespace lom
