#pragma once
// A top view (x-y, metres, equal aspect) of the trajectories: ground truth, dead
// reckoning and SLAM, with axes, a grid, start/end markers and a legend.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "reports/colormap.hpp"

namespace orthosonar::reports {

struct PlotSeries {
  std::string label;
  std::vector<Eigen::Vector2d> xy_m;
  Rgb colour{0, 0, 0};
};

struct PlotConfig {
  int width_px = 1280;
  int height_px = 960;
  std::string title = "trajectories (top view)";
};

// Fails when no series has two or more points.
Result<cv::Mat> draw_trajectory_plot(const std::vector<PlotSeries>& series, const PlotConfig& config = {});

}  // namespace orthosonar::reports
