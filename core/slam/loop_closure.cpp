// Loop closures (NSSM, SPEC §5): candidates among the older keyframes in sonar range,
// the ICP fit against their aggregated view, the gates against the odometry chain, and
// PCM over the queue of pending loops; accepted loops share their errors by distance.
// Part of KeyframeSlam (core/slam/keyframe_slam.hpp); sequential matching and the graph's
// solve are in keyframe_slam.cpp.
#include "core/slam/keyframe_slam.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace orthosonar::slam {
namespace {

// A loop fitted in translation only says so at every stage of its reason.
std::string with_heading_note(std::string reason, const Factor& f) {
  return f.heading_from_chain ? reason + " (heading from the chain)" : reason;
}

}  // namespace

void KeyframeSlam::loop_closure(int id) {
  const int newest_old = id - config_.nssm_min_separation;
  if (newest_old < 0) return;
  const auto& cur = keyframes_[static_cast<size_t>(id)];
  if (cur.cloud_V.size() < config_.nssm_min_points) return;
  const SE2& T_W_new = poses_[static_cast<size_t>(id)];
  const Eigen::Vector2d sonar_W = T_W_new * Eigen::Vector2d(config_.sonar_x_m, 0.0);
  // Candidate keyframes: old enough, within sonar range and, on an AHRS, seen from the same
  // side; the nearest few (ties by id); the anchor is the nearest. (With a FOG's heading a
  // loop's own heading is gated to the chain's instead: disagrees_with_chain.)
  const bool view_gate = !dr_from_sensors_ && config_.nssm_max_view_change_deg > 0.0;
  std::vector<std::pair<double, int>> near, other_side;
  const double travelled = path_m_[static_cast<size_t>(id)];
  for (int k = 0; k <= newest_old; ++k) {
    // Also far enough back along the path: with dense keyframes, min_separation keyframes
    // can be a few metres of the same wall, and a "loop" there is a sequential match that
    // slides along it (docs/SLAM.md).
    if (travelled - path_m_[static_cast<size_t>(k)] < config_.nssm_min_travel_m) continue;
    // Seen from the same side: the sonar's 2D outline of a 3D structure changes with the
    // view (docs/SLAM.md "Loops from the same side").
    const double d = (poses_[static_cast<size_t>(k)].translation() - sonar_W).norm();
    if (d > config_.nssm_range_m) continue;
    const bool same_side = !view_gate ||
                           std::abs(wrap_angle(poses_[static_cast<size_t>(k)].theta - T_W_new.theta)) <=
                               config_.nssm_max_view_change_deg * kRadPerDeg;
    (same_side ? near : other_side).emplace_back(d, k);
  }
  // None from the same side: the other side's loops are biased in heading by the view (a
  // degree on the aircraft): nssm_other_side says whether to take them, and how.
  using OtherSide = SlamConfig::OtherSide;
  const bool other_side_loop = near.empty() && !other_side.empty() && config_.nssm_other_side != OtherSide::kNone;
  if (other_side_loop) near.swap(other_side);
  std::sort(near.begin(), near.end());
  if (near.size() > static_cast<size_t>(std::max(config_.nssm_max_target_frames, 1))) {
    near.resize(static_cast<size_t>(std::max(config_.nssm_max_target_frames, 1)));
  }
  const int anchor = near.empty() ? -1 : near.front().second;
  std::vector<int> ids;
  for (const auto& [d, k] : near) {
    if (config_.nssm_target_same_pass && anchor >= 0 &&
        std::abs(path_m_[static_cast<size_t>(k)] - path_m_[static_cast<size_t>(anchor)]) > config_.nssm_min_travel_m)
      continue;
    ids.push_back(k);
  }
  std::sort(ids.begin(), ids.end());
  if (anchor < 0) return;
  // Field-of-view gating: only target points the new keyframe's sonar could have seen.
  const SE2 T_anchor_new = poses_[static_cast<size_t>(anchor)].inverse() * T_W_new;
  const SE2 T_new_anchor = T_anchor_new.inverse();
  const auto target = gate_to_sonar_view(aggregate(ids, anchor), T_new_anchor, gate_range_m(),
                                         gate_fov_deg(), config_.sonar_x_m);
  // The source: the new keyframe's cloud, or that and its predecessors' (never the
  // target's: they are nssm_min_separation keyframes back or more).
  const int first_source = std::max({0, id - config_.nssm_source_frames + 1, newest_old + 1});
  std::vector<int> source_ids;
  for (int k = first_source; k <= id; ++k) source_ids.push_back(k);
  std::vector<Eigen::Vector2d> aggregated;  // only when the source is several keyframes
  if (source_ids.size() > 1) aggregated = aggregate(source_ids, id);
  const auto source = seen_from(source_ids.size() > 1 ? aggregated : cur.cloud_V, T_W_new, ids);
  if (target.size() < config_.nssm_min_points || source.size() < config_.nssm_min_points) return;
  const bool fixed_heading = (dr_from_sensors_ && config_.nssm_fixed_heading_gyro) ||
                             (other_side_loop && config_.nssm_other_side == OtherSide::kTranslation);
  IcpConfig icp_config = config_.icp;
  icp_config.fix_rotation = fixed_heading;
  const IcpResult icp = icp_2d(source, target, T_anchor_new, icp_config);
  Factor f{FactorKind::kLoopClosure, anchor, id, icp.T_target_source,
           dr_from_sensors_ ? config_.sigma_loop_gyro : config_.sigma_loop, false, ""};
  // With a gyro only (docs/SLAM.md "Loop error against baseline"): on a drifting AHRS the
  // long loops are what corrects the heading, and weighing them less costs more than their
  // translation error.
  if (dr_from_sensors_ && config_.sigma_loop_per_m > 0.0) {
    const double grow = config_.sigma_loop_per_m * std::hypot(icp.T_target_source.x, icp.T_target_source.y);
    f.sigma.x() = std::hypot(f.sigma.x(), grow);
    f.sigma.y() = std::hypot(f.sigma.y(), grow);
  }
  f.source_frames = static_cast<int>(source_ids.size());
  for (int k : ids)
    f.target_span_m = std::max(f.target_span_m, std::abs(path_m_[static_cast<size_t>(k)] - path_m_[static_cast<size_t>(anchor)]));
  if (!icp.converged) {
    f.reason = "icp not converged";
  } else if (icp.rmse > config_.nssm_max_rmse_m) {
    f.reason = "icp rmse too large";
  } else if (icp.inliers < config_.nssm_min_points) {
    f.reason = "too few icp inliers";
  } else {
    shape(f, source, target, fixed_heading);  // appends its weak directions to the reason
    if (disagrees_with_chain(f)) {
      f.reason = "loop disagrees with the odometry chain" + f.reason;
    } else {
      f.reason = "pcm pending" + f.reason;
      pcm_queue_.push_back(static_cast<int>(factors_.size()));
    }
  }
  factors_.push_back(std::move(f));
  while (static_cast<int>(pcm_queue_.size()) > config_.pcm_queue) {
    Factor& old = factors_[static_cast<size_t>(pcm_queue_.front())];
    if (!old.accepted) old.reason = with_heading_note("pcm rejected", old);
    pcm_queue_.erase(pcm_queue_.begin());
  }
  run_pcm();
}

bool KeyframeSlam::disagrees_with_chain(const Factor& loop) const {
  const bool heading_sigmas = !dr_from_sensors_ && config_.nssm_max_heading_sigmas > 0.0;
  const bool heading_gyro = dr_from_sensors_ && config_.nssm_max_heading_diff_gyro_deg > 0.0;
  if (config_.nssm_max_mahalanobis <= 0.0 && !heading_sigmas && !heading_gyro) return false;
  // The loop against the graph's own estimate of the same relative pose, with the odometry
  // chain's covariance: an ICP that converged to another local minimum metres or degrees
  // away is rejected here even when several such loops agree with one another (PCM).
  const UncertainSE2 chain = odometry_between(loop.from, loop.to);
  const SE2 diff = chain.T.inverse() * loop.T_from_to;
  const Eigen::Vector3d d(diff.x, diff.y, wrap_angle(diff.theta));
  const Eigen::Matrix3d joint = chain.cov + loop.covariance();
  if (config_.nssm_max_mahalanobis > 0.0 && !(squared_mahalanobis(d, joint) <= config_.nssm_max_mahalanobis))
    return true;
  // On an AHRS the loop's graph sigma (sigma_loop, 0.05 rad) is loose on purpose, and the
  // joint test above lets a loop through that is turned by several degrees more than the
  // chain can have drifted: its heading is tested alone, against the chain's heading sigma
  // and what one scan match's fit knows (sigma_icp), as the gyro's is below.
  if (heading_sigmas && !(std::abs(d.z()) <= config_.nssm_max_heading_sigmas *
                                                 std::sqrt(chain.cov(2, 2) + config_.sigma_icp.z() * config_.sigma_icp.z())))
    return true;
  // With a FOG's heading the chain knows the relative heading to hundredths of a degree; a
  // loop turned by more than this is ICP's other minimum, whatever its translation says.
  return heading_gyro && std::abs(d.z()) > config_.nssm_max_heading_diff_gyro_deg * kRadPerDeg;
}

UncertainSE2 KeyframeSlam::odometry_between(int i, int j) const {
  if (i > j) return inverse(odometry_between(j, i));
  UncertainSE2 chain;  // identity, zero covariance
  for (int k = i + 1; k <= j; ++k) {
    const Factor& f = factors_[static_cast<size_t>(sequential_factor_[static_cast<size_t>(k)])];
    chain = compose(chain, {f.T_from_to, sequential_cov_[static_cast<size_t>(k)]});
  }
  chain.T = poses_[static_cast<size_t>(i)].inverse() * poses_[static_cast<size_t>(j)];
  return chain;
}

void KeyframeSlam::run_pcm() {
  const size_t n = pcm_queue_.size();
  if (n < static_cast<size_t>(std::max(config_.min_pcm, 1))) return;
  std::vector<LoopCandidate> candidates;
  for (int i : pcm_queue_) {
    const Factor& f = factors_[static_cast<size_t>(i)];
    candidates.push_back({f.from, f.to, {f.T_from_to, f.covariance()}});
  }
  const Adjacency adj = pcm_consistency(
      candidates, [this](int i, int j) { return odometry_between(i, j); }, config_.pcm_threshold);
  const std::vector<int> clique = maximum_clique(adj);
  if (static_cast<int>(clique.size()) < config_.min_pcm) return;
  for (int c : clique) {
    const size_t i = static_cast<size_t>(pcm_queue_[static_cast<size_t>(c)]);
    if (!factors_[i].accepted) accept_loop(i, clique.size());
  }
}

void KeyframeSlam::accept_loop(size_t factor, size_t clique_size) {
  Factor& f = factors_[factor];
  f.accepted = true;
  f.reason = with_heading_note("pcm clique of " + std::to_string(clique_size), f);
  const double ell = config_.loop_correlation_m;
  if (ell > 0.0) {
    // Distances between the keyframes' DR positions: fixed once added, so a loop's share
    // does not move with the estimate, only with the loops accepted after it.
    const auto at = [this](int k) -> Eigen::Vector2d {
      return keyframes_[static_cast<size_t>(k)].T_W_V_dr.translation().head<2>();
    };
    for (size_t j : accepted_loops_) {
      Factor& g = factors_[j];
      const double d = std::max((at(f.from) - at(g.from)).norm(), (at(f.to) - at(g.to)).norm());
      const double rho = std::exp(-d / ell);
      f.shared += rho;
      g.shared += rho;
    }
  }
  accepted_loops_.push_back(factor);
}

}  // namespace orthosonar::slam
