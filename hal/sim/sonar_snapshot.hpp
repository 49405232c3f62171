#pragma once
// Snapshots of both sonars with the vehicle at one chosen pose (`orthosonar simulate
// --snapshot-pose`): one fan PNG per mount, or the clean and field image-formation profiles
// side by side (docs/images/<scene>_profiles.jpg).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "core/geometry.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::sim {

// The vehicle at (x, y) and the scene's vehicle depth, level, heading yaw_deg.
SE3 snapshot_vehicle_pose(const Scene& scene, double x, double y, double yaw_deg);

// One ping of each sonar from T_W_V, as fan images 800 px wide: clean | field, the
// horizontal sonar's row above the vertical's, each cell labelled (BGR).
cv::Mat profile_comparison_image(const Scene& scene, const SimConfig& cfg, const SE3& T_W_V);

// One ping of each sonar from T_W_V with cfg's profile, written as fan PNGs
// <dir>/<scene>_horizontal.png and <dir>/<scene>_vertical.png; returns their paths.
Result<std::vector<std::string>> write_pose_snapshots(const Scene& scene, const SimConfig& cfg, const SE3& T_W_V,
                                                      const std::string& dir);

}  // namespace orthosonar::sim
