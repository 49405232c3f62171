#include "replay/run/run_config.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace orthosonar::run {
namespace {

// A table of (key -> how to read it, its valid range) per YAML map; anything else is an
// unknown key. Every value is checked against its range before it reaches a stage, and an
// error names the key (docs/CONFIG.md lists the ranges; `orthosonar config --ranges`).
using Reader = std::function<Status(const YAML::Node&, const std::string& where)>;
struct Entry;
using Table = std::map<std::string, Entry>;
struct Entry {
  Reader read;
  std::string range;                  // human-readable valid range ("" for a nested map)
  std::string bad;                    // one out-of-range YAML value (tests)
  std::function<Table()> children;    // nested map
};

std::string num(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

// A real number in [lo, hi] (lo_open / hi_open exclude the bound); never NaN or infinite.
Entry real(double& target, double lo, double hi, bool lo_open = false, bool hi_open = false) {
  Entry e;
  e.range = std::string(lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
  e.bad = lo_open ? num(lo) : num(lo - 1.0);
  e.read = [&target, lo, hi, lo_open, hi_open, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      return Error{"config: '" + where + "' must be a number in " + range};
    }
    const bool above = lo_open ? v > lo : v >= lo;
    const bool below = hi_open ? v < hi : v <= hi;
    if (!std::isfinite(v) || !above || !below)
      return Error{"config: '" + where + "' = " + num(v) + " is outside its valid range " + range};
    target = v;
    return {};
  };
  return e;
}

// An integer in [lo, hi] (stored in int or size_t); `odd` also requires an odd value.
template <class T>
Entry integer(T& target, int64_t lo, int64_t hi, bool odd = false) {
  Entry e;
  e.range = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" + (odd ? ", odd" : "");
  e.bad = std::to_string(lo - 1);
  e.read = [&target, lo, hi, odd, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    int64_t v = 0;
    try {
      v = n.as<int64_t>();
    } catch (const YAML::Exception&) {
      return Error{"config: '" + where + "' must be an " + range};
    }
    if (v < lo || v > hi || (odd && v % 2 == 0))
      return Error{"config: '" + where + "' = " + std::to_string(v) + " is outside its valid range: " + range};
    target = static_cast<T>(v);
    return {};
  };
  return e;
}

Entry boolean(bool& target) {
  Entry e;
  e.range = "true or false";
  e.bad = "maybe";
  e.read = [&target](const YAML::Node& n, const std::string& where) -> Status {
    try {
      target = n.as<bool>();
    } catch (const YAML::Exception&) {
      return Error{"config: '" + where + "' must be true or false"};
    }
    return {};
  };
  return e;
}

Entry choice(std::string range, std::function<bool(const std::string&)> set) {
  Entry e;
  e.range = "one of: " + range;
  e.bad = "none_of_these";
  e.read = [set, range](const YAML::Node& n, const std::string& where) -> Status {
    const auto text = n.IsScalar() ? n.Scalar() : std::string();
    if (!set(text)) return Error{"config: '" + where + "' must be one of " + range};
    return {};
  };
  return e;
}

// A pose "x y z roll pitch yaw": six finite numbers, |x|,|y|,|z| <= 100 m (a mount on the
// vehicle), angles in [-2 pi, 2 pi].
Entry pose(SE3& target) {
  Entry e;
  e.range = "\"x y z roll pitch yaw\": |x|,|y|,|z| <= 100 m, angles in [-6.2832, 6.2832] rad";
  e.bad = "\"0 0 0 0 0\"";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    std::istringstream s(n.IsScalar() ? n.Scalar() : std::string());
    double v[6];
    for (double& x : v)
      if (!(s >> x) || !std::isfinite(x)) return Error{"config: '" + where + "' must be " + range};
    std::string rest;
    if (s >> rest) return Error{"config: '" + where + "' has more than six numbers; must be " + range};
    for (int i = 0; i < 3; ++i)
      if (std::abs(v[i]) > 100.0) return Error{"config: '" + where + "' translation is outside " + range};
    for (int i = 3; i < 6; ++i)
      if (std::abs(v[i]) > 6.2832) return Error{"config: '" + where + "' angle is outside " + range};
    target = se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
    return {};
  };
  return e;
}

// A noise model "[sigma_x_m, sigma_y_m, sigma_theta_rad]", every entry in (0, 1000].
Entry sigma(Eigen::Vector3d& target) {
  Entry e;
  e.range = "[sigma_x_m, sigma_y_m, sigma_theta_rad], each in (0, 1000]";
  e.bad = "[0.1, 0, 0.01]";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    if (!n.IsSequence() || n.size() != 3) return Error{"config: '" + where + "' must be " + range};
    Eigen::Vector3d v;
    try {
      for (int i = 0; i < 3; ++i) v[i] = n[static_cast<size_t>(i)].as<double>();
    } catch (const YAML::Exception&) {
      return Error{"config: '" + where + "' must be " + range};
    }
    if (!v.allFinite() || !(v.array() > 0.0).all() || !(v.array() <= 1000.0).all())
      return Error{"config: '" + where + "' entries must each be in (0, 1000]"};
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
    if (!n.IsSequence() || n.size() != 2) return Error{"config: '" + where + "' must be " + range};
    Vec2 v;
    try {
      for (int i = 0; i < 2; ++i) v[i] = n[static_cast<size_t>(i)].as<double>();
    } catch (const YAML::Exception&) {
      return Error{"config: '" + where + "' must be " + range};
    }
    if (!v.allFinite() || !(v.array().abs() <= 1e7).all())
      return Error{"config: '" + where + "' entries must each be in [-1e7, 1e7]"};
    target = v;
    return {};
  };
  return e;
}

Status apply(const YAML::Node& node, const Table& table, const std::string& prefix) {
  if (!node.IsMap()) return Error{"config: '" + (prefix.empty() ? std::string("<root>") : prefix) + "' must be a map"};
  for (const auto& kv : node) {
    if (!kv.first.IsScalar())
      return Error{"config: a key in '" + (prefix.empty() ? std::string("<root>") : prefix) +
                   "' is not a plain name (a sequence, a map or '?' with no key)"};
    const std::string key = kv.first.as<std::string>();
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    const auto it = table.find(key);
    if (it == table.end()) return Error{"config: unknown key '" + where + "'"};
    if (Status s = it->second.read(kv.second, where); !s.ok()) return s;
  }
  return {};
}

Entry nested(std::function<Table()> make) {
  Entry e;
  e.children = make;
  e.read = [make](const YAML::Node& n, const std::string& where) { return apply(n, make(), where); };
  return e;
}

Table cfar_table(perception::CfarConfig& c) {
  return {{"train_cells", integer(c.train_cells, 1, 1000)},
          {"guard_cells", integer(c.guard_cells, 0, 1000)},
          {"pfa", real(c.pfa, 0.0, 1.0, true, true)},
          {"gate", real(c.gate, 0.0, 255.0)},
          {"min_neighbours", integer(c.min_neighbours, 0, 8)},
          {"method", choice("soca, ca, goca",
                            [&c](const std::string& s) {
                              if (s == "soca") c.method = perception::CfarMethod::kSoca;
                              else if (s == "ca") c.method = perception::CfarMethod::kCa;
                              else if (s == "goca") c.method = perception::CfarMethod::kGoca;
                              else return false;
                              return true;
                            })},
          {"window", choice("cross, range", [&c](const std::string& s) {
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
      {"threads", integer(c.threads, 1, kMaxThreads)},
      {"fusion", nested([&f] {
         return Table{{"max_pair_dt_s", real(f.max_pair_dt_s, 0.0, 10.0, true)},
                      {"overlap_deg", real(f.overlap_deg, 0.0, 90.0, true)},
                      {"patch", integer(f.patch, 1, 31, true)},
                      {"min_confidence", real(f.min_confidence, 0.0, 1.0)},
                      {"normalise_percentile", real(f.normalise_percentile, 0.0, 1.0, true)},
                      {"rotate_v_patch", boolean(f.rotate_v_patch)},
                      {"peak_window_deg", real(f.peak_window_deg, 0.0, 10.0)},
                      {"noise_floor_factor", real(f.noise_floor_factor, 0.0, 100.0)},
                      {"noise_floor_rows", integer(f.noise_floor_rows, 0, 1000)},
                      {"T_V_h", pose(f.T_V_h)},
                      {"T_V_v", pose(f.T_V_v)},
                      {"cfar_h", nested([&f] { return cfar_table(f.cfar_h); })},
                      {"cfar_v", nested([&f] { return cfar_table(f.cfar_v); })}};
       })},
      {"dr", nested([&d] {
         return Table{{"initial_xy_m", xy(d.initial_xy_m)},
                      {"max_speed_mps", real(d.max_speed_mps, 0.0, 100.0, true)},
                      {"hold_s", real(d.hold_s, 0.0, 3600.0)},
                      {"attitude_filter_tau_s", real(d.attitude_filter_tau_s, 0.0, 3600.0)},
                      {"attitude_filter_max_gap_s", real(d.attitude_filter_max_gap_s, 0.0, 3600.0, true)}};
       })},
      {"slam", nested([&s] {
         return Table{{"kf_distance_m", real(s.kf_distance_m, 0.0, 1000.0, true)},
                      {"kf_rotation_deg", real(s.kf_rotation_deg, 0.0, 360.0, true)},
                      {"voxel_m", real(s.voxel_m, 0.01, 100.0)},
                      {"outlier_radius_m", real(s.outlier_radius_m, 0.0, 100.0, true)},
                      {"outlier_min_neighbours", integer(s.outlier_min_neighbours, 0, 10000)},
                      {"ssm_target_frames", integer(s.ssm_target_frames, 1, 1000)},
                      {"ssm_min_points", integer(s.ssm_min_points, 1, 10000000)},
                      {"ssm_max_translation_m", real(s.ssm_max_translation_m, 0.0, 1000.0, true)},
                      {"ssm_max_rotation_deg", real(s.ssm_max_rotation_deg, 0.0, 180.0, true)},
                      {"ssm_keep_dr_factor", boolean(s.ssm_keep_dr_factor)},
                      {"ssm_max_mahalanobis", real(s.ssm_max_mahalanobis, 0.0, 1e6)},
                      {"nssm_min_separation", integer(s.nssm_min_separation, 1, 1000000)},
                      {"nssm_min_travel_m", real(s.nssm_min_travel_m, 0.0, 1e6)},
                      {"nssm_range_m", real(s.nssm_range_m, 0.0, 1000.0, true)},
                      {"nssm_min_points", integer(s.nssm_min_points, 1, 10000000)},
                      {"nssm_max_rmse_m", real(s.nssm_max_rmse_m, 0.0, 100.0, true)},
                      {"pcm_queue", integer(s.pcm_queue, 1, 1000)},
                      {"pcm_threshold", real(s.pcm_threshold, 0.0, 1e6, true)},
                      {"min_pcm", integer(s.min_pcm, 0, 1000)},
                      {"sigma_prior", sigma(s.sigma_prior)},
                      {"sigma_odometry", sigma(s.sigma_odometry)},
                      {"sigma_icp", sigma(s.sigma_icp)},
                      {"sigma_loop", sigma(s.sigma_loop)},
                      {"degeneracy_ratio", real(s.degeneracy_ratio, 0.0, 1.0)},
                      {"nssm_max_mahalanobis", real(s.nssm_max_mahalanobis, 0.0, 1e12)},
                      {"heading_drift_sigma_dps", real(s.heading_drift_sigma_dps, 0.0, 10.0)},
                      {"heading_drift_every_keyframes", integer(s.heading_drift_every_keyframes, 0, 1000000)},
                      {"heading_link_s", real(s.heading_link_s, 0.0, 1e6)},
                      {"heading_link_walk_dps", real(s.heading_link_walk_dps, 0.0, 10.0, true)},
                      {"heading_link_white_deg", real(s.heading_link_white_deg, 0.0, 10.0)},
                      {"loop_loss", choice("none, huber, cauchy",
                                           [&s](const std::string& v) {
                                             for (slam::GraphEdge::Loss l : slam::kLosses)
                                               if (v == slam::loss_name(l)) {
                                                 s.loop_loss = l;
                                                 return true;
                                               }
                                             return false;
                                           })},
                      {"loop_loss_scale", real(s.loop_loss_scale, 0.0, 1000.0, true)},
                      {"solver", nested([&s] {
                         auto& g = s.solver;
                         return Table{{"max_iterations", integer(g.max_iterations, 1, 10000)},
                                      {"function_tolerance", real(g.function_tolerance, 0.0, 1.0)},
                                      {"initial_trust_region_radius", real(g.initial_trust_region_radius, 0.0, 1e16, true)},
                                      {"model_agreement_stop", real(g.model_agreement_stop, 0.0, 1.0)}};
                       })},
                      {"fit_information", nested([&s] {
                         auto& f = s.fit_information;
                         return Table{{"max_correspondence_m", real(f.max_correspondence_m, 0.0, 100.0, true)},
                                      {"normal_radius_m", real(f.normal_radius_m, 0.0, 100.0, true)},
                                      {"line_ratio", real(f.line_ratio, 0.0, 1.0)}};
                       })},
                      {"icp", nested([&s] {
                         return Table{{"max_iterations", integer(s.icp.max_iterations, 1, 10000)},
                                      {"max_correspondence_m", real(s.icp.max_correspondence_m, 0.0, 1000.0, true)},
                                      {"trim_fraction", real(s.icp.trim_fraction, 0.0, 1.0, true)}};
                       })}};
       })},
      {"mapping", nested([&c] {
         return Table{{"fusion_batch_pairs", integer(c.pipeline.fusion_batch_pairs, 1, 4096)},
                      {"voxel_m", real(c.voxel_m, 0.01, 100.0)},
                      {"octomap_resolution_m", real(c.octomap_resolution_m, 0.01, 100.0)}};
       })},
  };
}

void list_ranges(const Table& t, const std::string& prefix, std::vector<ConfigKeyRange>& out) {
  for (const auto& [key, e] : t) {
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    if (e.children) list_ranges(e.children(), where, out);
    else out.push_back({where, e.range, e.bad});
  }
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
  try {
    if (Status s = apply(root, root_table(trial), ""); !s.ok()) return s;
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
  list_ranges(root_table(scratch), "", out);
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
                  {"T_V_h", pose6_string(f.T_V_h)}, {"T_V_v", pose6_string(f.T_V_v)},
                  {"cfar_h", cfar_json(f.cfar_h)}, {"cfar_v", cfar_json(f.cfar_v)}}},
      {"dr",
       {{"initial_xy_m", {d.initial_xy_m.x(), d.initial_xy_m.y()}},
        {"max_speed_mps", d.max_speed_mps},
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
                {"degeneracy_ratio", s.degeneracy_ratio},
                {"nssm_max_mahalanobis", s.nssm_max_mahalanobis},
                {"heading_drift_sigma_dps", s.heading_drift_sigma_dps},
                {"heading_drift_every_keyframes", s.heading_drift_every_keyframes},
                {"heading_link_s", s.heading_link_s},
                {"heading_link_walk_dps", s.heading_link_walk_dps},
                {"heading_link_white_deg", s.heading_link_white_deg},
                {"loop_loss", slam::loss_name(s.loop_loss)},
                {"loop_loss_scale", s.loop_loss_scale},
                {"solver", {{"max_iterations", s.solver.max_iterations},
                            {"function_tolerance", s.solver.function_tolerance},
                            {"initial_trust_region_radius", s.solver.initial_trust_region_radius},
                            {"model_agreement_stop", s.solver.model_agreement_stop}}},
                {"fit_information", {{"max_correspondence_m", s.fit_information.max_correspondence_m},
                                     {"normal_radius_m", s.fit_information.normal_radius_m},
                                     {"line_ratio", s.fit_information.line_ratio}}},
                {"icp", {{"max_iterations", s.icp.max_iterations},
                         {"max_correspondence_m", s.icp.max_correspondence_m},
                         {"trim_fraction", s.icp.trim_fraction}}}}},
      {"mapping", {{"fusion_batch_pairs", c.pipeline.fusion_batch_pairs}, {"voxel_m", c.voxel_m},
                   {"octomap_resolution_m", c.octomap_resolution_m}}},
  };
}

}  // namespace orthosonar::run
