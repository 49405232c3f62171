// Absolute bounds of golden scenarios: golden/bounds.yaml read and checked (see golden_bounds.hpp).
#include "replay/verify/golden_bounds.hpp"
#include "core/slam/trajectory_error.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace orthosonar::verify {
namespace {

// Every key of `n` must be one of `known`; names the first stranger with its place.
Status golden_bounds_known_keys(const YAML::Node& n, const std::set<std::string>& known, const std::string& where) {
  if (!n.IsMap()) return Error{where + ": expected a map"};
  for (const auto& kv : n) {
    const std::string k = kv.first.as<std::string>();
    if (!known.count(k)) return Error{where + ": unknown key '" + k + "'"};
  }
  return {};
}

Result<std::optional<double>> golden_bound_number(const YAML::Node& n, const std::string& key, const std::string& where) {
  if (!n[key]) return std::optional<double>();
  try {
    const double v = n[key].as<double>();
    if (!std::isfinite(v) || v < 0.0) return Error{where + "." + key + ": must be a finite number >= 0"};
    return std::optional<double>(v);
  } catch (const std::exception&) {
    return Error{where + "." + key + ": not a number"};
  }
}

std::string golden_bound_fmt(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}

}  // namespace

std::string default_golden_bounds_path(const std::string& scenario_path) {
  return (std::filesystem::path(scenario_path).parent_path().parent_path() / "bounds.yaml").string();
}

Result<std::map<std::string, GoldenScenarioBounds>> load_golden_bounds(const std::string& path) {
  std::map<std::string, GoldenScenarioBounds> out;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  if (auto st = golden_bounds_known_keys(root, {"scenarios"}, path); !st) return st.error();
  if (!root["scenarios"] || !root["scenarios"].IsMap()) return Error{path + ": needs a map 'scenarios'"};
  for (const auto& kv : root["scenarios"]) {
    const std::string name = kv.first.as<std::string>();
    const std::string where = path + ": scenarios." + name;
    const YAML::Node n = kv.second;
    if (auto st = golden_bounds_known_keys(
            n, {"ate_slam_max_m", "ate_slam_over_dr_max", "expected_failure", "systems"}, where);
        !st)
      return st.error();
    GoldenScenarioBounds b;
    auto ate = golden_bound_number(n, "ate_slam_max_m", where);
    if (!ate) return ate.error();
    b.ate_slam_max_m = *ate;
    auto k = golden_bound_number(n, "ate_slam_over_dr_max", where);
    if (!k) return k.error();
    b.ate_slam_over_dr_max = *k;
    if (n["expected_failure"]) {
      const YAML::Node xf = n["expected_failure"];
      if (auto st = golden_bounds_known_keys(xf, {"slam_worse_than_dr"}, where + ".expected_failure"); !st)
        return st.error();
      b.slam_worse_than_dr_expected_failure = xf["slam_worse_than_dr"].as<std::string>();
      if (b.slam_worse_than_dr_expected_failure.empty())
        return Error{where + ".expected_failure.slam_worse_than_dr: give the reason"};
    }
    if (n["systems"]) {
      if (!n["systems"].IsMap()) return Error{where + ".systems: expected a map"};
      for (const auto& skv : n["systems"]) {
        const std::string system = skv.first.as<std::string>();
        const std::string swhere = where + ".systems." + system;
        if (auto st = golden_bounds_known_keys(skv.second, {"mae_max_m", "rmse_max_m", "coverage_min_voxels"}, swhere); !st)
          return st.error();
        GoldenSystemBounds sb;
        for (const auto& [key, dst] : {std::pair{"mae_max_m", &sb.mae_max_m}, std::pair{"rmse_max_m", &sb.rmse_max_m},
                                       std::pair{"coverage_min_voxels", &sb.coverage_min_voxels}}) {
          auto v = golden_bound_number(skv.second, key, swhere);
          if (!v) return v.error();
          *dst = *v;
        }
        b.systems[system] = sb;
      }
    }
    out[name] = std::move(b);
  }
  return out;
}

GoldenBoundsVerdict check_golden_bounds(const GoldenScenarioBounds& bounds, const std::map<std::string, double>& metrics,
                                        const std::vector<std::string>& systems) {
  GoldenBoundsVerdict v;
  const auto fail = [&v](const std::string& line) {
    v.ok = false;
    v.lines.push_back("FAIL " + line);
  };
  const auto get = [&](const std::string& key) -> std::optional<double> {
    const auto it = metrics.find(key);
    if (it == metrics.end() || !std::isfinite(it->second)) return std::nullopt;
    return it->second;
  };
  // One "value <= limit" (or >= for floors) check; a missing or non-finite value fails.
  const auto check = [&](const std::string& key, const std::optional<double>& limit, bool is_floor) {
    if (!limit) return;
    const auto value = get(key);
    const std::string rel = is_floor ? " >= " : " <= ";
    if (!value) return fail(key + " missing or not finite (bound" + rel + golden_bound_fmt(*limit) + ")");
    const bool ok = is_floor ? *value >= *limit : *value <= *limit;
    const std::string line = key + " " + golden_bound_fmt(*value) + rel + golden_bound_fmt(*limit);
    if (ok) v.lines.push_back("ok   " + line);
    else fail(line);
  };
  check("ate_slam_m", bounds.ate_slam_max_m, false);
  const auto dr = get("ate_dr_m"), slam = get("ate_slam_m");
  if (!dr || !slam) {
    fail("ate_slam_m / ate_dr_m missing or not finite");
  } else {
    const double ratio = *dr > 0.0 ? *slam / *dr : INFINITY;
    if (bounds.ate_slam_over_dr_max) {
      const std::string line = "ate_slam_m / ate_dr_m " + golden_bound_fmt(ratio) + " <= k = " +
                               golden_bound_fmt(*bounds.ate_slam_over_dr_max);
      if (*slam <= *bounds.ate_slam_over_dr_max * *dr + slam::kAteTieM) v.lines.push_back("ok   " + line);
      else fail(line);
    }
    // SLAM no worse than dead reckoning: always evaluated; a known failure is marked.
    const std::string line = "ate_slam_m " + golden_bound_fmt(*slam) + " <= ate_dr_m " + golden_bound_fmt(*dr);
    const bool passes = slam::slam_no_worse_than_dr(*slam, *dr);
    const std::string& why = bounds.slam_worse_than_dr_expected_failure;
    if (why.empty()) {
      if (passes) v.lines.push_back("ok   " + line);
      else fail(line);
    } else if (passes) {
      fail(line + ": UNEXPECTED PASS of a check marked expected_failure (" + why +
           "); remove the marker from golden/bounds.yaml");
    } else {
      v.lines.push_back("KNOWN FAILURE (expected_failure in golden/bounds.yaml: " + why + "): " + line);
    }
  }
  for (const auto& system : systems) {
    const auto it = bounds.systems.find(system);
    if (it == bounds.systems.end()) {
      fail("no bounds for system " + system);
      continue;
    }
    check(system + ".mae_m", it->second.mae_max_m, false);
    check(system + ".rmse_m", it->second.rmse_max_m, false);
    check(system + ".coverage_voxels", it->second.coverage_min_voxels, true);
    if (!it->second.mae_max_m || !it->second.rmse_max_m || !it->second.coverage_min_voxels)
      fail("bounds of system " + system + " need mae_max_m, rmse_max_m and coverage_min_voxels");
  }
  if (!bounds.ate_slam_max_m || !bounds.ate_slam_over_dr_max)
    fail("bounds need ate_slam_max_m and ate_slam_over_dr_max");
  return v;
}

}  // namespace orthosonar::verify
