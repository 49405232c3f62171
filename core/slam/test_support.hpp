#pragma once
// Helpers shared by the keyframe SLAM tests (keyframe_slam_test.cpp,
// keyframe_slam_heading_test.cpp): a test-only header, Catch2 included.
#include <catch2/catch.hpp>
#include <vector>

#include "core/slam/keyframe_slam.hpp"
#include "core/slam/synthetic.hpp"

namespace orthosonar::slam::testing {

inline SE3 se3(const SE2& T) { return se3_from_se2(T, -3.0, 0.0, 0.0); }

inline bool graph_connected(const KeyframeSlam& slam) {
  // Every keyframe k >= 1 has an accepted sequential factor (k-1 -> k).
  for (size_t k = 1; k < slam.keyframes().size(); ++k) {
    bool found = false;
    for (const auto& f : slam.factors()) {
      found |= f.accepted && f.from == static_cast<int>(k) - 1 && f.to == static_cast<int>(k) &&
               (f.kind == FactorKind::kSequentialIcp || f.kind == FactorKind::kOdometryDr);
    }
    if (!found) return false;
  }
  return true;
}

// Keyframes at the `truth` poses of `world`'s basin, one a second, added at the `dr` poses;
// from keyframe 1 on each DR factor gets `sigma` (empty: sigma_odometry). Checks that the
// graph stays connected.
inline KeyframeSlam fly_route(const SlamConfig& config, const SyntheticWorld& world, const std::vector<SE2>& truth,
                              const std::vector<SE2>& dr, KeyframeSlam::DrSigma sigma = {}) {
  KeyframeSlam slam(config);
  for (size_t i = 0; i < truth.size(); ++i)
    slam.add_keyframe(Time::from_s(static_cast<int64_t>(i)), se3(dr[i]), synthetic_scan_V(world, truth[i], {}, 1, i),
                      i == 0 ? KeyframeSlam::DrSigma{} : sigma);
  CHECK(graph_connected(slam));
  return slam;
}

// Keyframes at the `dr` poses whose scans are taken at `truth`, except keyframes first..last,
// scanned from truth * offset (misplaced by `offset` from where DR puts them). Every solve
// must be usable.
inline KeyframeSlam fly_misplaced(const SlamConfig& config, const SyntheticWorld& world, const std::vector<SE2>& truth,
                                  const std::vector<SE2>& dr, size_t first, size_t last, const SE2& offset) {
  KeyframeSlam slam(config);
  for (size_t i = 0; i < truth.size(); ++i) {
    const bool misplaced = i >= first && i <= last;
    slam.add_keyframe(Time::from_s(static_cast<int64_t>(i)), se3(dr[i]),
                      synthetic_scan_V(world, misplaced ? truth[i] * offset : truth[i], {}, 1, i));
    REQUIRE(slam.last_solve().usable);
  }
  return slam;
}

// Laps of the basin (30 x 20 m route, 3 m keyframes) with DR drifting 0.003 rad per
// keyframe, flown by fly_route.
inline KeyframeSlam fly_basin(const SlamConfig& config, int laps, KeyframeSlam::DrSigma sigma = {}) {
  const auto truth = loop_route(30.0, 20.0, 3.0, laps);
  return fly_route(config, make_basin_world(5), truth, drifting_odometry(truth, 0.003, 0.0, 0.0, 9), sigma);
}

}  // namespace orthosonar::slam::testing
