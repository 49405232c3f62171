#pragma once
// Every number of the simulator (SPEC §10) with its default; units in field names.
#include <array>
#include <numbers>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/mesh.hpp"
#include "core/result.hpp"
#include "hal/config/pose6.hpp"

namespace orthosonar::sim {

// Full: 512 beams x 600 range bins at 0.05 m (30 m). Reduced: 256 x 300 at 0.10 m (30 m).
enum class Resolution { kFull, kReduced };
const char* resolution_name(Resolution r);
Result<Resolution> parse_resolution(const std::string& s);

// One sonar head as the device is set up (docs/SCENES.md "Devices"). The image the
// simulator writes has range_bins_full bins to max_range_m (the device's native range
// resolution is finer; fusion only needs the image's own range_resolution_m).
struct SonarHead {
  double frequency_hz = 750e3;
  double swath_deg = 130.0;            // total horizontal field of view of the fan
  double aperture_deg = 20.0;          // across the fan
  double beam_width_deg = 1.0;         // main lobe, two-way -3 dB (field profile; 0 = rectangular beams)
  int beams_full = 512;
  int range_bins_full = 600;
  double max_range_m = 30.0;
  double absorption_db_per_m = -1.0;   // one-way; < 0: from frequency and water (Ainslie & McColm 1998)
  double max_ping_rate_hz = 40.0;      // the device's ceiling (the two-way travel time bounds it too)
};
// Oculus M750d in its 750 kHz mode; M1200d in its 1.2 MHz or 2.1 MHz mode.
SonarHead oculus_m750d_750khz();
SonarHead oculus_m1200d_1200khz();
SonarHead oculus_m1200d_2100khz();

// The image formation profile. kField models what real Oculus images show: beam
// side lobes, surface multipath, Lambertian seabed with texture and relief, absorption, the
// device's TVG lifting the noise floor with range. kClean is the earlier calibration: no
// artefacts, a dark water column, range-independent noise. kField is the default.
enum class SonarProfile { kField, kClean };
const char* profile_name(SonarProfile p);
Result<SonarProfile> parse_profile(const std::string& s);

// Image formation of both Oculus sonars: shared physics and one SonarHead per mount.
struct SonarModelConfig {
  SonarHead head_h = oculus_m750d_750khz();
  SonarHead head_v = oculus_m1200d_1200khz();
  // Bearing table non-uniformity: theta = half_swath * ((1 - c) u + c u^3), u uniform in [-1, 1].
  double bearing_cubic = 0.08;
  int elevation_samples = 32;          // stratified rays across the aperture (>= 32)
  int beam_samples = 3;                // rays across each beam's width
  double beam_width_factor = 1.0;      // ray spread per beam as a multiple of the local beam spacing
  // Each ray stands for its elevation stratum: its echo is spread over the ranges the
  // stratum's footprint covers on the hit surface, not put in the hit's bin alone
  // (docs/SCENES.md "Range footprint"). With beam_samples 1 a field pair renders in about
  // two thirds of the time; off by default (it changes the images).
  bool range_footprint = false;
  double aperture_sigma_deg = 8.5;     // Gaussian elevation pattern (-3 dB near +-10 deg at 20 deg)
  double incidence_exponent = 1.0;     // k in cos(incidence)^k
  double spreading_exponent = 2.0;     // p in r^-p
  // Reflectivity per SemanticClass (index = class value).
  std::array<double, kSemanticClassCount> reflectivity = {0.0, 0.35, 0.9, 0.8, 0.85,
                                                          0.95, 0.75, 1.0, 0.6};
  int speckle_looks = 2;               // multiplicative speckle: Gamma(L, 1/L), mean 1
  double noise_floor = 0.000005;       // additive noise at tvg_reference_m (linear units, exponential intensity); docs/SCENES.md "Calibration" (clean: 0.0003)
  double tvg_exponent = 2.0;           // time-varied gain r^q (q = p: range-independent targets)
  double tvg_reference_m = 10.0;       // range where the TVG is 1
  double gain = 12.0;                  // linear gain before quantisation
  double gamma = 0.5;                  // display gamma of the 8-bit image
  double gain_percent = 50.0;          // what the ping reports as its gain setting
  // --- field profile (the defaults); apply_profile(kClean) switches these off ---
  bool beam_pattern = true;            // azimuth beam pattern: main lobe of head.beam_width_deg + side lobes
  double side_lobe_db = -28.0;         // first side-lobe peak, two-way, re the main lobe
  double side_lobe_floor_db = -55.0;   // the pattern is truncated below this
  double surface_reflection = 0.1;     // intensity reflection coefficient of the sea surface (z = 0)
  double seabed_reflection = 0.0;      // of the seabed plane at the scene's seafloor depth (optional)
  bool seabed_lambert = true;          // seafloor backscatter mu cos^2(theta) with texture and relief
  double seabed_mu = 0.50;             // Lambert's mu (linear, same units as reflectivity)
  double seabed_texture = 0.6;         // grain texture: log-normal sigma of the backscatter
  double seabed_texture_scale_m = 0.4; // its correlation length
  double seabed_relief_deg = 6.0;      // RMS slope of the relief (normal perturbation)
  double seabed_relief_scale_m = 1.5;  // its correlation length
  double absorption_scale = 1.0;       // multiplies each head's absorption (0 = none)
  double tvg_absorption_fraction = 1.0;  // share of the two-way absorption the TVG gives back
  bool noise_before_tvg = true;        // the noise floor is amplified by the TVG (rises with range)
  double water_temperature_c = 12.0;   // for the absorption model
  double salinity_ppt = 35.0;
  double water_ph = 8.0;
  double seafloor_depth_m = 0.0;       // set by the simulator from the scene (seabed multipath)
};
// Sets the fields a profile defines (noise floor, gain and the field-profile block).
void apply_profile(SonarModelConfig& c, SonarProfile p);
// Seawater absorption, dB/m, one-way (Ainslie & McColm 1998), frequency in Hz.
double absorption_db_per_m(double frequency_hz, double temperature_c, double salinity_ppt, double ph, double depth_m);
// The absorption a head applies (its explicit value, else the model's) times absorption_scale.
double head_absorption_db_per_m(const SonarModelConfig& c, const SonarHead& h);

struct VehicleConfig {
  double speed_mps = 0.4;              // 0.3-0.5 m/s
  double max_yaw_rate_dps = 8.0;
  double yaw_gain_per_s = 0.6;         // commanded yaw rate = gain * heading error
  double acceptance_radius_m = 1.5;    // waypoint reached
  double slow_turn_factor = 0.3;       // speed scale at 90 deg heading error
  double roll_amplitude_deg = 0.6;     // small sway: sinusoids, periods below
  double pitch_amplitude_deg = 0.4;
  double roll_period_s = 9.0;
  double pitch_period_s = 13.0;
  double current_x_mps = 0.02;         // water current in W (the autopilot does not correct it)
  double current_y_mps = -0.01;
  double step_s = 0.01;                // integration step (truth sampled here, interpolated)
};

struct NavConfig {
  double imu_rate_hz = 100.0;
  double dvl_rate_hz = 5.0;
  double depth_rate_hz = 5.0;
  double ping_rate_hz = 5.0;
  double ping_offset_s = 0.1;          // first horizontal ping (nav data precedes it)
  double vertical_delay_s = 0.003;     // vertical ping after the horizontal
  double dvl_offset_s = 0.0;
  double depth_offset_s = 0.02;
  double dvl_sigma_mps = 0.01;
  double dvl_invalid_probability = 0.02;
  double dvl_max_altitude_m = 50.0;    // bottom lock lost beyond this
  double imu_roll_pitch_sigma_deg = 0.1;
  double imu_yaw_sigma_deg = 0.2;
  double imu_yaw_bias_walk_deg_per_sqrt_s = 0.05;  // random walk of the yaw bias
  double imu_yaw_bias_rate_dps = 0.004;            // steady drift (2.4 deg over 10 min)
  double imu_gyro_sigma_dps = 0.05;
  double imu_gyro_bias_dps = 0.003;    // constant gyro bias per axis, drawn N(0, this) per mission
                                       // (a MEMS AHRS's ~10 deg/h in-run bias stability)
  double depth_sigma_m = 0.02;
  // Fibre-optic gyro (the paper's KVH DSP-1760, docs/SCENES.md "Navigation profiles"):
  // delta angles (or rates) about its own axes at gyro_rate_hz, with the Earth's rotation
  // at the scene's latitude in them. 0 = no gyro (profiles ahrs and consumer); 250 Hz is
  // the paper profile's, the default.
  double gyro_rate_hz = 250.0;
  bool gyro_rates = false;                     // false: delta angles (rad), as the authors configured it
  double gyro_arw_deg_per_sqrt_h = 0.012;      // angle random walk (datasheet: <= 0.012 deg/sqrt(h))
  double gyro_bias_dph = 0.05;                 // constant bias per axis, drawn N(0, this) per mission
};

// Navigation profiles: named sets of the nav.* values above (YAML `nav_profile`, applied
// before the nav keys, which refine it). paper (the default, NavConfig's values): the
// paper's vehicle, the VN-100 AHRS plus the DSP-1760 FOG at 250 Hz delta angles; ahrs: the
// drifting AHRS alone (every mission before 2026-12-05); consumer: a consumer-grade heading
// (3 deg/min drift, docs/CONFIG.md), no gyro.
enum class NavProfile { kAhrs, kPaper, kConsumer };
const char* nav_profile_name(NavProfile p);
Result<NavProfile> parse_nav_profile(const std::string& s);
void apply_nav_profile(NavConfig& n, NavProfile p);

struct SimConfig {
  SonarProfile profile = SonarProfile::kField;  // what apply_profile gave `sonar` (YAML: profile)
  NavProfile nav_profile = NavProfile::kPaper;  // what apply_nav_profile gave `nav` (YAML: nav_profile)
  double duration_s = 60.0;
  uint64_t seed = 1;                   // noise seed (scene geometry has its own seed)
  Resolution resolution = Resolution::kFull;
  bool labels = false;                 // emit SonarLabels per ping
  SE3 T_V_h = se3_from_xyz_rpy(0.35, 0.0, 0.0, 0.0, 0.0, 0.0);
  SE3 T_V_v = se3_from_xyz_rpy(0.35, 0.0, -0.10, std::numbers::pi / 2.0, 0.0, 0.0);
  SE3 T_V_gyro = SE3::Identity();  // the gyro's mounting (its rotation R_V_G is what matters)
  uint32_t device_id_h = 101;
  uint32_t device_id_v = 102;
  int render_threads = 1;              // pings rendered ahead in parallel (same bytes for any count)
  // Which of the scene's routes to fly: "" or "default" its own, or a named one ("survey":
  // harbor's, the demo's). Applied by sim::select_route where the scene is built, which
  // refuses a route the scene does not offer.
  std::string route;
  SonarModelConfig sonar;
  VehicleConfig vehicle;
  NavConfig nav;
};

// Beams and range bins for a resolution.
struct SonarGeometry {
  int beams = 512;
  int range_bins = 600;
  double range_resolution_m = 0.05;
};
SonarGeometry sonar_geometry(const SonarHead& h, Resolution r);

// Overrides fields from a YAML map whose keys mirror the struct fields, e.g.
// {duration_s: 120, sonar: {gain: 4}, nav: {dvl_sigma_mps: 0.02}}. Unknown keys are errors.
// `profile: clean|field` applies that profile first (whatever its place in the file); then
// `sonar.vertical_mode: 1.2MHz|2.1MHz` picks the M1200d mode; `sonar.horizontal:` and
// `sonar.vertical:` set SonarHead fields.
Status apply_sim_config_yaml(const std::string& yaml_text, SimConfig& config);
// The same from a YAML file; errors name the file.
Status load_sim_config_file(const std::string& path, SimConfig& config);
// Checks every key against its range (the same table the YAML reader uses) and what one
// key's range cannot say: side_lobe_floor_db below side_lobe_db, each head's ping-rate
// ceiling, vertical_delay_s within a ping period, the limits below. A SimConfig that passes
// can be simulated and rendered without overflow, division by zero or NaN.
Status validate(const SimConfig& config);

// Limits across keys (docs/SCENES.md "Valid ranges of the simulator configuration").
inline constexpr double kSimMaxDurationS = 86400.0;         // one day
inline constexpr double kSimMaxSamples = 1e7;               // duration_s / vehicle.step_s, duration_s x nav.imu_rate_hz
inline constexpr int64_t kSimMaxRaysPerHead = 1 << 22;      // beams_full x beam_samples x elevation_samples
inline constexpr double kSimMaxTwoWayAbsorptionDb = 200.0;  // 2 x absorption x max(max_range_m, tvg_reference_m)

// One key of the simulator configuration with its valid range, as docs/SCENES.md lists it
// (`orthosonar simulate --ranges`), and a value outside that range (for tests).
struct SimConfigKeyRange {
  std::string key;        // "vehicle.step_s"
  std::string range;      // "[0.0001, 1]"
  std::string bad_value;  // a YAML value the key rejects
};
std::vector<SimConfigKeyRange> sim_config_key_ranges();

// "x y z roll pitch yaw" (metres, radians), as fixture metadata stores extrinsics.
using config::format_pose6;
using config::parse_pose6;

}  // namespace orthosonar::sim
