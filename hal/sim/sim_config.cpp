#include "hal/sim/sim_config.hpp"

#include "hal/config/key_table.hpp"

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

const char* nav_profile_name(NavProfile p) {
  switch (p) {
    case NavProfile::kPaper: return "paper";
    case NavProfile::kConsumer: return "consumer";
    case NavProfile::kAhrs: break;
  }
  return "ahrs";
}

Result<NavProfile> parse_nav_profile(const std::string& s) {
  if (s == "ahrs") return NavProfile::kAhrs;
  if (s == "paper") return NavProfile::kPaper;
  if (s == "consumer") return NavProfile::kConsumer;
  return Error{"unknown navigation profile '" + s + "' (paper, ahrs, consumer)"};
}

void apply_nav_profile(NavConfig& n, NavProfile p) {
  const NavConfig base;  // paper: the VN-100 as every mission before the profiles had it, and the FOG
  n.imu_yaw_bias_rate_dps = base.imu_yaw_bias_rate_dps;
  n.imu_yaw_bias_walk_deg_per_sqrt_s = base.imu_yaw_bias_walk_deg_per_sqrt_s;
  n.gyro_rate_hz = base.gyro_rate_hz;
  n.gyro_rates = base.gyro_rates;
  n.gyro_arw_deg_per_sqrt_h = base.gyro_arw_deg_per_sqrt_h;
  n.gyro_bias_dph = base.gyro_bias_dph;
  switch (p) {
    case NavProfile::kPaper: break;  // the authors' 250 Hz delta angles
    case NavProfile::kAhrs: n.gyro_rate_hz = 0.0; break;
    case NavProfile::kConsumer:
      n.gyro_rate_hz = 0.0;
      n.imu_yaw_bias_rate_dps = 0.05;  // 3 deg/min
      break;
  }
}

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

// The simulator's key tables (hal/config/key_table.hpp, the run configuration's machinery
// in this file's wording): every value is checked against its range before it reaches the
// simulator, an error names the key, and validate() checks a SimConfig built in code
// against the same table. docs/SCENES.md lists the ranges (`orthosonar simulate --ranges`).
using config::Parity;
using config::Table;
const config::KeyTables kKeys({.prefix = "sim config: ", .choice_names_value = true});

// Any unsigned 64-bit integer (a seed); a '-' is an error, not a wrap-around.
config::Entry sim_seed(uint64_t& target) {
  config::Entry e;
  e.range = "integer in [0, 18446744073709551615]";
  e.bad = "-1";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    const std::string text = n.IsScalar() ? n.Scalar() : std::string();
    if (text.empty() || text.find('-') != std::string::npos)
      return kKeys.error("'" + where + "' must be an " + range);
    try {
      target = n.as<uint64_t>();
    } catch (const YAML::Exception&) {
      return kKeys.error("'" + where + "' must be an " + range);
    }
    return {};
  };
  return e;
}

Table head_table(SonarHead& h) {
  return {{"frequency_hz", kKeys.real(h.frequency_hz, 1e3, 1e7, true, true)},
          {"swath_deg", kKeys.real(h.swath_deg, 0.0, 180.0, true, true)},
          {"aperture_deg", kKeys.real(h.aperture_deg, 0.0, 90.0, true, true)},
          {"beam_width_deg", kKeys.real(h.beam_width_deg, 0.0, 30.0, false, true)},
          {"beams_full", kKeys.integer(h.beams_full, 4, 4096, Parity::kEven)},
          {"range_bins_full", kKeys.integer(h.range_bins_full, 4, 8192, Parity::kEven)},
          {"max_range_m", kKeys.real(h.max_range_m, 0.1, 500.0)},
          // < 0 (the default, -1): from the frequency and the water (Ainslie & McColm 1998).
          {"absorption_db_per_m", kKeys.real(h.absorption_db_per_m, -1.0, 10.0)},
          {"max_ping_rate_hz", kKeys.real(h.max_ping_rate_hz, 0.001, 1000.0)}};
}

Table sonar_table(SonarModelConfig& s) {
  Table t = {
      // Both heads at once (`sonar: {max_range_m: 20}`); sonar.horizontal/vertical.* check them.
      {"max_range_m", kKeys.real({&s.head_h.max_range_m, &s.head_v.max_range_m}, 0.1, 500.0, false, false, false)},
      {"beams_full", kKeys.integer<int>({&s.head_h.beams_full, &s.head_v.beams_full}, 4, 4096, Parity::kEven, false)},
      {"range_bins_full", kKeys.integer<int>({&s.head_h.range_bins_full, &s.head_v.range_bins_full}, 4, 8192, Parity::kEven, false)},
      {"swath_deg", kKeys.real({&s.head_h.swath_deg, &s.head_v.swath_deg}, 0.0, 180.0, true, true, false)},
      {"aperture_deg", kKeys.real({&s.head_h.aperture_deg, &s.head_v.aperture_deg}, 0.0, 90.0, true, true, false)},
      {"frequency_h_hz", kKeys.real({&s.head_h.frequency_hz}, 1e3, 1e7, true, true, false)},
      {"frequency_v_hz", kKeys.real({&s.head_v.frequency_hz}, 1e3, 1e7, true, true, false)},
      // theta = half_swath ((1 - c) u + c u^3) is monotonic for c in [0, 1].
      {"bearing_cubic", kKeys.real(s.bearing_cubic, 0.0, 1.0)},
      {"elevation_samples", kKeys.integer(s.elevation_samples, 32, 1024)},
      {"beam_samples", kKeys.integer(s.beam_samples, 1, 32)},
      {"beam_width_factor", kKeys.real(s.beam_width_factor, 0.01, 10.0)},
      {"range_footprint", kKeys.boolean(s.range_footprint)},
      {"aperture_sigma_deg", kKeys.real(s.aperture_sigma_deg, 0.1, 90.0)},
      {"incidence_exponent", kKeys.real(s.incidence_exponent, 0.0, 10.0)},
      // Exponents and the TVG reference bound r^-p (r / r_ref)^q to what a float holds.
      {"spreading_exponent", kKeys.real(s.spreading_exponent, 0.0, 4.0)},
      {"tvg_exponent", kKeys.real(s.tvg_exponent, 0.0, 4.0)},
      {"tvg_reference_m", kKeys.real(s.tvg_reference_m, 0.1, 100.0)},
      {"speckle_looks", kKeys.integer(s.speckle_looks, 1, 16)},
      {"noise_floor", kKeys.real(s.noise_floor, 0.0, 1000.0)},
      {"gain", kKeys.real(s.gain, 0.0, 1e6, true)},
      {"gamma", kKeys.real(s.gamma, 0.0, 10.0, true)},
      {"gain_percent", kKeys.real(s.gain_percent, 0.0, 100.0)},
      {"beam_pattern", kKeys.boolean(s.beam_pattern)},
      {"side_lobe_db", kKeys.real(s.side_lobe_db, -120.0, 0.0, true, true)},
      {"side_lobe_floor_db", kKeys.real(s.side_lobe_floor_db, -120.0, 0.0, false, true)},
      {"surface_reflection", kKeys.real(s.surface_reflection, 0.0, 1.0)},
      {"seabed_reflection", kKeys.real(s.seabed_reflection, 0.0, 1.0)},
      {"seabed_lambert", kKeys.boolean(s.seabed_lambert)},
      {"seabed_mu", kKeys.real(s.seabed_mu, 0.0, 10.0)},
      {"seabed_texture", kKeys.real(s.seabed_texture, 0.0, 3.0)},
      {"seabed_texture_scale_m", kKeys.real(s.seabed_texture_scale_m, 0.01, 1000.0)},
      {"seabed_relief_deg", kKeys.real(s.seabed_relief_deg, 0.0, 45.0, false, true)},
      {"seabed_relief_scale_m", kKeys.real(s.seabed_relief_scale_m, 0.01, 1000.0)},
      {"absorption_scale", kKeys.real(s.absorption_scale, 0.0, 10.0)},
      {"tvg_absorption_fraction", kKeys.real(s.tvg_absorption_fraction, 0.0, 1.0)},
      {"noise_before_tvg", kKeys.boolean(s.noise_before_tvg)},
      {"water_temperature_c", kKeys.real(s.water_temperature_c, -2.0, 40.0)},
      {"salinity_ppt", kKeys.real(s.salinity_ppt, 0.0, 50.0)},
      {"water_ph", kKeys.real(s.water_ph, 6.0, 10.0)},
      {"vertical_mode", kKeys.choice("1.2MHz, 2.1MHz",
                                   [&s](const std::string& mode) {
                                     if (mode == "1.2MHz") s.head_v = oculus_m1200d_1200khz();
                                     else if (mode == "2.1MHz") s.head_v = oculus_m1200d_2100khz();
                                     else return false;
                                     return true;
                                   })},
      {"horizontal", kKeys.nested([&s] { return head_table(s.head_h); })},
      {"vertical", kKeys.nested([&s] { return head_table(s.head_v); })},
      {"reflectivity", kKeys.nested([&s] {
         Table r;
         for (int c = 0; c < kSemanticClassCount; ++c)
           r.emplace(semantic_class_name(static_cast<SemanticClass>(c)),
                     kKeys.real(s.reflectivity[static_cast<size_t>(c)], 0.0, 10.0));
         return r;
       })}};
  return t;
}

Table vehicle_table(VehicleConfig& v) {
  return {{"speed_mps", kKeys.real(v.speed_mps, 0.0, 10.0, true)},
          {"max_yaw_rate_dps", kKeys.real(v.max_yaw_rate_dps, 0.0, 360.0, true)},
          {"yaw_gain_per_s", kKeys.real(v.yaw_gain_per_s, 0.0, 100.0)},
          {"acceptance_radius_m", kKeys.real(v.acceptance_radius_m, 0.0, 1000.0, true)},
          {"slow_turn_factor", kKeys.real(v.slow_turn_factor, 0.0, 1.0)},
          {"roll_amplitude_deg", kKeys.real(v.roll_amplitude_deg, 0.0, 45.0)},
          {"pitch_amplitude_deg", kKeys.real(v.pitch_amplitude_deg, 0.0, 45.0)},
          {"roll_period_s", kKeys.real(v.roll_period_s, 0.1, 3600.0)},
          {"pitch_period_s", kKeys.real(v.pitch_period_s, 0.1, 3600.0)},
          {"current_x_mps", kKeys.real(v.current_x_mps, -10.0, 10.0)},
          {"current_y_mps", kKeys.real(v.current_y_mps, -10.0, 10.0)},
          // At least 0.1 ms: a step that rounds to 0 ns divided the trajectory by zero.
          {"step_s", kKeys.real(v.step_s, 1e-4, 1.0)}};
}

Table nav_table(NavConfig& n) {
  return {{"imu_rate_hz", kKeys.real(n.imu_rate_hz, 0.001, 1000.0)},
          {"dvl_rate_hz", kKeys.real(n.dvl_rate_hz, 0.001, 1000.0)},
          {"depth_rate_hz", kKeys.real(n.depth_rate_hz, 0.001, 1000.0)},
          {"ping_rate_hz", kKeys.real(n.ping_rate_hz, 0.001, 1000.0)},
          {"ping_offset_s", kKeys.real(n.ping_offset_s, 0.0, 3600.0)},
          {"vertical_delay_s", kKeys.real(n.vertical_delay_s, 0.0, 1.0, false, true)},
          {"dvl_offset_s", kKeys.real(n.dvl_offset_s, 0.0, 3600.0)},
          {"depth_offset_s", kKeys.real(n.depth_offset_s, 0.0, 3600.0)},
          {"dvl_sigma_mps", kKeys.real(n.dvl_sigma_mps, 0.0, 10.0)},
          {"dvl_invalid_probability", kKeys.real(n.dvl_invalid_probability, 0.0, 1.0)},
          {"dvl_max_altitude_m", kKeys.real(n.dvl_max_altitude_m, 0.0, 10000.0)},
          {"imu_roll_pitch_sigma_deg", kKeys.real(n.imu_roll_pitch_sigma_deg, 0.0, 90.0)},
          {"imu_yaw_sigma_deg", kKeys.real(n.imu_yaw_sigma_deg, 0.0, 180.0)},
          {"imu_yaw_bias_walk_deg_per_sqrt_s", kKeys.real(n.imu_yaw_bias_walk_deg_per_sqrt_s, 0.0, 10.0)},
          {"imu_yaw_bias_rate_dps", kKeys.real(n.imu_yaw_bias_rate_dps, -10.0, 10.0)},
          {"imu_gyro_sigma_dps", kKeys.real(n.imu_gyro_sigma_dps, 0.0, 100.0)},
          {"imu_gyro_bias_dps", kKeys.real(n.imu_gyro_bias_dps, 0.0, 100.0)},
          {"depth_sigma_m", kKeys.real(n.depth_sigma_m, 0.0, 100.0)},
          {"gyro_rate_hz", kKeys.real(n.gyro_rate_hz, 0.0, 1000.0)},
          {"gyro_rates", kKeys.boolean(n.gyro_rates)},
          {"gyro_arw_deg_per_sqrt_h", kKeys.real(n.gyro_arw_deg_per_sqrt_h, 0.0, 100.0)},
          {"gyro_bias_dph", kKeys.real(n.gyro_bias_dph, 0.0, 3600.0)}};
}

// "default, survey (the scene must offer it: survey is harbor's)" from the built-in routes.
std::string route_choices() {
  std::string names = "default", whose;
  for (const auto& scene : builtin_scene_names())
    for (const auto& r : builtin_route_names(scene)) {
      names += ", " + r;
      whose += (whose.empty() ? "" : ", ") + r + " is " + scene + "'s";
    }
  return names + " (the scene must offer it" + (whose.empty() ? "" : ": " + whose) + ")";
}

Table root_sim_table(SimConfig& c) {
  return {{"duration_s", kKeys.real(c.duration_s, 0.0, kSimMaxDurationS, true)},
          {"seed", sim_seed(c.seed)},
          {"labels", kKeys.boolean(c.labels)},
          {"resolution", kKeys.choice("full, reduced",
                                    [&c](const std::string& v) {
                                      auto r = parse_resolution(v);
                                      if (r) c.resolution = *r;
                                      return r.ok();
                                    })},
          {"profile", kKeys.choice("field, clean",
                                 [&c](const std::string& v) {
                                   auto p = parse_profile(v);
                                   if (!p) return false;
                                   c.profile = *p;
                                   apply_profile(c.sonar, c.profile);
                                   return true;
                                 })},
          {"nav_profile", kKeys.choice("paper, ahrs, consumer",
                                     [&c](const std::string& v) {
                                       auto p = parse_nav_profile(v);
                                       if (!p) return false;
                                       c.nav_profile = *p;
                                       apply_nav_profile(c.nav, c.nav_profile);
                                       return true;
                                     })},
          {"T_V_h", kKeys.pose(c.T_V_h)},
          {"T_V_v", kKeys.pose(c.T_V_v)},
          {"T_V_gyro", kKeys.pose(c.T_V_gyro)},
          {"device_id_h", kKeys.integer(c.device_id_h, 0, 4294967295LL)},
          {"device_id_v", kKeys.integer(c.device_id_v, 0, 4294967295LL)},
          {"render_threads", kKeys.integer(c.render_threads, 1, 64)},
          {"route", kKeys.choice(route_choices(),
                                 [&c](const std::string& v) {
                                   const auto names = builtin_route_names();
                                   if (v != "default" && std::find(names.begin(), names.end(), v) == names.end())
                                     return false;
                                   c.route = v;
                                   return true;
                                 })},
          {"sonar", kKeys.nested([&c] { return sonar_table(c.sonar); })},
          {"vehicle", kKeys.nested([&c] { return vehicle_table(c.vehicle); })},
          {"nav", kKeys.nested([&c] { return nav_table(c.nav); })}};
}

Status apply_document(const std::string& yaml_text, SimConfig& c) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
  if (root.IsNull()) return Status::Ok();
  SimConfig trial = c;
  const Table top = root_sim_table(trial);
  auto only = [](std::initializer_list<const char*> keys) {
    return [keys](const std::string& k) {
      for (const char* x : keys)
        if (k == x) return true;
      return false;
    };
  };
  auto all_but = [](std::initializer_list<const char*> keys) {
    return [keys](const std::string& k) {
      for (const char* x : keys)
        if (k == x) return false;
      return true;
    };
  };
  // Order, whatever the file's: the profile (the keys below refine it), the other top-level
  // keys, then sonar (vertical_mode, the keys of both heads, then each head's own), vehicle, nav.
  if (Status s = kKeys.apply(root, top, "", only({"profile", "nav_profile"})); !s.ok()) return s;
  if (Status s = kKeys.apply(root, top, "", all_but({"profile", "nav_profile", "sonar", "vehicle", "nav"})); !s.ok())
    return s;
  if (const YAML::Node sonar = root["sonar"]) {
    const Table t = sonar_table(trial.sonar);
    if (Status s = kKeys.apply(sonar, t, "sonar", only({"vertical_mode"})); !s.ok()) return s;
    if (Status s = kKeys.apply(sonar, t, "sonar", all_but({"vertical_mode", "horizontal", "vertical"})); !s.ok()) return s;
    if (Status s = kKeys.apply(sonar, t, "sonar", only({"horizontal", "vertical"})); !s.ok()) return s;
  }
  if (Status s = kKeys.apply(root, top, "", only({"vehicle", "nav"})); !s.ok()) return s;
  if (Status s = validate(trial); !s.ok()) return s;
  c = trial;
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

Status apply_sim_config_yaml(const std::string& yaml_text, SimConfig& c) {
  // Every reader checks its node; this is the net under them (found by fuzz_sim_config: a
  // '? :' key threw yaml-cpp's TypedBadConversion through the API).
  try {
    return apply_document(yaml_text, c);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
}

std::vector<SimConfigKeyRange> sim_config_key_ranges() {
  SimConfig scratch;
  std::vector<SimConfigKeyRange> out;
  for (auto& k : config::KeyTables::ranges(root_sim_table(scratch))) out.push_back({k.key, k.range, k.bad_value});
  return out;
}

Status validate(const SimConfig& config) {
  SimConfig c = config;  // the tables bind to fields; checks only read them
  if (Status s = config::KeyTables::check(root_sim_table(c)); !s.ok()) return s;
  // What one key's range cannot say.
  const auto& s = c.sonar;
  if (!(s.side_lobe_floor_db < s.side_lobe_db))
    return Error{"sim config: 'sonar.side_lobe_floor_db' (" + config::number_text(s.side_lobe_floor_db) +
                 ") must be below 'sonar.side_lobe_db' (" + config::number_text(s.side_lobe_db) + ")"};
  const double rays_max = static_cast<double>(kSimMaxRaysPerHead);
  for (const SonarHead* h : {&s.head_h, &s.head_v}) {
    const std::string which = h == &s.head_h ? "sonar.horizontal" : "sonar.vertical";
    // Two-way travel time: a ping to max range at 1500 m/s must finish before the next.
    const double ceiling = std::min(h->max_ping_rate_hz, 1500.0 / (2.0 * h->max_range_m));
    if (c.nav.ping_rate_hz > ceiling * (1.0 + 1e-9))
      return Error{"sim config: 'nav.ping_rate_hz' exceeds " + which + "'s ceiling (" + std::to_string(ceiling) +
                   " Hz at its max_range_m)"};
    // The ray pattern per head (beams x beam_samples x elevation_samples) stays in memory.
    if (static_cast<double>(h->beams_full) * s.beam_samples * s.elevation_samples > rays_max)
      return Error{"sim config: '" + which + ".beams_full' x 'sonar.beam_samples' x 'sonar.elevation_samples' exceeds " +
                   std::to_string(kSimMaxRaysPerHead) + " rays"};
    // Two-way absorption over the head's range: the TVG's gain must stay a finite float.
    const double a = head_absorption_db_per_m(s, *h);
    if (!(2.0 * a * std::max(h->max_range_m, s.tvg_reference_m) <= kSimMaxTwoWayAbsorptionDb))
      return Error{"sim config: two-way absorption over " + which + ".max_range_m (" +
                   config::number_text(2.0 * a * h->max_range_m) + " dB from '" + which +
                   ".absorption_db_per_m' or its frequency, times 'sonar.absorption_scale') exceeds " +
                   config::number_text(kSimMaxTwoWayAbsorptionDb) + " dB"};
  }
  if (!(c.nav.vertical_delay_s < 1.0 / c.nav.ping_rate_hz))
    return Error{"sim config: 'nav.vertical_delay_s' must be in [0, ping period of 'nav.ping_rate_hz')"};
  // Samples held for the whole mission: the trajectory (every vehicle.step_s) and the IMU yaw bias.
  if (c.duration_s / c.vehicle.step_s > kSimMaxSamples)
    return Error{"sim config: 'duration_s' / 'vehicle.step_s' = " + config::number_text(c.duration_s / c.vehicle.step_s) +
                 " trajectory samples exceeds " + config::number_text(kSimMaxSamples)};
  if (c.duration_s * c.nav.imu_rate_hz > kSimMaxSamples)
    return Error{"sim config: 'duration_s' x 'nav.imu_rate_hz' = " + config::number_text(c.duration_s * c.nav.imu_rate_hz) +
                 " IMU samples exceeds " + config::number_text(kSimMaxSamples)};
  if (c.duration_s * c.nav.gyro_rate_hz > kSimMaxSamples)
    return Error{"sim config: 'duration_s' x 'nav.gyro_rate_hz' = " + config::number_text(c.duration_s * c.nav.gyro_rate_hz) +
                 " gyro samples exceeds " + config::number_text(kSimMaxSamples)};
  return Status::Ok();
}

}  // namespace orthosonar::sim
