#include "replay/run/run_config.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "hal/config/key_table.hpp"
#include "hal/config/pose6.hpp"

namespace orthosonar::run {
namespace {

// The run configuration's key tables (hal/config/key_table.hpp, shared with the simulator's,
// in this file's wording): every value is checked against its range before it reaches a
// stage, and an error names the key (docs/CONFIG.md lists the ranges; `orthosonar config --ranges`).
using config::Entry;
using config::Parity;
using config::Table;
const config::KeyTables kKeys({.prefix = "config: ", .integer_range_colon = true, .pose_names_part = true});

// A noise model "[sigma_x_m, sigma_y_m, sigma_theta_rad]", every entry in (0, 1000].
Entry sigma(Eigen::Vector3d& target) {
  Entry e;
  e.range = "[sigma_x_m, sigma_y_m, sigma_theta_rad], each in (0, 1000]";
  e.bad = "[0.1, 0, 0.01]";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    if (!n.IsSequence() || n.size() != 3) return kKeys.error("'" + where + "' must be " + range);
    Eigen::Vector3d v;
    try {
      for (int i = 0; i < 3; ++i) v[i] = n[static_cast<size_t>(i)].as<double>();
    } catch (const YAML::Exception&) {
      return kKeys.error("'" + where + "' must be " + range);
    }
    if (!v.allFinite() || !(v.array() > 0.0).all() || !(v.array() <= 1000.0).all())
      return kKeys.error("'" + where + "' entries must each be in (0, 1000]");
    target = v;
    return {};
  };
  return e;
}

// A position "[x_m, y_m]" in the world frame, each |v| <= 1e7 m.
Entry xy(Vec2& target) {
  Entry e;
  e.range = "[x_m, y_m], each in [-1e7, 1e7]";
  e.bad = "[0, 1e9]";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    if (!n.IsSequence() || n.size() != 2) return kKeys.error("'" + where + "' must be " + range);
    Vec2 v;
    try {
      for (int i = 0; i < 2; ++i) v[i] = n[static_cast<size_t>(i)].as<double>();
    } catch (const YAML::Exception&) {
      return kKeys.error("'" + where + "' must be " + range);
    }
    if (!v.allFinite() || !(v.array().abs() <= 1e7).all())
      return kKeys.error("'" + where + "' entries must each be in [-1e7, 1e7]");
    target = v;
    return {};
  };
  return e;
}

Table cfar_table(perception::CfarConfig& c) {
  return {{"train_cells", kKeys.integer(c.train_cells, 1, 1000)},
          {"guard_cells", kKeys.integer(c.guard_cells, 0, 1000)},
          {"pfa", kKeys.real(c.pfa, 0.0, 1.0, true, true)},
          {"gate", kKeys.real(c.gate, 0.0, 255.0)},
          {"min_neighbours", kKeys.integer(c.min_neighbours, 0, 8)},
          {"method", kKeys.choice("soca, ca, goca",
                            [&c](const std::string& s) {
                              if (s == "soca") c.method = perception::CfarMethod::kSoca;
                              else if (s == "ca") c.method = perception::CfarMethod::kCa;
                              else if (s == "goca") c.method = perception::CfarMethod::kGoca;
                              else return false;
                              return true;
                            })},
          {"window", kKeys.choice("cross, range", [&c](const std::string& s) {
             if (s == "cross") c.window = perception::CfarWindow::kCross;
             else if (s == "range") c.window = perception::CfarWindow::kRange;
             else return false;
             return true;
           })}};
}

Table root_table(RunConfig& c) {
  auto& f = c.pipeline.fusion;
  auto& d = c.pipeline.dr;
  auto& s = c.pipeline.slam;
  return {
      {"threads", kKeys.integer(c.threads, 1, kMaxThreads)},
      {"fusion", kKeys.nested([&f] {
         return Table{{"max_pair_dt_s", kKeys.real(f.max_pair_dt_s, 0.0, 10.0, true)},
                      {"overlap_deg", kKeys.real(f.overlap_deg, 0.0, 90.0, true)},
                      {"patch", kKeys.integer(f.patch, 1, 31, Parity::kOdd)},
                      {"min_confidence", kKeys.real(f.min_confidence, 0.0, 1.0)},
                      {"normalise_percentile", kKeys.real(f.normalise_percentile, 0.0, 1.0, true)},
                      {"rotate_v_patch", kKeys.boolean(f.rotate_v_patch)},
                      {"peak_window_deg", kKeys.real(f.peak_window_deg, 0.0, 10.0)},
                      {"noise_floor_factor", kKeys.real(f.noise_floor_factor, 0.0, 100.0)},
                      {"noise_floor_rows", kKeys.integer(f.noise_floor_rows, 0, 1000)},
                      {"slope_run_ratio", kKeys.real(f.slope_run_ratio, 0.0, 1000.0)},
                      {"slope_run_floor", kKeys.real(f.slope_run_floor, 0.0, 1.0)},
                      {"slope_run_max_gap", kKeys.integer(f.slope_run_max_gap, 0, 100)},
                      {"slope_v_span_deg", kKeys.real(f.slope_v_span_deg, 0.0, 90.0)},
                      {"slope_top_from_v", kKeys.boolean(f.slope_top_from_v)},
                      {"sigma_v_deg", kKeys.real(f.sigma_v_deg, 0.0, 90.0)},
                      {"sigma_v_per_wall_deg", kKeys.real(f.sigma_v_per_wall_deg, 0.0, 90.0)},
                      {"sigma_slope_near_deg", kKeys.real(f.sigma_slope_near_deg, 0.0, 90.0)},
                      {"sigma_slope_far_deg", kKeys.real(f.sigma_slope_far_deg, 0.0, 90.0)},
                      {"T_V_h", kKeys.pose(f.T_V_h)},
                      {"T_V_v", kKeys.pose(f.T_V_v)},
                      {"cfar_h", kKeys.nested([&f] { return cfar_table(f.cfar_h); })},
                      {"cfar_v", kKeys.nested([&f] { return cfar_table(f.cfar_v); })}};
       })},
      {"dr", kKeys.nested([&d] {
         return Table{{"initial_xy_m", xy(d.initial_xy_m)},
                      {"max_speed_mps", kKeys.real(d.max_speed_mps, 0.0, 100.0, true)},
                      {"hold_s", kKeys.real(d.hold_s, 0.0, 3600.0)},
                      {"attitude_filter_tau_s", kKeys.real(d.attitude_filter_tau_s, 0.0, 3600.0)},
                      {"attitude_filter_max_gap_s", kKeys.real(d.attitude_filter_max_gap_s, 0.0, 3600.0, true)},
                      {"use_gyro", kKeys.boolean(d.use_gyro)},
                      {"T_V_gyro", kKeys.pose(d.gyro.T_V_gyro)},
                      {"latitude_deg", kKeys.real(d.gyro.latitude_deg, -90.0, 90.0)},
                      {"gyro_align_s", kKeys.real(d.gyro.align_s, 0.0, 3600.0)},
                      {"gyro_arw_deg_per_sqrt_h", kKeys.real(d.gyro_arw_deg_per_sqrt_h, 0.0, 100.0)},
                      {"gyro_bias_dph", kKeys.real(d.gyro_bias_dph, 0.0, 3600.0)},
                      {"dvl_velocity_sigma_mps", kKeys.real(d.dvl_velocity_sigma_mps, 0.0, 10.0)},
                      {"dvl_scale_sigma", kKeys.real(d.dvl_scale_sigma, 0.0, 1.0)},
                      {"dvl_dropout_speed_sigma_mps", kKeys.real(d.dvl_dropout_speed_sigma_mps, 0.0, 100.0)}};
       })},
      {"slam", kKeys.nested([&s] {
         return Table{{"kf_distance_m", kKeys.real(s.kf_distance_m, 0.0, 1000.0, true)},
                      {"kf_rotation_deg", kKeys.real(s.kf_rotation_deg, 0.0, 360.0, true)},
                      {"voxel_m", kKeys.real(s.voxel_m, 0.01, 100.0)},
                      {"keyframe_cloud_s", kKeys.real(s.keyframe_cloud_s, 0.0, 600.0)},
                      {"keyframe_cloud_always", kKeys.boolean(s.keyframe_cloud_always)},
                      {"outlier_radius_m", kKeys.real(s.outlier_radius_m, 0.0, 100.0, true)},
                      {"outlier_min_neighbours", kKeys.integer(s.outlier_min_neighbours, 0, 10000)},
                      {"ssm_target_frames", kKeys.integer(s.ssm_target_frames, 1, 1000)},
                      {"ssm_min_points", kKeys.integer(s.ssm_min_points, 1, 10000000)},
                      {"ssm_max_translation_m", kKeys.real(s.ssm_max_translation_m, 0.0, 1000.0, true)},
                      {"ssm_max_rotation_deg", kKeys.real(s.ssm_max_rotation_deg, 0.0, 180.0, true)},
                      {"ssm_keep_dr_factor", kKeys.boolean(s.ssm_keep_dr_factor)},
                      {"ssm_max_mahalanobis", kKeys.real(s.ssm_max_mahalanobis, 0.0, 1e6)},
                      {"ssm_min_information_ratio", kKeys.real(s.ssm_min_information_ratio, 0.0, 1.0)},
                      {"nssm_min_separation", kKeys.integer(s.nssm_min_separation, 1, 1000000)},
                      {"nssm_min_travel_m", kKeys.real(s.nssm_min_travel_m, 0.0, 1e6)},
                      {"nssm_range_m", kKeys.real(s.nssm_range_m, 0.0, 1000.0, true)},
                      {"nssm_min_points", kKeys.integer(s.nssm_min_points, 1, 10000000)},
                      {"nssm_max_rmse_m", kKeys.real(s.nssm_max_rmse_m, 0.0, 100.0, true)},
                      {"pcm_queue", kKeys.integer(s.pcm_queue, 1, 1000)},
                      {"pcm_threshold", kKeys.real(s.pcm_threshold, 0.0, 1e6, true)},
                      {"min_pcm", kKeys.integer(s.min_pcm, 0, 1000)},
                      {"sigma_prior", sigma(s.sigma_prior)},
                      {"sigma_odometry", sigma(s.sigma_odometry)},
                      {"gyro_heading_sigma_min_deg", kKeys.real(s.gyro_heading_sigma_min_deg, 0.0, 90.0)},
                      {"sigma_icp", sigma(s.sigma_icp)},
                      {"sigma_loop", sigma(s.sigma_loop)},
                      {"sigma_loop_gyro", sigma(s.sigma_loop_gyro)},
                      {"degeneracy_ratio", kKeys.real(s.degeneracy_ratio, 0.0, 1.0)},
                      {"nssm_max_mahalanobis", kKeys.real(s.nssm_max_mahalanobis, 0.0, 1e12)},
                      {"nssm_max_heading_diff_gyro_deg", kKeys.real(s.nssm_max_heading_diff_gyro_deg, 0.0, 180.0)},
                      {"nssm_max_heading_sigmas", kKeys.real(s.nssm_max_heading_sigmas, 0.0, 1000.0)},
                      {"nssm_fixed_heading_gyro", kKeys.boolean(s.nssm_fixed_heading_gyro)},
                      {"nssm_target_same_pass", kKeys.boolean(s.nssm_target_same_pass)},
                      {"nssm_source_frames", kKeys.integer(s.nssm_source_frames, 1, 1000)},
                      {"nssm_max_view_change_deg", kKeys.real(s.nssm_max_view_change_deg, 0.0, 180.0)},
                      {"nssm_other_side", kKeys.choice_of(s.nssm_other_side, slam::SlamConfig::kOtherSides,
                                                             slam::SlamConfig::other_side_name)},
                      {"heading_drift_sigma_dps", kKeys.real(s.heading_drift_sigma_dps, 0.0, 10.0)},
                      {"heading_drift_sigma_gyro_dps", kKeys.real(s.heading_drift_sigma_gyro_dps, 0.0, 10.0)},
                      {"heading_drift_every_keyframes", kKeys.integer(s.heading_drift_every_keyframes, 0, 1000000)},
                      {"heading_link_s", kKeys.real(s.heading_link_s, 0.0, 1e6)},
                      {"heading_link_walk_dps", kKeys.real(s.heading_link_walk_dps, 0.0, 10.0, true)},
                      {"heading_link_white_deg", kKeys.real(s.heading_link_white_deg, 0.0, 10.0)},
                      {"loop_loss", kKeys.choice_of(s.loop_loss, slam::kLosses, slam::loss_name)},
                      {"loop_loss_scale", kKeys.real(s.loop_loss_scale, 0.0, 1000.0, true)},
                      {"loop_correlation_m", kKeys.real(s.loop_correlation_m, 0.0, 1000.0)},
                      {"sigma_loop_per_m", kKeys.real(s.sigma_loop_per_m, 0.0, 10.0)},
                      {"dr_sigma_model", kKeys.choice_of(s.dr_sigma_model, slam::SlamConfig::kDrSigmaModels,
                                                                   slam::SlamConfig::dr_sigma_model_name)},
                      {"dr_translation_sigma_min_m", kKeys.real(s.dr_translation_sigma_min_m, 0.0, 1000.0)},
                      {"solver", kKeys.nested([&s] {
                         auto& g = s.solver;
                         return Table{{"max_iterations", kKeys.integer(g.max_iterations, 1, 10000)},
                                      {"function_tolerance", kKeys.real(g.function_tolerance, 0.0, 1.0)},
                                      {"initial_trust_region_radius", kKeys.real(g.initial_trust_region_radius, 0.0, 1e16, true)},
                                      {"model_agreement_stop", kKeys.real(g.model_agreement_stop, 0.0, 1.0)},
                                      {"linear_solver", kKeys.choice_of(g.linear_solver, slam::kLinearSolvers,
                                                                        slam::linear_solver_name)},
                                      {"pcg_tolerance", kKeys.real(g.pcg_tolerance, 0.0, 1.0, true)},
                                      {"pcg_max_iterations", kKeys.integer(g.pcg_max_iterations, 1, 1000000)}};
                       })},
                      {"fit_information", kKeys.nested([&s] {
                         auto& f = s.fit_information;
                         return Table{{"max_correspondence_m", kKeys.real(f.max_correspondence_m, 0.0, 100.0, true)},
                                      {"normal_radius_m", kKeys.real(f.normal_radius_m, 0.0, 100.0, true)},
                                      {"line_ratio", kKeys.real(f.line_ratio, 0.0, 1.0)}};
                       })},
                      {"icp", kKeys.nested([&s] {
                         return Table{{"max_iterations", kKeys.integer(s.icp.max_iterations, 1, 10000)},
                                      {"max_correspondence_m", kKeys.real(s.icp.max_correspondence_m, 0.0, 1000.0, true)},
                                      {"trim_fraction", kKeys.real(s.icp.trim_fraction, 0.0, 1.0, true)},
                                      {"metric", kKeys.choice_of(s.icp.metric, slam::kIcpMetrics, slam::icp_metric_name)}};
                       })}};
       })},
      {"mapping", kKeys.nested([&c] {
         return Table{{"fusion_batch_pairs", kKeys.integer(c.pipeline.fusion_batch_pairs, 1, 4096)},
                      {"max_elevation_sigma_deg", kKeys.real(c.pipeline.max_elevation_sigma_deg, 0.0, 90.0)},
                      {"voxel_m", kKeys.real(c.voxel_m, 0.01, 100.0)},
                      {"octomap_resolution_m", kKeys.real(c.octomap_resolution_m, 0.01, 100.0)}};
       })},
  };
}

nlohmann::json cfar_json(const perception::CfarConfig& c) {
  return {{"method", perception::to_string(c.method)}, {"window", perception::to_string(c.window)},
          {"train_cells", c.train_cells}, {"guard_cells", c.guard_cells}, {"pfa", c.pfa}, {"gate", c.gate},
          {"min_neighbours", c.min_neighbours}};
}

}  // namespace

std::string pose6_string(const SE3& T) { return config::format_pose6(T); }

Status apply_config_yaml(const std::string& yaml_text, RunConfig& config) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Error{std::string("config: YAML parse error: ") + e.what()};
  }
  if (root.IsNull()) return {};
  RunConfig trial = config;
  try {
    if (Status s = kKeys.apply(root, root_table(trial), ""); !s.ok()) return s;
  } catch (const YAML::Exception& e) {
    // Every reader checks its node's type first; this is the net under them, so a document
    // no reader foresaw is an error, never an exception through the API.
    return Error{std::string("config: ") + e.what()};
  }
  config = trial;
  return {};
}

Result<std::string> read_config_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{"cannot open config '" + path + "'"};
  std::stringstream ss;
  ss << f.rdbuf();
  if (!f && !f.eof()) return Error{"cannot read config '" + path + "'"};
  return ss.str();
}

Status load_config_file(const std::string& path, RunConfig& config) {
  auto text = read_config_text(path);
  if (!text.ok()) return text.error();
  Status s = apply_config_yaml(*text, config);
  if (!s.ok()) return Error{path + ": " + s.error().message};
  return s;
}

std::vector<ConfigKeyRange> config_key_ranges() {
  RunConfig scratch;
  std::vector<ConfigKeyRange> out;
  for (auto& k : config::KeyTables::ranges(root_table(scratch))) out.push_back({k.key, k.range, k.bad_value});
  return out;
}

nlohmann::json config_to_json(const RunConfig& c) {
  const auto& f = c.pipeline.fusion;
  const auto& d = c.pipeline.dr;
  const auto& s = c.pipeline.slam;
  return {
      {"threads", c.threads},
      {"fusion", {{"max_pair_dt_s", f.max_pair_dt_s}, {"overlap_deg", f.overlap_deg}, {"patch", f.patch},
                  {"min_confidence", f.min_confidence}, {"normalise_percentile", f.normalise_percentile},
                  {"rotate_v_patch", f.rotate_v_patch}, {"peak_window_deg", f.peak_window_deg},
                  {"noise_floor_factor", f.noise_floor_factor}, {"noise_floor_rows", f.noise_floor_rows},
                  {"slope_run_ratio", f.slope_run_ratio}, {"slope_run_floor", f.slope_run_floor},
                  {"slope_run_max_gap", f.slope_run_max_gap}, {"slope_v_span_deg", f.slope_v_span_deg},
                  {"slope_top_from_v", f.slope_top_from_v},
                  {"sigma_v_deg", f.sigma_v_deg}, {"sigma_v_per_wall_deg", f.sigma_v_per_wall_deg},
                  {"sigma_slope_near_deg", f.sigma_slope_near_deg}, {"sigma_slope_far_deg", f.sigma_slope_far_deg},
                  {"T_V_h", pose6_string(f.T_V_h)}, {"T_V_v", pose6_string(f.T_V_v)},
                  {"cfar_h", cfar_json(f.cfar_h)}, {"cfar_v", cfar_json(f.cfar_v)}}},
      {"dr",
       {{"initial_xy_m", {d.initial_xy_m.x(), d.initial_xy_m.y()}},
        {"max_speed_mps", d.max_speed_mps},
        {"hold_s", d.hold_s},
        {"attitude_filter_tau_s", d.attitude_filter_tau_s},
        {"attitude_filter_max_gap_s", d.attitude_filter_max_gap_s},
        {"use_gyro", d.use_gyro},
        {"T_V_gyro", pose6_string(d.gyro.T_V_gyro)},
        {"latitude_deg", d.gyro.latitude_deg},
        {"gyro_align_s", d.gyro.align_s},
        {"gyro_arw_deg_per_sqrt_h", d.gyro_arw_deg_per_sqrt_h},
        {"gyro_bias_dph", d.gyro_bias_dph},
        {"dvl_velocity_sigma_mps", d.dvl_velocity_sigma_mps},
        {"dvl_scale_sigma", d.dvl_scale_sigma},
        {"dvl_dropout_speed_sigma_mps", d.dvl_dropout_speed_sigma_mps}}},
      {"slam", {{"kf_distance_m", s.kf_distance_m}, {"kf_rotation_deg", s.kf_rotation_deg},
                {"keyframe_cloud_s", s.keyframe_cloud_s},
                {"keyframe_cloud_always", s.keyframe_cloud_always}, {"voxel_m", s.voxel_m}, {"outlier_radius_m", s.outlier_radius_m},
                {"outlier_min_neighbours", s.outlier_min_neighbours}, {"ssm_target_frames", s.ssm_target_frames},
                {"ssm_min_points", s.ssm_min_points}, {"ssm_max_translation_m", s.ssm_max_translation_m},
                {"ssm_max_rotation_deg", s.ssm_max_rotation_deg}, {"ssm_keep_dr_factor", s.ssm_keep_dr_factor},
                {"ssm_max_mahalanobis", s.ssm_max_mahalanobis}, {"ssm_min_information_ratio", s.ssm_min_information_ratio}, {"nssm_min_separation", s.nssm_min_separation},
                {"nssm_min_travel_m", s.nssm_min_travel_m},
                {"nssm_range_m", s.nssm_range_m}, {"nssm_min_points", s.nssm_min_points},
                {"nssm_max_rmse_m", s.nssm_max_rmse_m}, {"pcm_queue", s.pcm_queue},
                {"pcm_threshold", s.pcm_threshold}, {"min_pcm", s.min_pcm},
                {"sigma_prior", {s.sigma_prior.x(), s.sigma_prior.y(), s.sigma_prior.z()}},
                {"sigma_odometry", {s.sigma_odometry.x(), s.sigma_odometry.y(), s.sigma_odometry.z()}},
                {"gyro_heading_sigma_min_deg", s.gyro_heading_sigma_min_deg},
                {"sigma_icp", {s.sigma_icp.x(), s.sigma_icp.y(), s.sigma_icp.z()}},
                {"sigma_loop", {s.sigma_loop.x(), s.sigma_loop.y(), s.sigma_loop.z()}},
                {"sigma_loop_gyro", {s.sigma_loop_gyro.x(), s.sigma_loop_gyro.y(), s.sigma_loop_gyro.z()}},
                {"degeneracy_ratio", s.degeneracy_ratio},
                {"nssm_max_heading_diff_gyro_deg", s.nssm_max_heading_diff_gyro_deg},
                {"nssm_max_heading_sigmas", s.nssm_max_heading_sigmas}, {"nssm_max_mahalanobis", s.nssm_max_mahalanobis},
                {"nssm_fixed_heading_gyro", s.nssm_fixed_heading_gyro},
                {"nssm_target_same_pass", s.nssm_target_same_pass},
                {"nssm_source_frames", s.nssm_source_frames},
                {"nssm_max_view_change_deg", s.nssm_max_view_change_deg},
                {"nssm_other_side", slam::SlamConfig::other_side_name(s.nssm_other_side)},
                {"heading_drift_sigma_dps", s.heading_drift_sigma_dps},
                {"heading_drift_sigma_gyro_dps", s.heading_drift_sigma_gyro_dps},
                {"heading_drift_every_keyframes", s.heading_drift_every_keyframes},
                {"heading_link_s", s.heading_link_s},
                {"heading_link_walk_dps", s.heading_link_walk_dps},
                {"heading_link_white_deg", s.heading_link_white_deg},
                {"loop_loss", slam::loss_name(s.loop_loss)},
                {"loop_loss_scale", s.loop_loss_scale}, {"loop_correlation_m", s.loop_correlation_m},
                {"sigma_loop_per_m", s.sigma_loop_per_m},
                {"dr_sigma_model", slam::SlamConfig::dr_sigma_model_name(s.dr_sigma_model)},
                {"dr_translation_sigma_min_m", s.dr_translation_sigma_min_m},
                {"solver", {{"max_iterations", s.solver.max_iterations},
                            {"function_tolerance", s.solver.function_tolerance},
                            {"initial_trust_region_radius", s.solver.initial_trust_region_radius},
                            {"model_agreement_stop", s.solver.model_agreement_stop},
                            {"linear_solver", slam::linear_solver_name(s.solver.linear_solver)},
                            {"pcg_tolerance", s.solver.pcg_tolerance},
                            {"pcg_max_iterations", s.solver.pcg_max_iterations}}},
                {"fit_information", {{"max_correspondence_m", s.fit_information.max_correspondence_m},
                                     {"normal_radius_m", s.fit_information.normal_radius_m},
                                     {"line_ratio", s.fit_information.line_ratio}}},
                {"icp", {{"max_iterations", s.icp.max_iterations},
                         {"max_correspondence_m", s.icp.max_correspondence_m},
                         {"trim_fraction", s.icp.trim_fraction},
                         {"metric", slam::icp_metric_name(s.icp.metric)}}}}},
      {"mapping", {{"fusion_batch_pairs", c.pipeline.fusion_batch_pairs},
                   {"max_elevation_sigma_deg", c.pipeline.max_elevation_sigma_deg}, {"voxel_m", c.voxel_m},
                   {"octomap_resolution_m", c.octomap_resolution_m}}},
  };
}

}  // namespace orthosonar::run
