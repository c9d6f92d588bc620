// Speed of the whole-map voxel passes, on a generated room-sized voxel set
// with sensor-like noise: lom::voxelSurface, the watertight surface that
// `export --format ply|obj|stl` and `render` build, and lom::euclideanClusters,
// the objects of `plan`, `export --format objects` and the studio's Objects
// panel. `lom_benchmarks --benchmark_filter='VoxelSurface|VoxelClusters'`.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "lom/export.hpp"
#include "lom/objects.hpp"

namespace {

// A floor, two walls and a few boxes, about 300,000 voxels; every surface
// voxel is moved by -1, 0 or +1 along the surface's normal at random, as
// depth noise leaves a fused map (steps, holes, voxels touching only along an
// edge).
const std::vector<lom::VoxelKey>& noisyRoom() {
  static const std::vector<lom::VoxelKey> keys = [] {
    std::vector<lom::VoxelKey> out;
    std::mt19937 random(11);
    std::uniform_int_distribution<int> offset(-1, 1);
    const int base = 32768;
    const auto add = [&](int x, int y, int z) {
      out.push_back({static_cast<std::uint16_t>(base + x), static_cast<std::uint16_t>(base + y),
                     static_cast<std::uint16_t>(base + z)});
    };
    for (int x = 0; x < 400; ++x)
      for (int y = 0; y < 350; ++y) add(x, y, offset(random));  // floor
    for (int x = 0; x < 400; ++x)
      for (int z = 2; z < 150; ++z) add(x, 350 + offset(random), z);  // wall along x
    for (int y = 0; y < 350; ++y)
      for (int z = 2; z < 150; ++z) add(400 + offset(random), y, z);  // wall along y
    for (int b = 0; b < 12; ++b)                                      // boxes standing on the floor
      for (int x = 0; x < 30; ++x)
        for (int y = 0; y < 20; ++y)
          for (int z = 2; z < 25; ++z)
            if (x == 0 || x == 29 || y == 0 || y == 19 || z == 24)
              add(30 * b + x, 40 + 20 * (b % 5) + y, z + (z == 24 ? offset(random) : 0));
    return out;
  }();
  return keys;
}

void BM_VoxelSurface(benchmark::State& state) {
  const std::vector<lom::VoxelKey>& keys = noisyRoom();
  lom::VoxelSurfaceOptions options;
  options.merge_coplanar = state.range(0) != 0;
  size_t triangles = 0;
  for (auto _ : state) {
    const lom::SurfaceMesh mesh = lom::voxelSurface(keys, 0.02, options);
    triangles = mesh.triangles.size();
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["voxels"] = static_cast<double>(keys.size());
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_VoxelSurface)->ArgName("merge")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// Every cluster (as `plan --all-clusters`), or every `stride`-th voxel of the
// room: many small clusters.
void BM_VoxelClusters(benchmark::State& state) {
  const std::vector<lom::VoxelKey>& room = noisyRoom();
  std::vector<lom::VoxelKey> keys;
  const auto stride = static_cast<size_t>(state.range(0));
  for (size_t i = 0; i < room.size(); i += stride) keys.push_back(room[i]);
  size_t clusters = 0;
  for (auto _ : state) {
    const auto found = lom::euclideanClusters(keys, 2.0);
    clusters = found.size();
    benchmark::DoNotOptimize(found.data());
  }
  state.counters["voxels"] = static_cast<double>(keys.size());
  state.counters["clusters"] = static_cast<double>(clusters);
}
BENCHMARK(BM_VoxelClusters)->ArgName("stride")->Arg(1)->Arg(7)->Unit(benchmark::kMillisecond);

}  // namespace
