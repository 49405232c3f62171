#pragma once
// Test-only: the small golden scenario, bounds and run output the verify tests share.
#include <string>

#include "replay/run/run.hpp"

namespace orthosonar::verify::testing {

// A scenario's settings, no expectations recorded.
inline const char* const kDemoScenario = R"(name: demo
scene: aircraft
seed: 3
duration_s: 20
resolution: reduced
keyframes: {distance_m: 3, rotation_deg: 30}
systems: [fusion]
tolerances: {coverage_rel: 0.01, mae_abs_m: 0.002, rmse_abs_m: 0.003, ate_abs_m: 0.004}
)";

// Bounds the demo run keeps (coverage floor 500, SLAM at most 0.8 x DR and 1 m).
inline const char* const kDemoBounds = R"(scenarios:
  demo:
    ate_slam_max_m: 1.0
    ate_slam_over_dr_max: 0.8
    systems:
      fusion: {mae_max_m: 0.1, rmse_max_m: 0.2, coverage_min_voxels: 500}
)";

// A run of the demo scenario without running it: digest "abc", one system "fusion".
inline run::RunOutput demo_run_output(int64_t coverage_voxels = 1000) {
  run::RunOutput r;
  r.digest.overall_hex = "abc";
  r.digest.outputs = {{"fusion/map", "111"}, {"fusion/traj", "222"}};
  run::SystemOutput s;
  s.name = "fusion";
  s.coverage_voxels = coverage_voxels;
  s.accuracy = mapping::AccuracyStats{};
  s.accuracy->mae_m = 0.05;
  s.accuracy->rmse_m = 0.07;
  r.systems.push_back(std::move(s));
  r.ate_dr_m = 1.5;
  r.ate_slam_m = 0.75;
  r.counts.keyframes = 12;
  r.counts.loop_closures = 2;
  return r;
}

}  // namespace orthosonar::verify::testing
