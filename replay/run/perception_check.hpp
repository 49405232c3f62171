#pragma once
// perception-check's driver (docs/PERCEPTION.md): measures the perception stage against
// the simulator's truth (core/mapping/perception_metrics.hpp) on simulated missions, one per
// image-formation profile, or on a recorded labelled fixture as recorded, beside raw Oculus
// pings' label-free figures; writes the figures as JSON and the true-pose fused points
// (--cloud) as PLY. `orthosonar perception-check` parses its arguments and prints.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/perception_metrics.hpp"
#include "core/perception/fusion.hpp"
#include "core/result.hpp"
#include "hal/drivers/oculus_ping_file.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/run/run_config.hpp"

namespace orthosonar::run {

struct PerceptionCheckOptions {
  std::string scene = "harbor";  // built-in scene (simulated missions)
  std::string scene_file;        // or a user scene YAML
  std::string fixture;           // or a recorded fixture with labels (simulate --labels)
  std::string profile = "both";  // field, clean or both (simulated missions)
  std::vector<std::string> real_pings;  // raw Oculus SimplePingResult files
  double duration_s = 60.0;
  uint64_t seed = 1;
  std::string resolution = "full";
  std::string sim_config;  // simulator config YAML (refines the profile)
  std::string run_config;  // run configuration YAML (its fusion: section applies)
  int every = 1;           // fuse every n-th pair
  bool keep_points = false;  // keep the fused points (write_cloud)
};

// What one profile (or one fixture) measured.
struct MeasuredProfile {
  std::string label;    // "field", "clean", or "fixture"
  std::string heading;  // "profile field", "fixture F.mcap (profile clean, as recorded)"
  std::string profile;  // the profile of the images (effective / recorded)
  std::string note;     // e.g. "(the sim config sets profile: clean)"
  double max_elevation_sigma_deg = 0;  // the run config's mapping.max_elevation_sigma_deg
  mapping::PerceptionMeasurement m;
};

// A raw Oculus ping and the histogram of all its pixels.
struct RealPing {
  std::string path;
  hal::drivers::oculus::PingResult raw;
  SonarPing ping;
  mapping::IntensityHistogram all;
};
Result<RealPing> load_real_ping(const std::string& path);

class PerceptionCheck {
 public:
  // Reads and checks every input before any measurement: the real pings, the run config,
  // the profile, and the fixture (its labels, scene and configuration) or the scene and
  // resolution. on_fixture_open (may be empty) sees the fixture's recovery report as soon
  // as it is open. Errors name the file or option.
  static Result<PerceptionCheck> open(
      const PerceptionCheckOptions& options,
      const std::function<void(const std::string& path, const replay::RecoveryReport&)>& on_fixture_open = {});

  bool is_fixture() const { return fixture_ != nullptr; }
  const sim::Scene& scene() const { return scene_; }
  // The fixture's metadata value of `key` ("" when absent); "" for simulated missions.
  std::string fixture_metadata(const std::string& key) const;
  sim::Resolution resolution() const { return resolution_; }  // simulated missions
  const std::vector<RealPing>& real_pings() const { return real_; }
  // The CFAR gate the real pings are compared with (the vertical head's: the M1200d's).
  double gate_real() const { return gate_real_; }

  // Measures the fixture, or simulates and measures each profile in turn (field first).
  Status measure();
  const std::vector<MeasuredProfile>& results() const { return results_; }

  // Every figure (deterministic: no timings), the document `--json` writes.
  nlohmann::json to_json() const;
  Status write_json(const std::string& path) const;

 private:
  PerceptionCheck() = default;
  Status open_fixture(const std::function<void(const std::string&, const replay::RecoveryReport&)>& on_open);
  Status measure_fixture();
  Status measure_profiles();

  PerceptionCheckOptions o_;
  std::vector<RealPing> real_;
  RunConfig run_;          // defaults, or the run config's values
  std::vector<sim::SonarProfile> profiles_;
  std::unique_ptr<replay::FixtureSource> fixture_;
  perception::FusionConfig fixture_fusion_;  // the fixture's effective configuration
  sim::Scene scene_;
  sim::Resolution resolution_ = sim::Resolution::kFull;
  double gate_real_ = 0.0;
  std::vector<MeasuredProfile> results_;
};

// The --cloud file of one measured profile: `path` itself when one profile was measured,
// else "<stem>_<label><ext>".
std::string cloud_path_for(const std::string& path, const std::string& label, size_t n_results);
// The true-pose fused points as a PLY (hal/sim's point writer), one vertex per point with
// its distance to the mesh and the fusion's range, bearing, elevation, confidence and stamp.
Status write_cloud(const std::string& path, const mapping::FusionTally& fusion);

}  // namespace orthosonar::run
