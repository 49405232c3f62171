// Both sonars rendered once at a chosen vehicle pose (see sonar_snapshot.hpp).
#include "hal/sim/sonar_snapshot.hpp"

#include <algorithm>
#include <filesystem>
#include <numbers>

#include <opencv2/imgproc.hpp>

#include "hal/sim/sonar_fan.hpp"
#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {
namespace {

// The scene's seafloor depth in the sonar model (as the simulator sets it).
SonarModelConfig scene_sonar(const Scene& scene, const SimConfig& cfg) {
  SonarModelConfig sonar = cfg.sonar;
  sonar.seafloor_depth_m = scene.seafloor_depth_m;
  return sonar;
}

}  // namespace

SE3 snapshot_vehicle_pose(const Scene& scene, double x, double y, double yaw_deg) {
  return se3_from_xyz_rpy(x, y, -scene.vehicle_depth_m, 0, 0, yaw_deg * std::numbers::pi / 180.0);
}

cv::Mat profile_comparison_image(const Scene& scene, const SimConfig& cfg, const SE3& T_W_V) {
  const SonarModelConfig sonar = scene_sonar(scene, cfg);
  std::vector<cv::Mat> rows;
  for (auto mount : {SonarMount::kHorizontal, SonarMount::kVertical}) {
    const bool h = mount == SonarMount::kHorizontal;
    std::vector<cv::Mat> cells;
    for (auto profile : {SonarProfile::kClean, SonarProfile::kField}) {
      SonarModelConfig c = sonar;
      apply_profile(c, profile);
      const SonarRenderer r(scene.mesh, c, cfg.resolution, cfg.seed);
      cv::Mat fan = fan_image(r.render(T_W_V * (h ? cfg.T_V_h : cfg.T_V_v), mount, Time::from_s(0), 0).ping, 800);
      cv::cvtColor(fan, fan, cv::COLOR_GRAY2BGR);
      const std::string label = std::string(profile_name(profile)) + (h ? ": M750d, horizontal" : ": M1200d, vertical");
      cv::putText(fan, label, {12, 30}, cv::FONT_HERSHEY_SIMPLEX, h ? 0.8 : 0.6, {80, 200, 255}, 2);
      cells.push_back(fan);
    }
    cv::Mat row;
    cv::hconcat(cells, row);
    rows.push_back(row);
  }
  const int w = std::max(rows[0].cols, rows[1].cols);
  for (cv::Mat& r : rows) cv::copyMakeBorder(r, r, 0, 0, 0, w - r.cols, cv::BORDER_CONSTANT, {24, 24, 24});
  cv::Mat all;
  cv::vconcat(rows, all);
  return all;
}

Result<std::vector<std::string>> write_pose_snapshots(const Scene& scene, const SimConfig& cfg, const SE3& T_W_V,
                                                      const std::string& dir) {
  const SonarRenderer renderer(scene.mesh, scene_sonar(scene, cfg), cfg.resolution, cfg.seed);
  std::vector<std::string> paths;
  for (auto mount : {SonarMount::kHorizontal, SonarMount::kVertical}) {
    const bool h = mount == SonarMount::kHorizontal;
    const auto r = renderer.render(T_W_V * (h ? cfg.T_V_h : cfg.T_V_v), mount, Time::from_s(0), 0);
    const auto path = (std::filesystem::path(dir) / (scene.name + (h ? "_horizontal.png" : "_vertical.png"))).string();
    if (Status s = write_fan_png(r.ping, path, 800); !s) return s.error();
    paths.push_back(path);
  }
  return paths;
}

}  // namespace orthosonar::sim
