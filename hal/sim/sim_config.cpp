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

// A table of (key -> how to read it, its valid range) per YAML map, as the run
// configuration has (replay/run/run_config.cpp): every value is checked against its range
// before it reaches the simulator, an error names the key, and validate() checks a
// SimConfig built in code against the same table. docs/SCENES.md lists the ranges
// (`orthosonar simulate --ranges`).
using SimReader = std::function<Status(const YAML::Node&, const std::string& where)>;
using SimCheck = std::function<Status(const std::string& where)>;
struct SimEntry;
using SimTable = std::map<std::string, SimEntry>;
struct SimEntry {
  SimReader read;
  SimCheck check;                       // the current value is in range (null: an alias or a map)
  std::string range;                    // human-readable valid range ("" for a nested map)
  std::string bad;                      // one out-of-range YAML value (tests)
  std::function<SimTable()> children;   // nested map
};

std::string sim_num(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

Status sim_out_of_range(const std::string& where, const std::string& value, const std::string& range) {
  return Error{"sim config: '" + where + "' = " + value + " is outside its valid range " + range};
}

// A real number in [lo, hi] (lo_open / hi_open exclude the bound), never NaN or infinite.
// `targets` are set together (`sonar.max_range_m` sets both heads); `checked` says whether
// validate() checks the first target under this key (false for an alias of another key).
SimEntry sim_real(std::vector<double*> targets, double lo, double hi, bool lo_open = false, bool hi_open = false,
                  bool checked = true) {
  SimEntry e;
  e.range = std::string(lo_open ? "(" : "[") + sim_num(lo) + ", " + sim_num(hi) + (hi_open ? ")" : "]");
  e.bad = lo_open ? sim_num(lo) : sim_num(lo - 1.0);
  auto in_range = [lo, hi, lo_open, hi_open](double v) {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  };
  e.read = [targets, in_range, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      return Error{"sim config: '" + where + "' must be a number in " + range};
    }
    if (!in_range(v)) return sim_out_of_range(where, sim_num(v), range);
    for (double* t : targets) *t = v;
    return {};
  };
  if (checked)
    e.check = [t = targets.front(), in_range, range = e.range](const std::string& where) -> Status {
      if (!in_range(*t)) return sim_out_of_range(where, sim_num(*t), range);
      return {};
    };
  return e;
}
SimEntry sim_real(double& target, double lo, double hi, bool lo_open = false, bool hi_open = false) {
  return sim_real(std::vector<double*>{&target}, lo, hi, lo_open, hi_open);
}

// An integer in [lo, hi] stored in T; `even` also requires an even value.
template <class T>
SimEntry sim_integer(std::vector<T*> targets, int64_t lo, int64_t hi, bool even = false, bool checked = true) {
  SimEntry e;
  e.range = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" + (even ? ", even" : "");
  e.bad = std::to_string(lo - 1);
  auto in_range = [lo, hi, even](int64_t v) { return v >= lo && v <= hi && (!even || v % 2 == 0); };
  e.read = [targets, in_range, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    int64_t v = 0;
    try {
      v = n.as<int64_t>();
    } catch (const YAML::Exception&) {
      return Error{"sim config: '" + where + "' must be an " + range};
    }
    if (!in_range(v)) return sim_out_of_range(where, std::to_string(v), range);
    for (T* t : targets) *t = static_cast<T>(v);
    return {};
  };
  if (checked)
    e.check = [t = targets.front(), in_range, range = e.range](const std::string& where) -> Status {
      if (!in_range(static_cast<int64_t>(*t))) return sim_out_of_range(where, std::to_string(*t), range);
      return {};
    };
  return e;
}
template <class T>
SimEntry sim_integer(T& target, int64_t lo, int64_t hi, bool even = false) {
  return sim_integer(std::vector<T*>{&target}, lo, hi, even);
}

// Any unsigned 64-bit integer (a seed); a '-' is an error, not a wrap-around.
SimEntry sim_seed(uint64_t& target) {
  SimEntry e;
  e.range = "integer in [0, 18446744073709551615]";
  e.bad = "-1";
  e.read = [&target, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    const std::string text = n.IsScalar() ? n.Scalar() : std::string();
    if (text.empty() || text.find('-') != std::string::npos)
      return Error{"sim config: '" + where + "' must be an " + range};
    try {
      target = n.as<uint64_t>();
    } catch (const YAML::Exception&) {
      return Error{"sim config: '" + where + "' must be an " + range};
    }
    return {};
  };
  e.check = [](const std::string&) { return Status::Ok(); };
  return e;
}

SimEntry sim_boolean(bool& target) {
  SimEntry e;
  e.range = "true or false";
  e.bad = "maybe";
  e.read = [&target](const YAML::Node& n, const std::string& where) -> Status {
    try {
      target = n.as<bool>();
    } catch (const YAML::Exception&) {
      return Error{"sim config: '" + where + "' must be true or false"};
    }
    return {};
  };
  e.check = [](const std::string&) { return Status::Ok(); };
  return e;
}

SimEntry sim_choice(std::string range, std::function<bool(const std::string&)> set) {
  SimEntry e;
  e.range = "one of: " + range;
  e.bad = "none_of_these";
  e.read = [set, range](const YAML::Node& n, const std::string& where) -> Status {
    const auto text = n.IsScalar() ? n.Scalar() : std::string();
    if (!set(text)) return Error{"sim config: '" + where + "' is '" + text + "', expected one of " + range};
    return {};
  };
  return e;
}

// A mount pose "x y z roll pitch yaw" as the run configuration bounds it: six finite
// numbers, |x|,|y|,|z| <= 100 m, angles in [-2 pi, 2 pi].
constexpr double kSimPoseMaxM = 100.0, kSimPoseMaxRad = 6.2832;
SimEntry sim_pose(SE3& target) {
  SimEntry e;
  e.range = "\"x y z roll pitch yaw\": |x|,|y|,|z| <= 100 m, angles in [-6.2832, 6.2832] rad";
  e.bad = "\"0 0 0 0 0\"";
  auto in_range = [](const double v[6]) {
    for (int i = 0; i < 6; ++i)
      if (!std::isfinite(v[i]) || std::abs(v[i]) > (i < 3 ? kSimPoseMaxM : kSimPoseMaxRad)) return false;
    return true;
  };
  e.read = [&target, in_range, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    std::istringstream s(n.IsScalar() ? n.Scalar() : std::string());
    double v[6];
    for (double& x : v)
      if (!(s >> x) || !std::isfinite(x)) return Error{"sim config: '" + where + "' must be " + range};
    std::string rest;
    if (s >> rest) return Error{"sim config: '" + where + "' has more than six numbers; must be " + range};
    if (!in_range(v)) return Error{"sim config: '" + where + "' is outside " + range};
    target = se3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
    return {};
  };
  e.check = [&target, in_range, range = e.range](const std::string& where) -> Status {
    const Vec3 t = target.translation();
    const Vec3 rpy = rpy_from_rotation(target.rotation());
    const double v[6] = {t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z()};
    if (!target.matrix().allFinite() || !in_range(v)) return Error{"sim config: '" + where + "' is outside " + range};
    return {};
  };
  return e;
}

SimEntry sim_nested(std::function<SimTable()> make);

SimTable head_table(SonarHead& h) {
  return {{"frequency_hz", sim_real(h.frequency_hz, 1e3, 1e7, true, true)},
          {"swath_deg", sim_real(h.swath_deg, 0.0, 180.0, true, true)},
          {"aperture_deg", sim_real(h.aperture_deg, 0.0, 90.0, true, true)},
          {"beam_width_deg", sim_real(h.beam_width_deg, 0.0, 30.0, false, true)},
          {"beams_full", sim_integer(h.beams_full, 4, 4096, true)},
          {"range_bins_full", sim_integer(h.range_bins_full, 4, 8192, true)},
          {"max_range_m", sim_real(h.max_range_m, 0.1, 500.0)},
          // < 0 (the default, -1): from the frequency and the water (Ainslie & McColm 1998).
          {"absorption_db_per_m", sim_real(h.absorption_db_per_m, -1.0, 10.0)},
          {"max_ping_rate_hz", sim_real(h.max_ping_rate_hz, 0.001, 1000.0)}};
}

SimTable sonar_table(SonarModelConfig& s) {
  SimTable t = {
      // Both heads at once (`sonar: {max_range_m: 20}`); sonar.horizontal/vertical.* check them.
      {"max_range_m", sim_real({&s.head_h.max_range_m, &s.head_v.max_range_m}, 0.1, 500.0, false, false, false)},
      {"beams_full", sim_integer<int>({&s.head_h.beams_full, &s.head_v.beams_full}, 4, 4096, true, false)},
      {"range_bins_full", sim_integer<int>({&s.head_h.range_bins_full, &s.head_v.range_bins_full}, 4, 8192, true, false)},
      {"swath_deg", sim_real({&s.head_h.swath_deg, &s.head_v.swath_deg}, 0.0, 180.0, true, true, false)},
      {"aperture_deg", sim_real({&s.head_h.aperture_deg, &s.head_v.aperture_deg}, 0.0, 90.0, true, true, false)},
      {"frequency_h_hz", sim_real({&s.head_h.frequency_hz}, 1e3, 1e7, true, true, false)},
      {"frequency_v_hz", sim_real({&s.head_v.frequency_hz}, 1e3, 1e7, true, true, false)},
      // theta = half_swath ((1 - c) u + c u^3) is monotonic for c in [0, 1].
      {"bearing_cubic", sim_real(s.bearing_cubic, 0.0, 1.0)},
      {"elevation_samples", sim_integer(s.elevation_samples, 32, 1024)},
      {"beam_samples", sim_integer(s.beam_samples, 1, 32)},
      {"beam_width_factor", sim_real(s.beam_width_factor, 0.01, 10.0)},
      {"aperture_sigma_deg", sim_real(s.aperture_sigma_deg, 0.1, 90.0)},
      {"incidence_exponent", sim_real(s.incidence_exponent, 0.0, 10.0)},
      // Exponents and the TVG reference bound r^-p (r / r_ref)^q to what a float holds.
      {"spreading_exponent", sim_real(s.spreading_exponent, 0.0, 4.0)},
      {"tvg_exponent", sim_real(s.tvg_exponent, 0.0, 4.0)},
      {"tvg_reference_m", sim_real(s.tvg_reference_m, 0.1, 100.0)},
      {"speckle_looks", sim_integer(s.speckle_looks, 1, 16)},
      {"noise_floor", sim_real(s.noise_floor, 0.0, 1000.0)},
      {"gain", sim_real(s.gain, 0.0, 1e6, true)},
      {"gamma", sim_real(s.gamma, 0.0, 10.0, true)},
      {"gain_percent", sim_real(s.gain_percent, 0.0, 100.0)},
      {"beam_pattern", sim_boolean(s.beam_pattern)},
      {"side_lobe_db", sim_real(s.side_lobe_db, -120.0, 0.0, true, true)},
      {"side_lobe_floor_db", sim_real(s.side_lobe_floor_db, -120.0, 0.0, false, true)},
      {"surface_reflection", sim_real(s.surface_reflection, 0.0, 1.0)},
      {"seabed_reflection", sim_real(s.seabed_reflection, 0.0, 1.0)},
      {"seabed_lambert", sim_boolean(s.seabed_lambert)},
      {"seabed_mu", sim_real(s.seabed_mu, 0.0, 10.0)},
      {"seabed_texture", sim_real(s.seabed_texture, 0.0, 3.0)},
      {"seabed_texture_scale_m", sim_real(s.seabed_texture_scale_m, 0.01, 1000.0)},
      {"seabed_relief_deg", sim_real(s.seabed_relief_deg, 0.0, 45.0, false, true)},
      {"seabed_relief_scale_m", sim_real(s.seabed_relief_scale_m, 0.01, 1000.0)},
      {"absorption_scale", sim_real(s.absorption_scale, 0.0, 10.0)},
      {"tvg_absorption_fraction", sim_real(s.tvg_absorption_fraction, 0.0, 1.0)},
      {"noise_before_tvg", sim_boolean(s.noise_before_tvg)},
      {"water_temperature_c", sim_real(s.water_temperature_c, -2.0, 40.0)},
      {"salinity_ppt", sim_real(s.salinity_ppt, 0.0, 50.0)},
      {"water_ph", sim_real(s.water_ph, 6.0, 10.0)},
      {"vertical_mode", sim_choice("1.2MHz, 2.1MHz",
                                   [&s](const std::string& mode) {
                                     if (mode == "1.2MHz") s.head_v = oculus_m1200d_1200khz();
                                     else if (mode == "2.1MHz") s.head_v = oculus_m1200d_2100khz();
                                     else return false;
                                     return true;
                                   })},
      {"horizontal", sim_nested([&s] { return head_table(s.head_h); })},
      {"vertical", sim_nested([&s] { return head_table(s.head_v); })},
      {"reflectivity", sim_nested([&s] {
         SimTable r;
         for (int c = 0; c < kSemanticClassCount; ++c)
           r.emplace(semantic_class_name(static_cast<SemanticClass>(c)),
                     sim_real(s.reflectivity[static_cast<size_t>(c)], 0.0, 10.0));
         return r;
       })}};
  return t;
}

SimTable vehicle_table(VehicleConfig& v) {
  return {{"speed_mps", sim_real(v.speed_mps, 0.0, 10.0, true)},
          {"max_yaw_rate_dps", sim_real(v.max_yaw_rate_dps, 0.0, 360.0, true)},
          {"yaw_gain_per_s", sim_real(v.yaw_gain_per_s, 0.0, 100.0)},
          {"acceptance_radius_m", sim_real(v.acceptance_radius_m, 0.0, 1000.0, true)},
          {"slow_turn_factor", sim_real(v.slow_turn_factor, 0.0, 1.0)},
          {"roll_amplitude_deg", sim_real(v.roll_amplitude_deg, 0.0, 45.0)},
          {"pitch_amplitude_deg", sim_real(v.pitch_amplitude_deg, 0.0, 45.0)},
          {"roll_period_s", sim_real(v.roll_period_s, 0.1, 3600.0)},
          {"pitch_period_s", sim_real(v.pitch_period_s, 0.1, 3600.0)},
          {"current_x_mps", sim_real(v.current_x_mps, -10.0, 10.0)},
          {"current_y_mps", sim_real(v.current_y_mps, -10.0, 10.0)},
          // At least 0.1 ms: a step that rounds to 0 ns divided the trajectory by zero.
          {"step_s", sim_real(v.step_s, 1e-4, 1.0)}};
}

SimTable nav_table(NavConfig& n) {
  return {{"imu_rate_hz", sim_real(n.imu_rate_hz, 0.001, 1000.0)},
          {"dvl_rate_hz", sim_real(n.dvl_rate_hz, 0.001, 1000.0)},
          {"depth_rate_hz", sim_real(n.depth_rate_hz, 0.001, 1000.0)},
          {"ping_rate_hz", sim_real(n.ping_rate_hz, 0.001, 1000.0)},
          {"ping_offset_s", sim_real(n.ping_offset_s, 0.0, 3600.0)},
          {"vertical_delay_s", sim_real(n.vertical_delay_s, 0.0, 1.0, false, true)},
          {"dvl_offset_s", sim_real(n.dvl_offset_s, 0.0, 3600.0)},
          {"depth_offset_s", sim_real(n.depth_offset_s, 0.0, 3600.0)},
          {"dvl_sigma_mps", sim_real(n.dvl_sigma_mps, 0.0, 10.0)},
          {"dvl_invalid_probability", sim_real(n.dvl_invalid_probability, 0.0, 1.0)},
          {"dvl_max_altitude_m", sim_real(n.dvl_max_altitude_m, 0.0, 10000.0)},
          {"imu_roll_pitch_sigma_deg", sim_real(n.imu_roll_pitch_sigma_deg, 0.0, 90.0)},
          {"imu_yaw_sigma_deg", sim_real(n.imu_yaw_sigma_deg, 0.0, 180.0)},
          {"imu_yaw_bias_walk_deg_per_sqrt_s", sim_real(n.imu_yaw_bias_walk_deg_per_sqrt_s, 0.0, 10.0)},
          {"imu_yaw_bias_rate_dps", sim_real(n.imu_yaw_bias_rate_dps, -10.0, 10.0)},
          {"imu_gyro_sigma_dps", sim_real(n.imu_gyro_sigma_dps, 0.0, 100.0)},
          {"imu_gyro_bias_dps", sim_real(n.imu_gyro_bias_dps, 0.0, 100.0)},
          {"depth_sigma_m", sim_real(n.depth_sigma_m, 0.0, 100.0)}};
}

SimTable root_sim_table(SimConfig& c) {
  return {{"duration_s", sim_real(c.duration_s, 0.0, kSimMaxDurationS, true)},
          {"seed", sim_seed(c.seed)},
          {"labels", sim_boolean(c.labels)},
          {"resolution", sim_choice("full, reduced",
                                    [&c](const std::string& v) {
                                      auto r = parse_resolution(v);
                                      if (r) c.resolution = *r;
                                      return r.ok();
                                    })},
          {"profile", sim_choice("field, clean",
                                 [&c](const std::string& v) {
                                   auto p = parse_profile(v);
                                   if (!p) return false;
                                   c.profile = *p;
                                   apply_profile(c.sonar, c.profile);
                                   return true;
                                 })},
          {"T_V_h", sim_pose(c.T_V_h)},
          {"T_V_v", sim_pose(c.T_V_v)},
          {"device_id_h", sim_integer(c.device_id_h, 0, 4294967295LL)},
          {"device_id_v", sim_integer(c.device_id_v, 0, 4294967295LL)},
          {"render_threads", sim_integer(c.render_threads, 1, 64)},
          {"sonar", sim_nested([&c] { return sonar_table(c.sonar); })},
          {"vehicle", sim_nested([&c] { return vehicle_table(c.vehicle); })},
          {"nav", sim_nested([&c] { return nav_table(c.nav); })}};
}

// Applies the keys of `node` that `now(key)` selects; every key must be in `table`.
Status sim_apply(const YAML::Node& node, const SimTable& table, const std::string& prefix,
                 const std::function<bool(const std::string&)>& now) {
  const std::string name = prefix.empty() ? std::string("<root>") : prefix;
  if (!node.IsMap()) return Error{"sim config: '" + name + "' must be a map"};
  for (const auto& kv : node) {
    if (!kv.first.IsScalar())
      return Error{"sim config: a key in '" + name + "' is not a plain name (a sequence, a map or '?' with no key)"};
    const std::string key = kv.first.as<std::string>();
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    const auto it = table.find(key);
    if (it == table.end()) return Error{"sim config: unknown key '" + where + "'"};
    if (!now(key)) continue;
    if (Status s = it->second.read(kv.second, where); !s.ok()) return s;
  }
  return {};
}

SimEntry sim_nested(std::function<SimTable()> make) {
  SimEntry e;
  e.children = make;
  e.read = [make](const YAML::Node& n, const std::string& where) {
    return sim_apply(n, make(), where, [](const std::string&) { return true; });
  };
  return e;
}

Status sim_check(const SimTable& t, const std::string& prefix) {
  for (const auto& [key, e] : t) {
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    if (e.children) {
      if (Status s = sim_check(e.children(), where); !s.ok()) return s;
    } else if (e.check) {
      if (Status s = e.check(where); !s.ok()) return s;
    }
  }
  return {};
}

void sim_list(const SimTable& t, const std::string& prefix, std::vector<SimConfigKeyRange>& out) {
  for (const auto& [key, e] : t) {
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    if (e.children) sim_list(e.children(), where, out);
    else out.push_back({where, e.range, e.bad});
  }
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
  const SimTable top = root_sim_table(trial);
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
  if (Status s = sim_apply(root, top, "", only({"profile"})); !s.ok()) return s;
  if (Status s = sim_apply(root, top, "", all_but({"profile", "sonar", "vehicle", "nav"})); !s.ok()) return s;
  if (const YAML::Node sonar = root["sonar"]) {
    const SimTable t = sonar_table(trial.sonar);
    if (Status s = sim_apply(sonar, t, "sonar", only({"vertical_mode"})); !s.ok()) return s;
    if (Status s = sim_apply(sonar, t, "sonar", all_but({"vertical_mode", "horizontal", "vertical"})); !s.ok()) return s;
    if (Status s = sim_apply(sonar, t, "sonar", only({"horizontal", "vertical"})); !s.ok()) return s;
  }
  if (Status s = sim_apply(root, top, "", only({"vehicle", "nav"})); !s.ok()) return s;
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
  sim_list(root_sim_table(scratch), "", out);
  return out;
}

Status validate(const SimConfig& config) {
  SimConfig c = config;  // the tables bind to fields; checks only read them
  if (Status s = sim_check(root_sim_table(c), ""); !s.ok()) return s;
  // What one key's range cannot say.
  const auto& s = c.sonar;
  if (!(s.side_lobe_floor_db < s.side_lobe_db))
    return Error{"sim config: 'sonar.side_lobe_floor_db' (" + sim_num(s.side_lobe_floor_db) +
                 ") must be below 'sonar.side_lobe_db' (" + sim_num(s.side_lobe_db) + ")"};
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
                   sim_num(2.0 * a * h->max_range_m) + " dB from '" + which +
                   ".absorption_db_per_m' or its frequency, times 'sonar.absorption_scale') exceeds " +
                   sim_num(kSimMaxTwoWayAbsorptionDb) + " dB"};
  }
  if (!(c.nav.vertical_delay_s < 1.0 / c.nav.ping_rate_hz))
    return Error{"sim config: 'nav.vertical_delay_s' must be in [0, ping period of 'nav.ping_rate_hz')"};
  // Samples held for the whole mission: the trajectory (every vehicle.step_s) and the IMU yaw bias.
  if (c.duration_s / c.vehicle.step_s > kSimMaxSamples)
    return Error{"sim config: 'duration_s' / 'vehicle.step_s' = " + sim_num(c.duration_s / c.vehicle.step_s) +
                 " trajectory samples exceeds " + sim_num(kSimMaxSamples)};
  if (c.duration_s * c.nav.imu_rate_hz > kSimMaxSamples)
    return Error{"sim config: 'duration_s' x 'nav.imu_rate_hz' = " + sim_num(c.duration_s * c.nav.imu_rate_hz) +
                 " IMU samples exceeds " + sim_num(kSimMaxSamples)};
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
