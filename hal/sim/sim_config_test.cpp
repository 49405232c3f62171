// The simulator configuration's ranges (issue 35): every key bounded, an error naming the
// key, and the values that crashed or poisoned a mission before they were bounded.
#include "hal/sim/sim_config.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "hal/sim/trajectory.hpp"

namespace orthosonar::sim {
namespace {

// "a.b.c: v" as nested YAML maps.
std::string sim_config_test_yaml(const std::string& key, const std::string& value) {
  std::string yaml, indent;
  size_t start = 0;
  for (size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
    yaml += indent + key.substr(start, dot - start) + ":\n";
    indent += "  ";
    start = dot + 1;
  }
  return yaml + indent + key.substr(start) + ": " + value + "\n";
}

Status sim_config_test_apply(const std::string& yaml) {
  SimConfig c;
  return apply_sim_config_yaml(yaml, c);
}

}  // namespace

TEST_CASE("the defaults and both profiles are within every range", "[hal]") {
  CHECK(validate(SimConfig{}).ok());
  SimConfig clean;
  apply_profile(clean.sonar, SonarProfile::kClean);
  CHECK(validate(clean).ok());
  for (const char* mode : {"1.2MHz", "2.1MHz"})
    CHECK(sim_config_test_apply(std::string("sonar: {vertical_mode: ") + mode + "}\n").ok());
}

TEST_CASE("every simulator config key rejects a value outside its range, naming the key", "[hal]") {
  const auto ranges = sim_config_key_ranges();
  REQUIRE(ranges.size() >= 100);
  std::set<std::string> keys;
  for (const auto& r : ranges) {
    INFO(r.key << " = " << r.bad_value << " (valid: " << r.range << ")");
    CHECK(keys.insert(r.key).second);
    const Status s = sim_config_test_apply(sim_config_test_yaml(r.key, r.bad_value));
    REQUIRE_FALSE(s.ok());
    CHECK(s.error().message.find("'" + r.key + "'") != std::string::npos);
  }
  // Every numeric key also rejects NaN and infinity (not only its range's far side).
  for (const auto& r : ranges) {
    if (r.range.front() != '[' && r.range.front() != '(') continue;
    for (const char* v : {".nan", ".inf", "-.inf"}) {
      INFO(r.key << " = " << v);
      const Status s = sim_config_test_apply(sim_config_test_yaml(r.key, v));
      REQUIRE_FALSE(s.ok());
      CHECK(s.error().message.find("'" + r.key + "'") != std::string::npos);
    }
  }
}

// Each of these was accepted before the ranges and crashed or poisoned the mission:
// step_s 1e-10 rounds to a 0 ns step (SIGFPE in Trajectory), roll_period_s 0 gives NaN
// poses, duration_s 1e12 sized a reservation of 1e14 samples, elevation x beam samples
// overflowed int, NaN currents and gains went straight into the poses and the image.
TEST_CASE("values that crashed the simulator past validation are errors naming the key", "[hal]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"vehicle: {step_s: 1e-10}\n", "vehicle.step_s"},
      {"vehicle: {roll_period_s: 0}\n", "vehicle.roll_period_s"},
      {"vehicle: {pitch_period_s: 0}\n", "vehicle.pitch_period_s"},
      {"duration_s: 1e12\n", "duration_s"},
      {"sonar: {elevation_samples: 100000, beam_samples: 100000}\n", "sonar.elevation_samples"},
      {"vehicle: {current_x_mps: .nan}\n", "vehicle.current_x_mps"},
      {"nav: {dvl_sigma_mps: .inf}\n", "nav.dvl_sigma_mps"},
      {"sonar: {reflectivity: {piling: .nan}}\n", "sonar.reflectivity.piling"},
      {"seed: -1\n", "seed"},
      {"duration_s: 86400\nvehicle: {step_s: 0.001}\n", "vehicle.step_s"},
      {"duration_s: 86400\nnav: {imu_rate_hz: 1000}\nvehicle: {step_s: 0.01}\n", "nav.imu_rate_hz"},
      {"sonar: {horizontal: {absorption_db_per_m: 10}, max_range_m: 500}\nnav: {ping_rate_hz: 1}\n", "absorption_db_per_m"},
      {"T_V_h: \"0 0 0 0 0 1e300\"\n", "T_V_h"},
  };
  for (const auto& [yaml, key] : cases) {
    INFO(yaml);
    const Status s = sim_config_test_apply(yaml);
    REQUIRE_FALSE(s.ok());
    CHECK(s.error().message.find(key) != std::string::npos);
  }
  // The limit on rays is across keys: beams x beam samples x elevation samples.
  const Status rays = sim_config_test_apply("sonar: {beams_full: 4096, beam_samples: 32, elevation_samples: 64}\n");
  REQUIRE_FALSE(rays.ok());
  CHECK(rays.error().message.find("elevation_samples") != std::string::npos);
  // validate() checks a SimConfig built in code with the same table.
  SimConfig c;
  c.vehicle.step_s = 1e-10;
  const Status s = validate(c);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find("vehicle.step_s") != std::string::npos);
  // A rejected document leaves the config as it was (nothing half-applied).
  SimConfig d;
  REQUIRE_FALSE(apply_sim_config_yaml("duration_s: 5\nvehicle: {step_s: 0}\n", d).ok());
  CHECK(d.duration_s == SimConfig{}.duration_s);
}

TEST_CASE("the extremes of the ranges give a finite trajectory", "[hal]") {
  SimConfig c;
  REQUIRE(apply_sim_config_yaml("duration_s: 100\nvehicle: {step_s: 1e-4, roll_period_s: 0.1, pitch_period_s: 0.1, "
                                "roll_amplitude_deg: 45, speed_mps: 10, max_yaw_rate_dps: 360, yaw_gain_per_s: 100, "
                                "current_x_mps: -10}\n",
                                c)
              .ok());
  const std::vector<Waypoint> route = {{0, 0}, {10, 0}, {10, 10}};
  const Trajectory t(route, 3.0, c.vehicle, Time::from_seconds(c.duration_s));
  for (int k = 0; k <= 1000; ++k) {
    const auto s = t.at(Time::from_ms(100 * k));
    INFO(k);
    REQUIRE(s.T_W_V().matrix().allFinite());
    REQUIRE(s.omega_V_rps.allFinite());
  }
}

TEST_CASE("the limits are what the ranges list says", "[hal]") {
  // Spot checks of the listed ranges against docs/SCENES.md's wording (the full table is
  // compared by cli:sim-config-ranges-doc).
  std::map<std::string, std::string> by_key;
  for (const auto& r : sim_config_key_ranges()) by_key[r.key] = r.range;
  CHECK(by_key.at("vehicle.step_s") == "[0.0001, 1]");
  CHECK(by_key.at("duration_s") == "(0, 86400]");
  CHECK(by_key.at("sonar.elevation_samples") == "integer in [32, 1024]");
  CHECK(by_key.at("vehicle.roll_period_s") == "[0.1, 3600]");
  CHECK(by_key.count("sonar.horizontal.beams_full") == 1);
  CHECK(by_key.count("sonar.reflectivity.seafloor") == 1);
}

}  // namespace orthosonar::sim
