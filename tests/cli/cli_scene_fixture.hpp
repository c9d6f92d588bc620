#pragma once
// A small generated scene and its fused map, made once per test suite, for the
// command-line tests that check options, outputs and messages against them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>

#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom::test {

// A path quoted for the shell.
inline std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// A copy of the sequence folder `scene` at `copy`, every camera moved `shift`
// metres along x (far out, for the map's extent).
inline void copyWithCamerasShifted(const std::filesystem::path& scene,
                                   const std::filesystem::path& copy, double shift) {
  std::filesystem::copy(scene, copy, std::filesystem::copy_options::recursive);
  Sequence sequence = loadSequence(copy);
  for (auto& frame : sequence.frames) frame.T_world_camera.translation().x() += shift;
  saveSequence(sequence, copy);
}

class CliSceneTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    auto r = runCli("synth --out " + q(scene()) +
                    " --seed 4 --objects 4 --frames 3 --views 3 --width 160 --height 120");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runCli("fuse " + q(scene()) + " --out " + q(map()) + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::filesystem::path scene() { return dir_->path() / "scene"; }
  static std::filesystem::path map() { return dir_->path() / "map.ot"; }
  static std::map<int, size_t> counts() {
    return lom::LabelMap::load(map()).occupiedCountPerLabel();
  }
  // An object label of the map, for plan's --target.
  static std::string target() { return std::to_string(std::prev(counts().end())->first); }

  inline static TempDir* dir_ = nullptr;
};

}  // namespace lom::test
