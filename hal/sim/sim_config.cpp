#include "hal/sim/sim_config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace orthosonar::sim {

const char* resolution_name(Resolution r) { return r == Resolution::kFull ? "full" : "reduced"; }

Result<Resolution> parse_resolution(const std::string& s) {
  if (s == "full") return Resolution::kFull;
  if (s == "reduced") return Resolution::kReduced;
  return Error{"resolution '" + s + "' is neither 'full' nor 'reduced'"};
}

SonarGeometry sonar_geometry(const SonarHead& h, Resolution r) {
  SonarGeometry g;
  const int div = r == Resolution::kFull ? 1 : 2;
  g.beams = h.beams_full / div;
  g.range_bins = h.range_bins_full / div;
  g.range_resolution_m = h.max_range_m / g.range_bins;
  return g;
}

// Oculus data sheets: M750d 750 kHz 130 x 20 deg, 1.0 deg angular resolution, 512 beams,
// 120 m; M1200d 1.2 MHz 130 x 20 deg, 0.6 deg, 512 beams, 30 m; 2.1 MHz 60 x 12 deg,
// 0.4 deg, 512 beams, 10 m; up to 40 pings/s. The image keeps 600 range bins.
SonarHead oculus_m750d_750khz() { return SonarHead{750e3, 130.0, 20.0, 1.0, 512, 600, 30.0, -1.0, 40.0}; }
SonarHead oculus_m1200d_1200khz() { return SonarHead{1.2e6, 130.0, 20.0, 0.6, 512, 600, 30.0, -1.0, 40.0}; }
SonarHead oculus_m1200d_2100khz() { return SonarHead{2.1e6, 60.0, 12.0, 0.4, 512, 600, 10.0, -1.0, 40.0}; }

const char* profile_name(SonarProfile p) { return p == SonarProfile::kField ? "field" : "clean"; }

Result<SonarProfile> parse_profile(const std::string& s) {
  if (s == "field") return SonarProfile::kField;
  if (s == "clean") return SonarProfile::kClean;
  return Error{"profile '" + s + "' is neither 'field' nor 'clean'"};
}

void apply_profile(SonarModelConfig& c, SonarProfile p) {
  const SonarModelConfig field;  // the struct's defaults are the field profile
  const bool f = p == SonarProfile::kField;
  c.noise_floor = f ? field.noise_floor : 0.0003;
  c.gain = field.gain;
  c.beam_pattern = f;
  c.surface_reflection = f ? field.surface_reflection : 0.0;
  c.seabed_reflection = f ? field.seabed_reflection : 0.0;
  c.seabed_lambert = f;
  c.absorption_scale = f ? field.absorption_scale : 0.0;
  c.tvg_absorption_fraction = f ? field.tvg_absorption_fraction : 0.0;
  c.noise_before_tvg = f;
}

double absorption_db_per_m(double f_hz, double T, double S, double pH, double depth_m) {
  // Ainslie & McColm (1998), J. Acoust. Soc. Am. 103(3): boric acid, magnesium sulphate and
  // pure water terms, dB/km with f in kHz and depth in km.
  const double f = f_hz / 1000.0, z = depth_m / 1000.0, f2 = f * f;
  const double f1 = 0.78 * std::sqrt(S / 35.0) * std::exp(T / 26.0);
  const double fm = 42.0 * std::exp(T / 17.0);
  const double boric = 0.106 * f1 * f2 / (f1 * f1 + f2) * std::exp((pH - 8.0) / 0.56);
  const double mgso4 = 0.52 * (1.0 + T / 43.0) * (S / 35.0) * fm * f2 / (fm * fm + f2) * std::exp(-z / 6.0);
  const double water = 0.00049 * f2 * std::exp(-(T / 27.0 + z / 17.0));
  return (boric + mgso4 + water) / 1000.0;
}

double head_absorption_db_per_m(const SonarModelConfig& c, const SonarHead& h) {
  const double a = h.absorption_db_per_m >= 0.0
                       ? h.absorption_db_per_m
                       : absorption_db_per_m(h.frequency_hz, c.water_temperature_c, c.salinity_ppt, c.water_ph, 0.0);
  return a * c.absorption_scale;
}

namespace {

// One settable field: a name and a setter from a YAML scalar.
using Setter = std::function<void(const YAML::Node&)>;
template <class T>
Setter set(T& field) {
  return [&field](const YAML::Node& n) { field = n.as<T>(); };
}

std::map<std::string, Setter> head_fields(SonarHead& h) {
  return {{"frequency_hz", set(h.frequency_hz)}, {"swath_deg", set(h.swath_deg)},
          {"aperture_deg", set(h.aperture_deg)}, {"beam_width_deg", set(h.beam_width_deg)},
          {"beams_full", set(h.beams_full)}, {"range_bins_full", set(h.range_bins_full)},
          {"max_range_m", set(h.max_range_m)}, {"absorption_db_per_m", set(h.absorption_db_per_m)},
          {"max_ping_rate_hz", set(h.max_ping_rate_hz)}};
}

// Fields of both heads at once (`sonar: {max_range_m: 20}` sets both).
template <class T>
Setter set_both(T SonarHead::*field, SonarModelConfig& s) {
  return [field, &s](const YAML::Node& n) { s.head_h.*field = s.head_v.*field = n.as<T>(); };
}

std::map<std::string, Setter> sonar_fields(SonarModelConfig& s) {
  return {{"max_range_m", set_both(&SonarHead::max_range_m, s)}, {"beams_full", set_both(&SonarHead::beams_full, s)},
          {"range_bins_full", set_both(&SonarHead::range_bins_full, s)}, {"swath_deg", set_both(&SonarHead::swath_deg, s)},
          {"aperture_deg", set_both(&SonarHead::aperture_deg, s)}, {"bearing_cubic", set(s.bearing_cubic)},
          {"elevation_samples", set(s.elevation_samples)}, {"beam_samples", set(s.beam_samples)},
          {"beam_width_factor", set(s.beam_width_factor)},
          {"aperture_sigma_deg", set(s.aperture_sigma_deg)},
          {"incidence_exponent", set(s.incidence_exponent)},
          {"spreading_exponent", set(s.spreading_exponent)},
          {"speckle_looks", set(s.speckle_looks)}, {"noise_floor", set(s.noise_floor)},
          {"tvg_exponent", set(s.tvg_exponent)}, {"tvg_reference_m", set(s.tvg_reference_m)},
          {"gain", set(s.gain)}, {"gamma", set(s.gamma)}, {"gain_percent", set(s.gain_percent)},
          {"frequency_h_hz", set(s.head_h.frequency_hz)}, {"frequency_v_hz", set(s.head_v.frequency_hz)},
          {"beam_pattern", set(s.beam_pattern)}, {"side_lobe_db", set(s.side_lobe_db)},
          {"side_lobe_floor_db", set(s.side_lobe_floor_db)},
          {"surface_reflection", set(s.surface_reflection)}, {"seabed_reflection", set(s.seabed_reflection)},
          {"seabed_lambert", set(s.seabed_lambert)}, {"seabed_mu", set(s.seabed_mu)},
          {"seabed_texture", set(s.seabed_texture)}, {"seabed_texture_scale_m", set(s.seabed_texture_scale_m)},
          {"seabed_relief_deg", set(s.seabed_relief_deg)}, {"seabed_relief_scale_m", set(s.seabed_relief_scale_m)},
          {"absorption_scale", set(s.absorption_scale)},
          {"tvg_absorption_fraction", set(s.tvg_absorption_fraction)},
          {"noise_before_tvg", set(s.noise_before_tvg)}, {"water_temperature_c", set(s.water_temperature_c)},
          {"salinity_ppt", set(s.salinity_ppt)}, {"water_ph", set(s.water_ph)},
          {"vertical_mode", [](const YAML::Node&) {}},  // applied before the other keys
          {"horizontal", [](const YAML::Node&) {}}, {"vertical", [](const YAML::Node&) {}},
          {"reflectivity", [&s](const YAML::Node& n) {
             for (const auto& kv : n) {
               bool known = false;
               for (int c = 0; c < kSemanticClassCount; ++c) {
                 if (kv.first.as<std::string>() == semantic_class_name(static_cast<SemanticClass>(c))) {
                   s.reflectivity[static_cast<size_t>(c)] = kv.second.as<double>();
                   known = true;
                 }
               }
               if (!known) throw YAML::Exception(YAML::Mark::null_mark(), "unknown class '" + kv.first.as<std::string>() + "'");
             }
           }}};
}

std::map<std::string, Setter> vehicle_fields(VehicleConfig& v) {
  return {{"speed_mps", set(v.speed_mps)}, {"max_yaw_rate_dps", set(v.max_yaw_rate_dps)},
          {"yaw_gain_per_s", set(v.yaw_gain_per_s)},
          {"acceptance_radius_m", set(v.acceptance_radius_m)},
          {"slow_turn_factor", set(v.slow_turn_factor)},
          {"roll_amplitude_deg", set(v.roll_amplitude_deg)},
          {"pitch_amplitude_deg", set(v.pitch_amplitude_deg)},
          {"roll_period_s", set(v.roll_period_s)}, {"pitch_period_s", set(v.pitch_period_s)},
          {"current_x_mps", set(v.current_x_mps)}, {"current_y_mps", set(v.current_y_mps)},
          {"step_s", set(v.step_s)}};
}

std::map<std::string, Setter> nav_fields(NavConfig& n) {
  return {{"imu_rate_hz", set(n.imu_rate_hz)}, {"dvl_rate_hz", set(n.dvl_rate_hz)},
          {"depth_rate_hz", set(n.depth_rate_hz)}, {"ping_rate_hz", set(n.ping_rate_hz)},
          {"ping_offset_s", set(n.ping_offset_s)}, {"vertical_delay_s", set(n.vertical_delay_s)},
          {"dvl_offset_s", set(n.dvl_offset_s)}, {"depth_offset_s", set(n.depth_offset_s)},
          {"dvl_sigma_mps", set(n.dvl_sigma_mps)},
          {"dvl_invalid_probability", set(n.dvl_invalid_probability)},
          {"dvl_max_altitude_m", set(n.dvl_max_altitude_m)},
          {"imu_roll_pitch_sigma_deg", set(n.imu_roll_pitch_sigma_deg)},
          {"imu_yaw_sigma_deg", set(n.imu_yaw_sigma_deg)},
          {"imu_yaw_bias_walk_deg_per_sqrt_s", set(n.imu_yaw_bias_walk_deg_per_sqrt_s)},
          {"imu_yaw_bias_rate_dps", set(n.imu_yaw_bias_rate_dps)},
          {"imu_gyro_sigma_dps", set(n.imu_gyro_sigma_dps)},
          {"imu_gyro_bias_dps", set(n.imu_gyro_bias_dps)},
          {"depth_sigma_m", set(n.depth_sigma_m)}};
}

Status apply_fields(const YAML::Node& node, const std::map<std::string, Setter>& fields,
                    const std::string& where) {
  if (!node.IsMap()) return Error{"sim config: '" + where + "' must be a map"};
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) return Error{"sim config: a key in '" + where + "' is not a plain name"};
    const auto key = kv.first.as<std::string>();
    const auto it = fields.find(key);
    if (it == fields.end()) return Error{"sim config: unknown key '" + where + key + "'"};
    try {
      it->second(kv.second);
    } catch (const YAML::Exception& e) {
      return Error{"sim config: bad value for '" + where + key + "': " + e.what()};
    }
  }
  return Status::Ok();
}

}  // namespace

Status load_sim_config_file(const std::string& path, SimConfig& config) {
  std::ifstream in(path);
  if (!in) return Error{"cannot read simulator config '" + path + "'"};
  std::stringstream text;
  text << in.rdbuf();
  if (Status s = apply_sim_config_yaml(text.str(), config); !s.ok()) return Error{path + ": " + s.error().message};
  return {};
}

static Status apply_document(const std::string& yaml_text, SimConfig& c) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
  if (root.IsNull()) return Status::Ok();
  std::string resolution, profile;
  std::string T_V_h, T_V_v;
  std::map<std::string, Setter> top = {
      {"duration_s", set(c.duration_s)}, {"seed", set(c.seed)}, {"labels", set(c.labels)},
      {"resolution", set(resolution)}, {"profile", set(profile)}, {"T_V_h", set(T_V_h)}, {"T_V_v", set(T_V_v)},
      {"device_id_h", set(c.device_id_h)}, {"device_id_v", set(c.device_id_v)},
      {"render_threads", set(c.render_threads)},
      {"sonar", [](const YAML::Node&) {}}, {"vehicle", [](const YAML::Node&) {}},
      {"nav", [](const YAML::Node&) {}}};
  if (auto s = apply_fields(root, top, ""); !s) return s;
  if (!profile.empty()) {  // first: the keys below refine the profile
    auto p = parse_profile(profile);
    if (!p) return Error{"sim config: " + p.error().message};
    c.profile = *p;
    apply_profile(c.sonar, c.profile);
  }
  if (root["sonar"]) {
    const YAML::Node sonar = root["sonar"];
    if (sonar.IsMap() && sonar["vertical_mode"]) {
      std::string mode;
      try {
        mode = sonar["vertical_mode"].as<std::string>();
      } catch (const YAML::Exception&) {
        return Error{"sim config: 'sonar.vertical_mode' must be 1.2MHz or 2.1MHz"};
      }
      if (mode == "1.2MHz") {
        c.sonar.head_v = oculus_m1200d_1200khz();
      } else if (mode == "2.1MHz") {
        c.sonar.head_v = oculus_m1200d_2100khz();
      } else {
        return Error{"sim config: 'sonar.vertical_mode' is '" + mode + "', expected 1.2MHz or 2.1MHz"};
      }
    }
    if (auto s = apply_fields(sonar, sonar_fields(c.sonar), "sonar."); !s) return s;
    for (auto [key, head] : {std::pair{"horizontal", &c.sonar.head_h}, std::pair{"vertical", &c.sonar.head_v}}) {
      if (!sonar[key]) continue;
      if (auto s = apply_fields(sonar[key], head_fields(*head), std::string("sonar.") + key + "."); !s) return s;
    }
  }
  if (root["vehicle"]) {
    if (auto s = apply_fields(root["vehicle"], vehicle_fields(c.vehicle), "vehicle."); !s) return s;
  }
  if (root["nav"]) {
    if (auto s = apply_fields(root["nav"], nav_fields(c.nav), "nav."); !s) return s;
  }
  if (!resolution.empty()) {
    auto r = parse_resolution(resolution);
    if (!r) return r.error();
    c.resolution = *r;
  }
  for (auto [text, T] : {std::pair{&T_V_h, &c.T_V_h}, std::pair{&T_V_v, &c.T_V_v}}) {
    if (text->empty()) continue;
    auto p = parse_pose6(*text);
    if (!p) return p.error();
    *T = *p;
  }
  return validate(c);
}

Status apply_sim_config_yaml(const std::string& yaml_text, SimConfig& c) {
  // Every setter checks its node; this is the net under them (found by fuzz_sim_config: a
  // '? :' key threw yaml-cpp's TypedBadConversion through the API).
  try {
    return apply_document(yaml_text, c);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
}

Status validate(const SimConfig& c) {
  const auto& s = c.sonar;
  if (!(c.duration_s > 0)) return Error{"sim config: duration_s must be > 0"};
  if (s.elevation_samples < 32) return Error{"sim config: sonar.elevation_samples must be >= 32"};
  if (s.beam_samples < 1) return Error{"sim config: sonar.beam_samples must be >= 1"};
  for (const SonarHead* h : {&s.head_h, &s.head_v}) {
    const char* which = h == &s.head_h ? "sonar.horizontal" : "sonar.vertical";
    if (h->beams_full < 4 || h->beams_full % 2 != 0 || h->range_bins_full < 4 || h->range_bins_full % 2 != 0 ||
        h->beams_full > 4096 || h->range_bins_full > 8192)
      return Error{std::string("sim config: ") + which + ": beams_full and range_bins_full must be even, >= 4 (<= 4096, 8192)"};
    if (!(h->max_range_m > 0 && h->max_range_m <= 500 && h->swath_deg > 0 && h->swath_deg < 180 &&
          h->aperture_deg > 0 && h->aperture_deg < 90 && h->frequency_hz > 1e3 && h->frequency_hz < 1e7 &&
          h->beam_width_deg >= 0 && h->beam_width_deg < 30 && h->absorption_db_per_m < 100 && h->max_ping_rate_hz > 0))
      return Error{std::string("sim config: ") + which +
                   ": max_range_m in (0, 500], swath_deg in (0, 180), aperture_deg in (0, 90), frequency_hz in (1e3, 1e7), "
                   "beam_width_deg in [0, 30), absorption_db_per_m < 100, max_ping_rate_hz > 0"};
    // Two-way travel time: a ping to max range at 1500 m/s must finish before the next.
    const double ceiling = std::min(h->max_ping_rate_hz, 1500.0 / (2.0 * h->max_range_m));
    if (c.nav.ping_rate_hz > ceiling * (1.0 + 1e-9))
      return Error{std::string("sim config: nav.ping_rate_hz exceeds ") + which + "'s ceiling (" +
                   std::to_string(ceiling) + " Hz at its max_range_m)"};
  }
  if (s.speckle_looks < 1 || s.speckle_looks > 16) return Error{"sim config: sonar.speckle_looks in 1..16"};
  if (!(s.gamma > 0 && s.gain > 0)) return Error{"sim config: sonar gamma, gain must be > 0"};
  if (!(s.side_lobe_db < 0 && s.side_lobe_floor_db < s.side_lobe_db && s.side_lobe_floor_db >= -120))
    return Error{"sim config: sonar.side_lobe_db must be < 0 and side_lobe_floor_db in [-120, side_lobe_db)"};
  if (!(s.surface_reflection >= 0 && s.surface_reflection <= 1 && s.seabed_reflection >= 0 && s.seabed_reflection <= 1))
    return Error{"sim config: sonar.surface_reflection and seabed_reflection in [0, 1]"};
  if (!(s.seabed_mu >= 0 && s.seabed_texture >= 0 && s.seabed_texture <= 3 && s.seabed_texture_scale_m > 0 &&
        s.seabed_relief_deg >= 0 && s.seabed_relief_deg < 45 && s.seabed_relief_scale_m > 0))
    return Error{"sim config: sonar seabed_mu >= 0, seabed_texture in [0, 3], seabed_relief_deg in [0, 45), scales > 0"};
  if (!(s.absorption_scale >= 0 && s.tvg_absorption_fraction >= 0 && s.tvg_absorption_fraction <= 1 &&
        s.noise_floor >= 0 && s.tvg_reference_m > 0))
    return Error{"sim config: sonar absorption_scale >= 0, tvg_absorption_fraction in [0, 1], noise_floor >= 0, tvg_reference_m > 0"};
  const auto& n = c.nav;
  for (double r : {n.imu_rate_hz, n.dvl_rate_hz, n.depth_rate_hz, n.ping_rate_hz}) {
    if (!(r > 0 && r <= 1000)) return Error{"sim config: sensor rates must be in (0, 1000] Hz"};
  }
  if (!(n.vertical_delay_s >= 0 && n.vertical_delay_s < 1.0 / n.ping_rate_hz))
    return Error{"sim config: nav.vertical_delay_s must be in [0, ping period)"};
  if (!(c.vehicle.speed_mps > 0 && c.vehicle.step_s > 0 && c.vehicle.max_yaw_rate_dps > 0))
    return Error{"sim config: vehicle speed, step and yaw rate must be > 0"};
  if (c.render_threads < 1 || c.render_threads > 64) return Error{"sim config: render_threads in 1..64"};
  return Status::Ok();
}

std::string format_pose6(const SE3& T) {
  const Vec3 t = T.translation();
  const Vec3 rpy = rpy_from_rotation(T.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", t.x(), t.y(), t.z(),
                rpy.x(), rpy.y(), rpy.z());
  return buf;
}

Result<SE3> parse_pose6(const std::string& s) {
  std::istringstream in(s);
  double v[6];
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) return Error{"pose '" + s + "': expected 'x y z roll pitch yaw'"};
  }
  std::string rest;
  if (in >> rest) return Error{"pose '" + s + "': trailing text '" + rest + "'"};
  return se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
}

}  // namespace orthosonar::sim
