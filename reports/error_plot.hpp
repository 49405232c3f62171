#pragma once
// Trajectory error over time: the distance of each estimated pose (dead reckoning, SLAM;
// the keyframes of traj_*.tum) from the ground truth at the same stamp, unaligned as the
// run's ATE (which is taken over every pair, so its RMS differs a little from this one).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "reports/colormap.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::reports {

struct ErrorSeries {
  std::string label;
  std::vector<Eigen::Vector2d> t_error;  // (seconds since the truth's first stamp, metres)
  Rgb colour{0, 0, 0};
};

// The error of `estimate` against `truth` (linear interpolation of the truth's positions;
// estimate poses outside the truth's span are left out). 3D distance when with_z.
ErrorSeries trajectory_error_series(const Trajectory& estimate, const Trajectory& truth, const std::string& label,
                                    Rgb colour, bool with_z = false);

// Fails when no series has two or more samples.
Result<cv::Mat> draw_error_over_time(const std::vector<ErrorSeries>& series, int width_px = 1280, int height_px = 560,
                                     const std::string& title = "trajectory error over time");

}  // namespace orthosonar::reports
