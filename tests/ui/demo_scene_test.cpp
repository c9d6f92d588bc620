// The studio's --demo scene is a cache: written once, reused while it is
// whole, and written again when a file of it went missing or empty since.
#include "lom/ui/demo_scene.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;

TEST(DemoSceneTest, AWholeCacheIsReusedAndADamagedOneWrittenAgain) {
  lom::test::TempDir temp;
  const fs::path folder = temp.path() / "demo-shelf";
  const QString qfolder = QString::fromStdString(folder.string());
  prepareDemoScene(qfolder);
  const Sequence sequence = loadSequence(folder);
  ASSERT_FALSE(sequence.frames.empty());
  const fs::path depth = sequence.pathOf(sequence.frames.front().depth);
  const fs::path proba = sequence.pathOf(sequence.frames.back().proba);
  ASSERT_TRUE(fs::exists(depth));
  ASSERT_TRUE(fs::exists(proba));

  // Whole: not written again (a marker left in the folder's json stays).
  const fs::file_time_type written = fs::last_write_time(folder / "sequence.json");
  fs::last_write_time(folder / "sequence.json", written - std::chrono::hours(1));
  const fs::file_time_type marked = fs::last_write_time(folder / "sequence.json");
  prepareDemoScene(qfolder);
  EXPECT_EQ(fs::last_write_time(folder / "sequence.json"), marked);

  // A frame file deleted: the scene is written again and opens.
  fs::remove(depth);
  prepareDemoScene(qfolder);
  EXPECT_TRUE(fs::exists(depth));
  EXPECT_GT(fs::file_size(depth), 0u);
  EXPECT_NE(fs::last_write_time(folder / "sequence.json"), marked);

  // A frame file cut to nothing (a full disk): the same.
  std::ofstream(proba, std::ios::trunc).close();
  ASSERT_EQ(fs::file_size(proba), 0u);
  prepareDemoScene(qfolder);
  EXPECT_GT(fs::file_size(proba), 0u);
}

}  // namespace
}  // namespace lom::ui
