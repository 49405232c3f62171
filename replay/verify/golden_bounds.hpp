#pragma once
// Absolute bounds on golden scenarios (issue 35): limits on what a scenario's run measures
// (SLAM ATE against dead reckoning and in metres, each map's MAE/RMSE against the scene
// mesh, coverage floors), kept in golden/bounds.yaml. `golden --update` rewrites a
// scenario's expectations (digest, metrics, images) but never this file, so an update
// cannot bless a regression past a bound: `golden --check` checks the bounds separately
// from the digest, and `golden --update` reports a violated bound and exits 1.
//
// A check the code is known to fail today carries an explicit expected-failure marker with
// its reason; it is still evaluated on every run, reported as KNOWN FAILURE, and turns into
// a failure the day it passes (so the marker is removed, not forgotten).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::verify {

struct GoldenSystemBounds {
  std::optional<double> mae_max_m, rmse_max_m;
  std::optional<double> coverage_min_voxels;
};

struct GoldenScenarioBounds {
  std::optional<double> ate_slam_max_m;       // ATE of the SLAM trajectory, metres
  std::optional<double> ate_slam_over_dr_max;  // k in ATE_SLAM <= k * ATE_DR
  // Reason the check "ATE_SLAM <= ATE_DR" is known to fail; empty: it must pass.
  std::string slam_worse_than_dr_expected_failure;
  std::map<std::string, GoldenSystemBounds> systems;
};

// scenario name -> bounds. Unknown keys and non-numeric values are errors naming the key.
Result<std::map<std::string, GoldenScenarioBounds>> load_golden_bounds(const std::string& path);

// golden/bounds.yaml for a scenario at golden/scenarios/<name>.yaml.
std::string default_golden_bounds_path(const std::string& scenario_path);

struct GoldenBoundsVerdict {
  bool ok = true;
  std::vector<std::string> lines;  // one per check: "ok ...", "FAIL ...", "KNOWN FAILURE ..."
};

// Checks `metrics` (the flattened "system.metric" -> value map a scenario pins, e.g.
// "fusion.mae_m", "ate_slam_m") against `bounds`. Every system in `systems` needs bounds
// and every bounded metric must be present: a missing one fails, never passes.
GoldenBoundsVerdict check_golden_bounds(const GoldenScenarioBounds& bounds, const std::map<std::string, double>& metrics,
                                        const std::vector<std::string>& systems);

}  // namespace orthosonar::verify
