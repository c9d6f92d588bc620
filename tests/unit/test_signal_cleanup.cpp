// A process stopped by SIGINT, SIGTERM or SIGHUP in the middle of a write
// removes its temporary files, staging folders and the folders it made for
// its outputs; what it had already put in place, and every older file, stays.
// Each case runs in a child process (a death test) that the signal ends.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>

#include "lom/atomic_file.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

// Every file and folder under `folder`, relative to it.
std::set<std::string> everythingIn(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    names.insert(fs::relative(entry.path(), folder).string());
  return names;
}

// The child of a death test runs the test again from its start (the
// threadsafe style): it works in the folder the parent made, whose path it
// finds in the environment.
constexpr const char* kFolderVariable = "LOM_SIGNAL_TEST_FOLDER";

class SignalCleanup : public ::testing::Test {
 protected:
  void SetUp() override {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    if (const char* shared = std::getenv(kFolderVariable)) {
      dir_ = shared;
      return;
    }
    own_.emplace();
    dir_ = own_->path();
    ::setenv(kFolderVariable, dir_.c_str(), 1);
  }
  void TearDown() override {
    if (own_) ::unsetenv(kFolderVariable);
  }

  std::optional<lom::test::TempDir> own_;
  fs::path dir_;
};

TEST_F(SignalCleanup, AWriteStoppedHalfwayLeavesOnlyTheOldFiles) {
  std::ofstream(dir_ / "map.ot") << "the old map";
  std::ofstream(dir_ / "notes.txt") << "kept";
  EXPECT_EXIT(
      {
        lom::removePendingOutputsOnSignals();
        lom::NewFolders made(dir_ / "meshes" / "labels");
        fs::create_directories(dir_ / "meshes" / "labels");
        lom::StagedFiles files;
        files.add(dir_ / "meshes" / "labels" / "01_box.ply",
                  [](std::ostream& out) { out << "complete"; });
        lom::writeFileAtomically(dir_ / "map.ot", [](std::ostream& out) {
          out << std::string(1 << 16, 'x') << std::flush;  // half a map on the disk
          std::raise(SIGTERM);
        });
      },
      ::testing::KilledBySignal(SIGTERM), "");
  EXPECT_EQ(everythingIn(dir_), (std::set<std::string>{"map.ot", "notes.txt"}));
  EXPECT_EQ(lom::test::slurp(dir_ / "map.ot"), "the old map");
}

TEST_F(SignalCleanup, AStagingFolderGoesWithEverythingInIt) {
  fs::create_directories(dir_ / "out");
  std::ofstream(dir_ / "out" / "old.ply") << "old";
  EXPECT_EXIT(
      {
        lom::removePendingOutputsOnSignals();
        lom::PendingOutput pending;
        const fs::path staging = lom::createStagingFolder(dir_ / "out", "export", pending);
        // Deep enough, and with enough names, to need several reads of a folder.
        fs::path deep = staging;
        for (int level = 0; level < 6; ++level) {
          deep /= "level" + std::to_string(level);
          fs::create_directories(deep);
          for (int i = 0; i < 150; ++i)
            std::ofstream(deep / ("frame-with-a-long-name-" + std::to_string(i) + ".png")) << i;
        }
        fs::create_symlink(dir_ / "out" / "old.ply", staging / "link-to-old");
        std::raise(SIGINT);
      },
      ::testing::KilledBySignal(SIGINT), "");
  EXPECT_EQ(everythingIn(dir_), (std::set<std::string>{"out", "out/old.ply"}));
  EXPECT_EQ(lom::test::slurp(dir_ / "out" / "old.ply"), "old") << "a link is removed, not followed";
}

TEST_F(SignalCleanup, WhatWasReleasedOrPutInPlaceStays) {
  EXPECT_EXIT(
      {
        lom::removePendingOutputsOnSignals();
        lom::writeTextFileAtomically(dir_ / "boxes.json", "{}");
        fs::create_directories(dir_ / "replaced");
        lom::PendingOutput held(dir_ / "replaced", lom::PendingOutput::Kind::Tree);
        held.release();
        lom::NewFolders made(dir_ / "report");
        fs::create_directories(dir_ / "report");
        lom::writeTextFileAtomically(dir_ / "report" / "report.md", "# done");
        made.keep();
        std::raise(SIGHUP);
      },
      ::testing::KilledBySignal(SIGHUP), "");
  EXPECT_EQ(everythingIn(dir_),
            (std::set<std::string>{"boxes.json", "replaced", "report", "report/report.md"}));
}

TEST_F(SignalCleanup, AnIgnoredSignalStaysIgnored) {
  EXPECT_EXIT(
      {
        std::signal(SIGHUP, SIG_IGN);  // as nohup starts a command
        lom::removePendingOutputsOnSignals();
        std::raise(SIGHUP);
        std::exit(7);
      },
      ::testing::ExitedWithCode(7), "");
}

TEST(PendingOutputs, AFullRecordRecordsNothingMoreAndFreesItsSlots) {
  lom::test::TempDir dir;
  std::vector<lom::PendingOutput> outputs;
  for (int i = 0; i < lom::PendingOutput::kMaxPendingOutputs; ++i) {
    outputs.emplace_back(dir / std::to_string(i), lom::PendingOutput::Kind::File);
    ASSERT_TRUE(outputs.back().recorded()) << i;
  }
  const lom::PendingOutput extra(dir / "extra", lom::PendingOutput::Kind::File);
  EXPECT_FALSE(extra.recorded());
  outputs.pop_back();
  const lom::PendingOutput again(dir / "again", lom::PendingOutput::Kind::File);
  EXPECT_TRUE(again.recorded());
}

}  // namespace
