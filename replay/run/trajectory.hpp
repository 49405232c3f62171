#pragma once
// Trajectory and keyframe-table files (outputs contract): TUM trajectories
// ("t x y z qx qy qz qw", t in seconds with 9 decimals) that evo reads, and keyframes.csv.
// File I/O lives here, in tools, not in core.
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/result.hpp"
#include "core/slam/keyframe_slam.hpp"
#include "core/time.hpp"
#include "replay/run/truth_spill.hpp"

namespace orthosonar::run {

struct StampedPose {
  Time stamp;
  SE3 T_W_V;
};

// One TUM line without the newline. Exact stamp from integer ns; quaternion with qw >= 0.
std::string tum_line(Time stamp, const SE3& T_W_V);
std::string tum_text(const std::vector<StampedPose>& poses);
Status write_tum(const std::string& path, const std::vector<StampedPose>& poses);
// Ground truth as a TUM file, written line by line (a long mission has ~110 poses per second:
// no second copy of them in memory).
Status write_tum(const std::string& path, const std::vector<TruthPose>& truth);
// The same from a run's truth on disk (same bytes as from the poses in memory).
Status write_tum(const std::string& path, const TruthSpill& truth);

// DR and SLAM keyframe trajectories.
std::vector<StampedPose> keyframe_poses_dr(const slam::KeyframeSlam& slam);
std::vector<StampedPose> keyframe_poses_slam(const slam::KeyframeSlam& slam);

// keyframes.csv: one row per keyframe; header
//   id,stamp_ns,dr_x,dr_y,dr_z,dr_roll,dr_pitch,dr_yaw,slam_x,...,slam_yaw,factors
// where factors lists every factor ending at that keyframe as
//   kind:from>to:accepted (accepted is 1 or 0), separated by ';'.
std::string keyframe_table_csv(const slam::KeyframeSlam& slam);
Status write_keyframe_table(const std::string& path, const slam::KeyframeSlam& slam);

// factors.csv: one row per SLAM factor, in creation order; header
//   kind,from,to,x,y,theta,sigma_x,sigma_y,sigma_theta,weakened,accepted,robust_weight,reason,
//   true_x,true_y,true_theta,err_x,err_y,err_theta
// (x, y, theta: the measured relative pose from -> to in the `from` keyframe's plane frame,
// metres and radians; the true_ and err_ columns (measured - true, theta wrapped) are
// filled when `truth` spans both keyframes, else empty; the prior's are always empty).
// Shows each scan match's bias against the simulator's truth.
std::string factor_table_csv(const slam::KeyframeSlam& slam, const std::vector<TruthPose>& truth);
Status write_factor_table(const std::string& path, const slam::KeyframeSlam& slam,
                          const std::vector<TruthPose>& truth);

}  // namespace orthosonar::run
