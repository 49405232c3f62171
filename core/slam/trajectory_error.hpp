#pragma once
// Absolute trajectory error (SPEC §7): RMSE of estimated positions against ground truth at
// the same stamps (keyframes). The dead-reckoning frame starts wherever DrConfig puts it,
// so by default both trajectories are first translated so their first positions coincide
// (rotation is not aligned: yaw comes from the IMU and its drift is part of the error).
#include <vector>

#include "core/geometry.hpp"
#include "core/result.hpp"

namespace orthosonar::slam {

enum class AteAlignment { kNone, kFirstPosition };

// est and truth are paired by index. Empty trajectories or different sizes are an Error
// (naming both sizes), never a score: a 0 there would read as a perfect trajectory.
Result<double> ate_rmse(const std::vector<Vec3>& est, const std::vector<Vec3>& truth,
                        AteAlignment alignment = AteAlignment::kFirstPosition);

// "SLAM no worse than DR": a SLAM trajectory that is DR's (no scan match or loop closure
// added anything) differs from it by rounding in the graph solve, 1e-15 m; a nanometre of
// ATE is a tie, not a loss.
inline constexpr double kAteTieM = 1e-9;
inline bool slam_no_worse_than_dr(double ate_slam_m, double ate_dr_m) { return ate_slam_m <= ate_dr_m + kAteTieM; }

}  // namespace orthosonar::slam
