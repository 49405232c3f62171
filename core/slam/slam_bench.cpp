// SLAM update benchmark (issue 6): one keyframe added — planar cloud preparation, SSM
// ICP, loop-closure search with ICP and PCM, and the warm-started Ceres re-solve — to a
// graph that already holds 100 or 1000 keyframes. Targets: <= 20 ms and <= 100 ms.
// The world is the synthetic basin (walls and pilings), the route loops round it with a
// drifting DR, so loop closures are found all the time (the expensive case).
#include <benchmark/benchmark.h>

#include <map>

#include "core/slam/keyframe_slam.hpp"
#include "core/slam/synthetic.hpp"

namespace {

using namespace orthosonar;
using namespace orthosonar::slam;

struct Fixture {
  KeyframeSlam slam;
  SE3 next_dr;
  std::vector<Eigen::Vector2d> next_points;
};

SE3 se3(const SE2& T) { return se3_from_se2(T, -3.0, 0.0, 0.0); }

// Built once per size (building 1000 keyframes takes a while) and copied per iteration.
const Fixture& fixture(int keyframes) {
  static std::map<int, Fixture> cache;
  auto it = cache.find(keyframes);
  if (it != cache.end()) return it->second;
  static const SyntheticWorld world = make_basin_world(5);
  const int laps = keyframes / 60 + 2;
  const auto truth = loop_route(30.0, 20.0, 3.0, laps);
  const auto dr = drifting_odometry(truth, 0.003, 0.0005, 0.02, 9);
  Fixture f;
  for (int i = 0; i < keyframes; ++i) {
    const auto k = static_cast<size_t>(i);
    f.slam.add_keyframe(Time::from_s(i), se3(dr[k]), synthetic_scan_V(world, truth[k], {}, 1, k));
  }
  const auto k = static_cast<size_t>(keyframes);
  f.next_dr = se3(dr[k]);
  f.next_points = synthetic_scan_V(world, truth[k], {}, 1, k);
  return cache.emplace(keyframes, std::move(f)).first->second;
}

void BM_SlamUpdate(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    state.PauseTiming();
    KeyframeSlam slam = f.slam;
    auto points = f.next_points;
    state.ResumeTiming();
    benchmark::DoNotOptimize(slam.add_keyframe(Time::from_s(1000000), f.next_dr, std::move(points)));
  }
  state.counters["cloud_points"] = static_cast<double>(f.slam.keyframes().back().cloud_V.size());
  state.counters["loop_closures"] = static_cast<double>(f.slam.accepted_loop_closures());
}
BENCHMARK(BM_SlamUpdate)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_PoseGraphSolveOnly(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::vector<SE2> start;
  for (const auto& k : f.slam.keyframes()) start.push_back(se2_from_se3(k.T_W_V_slam));
  std::vector<GraphEdge> edges;
  for (const auto& fac : f.slam.factors()) {
    if (fac.accepted && fac.kind != FactorKind::kPrior) edges.push_back({fac.from, fac.to, fac.T_from_to, fac.sigma, fac.mix});
  }
  for (auto _ : state) {
    auto poses = start;
    benchmark::DoNotOptimize(solve_pose_graph(poses, f.slam.factors().front().T_from_to,
                                              f.slam.config().sigma_prior, edges, f.slam.config().solver));
  }
}
BENCHMARK(BM_PoseGraphSolveOnly)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace
