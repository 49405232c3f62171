// The output directory of the outputs contract: per-system maps (PCD, PLY, OctoMap) and
// metrics.json, keyframes.csv, factors.csv, TUM trajectories, scene mesh, the ping pair
// perception saw (ping_pair/), summary.json and digest.json.
#include <filesystem>
#include <fstream>
#include <future>
#include <functional>
#include <numbers>
#include <string>

#include "core/slam/keyframe_slam.hpp"
#include "hal/sim/mesh_io.hpp"
#include "orthosonar/version.hpp"
#include "replay/outputs/map_writers.hpp"
#include "replay/outputs/ping_pair_io.hpp"
#include "replay/run/results_mcap.hpp"
#include "replay/run/run.hpp"
#include "replay/run/trajectory.hpp"
#include "replay/run/truth_spill.hpp"

namespace orthosonar::run {

// ---------------------------------------------------------------- outputs

namespace {

nlohmann::json runtime_json(const std::vector<std::pair<std::string, mapping::RuntimeStats>>& rt) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, s] : rt) j[name] = {{"mean_ms", s.mean_ms()}, {"sd_ms", s.sd_ms()}, {"count", s.count}};
  return j;
}

nlohmann::json opt_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
// Keyframe heading against truth (issue 33): degrees, or null without truth.
nlohmann::json heading_json(const std::optional<mapping::HeadingErrorStats>& h) {
  if (!h) return nullptr;
  return {{"keyframes", h->count}, {"rms_deg", h->rms_deg}, {"mean_deg", h->mean_deg}, {"max_abs_deg", h->max_abs_deg}};
}

Status write_json(const std::filesystem::path& path, const nlohmann::json& j) {
  std::ofstream f(path, std::ios::trunc);
  if (!f) return Error{"cannot open '" + path.string() + "' for writing"};
  f << j.dump(2) << "\n";
  if (!f) return Error{"write failed for '" + path.string() + "'"};
  return {};
}

// `path` complete or not at all: written beside it, then renamed over it (issue 40).
Status write_run_file_atomically(const std::filesystem::path& path, const std::function<Status(const std::string&)>& write) {
  std::filesystem::path tmp = path;
  tmp += ".partial";
  if (Status st = write(tmp.string()); !st.ok()) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return st;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Error{"cannot rename '" + tmp.string() + "' to '" + path.string() + "': " + ec.message()};
  return {};
}

nlohmann::json run_input_json(const RunOutput& run) {
  const replay::RecoveryReport& r = run.input_recovery;
  nlohmann::json j = {{"path", run.input_path}, {"complete", r.complete}};
  if (!r.complete) {
    j["cut_at_byte"] = r.bytes_recovered;
    j["bytes_total"] = r.bytes_total;
    j["sensor_s_recovered"] = r.sensor_seconds();
    j["messages_recovered"] = r.messages_recovered;
    j["detail"] = r.detail;
  }
  return j;
}

// What SLAM did with its factors, per kind: how many joined the graph, and every outcome
// reason (KeyframeSlam's Factor::reason up to its first number or "(n weak directions)"
// note) with its count; loop closures also count those the robust loss down-weights below one half.
// Answers "why did SLAM not beat DR here" without a debugger.
nlohmann::json slam_factors_json(const slam::KeyframeSlam& slam) {
  nlohmann::json out = nlohmann::json::object();
  for (const slam::Factor& f : slam.factors()) {
    nlohmann::json& k = out[slam::factor_kind_name(f.kind)];
    if (k.is_null()) k = {{"total", 0}, {"accepted", 0}, {"reasons", nlohmann::json::object()}};
    k["total"] = k["total"].get<int64_t>() + 1;
    if (f.accepted) k["accepted"] = k["accepted"].get<int64_t>() + 1;
    std::string reason = f.reason.substr(0, f.reason.find(" ("));
    reason = reason.substr(0, reason.find_first_of("0123456789"));  // "pcm clique of 3" -> "pcm clique of"
    while (!reason.empty() && reason.back() == ' ') reason.pop_back();
    nlohmann::json& r = k["reasons"][reason.empty() ? "unspecified" : reason];
    r = r.is_null() ? 1 : r.get<int64_t>() + 1;
    if (f.kind == slam::FactorKind::kLoopClosure && f.accepted) {
      nlohmann::json& d = k["downweighted_below_half"];
      d = (d.is_null() ? 0 : d.get<int64_t>()) + (f.robust_weight < 0.5 ? 1 : 0);
    }
  }
  return out;
}

}  // namespace

nlohmann::json system_metrics_json(const RunOutput& run, const SystemOutput& s) {
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [k, v] : count_fields(run.counts, run.pipeline->dead_reckoning().counts())) counts[k] = v;
  counts["map_points"] = s.map_W.size();
  for (const auto& [k, v] : s.system_counts) counts[k] = v;
  return {{"system", s.name},
          {"coverage_voxels", s.coverage_voxels},
          {"mae_m", s.accuracy ? nlohmann::json(s.accuracy->mae_m) : nlohmann::json(nullptr)},
          {"rmse_m", s.accuracy ? nlohmann::json(s.accuracy->rmse_m) : nlohmann::json(nullptr)},
          {"true_pose_mae_m",
           s.true_pose_accuracy ? nlohmann::json(s.true_pose_accuracy->mae_m) : nlohmann::json(nullptr)},
          {"true_pose_rmse_m",
           s.true_pose_accuracy ? nlohmann::json(s.true_pose_accuracy->rmse_m) : nlohmann::json(nullptr)},
          {"ate_dr_m", opt_json(run.ate_dr_m)},
          {"ate_slam_m", opt_json(run.ate_slam_m)},
          {"heading_error_dr", heading_json(run.heading_dr)},
          {"heading_error_slam", heading_json(run.heading_slam)},
          {"runtime", runtime_json([&] {
             auto rt = s.runtime;
             for (const auto& p : run.runtime)
               if (p.first == "fusion" || p.first == "slam_update") rt.push_back(p);
             return rt;
           }())},
          {"counts", counts}};
}

Status clear_run_verdicts(const std::string& out_dir) {
  namespace fs = std::filesystem;
  for (const char* name : {"digest.json", "summary.json"}) {
    std::error_code ec;
    fs::remove(fs::path(out_dir) / name, ec);
    if (ec) return Error{"cannot remove '" + (fs::path(out_dir) / name).string() + "': " + ec.message()};
  }
  return {};
}

Status write_run_outputs(const RunOutput& run, const RunOptions& options, const std::string& out_dir) {
  namespace fs = std::filesystem;
  const fs::path out(out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return Error{"cannot create '" + out_dir + "': " + ec.message()};
  // A caller that did not clear them before its run: the verdicts of an earlier run must
  // not sit beside this run's half-written maps.
  if (Status st = clear_run_verdicts(out_dir); !st.ok()) return st;
  // results.mcap (the largest writer: every truth pose as Foxglove JSON, zstd) on a thread
  // of its own beside the others; its bytes do not depend on it. std::async's future waits
  // for it on every return below.
  auto results = std::async(std::launch::async,
                            [&] { return write_results_mcap(run, (out / kResultsMcapFile).string()); });
  nlohmann::json octomap_outside = nlohmann::json::object();  // per system, only where points were left out
  for (const auto& s : run.systems) {
    const fs::path d = out / s.name;
    fs::create_directories(d, ec);
    if (ec) return Error{"cannot create '" + d.string() + "': " + ec.message()};
    if (Status st = outputs::write_pcd((d / "map.pcd").string(), s.map_W); !st.ok()) return st;
    if (Status st = outputs::write_ply((d / "map.ply").string(), s.map_W); !st.ok()) return st;
    size_t outside = 0;
    if (Status st = outputs::write_octomap((d / "map.bt").string(), s.map_W, run.config.octomap_resolution_m, &outside);
        !st.ok())
      return st;
    if (outside > 0) octomap_outside[s.name] = outside;
    if (Status st = write_json(d / "metrics.json", system_metrics_json(run, s)); !st.ok()) return st;
  }
  const auto& slam = run.pipeline->slam();
  if (Status st = write_keyframe_table((out / "keyframes.csv").string(), slam); !st.ok()) return st;
  if (Status st = write_factor_table((out / "factors.csv").string(), slam, run.truth); !st.ok()) return st;
  if (Status st = write_tum((out / "traj_dr.tum").string(), keyframe_poses_dr(slam)); !st.ok()) return st;
  if (Status st = write_tum((out / "traj_slam.tum").string(), keyframe_poses_slam(slam)); !st.ok()) return st;
  if (run.truth_all) {
    if (!run.truth_all->empty())
      if (Status st = write_tum((out / "traj_truth.tum").string(), *run.truth_all); !st.ok()) return st;
  } else if (!run.truth.empty()) {
    if (Status st = write_tum((out / "traj_truth.tum").string(), run.truth); !st.ok()) return st;
  }
  if (run.mesh)
    if (Status st = sim::write_mesh_ply(*run.mesh, (out / "scene_mesh.ply").string()); !st.ok()) return st;
  if (Status st = results.get(); !st.ok()) return st;
  if (run.ping_pair) {
    const auto& pp = *run.ping_pair;
    if (Status st = outputs::write_ping_pair((out / "ping_pair").string(), pp.h, pp.v, pp.fused,
                                                 run.config.pipeline.fusion.overlap_deg); !st.ok()) return st;
  } else {
    fs::remove_all(out / "ping_pair", ec);  // an earlier run's pair is not this run's
  }

  nlohmann::json summary;
  nlohmann::json fixture = nlohmann::json::object();
  for (const auto& [k, v] : run.metadata) fixture[k] = v;
  summary["fixture"] = fixture;
  if (!run.input_path.empty()) summary["input"] = run_input_json(run);
  summary["software_version"] = kVersion;
  summary["config"] = config_to_json(run.config);
  nlohmann::json sources = nlohmann::json::object();
  for (const auto& [k, v] : run.config_sources) sources[k] = v;
  summary["config_sources"] = sources;
  summary["systems"] = options.systems;
  summary["ground_truth_mesh"] = run.mesh_note;
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [k, v] : count_fields(run.counts, run.pipeline->dead_reckoning().counts())) counts[k] = v;
  summary["counts"] = counts;
  summary["stream_s"] = run.stream_span.seconds();
  summary["runtime"] = runtime_json(run.runtime);
  summary["ate_dr_m"] = opt_json(run.ate_dr_m);
  summary["ate_slam_m"] = opt_json(run.ate_slam_m);
  summary["heading_error_dr"] = heading_json(run.heading_dr);
  summary["heading_error_slam"] = heading_json(run.heading_slam);
  summary["slam_factors"] = slam_factors_json(run.pipeline->slam());
  if (run.pipeline->slam().drift_sigma_dps() > 0.0) {
    summary["slam_heading_drift_dps"] = run.pipeline->slam().heading_drift_rad_s() * 180.0 / std::numbers::pi;
  }
  // Points map.bt could not hold (OctoMap's key range is +-32768 x octomap_resolution_m):
  // named here rather than dropped silently; map.pcd and map.ply have them all.
  if (!octomap_outside.empty()) summary["octomap_points_outside_key_range"] = octomap_outside;
  summary["digest"] = run.digest.overall_hex;
  // Last, each complete or absent: their presence means the run finished.
  if (Status st = write_run_file_atomically(out / "summary.json",
                                            [&](const std::string& p) { return write_json(p, summary); });
      !st.ok())
    return st;
  return write_run_file_atomically(out / "digest.json",
                                   [&](const std::string& p) { return replay::write_digest_json(p, run.digest); });
}

}  // namespace orthosonar::run
