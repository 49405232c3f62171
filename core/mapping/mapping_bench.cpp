// Mapping benchmarks: submap construction per timestep (paper Table III "submap
// construction"; target <= 0.1 ms), map assembly, voxel metrics and mesh distance.
#include <benchmark/benchmark.h>

#include "core/geometry.hpp"
#include "core/mapping/mesh_distance.hpp"
#include "core/mapping/metrics.hpp"
#include "core/mapping/submap.hpp"
#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {

std::vector<Eigen::Vector3f> random_cloud(Rng& rng, int n) {
  std::vector<Eigen::Vector3f> c;
  for (int i = 0; i < n; ++i)
    c.emplace_back(static_cast<float>(rng.uniform(0, 30)), static_cast<float>(rng.uniform(-5, 5)),
                   static_cast<float>(rng.uniform(-5, 5)));
  return c;
}

// One timestep: register one fused cloud (state.range(0) points) into the open submap.
void BM_SubmapConstructionPerTimestep(benchmark::State& state) {
  Rng rng(1);
  const auto cloud = random_cloud(rng, static_cast<int>(state.range(0)));
  SubmapStore store;
  store.begin(0, se3_from_xyz_rpy(1, 2, -3, 0, 0, 0.3));
  int64_t steps = 0;
  for (auto _ : state) {
    const SE3 T = se3_from_xyz_rpy(0.01 * static_cast<double>(steps % 100), 2, -3, 0.01, 0.0, 0.3);
    store.add(T, cloud);
    if (++steps % 1000 == 0) {  // keep memory bounded: a new submap every 1000 steps
      state.PauseTiming();
      store = SubmapStore();
      store.begin(0, SE3::Identity());
      state.ResumeTiming();
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SubmapConstructionPerTimestep)->Arg(100)->Arg(500)->Arg(2000);

void BM_MapAssembly100kPoints(benchmark::State& state) {
  Rng rng(2);
  SubmapStore store;
  std::vector<SE3> poses;
  for (int k = 0; k < 100; ++k) {
    poses.push_back(se3_from_xyz_rpy(k, 0, -3, 0, 0, 0.01 * k));
    store.begin(k, poses.back());
    store.add(poses.back(), random_cloud(rng, 1000));
  }
  for (auto _ : state) benchmark::DoNotOptimize(store.assemble(poses));
}
BENCHMARK(BM_MapAssembly100kPoints)->Unit(benchmark::kMillisecond);

void BM_VoxelCentroids100kPoints(benchmark::State& state) {
  Rng rng(3);
  const auto cloud = random_cloud(rng, 100000);
  for (auto _ : state) benchmark::DoNotOptimize(voxel_centroids(cloud));
}
BENCHMARK(BM_VoxelCentroids100kPoints)->Unit(benchmark::kMillisecond);

void BM_MeshDistanceQuery(benchmark::State& state) {
  Rng rng(4);
  TriangleMesh m;
  for (int i = 0; i < 50000; ++i) {
    const Eigen::Vector3f c(static_cast<float>(rng.uniform(-100, 100)), static_cast<float>(rng.uniform(-100, 100)),
                            static_cast<float>(rng.uniform(-10, 0)));
    const int b = static_cast<int>(m.vertices.size());
    for (int k = 0; k < 3; ++k)
      m.vertices.push_back(c + Eigen::Vector3f(static_cast<float>(rng.uniform(-1, 1)),
                                               static_cast<float>(rng.uniform(-1, 1)),
                                               static_cast<float>(rng.uniform(-1, 1))));
    m.triangles.emplace_back(b, b + 1, b + 2);
    m.object_id.push_back(1);
    m.semantic.push_back(SemanticClass::kOther);
  }
  const MeshDistance md(m);
  int64_t i = 0;
  for (auto _ : state) {
    const double x = -100.0 + static_cast<double>((i * 7919) % 200);
    const double y = -100.0 + static_cast<double>((i * 104729) % 200);
    benchmark::DoNotOptimize(md.distance({x, y, -5.0}));
    ++i;
  }
}
BENCHMARK(BM_MeshDistanceQuery);

}  // namespace
