// labeloctomap score end to end: reports, errors, --map, --iou and --batch.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_scene_fixture.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

using lom::test::runCli;
using lom::test::TempDir;
using Json = nlohmann::json;

using lom::test::slurp;

std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

class CliScoreTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new TempDir();
    for (const char* name : {"bin_a", "bin_b"}) {
      const auto r = runCli("synth --out " + quoted(root_->path() / name) + " --seed " +
                            (std::string(name) == "bin_a" ? "5" : "6") +
                            " --objects 4 --frames 4 --views 3 --width 160 --height 120");
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
  }
  static void TearDownTestSuite() {
    delete root_;
    root_ = nullptr;
  }
  static std::filesystem::path scene(const char* name = "bin_a") { return root_->path() / name; }
  static std::string scoreArgs(const std::filesystem::path& out, const std::string& annotations = {}) {
    return "score " + quoted(scene()) + " --annotations " +
           quoted(annotations.empty() ? scene() / "annotations.json" : std::filesystem::path(annotations)) +
           " --out " + quoted(out);
  }
  static TempDir* root_;
};
TempDir* CliScoreTest::root_ = nullptr;

void expectScores(const Json& scores) {
  for (const char* method : {"projection_mean", "projection_max", "labeloctomap"}) {
    ASSERT_TRUE(scores.contains(method)) << method;
    const double v = scores[method].get<double>();
    EXPECT_TRUE(v >= 0.0 && v <= 1.0) << method << " " << v;
  }
}

TEST_F(CliScoreTest, WritesTheFourReports) {
  TempDir out;
  const auto dir = out / "report";
  const auto r = runCli(scoreArgs(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Summary (4 objects)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("LabelOctoMap"), std::string::npos);

  const Json report = Json::parse(slurp(dir / "report.json"));
  EXPECT_EQ(report["format"], "labeloctomap-score-report");
  EXPECT_EQ(report["sequence"], "bin_a");
  EXPECT_DOUBLE_EQ(report["resolution"].get<double>(), 0.01);
  EXPECT_EQ(report["iou_mode"], "exact");
  ASSERT_EQ(report["views"].size(), 3u);
  ASSERT_EQ(report["objects"].size(), 4u);
  for (const auto& object : report["objects"]) {
    EXPECT_TRUE(object["label"].is_number_integer());
    EXPECT_TRUE(object["name"].is_string());
    EXPECT_TRUE(object["voxels"].is_number_unsigned());
    expectScores(object["iou_3d"]);
    expectScores(object["box_iou"]);
    EXPECT_EQ(object["per_view"].size(), 3u);
    // The terms of LabelOctoMap's IU_3d, in cubic metres: tp / (tp + fp + fn).
    const Json& volumes = object["labeloctomap_volumes"];
    const double tp = volumes["true_positive"], fp = volumes["false_positive"],
                 fn = volumes["false_negative"];
    EXPECT_GE(tp, 0.0);
    EXPECT_GE(fp, -1e-12);
    EXPECT_GE(fn, -1e-12);
    if (tp > 0.0) {
      EXPECT_NEAR(tp / (tp + fp + fn), object["iou_3d"]["labeloctomap"].get<double>(), 1e-9);
    }
  }
  const Json& summary = report["summary"];
  EXPECT_EQ(summary["objects"], 4);
  expectScores(summary["iou_3d"]);
  EXPECT_LE(summary["labeloctomap_beats_projection_max"].get<int>(), 4);
  // Generated frames carry ground-truth label images and probabilities.
  ASSERT_TRUE(report.contains("metrics_2d"));
  for (const char* metric : {"pixel_accuracy", "mean_accuracy", "mean_iu", "fw_iu"}) {
    const double v = report["metrics_2d"][metric].get<double>();
    EXPECT_TRUE(v > 0.0 && v <= 1.0) << metric;
  }
  EXPECT_FALSE(report.contains("metrics_2d_candidates"));

  const std::string csv = slurp(dir / "report.csv");
  EXPECT_EQ(csv.rfind("label,name,voxels,iou3d_projection_mean", 0), 0u) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  // Per view: IU_3d, then box IU, as report.json's per_view and per_view_box_iou.
  const std::string header = csv.substr(0, csv.find('\n'));
  const size_t views = report["views"].size();
  ASSERT_GE(views, 1u);
  const std::string last_view = std::to_string(report["views"].back().get<size_t>());
  EXPECT_NE(header.find(",box_iou_frame_" + last_view), std::string::npos) << header;
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 8 + 2 * static_cast<long>(views))
      << header;
  const std::string row =
      csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
  const double last_box = std::stod(row.substr(row.rfind(',') + 1));
  EXPECT_NEAR(last_box, report["objects"][0]["per_view_box_iou"].back().get<double>(), 1e-6) << row;
  const std::string markdown = slurp(dir / "report.md");
  EXPECT_NE(markdown.find("| label | name | voxels | Projection (Mean) | Projection (Max) | LabelOctoMap |"),
            std::string::npos);
  EXPECT_NE(markdown.find("**"), std::string::npos);  // the best value of a row is bold
  EXPECT_NE(markdown.find("| label | name | inside the box | outside | box not covered | box |"),
            std::string::npos);
  const std::string svg = slurp(dir / "report.svg");
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("LabelOctoMap"), std::string::npos);
}

TEST_F(CliScoreTest, SavedMapScoresLikeTheFusedOne) {
  TempDir out;
  ASSERT_EQ(runCli("fuse " + quoted(scene()) + " --out " + quoted(out / "map.ot") + " --quiet").exit_code, 0);
  ASSERT_EQ(runCli(scoreArgs(out / "fused")).exit_code, 0);
  const auto r = runCli(scoreArgs(out / "loaded") + " --map " + quoted(out / "map.ot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json fused = Json::parse(slurp(out / "fused" / "report.json"));
  const Json loaded = Json::parse(slurp(out / "loaded" / "report.json"));
  EXPECT_EQ(fused["objects"], loaded["objects"]);
  // A saved map is scored as it was fused; --frames chooses the frames projected, and a
  // note says the comparison is matched only for a map fused from the same frames.
  ASSERT_EQ(runCli("fuse " + quoted(scene()) + " --frames 0:1 --out " + quoted(out / "m01.ot") +
                   " --quiet")
                .exit_code,
            0);
  const auto part =
      runCli(scoreArgs(out / "part") + " --map " + quoted(out / "m01.ot") + " --frames 0:1");
  EXPECT_EQ(part.exit_code, 0) << part.err;
  EXPECT_NE(part.err.find("is scored as it was fused; --frames 0:1 chooses the frames projected"),
            std::string::npos)
      << part.err;
  EXPECT_TRUE(std::filesystem::exists(out / "part" / "report.json"));
  // As many frames as were fused, but other ones: the recorded camera
  // directions tell, a warning.
  const auto other = runCli(scoreArgs(out / "other") + " --map " + quoted(out / "m01.ot") +
                            " --frames 2:3 --quiet");
  EXPECT_EQ(other.exit_code, 0) << other.err;
  EXPECT_NE(other.err.find("warning: " + (out / "m01.ot").string() +
                           " was fused from 1 frame, as many as are scored, but not from frames "
                           "2 to 2: the directions its cameras looked in differ"),
            std::string::npos)
      << other.err;
  // The map's own max range and p_miss override those given, each said.
  const auto own = runCli(scoreArgs(out / "own") + " --map " + quoted(out / "m01.ot") +
                          " --frames 0:1 --max-range 0.9 --p-miss 0.4");
  EXPECT_EQ(own.exit_code, 0) << own.err;
  EXPECT_NE(own.err.find("m; it overrides --max-range 0.9 (a map keeps the settings it was "
                         "fused with)"),
            std::string::npos)
      << own.err;
  EXPECT_NE(own.err.find(" has p_miss 0.3; it overrides --p-miss 0.4"), std::string::npos)
      << own.err;
  // --quiet leaves out every note (warnings stay).
  const auto quiet = runCli(scoreArgs(out / "quiet") + " --map " + quoted(out / "m01.ot") +
                            " --frames 0:1 --resolution 0.02 --quiet");
  EXPECT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("note:"), std::string::npos) << quiet.err;
  // Scored over every frame, the map of frame 0 alone meets baselines that
  // saw all four: a warning, in the report too.
  const auto whole = runCli(scoreArgs(out / "whole") + " --map " + quoted(out / "m01.ot"));
  EXPECT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(whole.err.find("note:"), std::string::npos) << whole.err;
  const std::string unmatched = (out / "m01.ot").string() +
                                " was fused from 1 frame, the baselines project the 4 frames "
                                "scored (frames 0 to 3): the comparison is not matched";
  EXPECT_NE(whole.err.find("warning: " + unmatched), std::string::npos) << whole.err;
  const Json whole_report = Json::parse(slurp(out / "whole" / "report.json"));
  EXPECT_NE(whole_report["warnings"].dump().find("the comparison is not matched"),
            std::string::npos)
      << whole_report["warnings"].dump();
  EXPECT_EQ(r.err.find("warning:"), std::string::npos) << r.err;  // the map fits its sequence
  EXPECT_EQ(part.err.find("warning:"), std::string::npos)
      << part.err;  // so does one of its first frame

  // A map fused with every camera half a metre away does not fit: scored, with a warning.
  std::filesystem::copy(scene(), out / "moved", std::filesystem::copy_options::recursive);
  lom::Sequence moved = lom::loadSequence(out / "moved");
  for (lom::FrameRecord& frame : moved.frames) frame.T_world_camera.translation().y() += 0.5;
  lom::saveSequence(moved, out / "moved");
  ASSERT_EQ(
      runCli("fuse " + quoted(out / "moved") + " --out " + quoted(out / "moved.ot") + " --quiet")
          .exit_code,
      0);
  const auto poor = runCli(scoreArgs(out / "poor") + " --map " + quoted(out / "moved.ot"));
  EXPECT_EQ(poor.exit_code, 0) << poor.err;
  EXPECT_NE(poor.err.find("warning: " + (out / "moved.ot").string() + ": only "), std::string::npos)
      << poor.err;
  EXPECT_NE(poor.err.find("fall on occupied voxels of the map"), std::string::npos) << poor.err;
}

TEST_F(CliScoreTest, YamlBoxesOfTheOriginalExperimentsScoreLikeTheirJson) {
  TempDir out;
  // The same boxes as YAML, in the experiments' robot frame "base".
  const Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  std::ostringstream yaml;
  yaml << std::setprecision(17) << "boxes:\n";
  for (const Json& box : annotations["boxes"]) {
    auto list = [&](const Json& numbers) {
      std::string text = "[";
      for (size_t i = 0; i < numbers.size(); ++i) {
        std::ostringstream number;
        number << std::setprecision(17) << numbers[i].get<double>();
        text += (i ? ", " : "") + number.str();
      }
      return text + "]";
    };
    yaml << "  - dimensions: " << list(box["size"]) << "\n    position: " << list(box["center"])
         << "\n    orientation: " << list(box["rotation"]) << "\n    name: object_"
         << box["label"].get<int>() << "\n    frame_id: base\n";
  }
  const auto boxes = out / "boxes.YAML";
  std::ofstream(boxes) << yaml.str();
  ASSERT_EQ(runCli(scoreArgs(out / "json") + " --quiet").exit_code, 0);
  const auto r = runCli(scoreArgs(out / "yaml", boxes.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + boxes.string() + ": YAML boxes of the original experiments"),
            std::string::npos)
      << r.err;
  const Json from_json = Json::parse(slurp(out / "json" / "report.json"));
  const Json from_yaml = Json::parse(slurp(out / "yaml" / "report.json"));
  ASSERT_EQ(from_yaml["objects"].size(), annotations["boxes"].size());
  EXPECT_EQ(from_yaml["objects"], from_json["objects"]);

  // A YAML box file with a mistake fails like a JSON one: file, field, nothing written.
  std::ofstream(out / "bad.yaml") << "boxes:\n  - dimensions: [0.1, 0.1]\n    position: [0, 0, 0]\n"
                                     "    orientation: [0, 0, 0, 1]\n    name: object_3\n";
  const auto bad = runCli(scoreArgs(out / "bad", (out / "bad.yaml").string()));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("bad.yaml"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("boxes[0].dimensions"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(out / "bad"));
  // A label the sequence does not have is named by the YAML field that holds
  // it (YAML boxes have no `label`).
  std::ofstream(out / "unknown.yaml") << "boxes:\n  - dimensions: [0.1, 0.1, 0.1]\n"
                                         "    position: [0, 0, 0]\n    orientation: [0, 0, 0, 1]\n"
                                         "    name: object_45\n";
  const auto unknown = runCli(scoreArgs(out / "unknown", (out / "unknown.yaml").string()));
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.err.find("boxes[0].name"), std::string::npos) << unknown.err;
  EXPECT_EQ(unknown.err.find("boxes[0].label"), std::string::npos) << unknown.err;
  // Several YAML documents: refused, not scored from the first alone.
  std::ofstream(out / "two.yaml") << yaml.str() << "---\n" << yaml.str();
  const auto two = runCli(scoreArgs(out / "two", (out / "two.yaml").string()));
  EXPECT_EQ(two.exit_code, 1);
  EXPECT_NE(two.err.find("expected one YAML document of boxes, found 2 documents"),
            std::string::npos)
      << two.err;
  EXPECT_FALSE(std::filesystem::exists(out / "two"));
}

TEST_F(CliScoreTest, CentreModeAndCandidatesAreReported) {
  TempDir out;
  const Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  std::string candidates = "0";
  for (const auto& box : annotations["boxes"]) candidates += "," + std::to_string(box["label"].get<int>());
  const auto r = runCli(scoreArgs(out / "r") + " --iou center --candidates " + candidates);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json report = Json::parse(slurp(out / "r" / "report.json"));
  EXPECT_EQ(report["iou_mode"], "center");
  EXPECT_EQ(report["candidates"].size(), annotations["boxes"].size() + 1);
  ASSERT_TRUE(report.contains("metrics_2d_candidates"));
  EXPECT_GE(report["metrics_2d_candidates"]["pixel_accuracy"].get<double>(),
            report["metrics_2d"]["pixel_accuracy"].get<double>());
}

// A map fused with candidates records them: scored without --candidates, its
// projection baselines use the same, as when the sequence is fused and scored
// in one go; other candidates are used as asked, with a warning.
TEST_F(CliScoreTest, AMapsCandidatesAreTheBaselinesCandidates) {
  TempDir out;
  const Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  // The background and all boxed objects but the last: that one cannot be
  // segmented by the fusion nor by the projection.
  std::set<int> ids{0};
  for (size_t i = 0; i + 1 < annotations["boxes"].size(); ++i)
    ids.insert(annotations["boxes"][i]["label"].get<int>());
  std::string candidates;  // in ascending order, as the messages list them
  for (const int id : ids) candidates += (candidates.empty() ? "" : ",") + std::to_string(id);
  const int left_out = annotations["boxes"].back()["label"].get<int>();
  ASSERT_EQ(runCli("fuse " + quoted(scene()) + " --candidates " + candidates + " --out " +
                   quoted(out / "map.ot") + " --quiet")
                .exit_code,
            0);
  const auto info = runCli("info " + quoted(out / "map.ot"));
  EXPECT_NE(info.out.find("candidates:       " + candidates), std::string::npos) << info.out;
  ASSERT_EQ(runCli(scoreArgs(out / "together") + " --candidates " + candidates).exit_code, 0);
  const auto r = runCli(scoreArgs(out / "loaded") + " --map " + quoted(out / "map.ot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + (out / "map.ot").string() + " was fused with candidates " +
                       candidates + "; the projection baselines and the 2D metrics use them too"),
            std::string::npos)
      << r.err;
  // The one warning: the box left out of the candidates can only score 0.
  const std::string box_warning = "boxes[" + std::to_string(annotations["boxes"].size() - 1) +
                                  "] is of label " + std::to_string(left_out) + " (";
  const size_t first_warning = r.err.find("warning:");
  EXPECT_NE(r.err.find(box_warning), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("which is not among the candidates " + candidates +
                       ": no voxel or pixel can take that label, so it scores 0"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("warning:", first_warning + 1), std::string::npos) << r.err;
  const Json together = Json::parse(slurp(out / "together" / "report.json"));
  const Json loaded = Json::parse(slurp(out / "loaded" / "report.json"));
  // The reports say it too, and which map they scored.
  ASSERT_EQ(loaded["warnings"].size(), 1u) << loaded["warnings"];
  EXPECT_NE(loaded["warnings"][0].get<std::string>().find(box_warning), std::string::npos);
  EXPECT_EQ(loaded["warnings"], together["warnings"]);
  EXPECT_EQ(loaded["map"], (out / "map.ot").string());
  EXPECT_TRUE(together["map"].is_null()) << "fused from the sequence";
  EXPECT_NE(slurp(out / "loaded" / "report.md").find(box_warning), std::string::npos);
  EXPECT_EQ(loaded["candidates"], together["candidates"]);
  EXPECT_EQ(loaded["objects"], together["objects"]);
  for (const Json& object : loaded["objects"])
    if (object["label"].get<int>() == left_out) {
      EXPECT_EQ(object["iou_3d"]["projection_max"].get<double>(), 0.0);
      EXPECT_EQ(object["iou_3d"]["labeloctomap"].get<double>(), 0.0);
    }

  // Every label for the baselines of this map: used as asked, with a warning.
  const auto every =
      runCli(scoreArgs(out / "every") + " --map " + quoted(out / "map.ot") + " --candidates none");
  ASSERT_EQ(every.exit_code, 0) << every.err;
  EXPECT_NE(every.err.find("warning: " + (out / "map.ot").string() + " was fused with candidates " +
                           candidates +
                           ", but the projection baselines and the 2D metrics use "
                           "every label: the comparison is not matched"),
            std::string::npos)
      << every.err;
  EXPECT_TRUE(Json::parse(slurp(out / "every" / "report.json"))["candidates"].is_null());
  // The same candidates given again: nothing to say.
  const auto same = runCli(scoreArgs(out / "same") + " --map " + quoted(out / "map.ot") +
                           " --candidates " + candidates);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(same.err.find("was fused with"), std::string::npos) << same.err;
  // A map fused with every label, scored with candidates: a warning too.
  ASSERT_EQ(
      runCli("fuse " + quoted(scene()) + " --out " + quoted(out / "all.ot") + " --quiet").exit_code,
      0);
  EXPECT_NE(runCli("info " + quoted(out / "all.ot")).out.find("candidates:       every label"),
            std::string::npos);
  // Its box of a label left out of the candidates is not 0 in every column:
  // the map was fused with that label, only the baselines cannot take it.
  const auto wider = runCli(scoreArgs(out / "wider") + " --map " + quoted(out / "all.ot") +
                            " --candidates " + candidates);
  ASSERT_EQ(wider.exit_code, 0) << wider.err;
  EXPECT_NE(wider.err.find("which is not among the candidates " + candidates +
                           ": no pixel of the projection baselines and the 2D metrics can take "
                           "that label, so they score 0 for it, while " +
                           (out / "all.ot").string() + " was fused with it"),
            std::string::npos)
      << wider.err;
  EXPECT_EQ(wider.err.find("so it scores 0 in every column"), std::string::npos) << wider.err;
  // Candidates without the background make every pixel an object: said.
  const std::string objects_only = candidates.substr(2);
  const auto no_background = runCli("fuse " + quoted(scene()) + " --candidates " + objects_only +
                                    " --out " + quoted(out / "objects.ot"));
  ASSERT_EQ(no_background.exit_code, 0) << no_background.err;
  EXPECT_NE(no_background.err.find("note: --candidates " + objects_only +
                                   " leaves out 0, the background"),
            std::string::npos)
      << no_background.err;
  EXPECT_EQ(runCli("fuse " + quoted(scene()) + " --candidates " + candidates + " --out " +
                   quoted(out / "with0.ot"))
                .err.find("leaves out 0"),
            std::string::npos);
  const auto fewer = runCli(scoreArgs(out / "fewer") + " --map " + quoted(out / "all.ot") +
                            " --candidates " + candidates);
  ASSERT_EQ(fewer.exit_code, 0) << fewer.err;
  EXPECT_NE(fewer.err.find("was fused with every label, but the projection baselines and the 2D "
                           "metrics use candidates " +
                           candidates),
            std::string::npos)
      << fewer.err;
}

// A box named for another label than its own (boxes drawn for another label
// numbering?) is scored by its label, named as the sequence names that
// label, with a warning naming the box.
TEST_F(CliScoreTest, ABoxNamedForAnotherLabelIsWarnedAbout) {
  TempDir out;
  Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  const std::string name = annotations["boxes"][1]["name"].get<std::string>();
  const int label = annotations["boxes"][1]["label"].get<int>();
  annotations["boxes"][1]["name"] = "dasani_water_bottle_2";
  std::ofstream(out / "renamed.json") << annotations.dump(2);
  const auto r = runCli(scoreArgs(out / "r", (out / "renamed.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + (out / "renamed.json").string() +
                       ": boxes[1].name is 'dasani_water_bottle_2', but label " +
                       std::to_string(label) + " of "),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("is '" + name + "'"), std::string::npos) << r.err;
  const Json report = Json::parse(slurp(out / "r" / "report.json"));
  bool found = false;
  for (const Json& object : report["objects"])
    if (object["label"].get<int>() == label) {
      EXPECT_EQ(object["name"], name);
      found = true;
    }
  EXPECT_TRUE(found);
  // The file as written: no warning.
  EXPECT_EQ(runCli(scoreArgs(out / "plain")).err.find("warning:"), std::string::npos);
}

// The frames layout (frame-NNNNNN.depth/pose/label + intrinsics) of a generated scene,
// as TSDF-fusion tools store recordings whose label images were drawn by hand.
void writeFramesLayout(const std::filesystem::path& scene, const std::filesystem::path& out) {
  const lom::Sequence sequence = lom::loadSequence(scene);
  std::filesystem::create_directories(out);
  const lom::CameraIntrinsics& k = sequence.camera;
  std::ofstream(out / "intrinsics.K.txt") << std::setprecision(17) << k.fx << " 0 " << k.cx
                                          << "\n0 " << k.fy << " " << k.cy << "\n0 0 1\n";
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06zu", 10 + 2 * i);
    const lom::FrameData frame = lom::loadFrame(sequence, i);
    lom::writeDepthPng(out / (std::string(base) + ".depth.png"), frame.depth, 0.001);
    lom::writeLabelPng(out / (std::string(base) + ".label.png"), *frame.label);
    std::ofstream pose(out / (std::string(base) + ".pose.txt"));
    pose << std::setprecision(17);
    const Eigen::Matrix4d m = sequence.frames[i].T_world_camera.matrix();
    for (int r = 0; r < 4; ++r)
      pose << m(r, 0) << " " << m(r, 1) << " " << m(r, 2) << " " << m(r, 3) << "\n";
  }
}

TEST_F(CliScoreTest, FramesImportedFromLabelImagesAreNotScoredIn2d) {
  TempDir out;
  writeFramesLayout(scene(), out / "recording");
  const auto imported =
      runCli("import auto " + quoted(out / "recording") + " --out " + quoted(out / "seq"));
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const std::string import_text = imported.out + imported.err;
  EXPECT_NE(import_text.find("label images became one-hot probabilities"), std::string::npos)
      << import_text;
  EXPECT_NE(
      import_text.find("intrinsics read from " + (out / "recording" / "intrinsics.K.txt").string()),
      std::string::npos)
      << import_text;

  const auto r = runCli("score " + quoted(out / "seq") + " --annotations " +
                        quoted(scene() / "annotations.json") + " --out " + quoted(out / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string sentence =
      "the probabilities were made from the label images, which are not an independent ground "
      "truth";
  EXPECT_NE(r.out.find("2D segmentation: not scored: " + sentence), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("pixel acc."), std::string::npos) << "no 100 % against itself\n" << r.out;

  const Json report = Json::parse(slurp(out / "report" / "report.json"));
  EXPECT_FALSE(report.contains("metrics_2d"));
  EXPECT_EQ(report["metrics_2d_not_scored"], sentence);
  EXPECT_EQ(report["metrics_2d_excluded_frames"], Json({0, 1, 2, 3}));
  EXPECT_EQ(report["objects"].size(), 4u) << "the 3D scores are unaffected";
  const std::string markdown = slurp(out / "report" / "report.md");
  EXPECT_NE(markdown.find("## 2D segmentation\n\nNot scored: " + sentence + "."), std::string::npos)
      << markdown;

  // The generated frames keep their independent probabilities: scored as before.
  const auto original = runCli(scoreArgs(out / "original"));
  ASSERT_EQ(original.exit_code, 0) << original.err;
  EXPECT_NE(original.out.find("2D segmentation without candidates: pixel acc."), std::string::npos);
  EXPECT_EQ(original.out.find("not scored"), std::string::npos) << original.out;
  EXPECT_FALSE(
      Json::parse(slurp(out / "original" / "report.json")).contains("metrics_2d_excluded_frames"));
}

TEST_F(CliScoreTest, PlaceholderLabelImagesAreNoGroundTruth) {
  // An import of colour and depth alone writes all-background label images
  // marked label_placeholder: a network's probabilities are not scored
  // against them (they would be "58 % accurate" against nothing).
  TempDir out;
  std::filesystem::copy(scene(), out / "seq", std::filesystem::copy_options::recursive);
  Json sequence = Json::parse(slurp(out / "seq" / "sequence.json"));
  for (Json& frame : sequence["frames"]) frame["label_placeholder"] = true;
  std::ofstream(out / "seq" / "sequence.json") << sequence.dump();
  const auto r = runCli("score " + quoted(out / "seq") + " --annotations " +
                        quoted(scene() / "annotations.json") + " --out " + quoted(out / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("pixel acc."), std::string::npos) << r.out;
  const Json report = Json::parse(slurp(out / "report" / "report.json"));
  EXPECT_FALSE(report.contains("metrics_2d"));
  EXPECT_EQ(report["objects"].size(), 4u) << "the 3D scores are unaffected";
  // The reports say why there are no 2D metrics.
  EXPECT_NE(r.out.find("2D segmentation: not scored: the label images are placeholders written "
                       "by an import of colour and depth only"),
            std::string::npos)
      << r.out;
  EXPECT_NE(report.value("metrics_2d_not_scored", std::string()).find("placeholders"),
            std::string::npos)
      << report.dump();
  // The same frames without the mark are scored.
  const auto original = runCli(scoreArgs(out / "original"));
  ASSERT_EQ(original.exit_code, 0) << original.err;
  EXPECT_NE(original.out.find("pixel acc."), std::string::npos) << original.out;
}

TEST_F(CliScoreTest, BoxOfAnUnknownLabelFailsAndWritesNothing) {
  TempDir out;
  Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  annotations["boxes"][2]["label"] = 77;
  const auto bad = out / "bad annotations.json";
  std::ofstream(bad) << annotations.dump();
  const auto dir = out / "report";
  const auto r = runCli(scoreArgs(dir, bad.string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("boxes[2].label"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("77"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
}

// A full disk (here: a limit on the size of any file written) keeps an earlier
// report whole, and a report folder created for the run is taken away again.
TEST_F(CliScoreTest, AFullDiskKeepsTheEarlierReportWhole) {
  TempDir out;
  const auto dir = out / "report";
  ASSERT_EQ(runCli(scoreArgs(dir)).exit_code, 0);
  const char* const names[] = {"report.json", "report.csv", "report.md", "report.svg"};
  std::vector<std::string> before;
  for (const char* name : names) before.push_back(slurp(dir / name));
  lom::test::CliLimits full_disk;
  full_disk.file_kib = 2;  // room for the CSV and the Markdown, not for the others
  auto r = runCli(scoreArgs(dir) + " --iou center", full_disk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("write failed (the file-size limit of "), std::string::npos) << r.err;
  for (size_t i = 0; i < before.size(); ++i) EXPECT_EQ(slurp(dir / names[i]), before[i]) << names[i];
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            4)
      << "no temporary file left";

  const auto fresh = out / "new" / "report";
  r = runCli(scoreArgs(fresh), full_disk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "new")) << "the folders made for the report go again";
}

TEST_F(CliScoreTest, OtherFrameFailsAndWritesNothing) {
  TempDir out;
  Json annotations = Json::parse(slurp(scene() / "annotations.json"));
  annotations["frame_id"] = "base_link";
  const auto bad = out / "boxes.json";
  std::ofstream(bad) << annotations.dump();
  const auto r = runCli(scoreArgs(out / "report", bad.string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("frame_id"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("base_link"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "report"));
}

// A copy of `scene` named "far", every camera and box moved `shift` metres along x.
std::filesystem::path shiftedScene(const TempDir& out, const std::filesystem::path& scene,
                                   double shift) {
  const auto copy = out / "far";
  lom::test::copyWithCamerasShifted(scene, copy, shift);
  Json annotations = Json::parse(slurp(copy / "annotations.json"));
  for (auto& box : annotations["boxes"]) box["center"][0] = box["center"][0].get<double>() + shift;
  std::ofstream(copy / "annotations.json") << annotations.dump();
  return copy;
}

// The map fused for the scores leaves out depths outside its extent: the
// scores are of what it holds, and score says so.
TEST_F(CliScoreTest, DepthsOutsideTheMapAreAWarning) {
  TempDir out;
  const auto copy = shiftedScene(out, scene(), 327.4);
  const auto r = runCli("score " + quoted(copy) + " --annotations " +
                        quoted(copy / "annotations.json") + " --out " + quoted(out / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + (copy / "sequence.json").string() + ": "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("lie outside the map's extent, 327.68 m either side"), std::string::npos)
      << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "report" / "report.json"));
  const Json report = Json::parse(slurp(out / "report" / "report.json"));
  ASSERT_FALSE(report["warnings"].empty());
  EXPECT_NE(report["warnings"][0].get<std::string>().find("lie outside the map's extent"),
            std::string::npos);
}

// A depth_scale ten times too small shrinks the map ten times: score says so
// as fuse does (the scores would compare a tiny map with the boxes).
TEST_F(CliScoreTest, DepthsNearerThanCamerasMeasureAreAWarning) {
  TempDir out;
  const auto copy = out / "tiny";
  std::filesystem::copy(scene(), copy, std::filesystem::copy_options::recursive);
  lom::Sequence sequence = lom::loadSequence(copy);
  sequence.camera.depth_scale /= 10.0;
  lom::saveSequence(sequence, copy);
  const auto r =
      runCli("score " + quoted(copy) + " --annotations " + quoted(copy / "annotations.json") +
             " --frames 1:3 --out " + quoted(out / "report"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string expected = (copy / "sequence.json").string() +
                               ": camera.depth_scale: the farthest measured point of the 2 frames "
                               "fused lies ";
  EXPECT_NE(r.err.find("warning: " + expected), std::string::npos) << r.err;
  const Json report = Json::parse(slurp(out / "report" / "report.json"));
  bool found = false;
  for (const auto& warning : report["warnings"])
    found = found || warning.get<std::string>().rfind(expected, 0) == 0;
  EXPECT_TRUE(found) << report["warnings"];
}

// Scoring fuses the sequence as fuse does, and says as fuse does when max
// range threw most of the depths away (every object then scores 0).
TEST_F(CliScoreTest, DepthsBeyondMaxRangeAreAWarning) {
  TempDir out;
  const auto r = runCli(scoreArgs(out / "near") + " --max-range 0.3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("were beyond the max range of 0.3 m: they mapped nothing, at most cleared "
                       "free space. The depths reach"),
            std::string::npos)
      << r.err;
  const Json report = Json::parse(slurp(out / "near" / "report.json"));
  // Said besides: the boxes past the range that nothing was mapped in.
  ASSERT_EQ(report["warnings"].size(), 3u) << report["warnings"];
  EXPECT_NE(report["warnings"][0].get<std::string>().find("outside everything the map observed"),
            std::string::npos);
  EXPECT_EQ(report["warnings"][0].get<std::string>().find("other units"), std::string::npos);
  EXPECT_NE(report["warnings"][1].get<std::string>().find("no occupied voxel"), std::string::npos);
  EXPECT_NE(report["warnings"][2].get<std::string>().find("beyond the max range of 0.3 m"),
            std::string::npos);
  // The default range takes the scene: nothing to say.
  const auto fine = runCli(scoreArgs(out / "fine"));
  ASSERT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_EQ(fine.err.find("max range"), std::string::npos) << fine.err;
  EXPECT_TRUE(Json::parse(slurp(out / "fine" / "report.json"))["warnings"].empty());
}

// What the command prints must reach standard output: a full disk there is a failure.
TEST_F(CliScoreTest, AnUnwritableStandardOutputIsAFailure) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  TempDir out;
  const std::string command = std::string("'") + LOM_CLI_PATH + "' " + scoreArgs(out / "r") +
                              " --quiet >/dev/full 2>" + quoted(out / "err.txt") + " </dev/null";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = slurp(out / "err.txt");
  EXPECT_NE(err.find("could not write to standard output"), std::string::npos) << err;
  EXPECT_TRUE(std::filesystem::exists(out / "r" / "report.json")) << "the files are kept";
}

TEST_F(CliScoreTest, CameraOutsideTheMapFailsBeforeWritingAnything) {
  TempDir out;
  const auto copy = shiftedScene(out, scene(), 400.0);
  const auto r = runCli("score " + quoted(copy) + " --annotations " +
                        quoted(copy / "annotations.json") + " --out " + quoted(out / "report"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((copy / "sequence.json").string() +
                       ": frames[0].pose: expected a camera position inside the map's extent, "
                       "327.68 m either side"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "report"));
  // In a batch, before any sequence is scored.
  std::ofstream(out / "list.txt") << scene() << " " << scene() / "annotations.json"
                                  << "\n"
                                  << copy << " " << copy / "annotations.json"
                                  << "\n";
  const auto batch =
      runCli("score --batch " + quoted(out / "list.txt") + " --out " + quoted(out / "batch"));
  EXPECT_EQ(batch.exit_code, 1) << batch.err;
  EXPECT_NE(batch.err.find("frames[0].pose"), std::string::npos) << batch.err;
  EXPECT_EQ(batch.out.find("Segmentation results"), std::string::npos) << batch.out;
  EXPECT_FALSE(std::filesystem::exists(out / "batch"));
}

TEST_F(CliScoreTest, UsageMistakesExitWithTwo) {
  TempDir out;
  EXPECT_EQ(runCli("score " + quoted(scene()) + " --annotations x.json").exit_code, 2);  // no --out
  EXPECT_EQ(runCli(scoreArgs(out / "r") + " --iou volume").exit_code, 2);
  EXPECT_EQ(runCli(scoreArgs(out / "r") + " --candidates 0,99").exit_code, 2);
  EXPECT_EQ(runCli("score --batch list.txt " + quoted(scene()) + " --out " + quoted(out / "r")).exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(out / "r"));
}

TEST_F(CliScoreTest, BatchWritesOneReportPerSequenceAndTheAggregate) {
  TempDir out;
  const auto list = out / "list.txt";
  // Paths relative to the list's folder, a comment and a blank line.
  std::ofstream(list) << "# two bins\n"
                      << std::filesystem::relative(scene("bin_a"), out.path()).string() << " "
                      << std::filesystem::relative(scene("bin_a") / "annotations.json", out.path()).string()
                      << "\n\n"
                      << scene("bin_b").string() << " " << (scene("bin_b") / "annotations.json").string() << "\n";
  const auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"bin_a", "bin_b"})
    for (const char* file : {"report.json", "report.csv", "report.md", "report.svg"})
      EXPECT_TRUE(std::filesystem::exists(out / "reports" / name / file)) << name << "/" << file;
  EXPECT_NE(r.out.find("wrote 2 reports and "), std::string::npos) << r.out;
  const Json aggregate = Json::parse(slurp(out / "reports" / "aggregate.json"));
  ASSERT_EQ(aggregate["sequences"].size(), 2u);
  EXPECT_EQ(aggregate["sequences"][0]["sequence"], "bin_a");
  EXPECT_EQ(aggregate["summary"]["objects"], 8);
  // aggregate.csv: a row per object of both sequences, each naming its sequence.
  const std::string csv = slurp(out / "reports" / "aggregate.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 9) << csv;
  EXPECT_NE(csv.find("\nbin_a,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nbin_b,"), std::string::npos) << csv;
  // The aggregate is the mean over all objects of both sequences.
  double sum = 0.0;
  for (const char* name : {"bin_a", "bin_b"}) {
    const Json report = Json::parse(slurp(out / "reports" / name / "report.json"));
    for (const auto& o : report["objects"]) sum += o["iou_3d"]["labeloctomap"].get<double>();
  }
  EXPECT_NEAR(aggregate["summary"]["iou_3d"]["labeloctomap"].get<double>(), sum / 8, 1e-12);
  EXPECT_TRUE(std::filesystem::exists(out / "reports" / "aggregate.md"));
  EXPECT_TRUE(std::filesystem::exists(out / "reports" / "aggregate.svg"));
  // One sequence, one report.
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n";
  const auto one =
      runCli("score --batch " + quoted(list) + " --out " + quoted(out / "one") + " --quiet");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.out.find("wrote 1 report and "), std::string::npos) << one.out;
}

// --out DIR writes DIR/<name>/ for each sequence: with DIR the folder holding a
// listed sequence, that is the sequence folder itself, which score only reads.
TEST_F(CliScoreTest, BatchRefusesReportFoldersInsideAScoredSequence) {
  TempDir dir;
  auto r = runCli("synth --out " + quoted(dir / "x") + " --frames 4 --width 80 --height 60");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ofstream(dir / "list.txt") << "x x/annotations.json\n";
  r = runCli("score --batch " + quoted(dir / "list.txt") + " --out " + quoted(dir.path()) +
             " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--out: the report of x (" + (dir / "list.txt").string() + " line 1)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("lies inside the input sequence folder"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("choose another --out"), std::string::npos) << r.err;
  for (const char* file : {"report.json", "report.csv", "report.md", "report.svg"})
    EXPECT_FALSE(std::filesystem::exists(dir / "x" / file)) << file;
  EXPECT_FALSE(std::filesystem::exists(dir / "aggregate.json"));
}

// A sequence folder named like a summary file is refused before anything is
// written (its report folder would take the summary's place, found only after
// the reports were written).
TEST_F(CliScoreTest, BatchRefusesASequenceNamedLikeTheSummary) {
  TempDir dir;
  auto r =
      runCli("synth --out " + quoted(dir / "aggregate.md") + " --frames 4 --width 80 --height 60");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ofstream(dir / "list.txt") << "aggregate.md aggregate.md/annotations.json\n";
  r = runCli("score --batch " + quoted(dir / "list.txt") + " --out " + quoted(dir / "reports") +
             " --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((dir / "list.txt").string() + ": line 1: expected a sequence folder not "
                                                     "named aggregate.json"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "reports"));
}

TEST_F(CliScoreTest, BatchWithABadLineFailsAndWritesNothing) {
  TempDir out;
  const auto list = out / "list.txt";
  std::ofstream(list) << scene("bin_a").string() << " " << (scene("bin_a") / "annotations.json").string() << "\n"
                      << scene("bin_b").string() << "\n";
  const auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(list.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "reports"));
}

// The boxes of every line are checked before the first sequence is fused: a
// bad file on line 2 failed only after line 1's fusion and scoring.
TEST_F(CliScoreTest, BatchChecksEveryLinesBoxesBeforeFusingAny) {
  TempDir out;
  Json boxes = Json::parse(slurp(scene("bin_b") / "annotations.json"));
  boxes["boxes"][1]["label"] = 77;
  std::ofstream(out / "bad.json") << boxes.dump(2);
  const auto list = out / "list.txt";
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n"
                      << scene("bin_b").string() << " bad.json\n";
  const auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line 2 (bin_b) failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("boxes[1].label"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("fusing"), std::string::npos) << "line 1 was fused first:\n" << r.err;
  EXPECT_EQ(r.out.find("bin_a"), std::string::npos) << "line 1 was scored first:\n" << r.out;
  EXPECT_FALSE(std::filesystem::exists(out / "reports"));
}

// So are the frame files each line's scoring reads: a missing depth image on
// line 2 failed only after line 1 was fused and its table printed.
TEST_F(CliScoreTest, BatchChecksEveryLinesFrameFilesBeforeFusingAny) {
  TempDir out;
  std::filesystem::copy(scene("bin_b"), out / "bin_b", std::filesystem::copy_options::recursive);
  const lom::Sequence copy = lom::loadSequence(out / "bin_b");
  std::filesystem::remove(out / "bin_b" / copy.frames[2].depth);
  const auto list = out / "list.txt";
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n"
                      << "bin_b bin_b/annotations.json\n";
  const auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line 2 (bin_b) failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sequence.json: frames[2].depth: expected an existing image file"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("bin_a"), std::string::npos) << "line 1 was scored first:\n" << r.out;
  EXPECT_FALSE(std::filesystem::exists(out / "reports"));
}

// A batch written into the folder of an earlier, longer one says which report
// folders there are not of this batch (a script collecting DIR/*/report.json
// would mix them in); it leaves them.
TEST_F(CliScoreTest, BatchOverAnEarlierOneNamesTheReportsItDidNotWrite) {
  TempDir out;
  const auto list = out / "list.txt";
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n"
                      << scene("bin_b").string() << " "
                      << (scene("bin_b") / "annotations.json").string() << "\n";
  auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("not in this batch"), std::string::npos) << r.err;
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n";
  r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + (out / "reports").string() +
                       " also holds reports of sequences not in this batch (bin_b)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("aggregate.json covers only the 1 listed"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "reports" / "bin_b" / "report.json"));
  // A warning, not a note: --quiet says it too.
  r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("also holds reports of sequences not in this batch (bin_b)"),
            std::string::npos)
      << r.err;
}

// A listed map of another label set (or a --threshold it cannot take) fails
// before the first line is fused, as a missing map does, naming its line.
TEST_F(CliScoreTest, BatchChecksEveryLinesMapBeforeFusingAny) {
  TempDir out;
  std::vector<lom::LabelInfo> two(2);
  two[1].id = 1;
  two[0].name = "background";
  two[1].name = "thing";
  lom::LabelMap(lom::LabelSet(two)).save(out / "other.ot");
  const auto list = out / "list.txt";
  std::ofstream(list) << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n"
                      << scene("bin_b").string() << " "
                      << (scene("bin_b") / "annotations.json").string() << " "
                      << (out / "other.ot").string() << "\n";
  const auto r = runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line 2 (bin_b) failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((out / "other.ot").string() + ": labels: expected"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.out.find("bin_a"), std::string::npos) << "line 1 was scored first:\n" << r.out;
  EXPECT_FALSE(std::filesystem::exists(out / "reports"));
}

// A list saved with a UTF-8 byte-order mark (some Windows editors) reads as
// without: the mark was taken for part of the first path.
TEST_F(CliScoreTest, BatchListWithAByteOrderMarkIsRead) {
  TempDir out;
  const auto list = out / "list.txt";
  std::ofstream(list) << "\xEF\xBB\xBF" << scene("bin_a").string() << " "
                      << (scene("bin_a") / "annotations.json").string() << "\n";
  const auto r =
      runCli("score --batch " + quoted(list) + " --out " + quoted(out / "reports") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "reports" / "bin_a" / "report.json"));
}

}  // namespace
