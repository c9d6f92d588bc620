// Fusion speed and memory. `lom_benchmarks --table` prints the comparison table
// of docs/performance.md (fast path vs reference path vs OctoMap's own
// insertPointCloud, measured in the same run on the same frames) and the
// table of reading and fusing frames from disk (`--reading` prints that one
// alone); without either it runs the Google Benchmark cases.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <octomap/OcTree.h>

#include "lom/fusion.hpp"
#include "lom/octree/label_octree.hpp"
#include "lom/synth.hpp"

namespace {

namespace fs = std::filesystem;

struct LoadedFrame {
  lom::CameraIntrinsics camera;
  Eigen::Isometry3d pose;
  lom::DepthImage depth;
  lom::ProbabilityImage proba;         // the scene's probability image (40-label map)
  lom::ProbabilityImage single_label;  // one channel: "occupied" with OctoMap's p_hit 0.7
};

struct Scene {
  lom::LabelSet labels;
  std::vector<LoadedFrame> frames;
};

// Where the scene of one image size and frame count is written (once).
fs::path sceneFolder(int width, int height, int frames) {
  return fs::temp_directory_path() / "labeloctomap-benchmark-scenes" /
         (std::to_string(width) + "x" + std::to_string(height) + "-" + std::to_string(frames));
}

// The synthetic shelf-bin scene at one image size (cached between runs).
const Scene& scene(int width, int height, int frames) {
  static std::map<fs::path, Scene> cache;
  const fs::path folder = sceneFolder(width, height, frames);
  if (auto it = cache.find(folder); it != cache.end()) return it->second;
  if (!fs::exists(folder / "sequence.json")) {
    lom::SynthOptions options;
    options.seed = 7;
    options.objects = 8;
    options.frames = frames;
    options.views = 3;
    options.width = width;
    options.height = height;
    fs::create_directories(folder);
    lom::writeSyntheticScene(options, folder);
  }
  const lom::Sequence sequence = lom::loadSequence(folder);
  Scene s;
  s.labels = sequence.labels;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    lom::FrameData data = lom::loadFrame(sequence, i);
    LoadedFrame f;
    f.camera = sequence.cameraOf(i);
    f.pose = sequence.frames[i].T_world_camera;
    f.depth = std::move(data.depth);
    f.proba = std::move(*data.proba);
    f.single_label = {f.depth.width, f.depth.height, 1, {0},
                      std::vector<float>(f.depth.metres.size(), 0.7f), {}};
    s.frames.push_back(std::move(f));
  }
  return cache.emplace(folder, std::move(s)).first->second;
}

lom::LabelSet singleLabel() { return lom::LabelSet({{0, "occupied", {255, 255, 255}}}); }

struct Config {
  int width, height;
  double resolution;
  int labels;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Fuses frames [0, count) into a fresh map; returns per-frame seconds.
std::vector<double> fuse(const Scene& s, const Config& c, lom::IntegrationPath path, size_t count,
                         std::unique_ptr<lom::LabelMap>* keep = nullptr, int threads = 0) {
  lom::MapParameters parameters;
  parameters.resolution = c.resolution;
  auto map = std::make_unique<lom::LabelMap>(c.labels == 1 ? singleLabel() : s.labels, parameters);
  lom::IntegrationOptions options;
  options.path = path;
  options.threads = threads;
  std::vector<double> seconds;
  for (size_t i = 0; i < std::min(count, s.frames.size()); ++i) {
    const LoadedFrame& f = s.frames[i];
    const lom::ProbabilityImage& proba = c.labels == 1 ? f.single_label : f.proba;
    const lom::FrameEvidence evidence(map->numLabels(), &proba, nullptr, std::nullopt, 0.9);
    const auto start = std::chrono::steady_clock::now();
    lom::integrateFrame(*map, f.camera, f.pose, f.depth, evidence, options);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  map->prune();  // as fuseSequence does at the end
  if (keep) *keep = std::move(map);
  return seconds;
}

// OctoMap's own insertion of the same frames (single label, discretize = true).
std::vector<double> fuseOctomap(const Scene& s, double resolution, size_t count,
                                double* bytes_per_voxel) {
  octomap::OcTree tree(resolution);
  std::vector<double> seconds;
  for (size_t i = 0; i < std::min(count, s.frames.size()); ++i) {
    const LoadedFrame& f = s.frames[i];
    octomap::Pointcloud cloud;
    for (int v = 0; v < f.depth.height; ++v)
      for (int u = 0; u < f.depth.width; ++u) {
        const float z = f.depth.at(u, v);
        if (!(z > 0.f)) continue;
        const Eigen::Vector3d p = f.pose * f.camera.backProject(u, v, z);
        cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                        static_cast<float>(p.z()));
      }
    const Eigen::Vector3d o = f.pose.translation();
    const auto start = std::chrono::steady_clock::now();
    tree.insertPointCloud(cloud, octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                                  static_cast<float>(o.z())),
                          1.0, false, true);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  *bytes_per_voxel = static_cast<double>(tree.memoryUsage()) / static_cast<double>(tree.getNumLeafNodes());
  return seconds;
}

// Per configuration, `repeats` rounds of: the fast path over the frames, the
// reference path over the first `reference_frames` of them, and (once per
// image size and voxel size) OctoMap over the frames, each into a fresh map.
// The rounds interleave the paths, so a slow spell of a shared machine slows
// all of them alike; each ratio compares medians over the same frames.
int printTable(int repeats, size_t frames, size_t reference_frames) {
  const Config configs[] = {
      {160, 120, 0.01, 1},  {160, 120, 0.01, 40},  {160, 120, 0.005, 1},  {160, 120, 0.005, 40},
      {640, 480, 0.01, 1},  {640, 480, 0.01, 40},  {640, 480, 0.005, 1},  {640, 480, 0.005, 40},
  };
  reference_frames = std::min(reference_frames, frames);
  std::printf("Fusion of the synthetic shelf-bin scene (%zu frames, max range 1.0 m), %d rounds.\n", frames,
              repeats);
  std::printf("Each round: fast path over all frames, reference path over the first %zu, OctoMap over all\n",
              reference_frames);
  std::printf("(OcTree::insertPointCloud, discretize=true, single label). ms/frame: median over the rounds'\n"
              "frames; x reference compares the medians of the frames both paths fused.\n\n");
  std::printf("| image | voxel | labels | fast ms/frame | fast fps | reference ms/frame | "
              "OctoMap ms/frame | x OctoMap | x reference | bytes/voxel | OctoMap bytes/voxel | "
              "memory ratio |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::map<std::string, std::pair<double, double>> octomap_cache;  // time, bytes per voxel
  for (const Config& c : configs) {
    const Scene& s = scene(c.width, c.height, static_cast<int>(frames));
    const std::string key = std::to_string(c.width) + "/" + std::to_string(c.resolution);
    const bool measure_octomap = !octomap_cache.count(key);
    std::vector<double> fast_times, fast_reference_frames, reference_times, octomap_times;
    double octomap_bytes = 0.0;
    std::unique_ptr<lom::LabelMap> map;
    for (int r = 0; r < repeats; ++r) {
      const auto fast = fuse(s, c, lom::IntegrationPath::Fast, frames, &map);
      fast_times.insert(fast_times.end(), fast.begin(), fast.end());
      const size_t both = std::min(reference_frames, fast.size());  // frames both paths fuse
      fast_reference_frames.insert(fast_reference_frames.end(), fast.begin(),
                                   fast.begin() + static_cast<std::ptrdiff_t>(both));
      const auto reference = fuse(s, c, lom::IntegrationPath::Reference, reference_frames);
      reference_times.insert(reference_times.end(), reference.begin(), reference.end());
      if (measure_octomap) {
        const auto octomap = fuseOctomap(s, c.resolution, frames, &octomap_bytes);
        octomap_times.insert(octomap_times.end(), octomap.begin(), octomap.end());
      }
    }
    if (measure_octomap) octomap_cache[key] = {median(octomap_times), octomap_bytes};
    const double fast = median(fast_times);
    const double reference = median(reference_times);
    const auto [octomap_time, octomap_bytes_per_voxel] = octomap_cache[key];
    const double bytes = static_cast<double>(map->memoryBytes()) / static_cast<double>(map->numLeaves());
    std::printf("| %dx%d | %g mm | %d | %.1f | %.0f | %.0f | %.0f | %.1f | %.1f | %.1f | %.1f | %.2f |\n",
                c.width, c.height, c.resolution * 1000.0, c.labels, fast * 1e3, 1.0 / fast,
                reference * 1e3, octomap_time * 1e3, octomap_time / fast,
                reference / median(fast_reference_frames), bytes, octomap_bytes_per_voxel,
                bytes / octomap_bytes_per_voxel);
    std::fflush(stdout);
  }
  return 0;
}

void BM_FastFusion(benchmark::State& state) {
  const Config c{static_cast<int>(state.range(0)), static_cast<int>(state.range(0)) * 3 / 4,
                 state.range(1) / 1000.0, static_cast<int>(state.range(2))};
  const Scene& s = scene(c.width, c.height, 8);
  for (auto _ : state) {
    auto times = fuse(s, c, lom::IntegrationPath::Fast, s.frames.size());
    benchmark::DoNotOptimize(times.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.frames.size()));
  state.SetLabel("items = frames");
}
BENCHMARK(BM_FastFusion)
    ->Args({160, 10, 40})
    ->Args({640, 10, 1})
    ->Args({640, 10, 40})
    ->Args({640, 5, 40})
    ->Unit(benchmark::kMillisecond);

void BM_ReferenceFusion(benchmark::State& state) {
  const Config c{160, 120, 0.01, 40};
  const Scene& s = scene(c.width, c.height, 8);
  for (auto _ : state) {
    auto times = fuse(s, c, lom::IntegrationPath::Reference, s.frames.size());
    benchmark::DoNotOptimize(times.data());
  }
}
// One thread, for repeatable instruction counts under valgrind --tool=callgrind.
void BM_FastFusionOneThread(benchmark::State& state) {
  const Config c{640, 480, 0.01, 40};
  const Scene& s = scene(c.width, c.height, 8);
  for (auto _ : state) {
    auto times = fuse(s, c, lom::IntegrationPath::Fast, s.frames.size(), nullptr, 1);
    benchmark::DoNotOptimize(times.data());
  }
}
BENCHMARK(BM_FastFusionOneThread)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_ReferenceFusion)->Unit(benchmark::kMillisecond);

// The on-disk scene of scene(width, ...), 8 frames.
lom::Sequence sceneOnDisk(int width) {
  const int frames = 8;
  scene(width, width * 3 / 4, frames);  // writes the scene once
  return lom::loadSequence(sceneFolder(width, width * 3 / 4, frames));
}

// Reading a frame from disk, checked as it is read: /0 every image (colour,
// depth, label and the 8-bit probability image as codes and floats, what the
// studio's frame view reads), /1 what fusion reads (lom::loadFusionFrame:
// depth and the probability codes). In `labeloctomap fuse` and the studio
// this comes on top of integrating the frame.
void BM_LoadFrame(benchmark::State& state) {
  const lom::Sequence sequence = sceneOnDisk(static_cast<int>(state.range(0)));
  const bool for_fusion = state.range(1) != 0;
  size_t index = 0;
  for (auto _ : state) {
    const size_t i = index++ % sequence.frames.size();
    lom::FrameData frame =
        for_fusion ? lom::loadFusionFrame(sequence, i, nullptr) : lom::loadFrame(sequence, i);
    benchmark::DoNotOptimize(frame.depth.metres.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel("items = frames");
}
BENCHMARK(BM_LoadFrame)->Args({640, 0})->Args({640, 1})->Unit(benchmark::kMillisecond);

// What `labeloctomap fuse` spends per frame, reading included: each round
// reads and fuses the 640x480 scene from disk into a fresh map (40 labels,
// 1 cm), once reading every image of a frame (lom::loadFrame, as fusion did
// before 2026-11-26) and once what fusion reads (lom::loadFusionFrame).
int printReadingTable(int repeats) {
  const lom::Sequence sequence = sceneOnDisk(640);
  lom::MapParameters parameters;
  parameters.resolution = 0.01;
  struct Times {
    std::vector<double> read, fuse, frame;
  };
  Times every, fusion_only;
  const auto round = [&](bool for_fusion, Times& times) {
    lom::LabelMap map(sequence.labels, parameters);
    for (size_t i = 0; i < sequence.frames.size(); ++i) {
      const auto start = std::chrono::steady_clock::now();
      const lom::FrameData frame =
          for_fusion ? lom::loadFusionFrame(sequence, i, nullptr) : lom::loadFrame(sequence, i);
      const auto read = std::chrono::steady_clock::now();
      const lom::FrameEvidence evidence(map.numLabels(), &*frame.proba, nullptr, std::nullopt, 0.9);
      lom::integrateFrame(map, sequence.cameraOf(i), sequence.frames[i].T_world_camera, frame.depth,
                          evidence, {});
      const auto end = std::chrono::steady_clock::now();
      times.read.push_back(std::chrono::duration<double>(read - start).count());
      times.fuse.push_back(std::chrono::duration<double>(end - read).count());
      times.frame.push_back(std::chrono::duration<double>(end - start).count());
    }
  };
  for (int r = 0; r < repeats; ++r) {  // alternately, so that a slow spell slows both
    round(false, every);
    round(true, fusion_only);
  }
  std::printf(
      "\nReading and fusing the 640x480 scene from disk (%zu frames, 40 labels, 1 cm), %d rounds;\n"
      "ms/frame: median over the rounds' frames.\n\n",
      sequence.frames.size(), repeats);
  std::printf(
      "| frames read as | read ms/frame | fuse ms/frame | read + fuse ms/frame | frames/s | x "
      "every image |\n");
  std::printf("|---|---|---|---|---|---|\n");
  const double baseline = median(every.frame);
  for (const auto& [name, t] :
       {std::pair<const char*, const Times*>{"every image (loadFrame)", &every},
        {"what fusion reads (loadFusionFrame)", &fusion_only}}) {
    const double frame = median(t->frame);
    std::printf("| %s | %.1f | %.1f | %.1f | %.0f | %.2f |\n", name, median(t->read) * 1e3,
                median(t->fuse) * 1e3, frame * 1e3, 1.0 / frame, baseline / frame);
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 5;
  size_t frames = 8, reference_frames = 8;
  bool table = false, reading = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--table")) table = true;
    else if (!std::strcmp(argv[i], "--reading"))
      reading = true;
    else if (!std::strncmp(argv[i], "--repeats=", 10)) repeats = std::atoi(argv[i] + 10);
    else if (!std::strncmp(argv[i], "--frames=", 9)) frames = static_cast<size_t>(std::atoi(argv[i] + 9));
    else if (!std::strncmp(argv[i], "--reference-frames=", 19))
      reference_frames = static_cast<size_t>(std::atoi(argv[i] + 19));
  }
  if (reading && !table) return printReadingTable(std::max(1, repeats));
  if (table) {
    const int status = printTable(std::max(1, repeats), std::max<size_t>(1, frames),
                                  std::max<size_t>(1, reference_frames));
    return status ? status : printReadingTable(std::max(1, repeats));
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
