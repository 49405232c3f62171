#include "tools/support_config.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace orthosonar::cli {
namespace {

// A table of (key -> how to read it) per YAML map; anything else is an unknown key.
using Reader = std::function<Status(const YAML::Node&, const std::string& where)>;
using Table = std::map<std::string, Reader>;

template <class T>
Reader field(T& target) {
  return [&target](const YAML::Node& n, const std::string& where) -> Status {
    try {
      target = n.as<T>();
    } catch (const YAML::Exception& e) {
      return Error{"config: bad value for '" + where + "': " + e.what()};
    }
    return {};
  };
}

Reader pose_field(SE3& target) {
  return [&target](const YAML::Node& n, const std::string& where) -> Status {
    std::istringstream s(n.as<std::string>(""));
    double v[6];
    for (double& x : v)
      if (!(s >> x)) return Error{"config: '" + where + "' must be \"x y z roll pitch yaw\""};
    target = se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
    return {};
  };
}

// A noise model "[sigma_x_m, sigma_y_m, sigma_theta_rad]", every entry > 0.
Reader sigma_field(Eigen::Vector3d& target) {
  return [&target](const YAML::Node& n, const std::string& where) -> Status {
    if (!n.IsSequence() || n.size() != 3) return Error{"config: '" + where + "' must be [sigma_x_m, sigma_y_m, sigma_theta_rad]"};
    Eigen::Vector3d v;
    try {
      for (int i = 0; i < 3; ++i) v[i] = n[static_cast<size_t>(i)].as<double>();
    } catch (const YAML::Exception& e) {
      return Error{"config: bad value for '" + where + "': " + e.what()};
    }
    if (!(v.array() > 0.0).all() || !v.allFinite()) return Error{"config: '" + where + "' entries must be finite and > 0"};
    target = v;
    return {};
  };
}

Status apply(const YAML::Node& node, const Table& table, const std::string& prefix) {
  if (!node.IsMap()) return Error{"config: '" + (prefix.empty() ? std::string("<root>") : prefix) + "' must be a map"};
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    const auto it = table.find(key);
    if (it == table.end()) return Error{"config: unknown key '" + where + "'"};
    if (Status s = it->second(kv.second, where); !s.ok()) return s;
  }
  return {};
}

Reader nested(std::function<Table()> make) {
  return [make](const YAML::Node& n, const std::string& where) { return apply(n, make(), where); };
}

Table cfar_table(perception::CfarConfig& c) {
  return {{"train_cells", field(c.train_cells)},
          {"guard_cells", field(c.guard_cells)},
          {"pfa", field(c.pfa)},
          {"gate", field(c.gate)},
          {"min_neighbours", field(c.min_neighbours)},
          {"method", [&c](const YAML::Node& n, const std::string& w) -> Status {
             const auto s = n.as<std::string>("");
             if (s == "soca") c.method = perception::CfarMethod::kSoca;
             else if (s == "ca") c.method = perception::CfarMethod::kCa;
             else if (s == "goca") c.method = perception::CfarMethod::kGoca;
             else return Error{"config: '" + w + "' must be soca, ca or goca"};
             return {};
           }},
          {"window", [&c](const YAML::Node& n, const std::string& w) -> Status {
             const auto s = n.as<std::string>("");
             if (s == "cross") c.window = perception::CfarWindow::kCross;
             else if (s == "range") c.window = perception::CfarWindow::kRange;
             else return Error{"config: '" + w + "' must be cross or range"};
             return {};
           }}};
}

Table root_table(RunConfig& c) {
  auto& f = c.pipeline.fusion;
  auto& d = c.pipeline.dr;
  auto& s = c.pipeline.slam;
  return {
      {"threads", field(c.threads)},
      {"fusion", nested([&f] {
         return Table{{"max_pair_dt_s", field(f.max_pair_dt_s)},
                      {"overlap_deg", field(f.overlap_deg)},
                      {"patch", field(f.patch)},
                      {"min_confidence", field(f.min_confidence)},
                      {"normalise_percentile", field(f.normalise_percentile)},
                      {"rotate_v_patch", field(f.rotate_v_patch)},
                      {"T_V_h", pose_field(f.T_V_h)},
                      {"T_V_v", pose_field(f.T_V_v)},
                      {"cfar_h", nested([&f] { return cfar_table(f.cfar_h); })},
                      {"cfar_v", nested([&f] { return cfar_table(f.cfar_v); })}};
       })},
      {"dr", nested([&d] {
         return Table{{"max_speed_mps", field(d.max_speed_mps)},
                      {"hold_s", field(d.hold_s)},
                      {"attitude_filter_tau_s", field(d.attitude_filter_tau_s)},
                      {"attitude_filter_max_gap_s", field(d.attitude_filter_max_gap_s)}};
       })},
      {"slam", nested([&s] {
         return Table{{"kf_distance_m", field(s.kf_distance_m)},
                      {"kf_rotation_deg", field(s.kf_rotation_deg)},
                      {"voxel_m", field(s.voxel_m)},
                      {"outlier_radius_m", field(s.outlier_radius_m)},
                      {"outlier_min_neighbours", field(s.outlier_min_neighbours)},
                      {"ssm_target_frames", field(s.ssm_target_frames)},
                      {"ssm_min_points", field(s.ssm_min_points)},
                      {"ssm_max_translation_m", field(s.ssm_max_translation_m)},
                      {"ssm_max_rotation_deg", field(s.ssm_max_rotation_deg)},
                      {"ssm_keep_dr_factor", field(s.ssm_keep_dr_factor)},
                      {"ssm_max_mahalanobis", field(s.ssm_max_mahalanobis)},
                      {"nssm_min_separation", field(s.nssm_min_separation)},
                      {"nssm_min_travel_m", field(s.nssm_min_travel_m)},
                      {"nssm_range_m", field(s.nssm_range_m)},
                      {"nssm_min_points", field(s.nssm_min_points)},
                      {"nssm_max_rmse_m", field(s.nssm_max_rmse_m)},
                      {"pcm_queue", field(s.pcm_queue)},
                      {"pcm_threshold", field(s.pcm_threshold)},
                      {"min_pcm", field(s.min_pcm)},
                      {"sigma_prior", sigma_field(s.sigma_prior)},
                      {"sigma_odometry", sigma_field(s.sigma_odometry)},
                      {"sigma_icp", sigma_field(s.sigma_icp)},
                      {"sigma_loop", sigma_field(s.sigma_loop)},
                      {"icp", nested([&s] {
                         return Table{{"max_iterations", field(s.icp.max_iterations)},
                                      {"max_correspondence_m", field(s.icp.max_correspondence_m)},
                                      {"trim_fraction", field(s.icp.trim_fraction)}};
                       })}};
       })},
      {"mapping", nested([&c] {
         return Table{{"fusion_batch_pairs", field(c.pipeline.fusion_batch_pairs)},
                      {"voxel_m", field(c.voxel_m)},
                      {"octomap_resolution_m", field(c.octomap_resolution_m)}};
       })},
  };
}

nlohmann::json cfar_json(const perception::CfarConfig& c) {
  return {{"method", perception::to_string(c.method)}, {"window", perception::to_string(c.window)},
          {"train_cells", c.train_cells}, {"guard_cells", c.guard_cells}, {"pfa", c.pfa}, {"gate", c.gate},
          {"min_neighbours", c.min_neighbours}};
}

}  // namespace

std::string pose6_string(const SE3& T) {
  const Vec3 rpy = rpy_from_rotation(T.linear());
  std::ostringstream s;
  s.precision(17);
  s << T.translation().x() << " " << T.translation().y() << " " << T.translation().z() << " " << rpy.x()
    << " " << rpy.y() << " " << rpy.z();
  return s.str();
}

Status apply_config_yaml(const std::string& yaml_text, RunConfig& config) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Error{std::string("config: YAML parse error: ") + e.what()};
  }
  if (root.IsNull()) return {};
  RunConfig trial = config;
  if (Status s = apply(root, root_table(trial), ""); !s.ok()) return s;
  if (trial.threads < 1) return Error{"config: 'threads' must be >= 1"};
  if (!(trial.voxel_m > 0.0)) return Error{"config: 'mapping.voxel_m' must be > 0"};
  const slam::DrConfig& dr = trial.pipeline.dr;  // NaN fails the comparisons, +inf isfinite
  if (!(dr.attitude_filter_tau_s >= 0.0) || !std::isfinite(dr.attitude_filter_tau_s))
    return Error{"config: 'dr.attitude_filter_tau_s' must be finite and >= 0 (0 = off)"};
  if (!(dr.attitude_filter_max_gap_s > 0.0) || !std::isfinite(dr.attitude_filter_max_gap_s))
    return Error{"config: 'dr.attitude_filter_max_gap_s' must be finite and > 0"};
  config = trial;
  return {};
}

Status load_config_file(const std::string& path, RunConfig& config) {
  std::ifstream f(path);
  if (!f) return Error{"cannot open config '" + path + "'"};
  std::stringstream ss;
  ss << f.rdbuf();
  Status s = apply_config_yaml(ss.str(), config);
  if (!s.ok()) return Error{path + ": " + s.error().message};
  return s;
}

nlohmann::json config_to_json(const RunConfig& c) {
  const auto& f = c.pipeline.fusion;
  const auto& d = c.pipeline.dr;
  const auto& s = c.pipeline.slam;
  return {
      {"threads", c.threads},
      {"fusion", {{"max_pair_dt_s", f.max_pair_dt_s}, {"overlap_deg", f.overlap_deg}, {"patch", f.patch},
                  {"min_confidence", f.min_confidence}, {"normalise_percentile", f.normalise_percentile},
                  {"rotate_v_patch", f.rotate_v_patch},
                  {"T_V_h", pose6_string(f.T_V_h)}, {"T_V_v", pose6_string(f.T_V_v)},
                  {"cfar_h", cfar_json(f.cfar_h)}, {"cfar_v", cfar_json(f.cfar_v)}}},
      {"dr",
       {{"max_speed_mps", d.max_speed_mps},
        {"hold_s", d.hold_s},
        {"attitude_filter_tau_s", d.attitude_filter_tau_s},
        {"attitude_filter_max_gap_s", d.attitude_filter_max_gap_s}}},
      {"slam", {{"kf_distance_m", s.kf_distance_m}, {"kf_rotation_deg", s.kf_rotation_deg},
                {"voxel_m", s.voxel_m}, {"outlier_radius_m", s.outlier_radius_m},
                {"outlier_min_neighbours", s.outlier_min_neighbours}, {"ssm_target_frames", s.ssm_target_frames},
                {"ssm_min_points", s.ssm_min_points}, {"ssm_max_translation_m", s.ssm_max_translation_m},
                {"ssm_max_rotation_deg", s.ssm_max_rotation_deg}, {"ssm_keep_dr_factor", s.ssm_keep_dr_factor},
                {"ssm_max_mahalanobis", s.ssm_max_mahalanobis}, {"nssm_min_separation", s.nssm_min_separation},
                {"nssm_min_travel_m", s.nssm_min_travel_m},
                {"nssm_range_m", s.nssm_range_m}, {"nssm_min_points", s.nssm_min_points},
                {"nssm_max_rmse_m", s.nssm_max_rmse_m}, {"pcm_queue", s.pcm_queue},
                {"pcm_threshold", s.pcm_threshold}, {"min_pcm", s.min_pcm},
                {"sigma_prior", {s.sigma_prior.x(), s.sigma_prior.y(), s.sigma_prior.z()}},
                {"sigma_odometry", {s.sigma_odometry.x(), s.sigma_odometry.y(), s.sigma_odometry.z()}},
                {"sigma_icp", {s.sigma_icp.x(), s.sigma_icp.y(), s.sigma_icp.z()}},
                {"sigma_loop", {s.sigma_loop.x(), s.sigma_loop.y(), s.sigma_loop.z()}},
                {"icp", {{"max_iterations", s.icp.max_iterations},
                         {"max_correspondence_m", s.icp.max_correspondence_m},
                         {"trim_fraction", s.icp.trim_fraction}}}}},
      {"mapping", {{"fusion_batch_pairs", c.pipeline.fusion_batch_pairs}, {"voxel_m", c.voxel_m},
                   {"octomap_resolution_m", c.octomap_resolution_m}}},
  };
}

}  // namespace orthosonar::cli
