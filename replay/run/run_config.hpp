#pragma once
// Run configuration from YAML: every stage's Config (fusion with CFAR, dead reckoning,
// SLAM, mapping) plus run options. Keys mirror the struct fields; unknown keys are errors
// naming the key. Example (see docs/CONFIG.md):
//   threads: 2
//   fusion: {min_confidence: 0.05, cfar_h: {pfa: 0.1, gate: 65}, T_V_h: "0.35 0 0 0 0 0"}
//   dr: {max_speed_mps: 2.0}
//   slam: {kf_distance_m: 3, kf_rotation_deg: 30, icp: {max_iterations: 40}}
//   mapping: {fusion_batch_pairs: 8, voxel_m: 0.1, octomap_resolution_m: 0.1}
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/pipeline.hpp"
#include "core/result.hpp"

namespace orthosonar::run {

inline constexpr int kMaxThreads = 256;

struct RunConfig {
  mapping::PipelineConfig pipeline;
  int threads = 1;
  double voxel_m = 0.1;               // coverage / accuracy voxel
  double octomap_resolution_m = 0.1;  // map.bt
};

// Applies a YAML document to `config` (fields not mentioned keep their values).
Status apply_config_yaml(const std::string& yaml_text, RunConfig& config);
Status load_config_file(const std::string& path, RunConfig& config);
Result<std::string> read_config_text(const std::string& path);

// Every leaf key ("slam.icp.trim_fraction"), its valid range in words, and one value
// outside it (for tests and `orthosonar config --ranges`). Sorted by key.
struct ConfigKeyRange {
  std::string key, range, bad_value;
};
std::vector<ConfigKeyRange> config_key_ranges();
// The configuration as JSON (for summary.json), every field.
nlohmann::json config_to_json(const RunConfig& config);
// "x y z roll pitch yaw" (m, rad).
std::string pose6_string(const SE3& T);

}  // namespace orthosonar::run
