#include "core/slam/keyframe_slam.hpp"

#include "core/memory.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace orthosonar::slam {
namespace {

Eigen::Matrix3d covariance(const Eigen::Vector3d& sigma) {
  return sigma.cwiseProduct(sigma).asDiagonal();
}

// The directions a sigma-whitened fit Hessian Hu (u = e / sigma: nominal information the
// identity) observes weakly: its eigenvectors V (columns) and weights w = λ / (ratio λmax)
// clamped to [0, 1]. Returns how many weights are below 1, or -1 when Hu observes nothing
// (V and w then untouched).
template <int N>
int weak_directions(const Eigen::Matrix<double, N, N>& Hu, double ratio, Eigen::Matrix<double, N, N>& V,
                    Eigen::Matrix<double, N, 1>& w) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(Hu);
  const Eigen::Matrix<double, N, 1> lambda = es.eigenvalues();  // ascending
  if (!(lambda(N - 1) > 0.0)) return -1;
  int weakened = 0;
  for (int k = 0; k < N; ++k) {
    w(k) = std::clamp(lambda(k) / (ratio * lambda(N - 1)), 0.0, 1.0);
    if (w(k) < 1.0) ++weakened;
  }
  V = es.eigenvectors();
  return weakened;
}

}  // namespace

Eigen::Matrix3d Factor::information() const {
  const Eigen::Matrix3d D = sigma.cwiseInverse().asDiagonal();
  return D * mix.transpose() * mix * D;
}

Eigen::Matrix3d Factor::covariance() const {
  if (mix.isIdentity(0.0)) return slam::covariance(sigma);
  const Eigen::Matrix3d S = sigma.asDiagonal();
  const Eigen::Matrix3d W = mix.transpose() * mix + 1e-6 * Eigen::Matrix3d::Identity();
  return S * W.inverse() * S;
}

void KeyframeSlam::shape(Factor& f, const std::vector<Eigen::Vector2d>& source,
                         const std::vector<Eigen::Vector2d>& target, bool translation_only) const {
  if (translation_only) {
    // The heading row of the residual is dropped (weight 0: covariance() then reads it as
    // unobserved); the translation block is shaped as the full fit is below.
    Eigen::Matrix2d V = Eigen::Matrix2d::Identity();
    Eigen::Vector2d w = Eigen::Vector2d::Ones();
    int weakened = 0;
    if (config_.degeneracy_ratio > 0.0) {
      const FitInformation fit = icp_fit_information(source, target, f.T_from_to, config_.fit_information);
      const Eigen::Matrix2d S = f.sigma.head<2>().asDiagonal();
      const Eigen::Matrix2d Hu = S * fit.hessian.topLeftCorner<2, 2>() * S;
      weakened = std::max(0, weak_directions<2>(Hu, config_.degeneracy_ratio, V, w));
    }
    f.mix.setZero();
    f.mix.topLeftCorner<2, 2>() = w.cwiseSqrt().asDiagonal() * V.transpose();
    f.weakened = weakened + 1;
    f.heading_from_chain = true;
    f.reason += " (heading from the chain";
    if (weakened > 0) f.reason += ", " + std::to_string(weakened) + " weak direction" + (weakened > 1 ? "s" : "");
    f.reason += ")";
    return;
  }
  if (config_.degeneracy_ratio <= 0.0) return;
  const FitInformation fit = icp_fit_information(source, target, f.T_from_to, config_.fit_information);
  // In sigma-whitened coordinates u = e / sigma the nominal information is the identity.
  const Eigen::Matrix3d S = f.sigma.asDiagonal();
  const Eigen::Matrix3d Hu = S * fit.hessian * S;
  Eigen::Matrix3d V;
  Eigen::Vector3d w;
  const int weakened = weak_directions<3>(Hu, config_.degeneracy_ratio, V, w);
  if (weakened <= 0) return;  // nothing observed, or fully observed: the diagonal sigmas as they are
  f.mix = w.cwiseSqrt().asDiagonal() * V.transpose();
  f.weakened = weakened;
  f.reason += " (" + std::to_string(weakened) + " weak direction" + (weakened > 1 ? "s)" : ")");
}

const char* factor_kind_name(FactorKind k) {
  switch (k) {
    case FactorKind::kPrior: return "prior";
    case FactorKind::kOdometryDr: return "odometry_dr";
    case FactorKind::kSequentialIcp: return "ssm_icp";
    case FactorKind::kLoopClosure: return "loop_closure";
    case FactorKind::kHeadingLink: return "heading_link";
  }
  return "unknown";
}

KeyframeSlam::KeyframeSlam(SlamConfig config) : config_(std::move(config)) {}

bool KeyframeSlam::should_add(const SE3& T_W_V_dr) const {
  if (keyframes_.empty()) return true;
  const SE2 last = se2_from_se3(keyframes_.back().T_W_V_dr);
  const SE2 now = se2_from_se3(T_W_V_dr);
  const double dist = std::hypot(now.x - last.x, now.y - last.y);
  const double dyaw = std::abs(wrap_angle(now.theta - last.theta));
  return dist >= config_.kf_distance_m || dyaw >= config_.kf_rotation_deg * kRadPerDeg;
}

double KeyframeSlam::drift_sigma_dps() const {
  return dr_from_sensors_ ? config_.heading_drift_sigma_gyro_dps : config_.heading_drift_sigma_dps;
}

size_t KeyframeSlam::accepted_loop_closures() const {
  return static_cast<size_t>(std::count_if(factors_.begin(), factors_.end(), [](const Factor& f) {
    return f.kind == FactorKind::kLoopClosure && f.accepted;
  }));
}

int KeyframeSlam::add_keyframe(Time stamp, const SE3& T_W_V_dr,
                               std::vector<Eigen::Vector2d> planar_points_V,
                               DrSigma dr_sigma) {
  const int id = static_cast<int>(keyframes_.size());
  sigma_dr_ = config_.sigma_odometry;
  using Model = SlamConfig::DrSigmaModel;
  const Model model = config_.dr_sigma_model;
  if (dr_sigma.heading_rad && model != Model::kConstant)
    sigma_dr_.z() = std::max(*dr_sigma.heading_rad, config_.gyro_heading_sigma_min_deg * kRadPerDeg);
  const bool sensors = model == Model::kSensors || (model == Model::kAuto && dr_sigma.heading_rad.has_value());
  dr_from_sensors_ = sensors && dr_sigma.translation_m.has_value();
  if (dr_from_sensors_) {
    const double t = std::max(*dr_sigma.translation_m, config_.dr_translation_sigma_min_m);
    sigma_dr_.x() = sigma_dr_.y() = t;
  }
  Keyframe kf;
  kf.id = id;
  kf.stamp = stamp;
  kf.T_W_V_dr = T_W_V_dr;
  kf.T_W_V_slam = T_W_V_dr;
  kf.cloud_V = prepare_planar_cloud(
      planar_points_V, {config_.voxel_m, config_.outlier_radius_m, config_.outlier_min_neighbours});
  path_m_.push_back(id == 0 ? 0.0
                            : path_m_.back() + (T_W_V_dr.translation() - keyframes_.back().T_W_V_dr.translation())
                                                   .head<2>()
                                                   .norm());
  keyframes_.push_back(std::move(kf));
  const size_t loops_before = accepted_loop_closures();
  if (id == 0) {
    const SE2 prior = se2_from_se3(T_W_V_dr);
    poses_.push_back(prior);
    sequential_factor_.push_back(-1);
    sequential_cov_.push_back(Eigen::Matrix3d::Zero());
    factors_.push_back({FactorKind::kPrior, 0, 0, prior, config_.sigma_prior, true, "first pose"});
  } else {
    sequential_match(id);
    loop_closure(id);
  }
  const bool linked = id > 0 && link_heading(id);
  // No loop closure joined the graph: the new keyframe hangs off the previous one alone,
  // and the optimum of the rest is the one already solved (solve_leaf_pose).
  const bool drift_update = drift_sigma_dps() > 0.0 && config_.heading_drift_every_keyframes > 0 &&
                            id % config_.heading_drift_every_keyframes == 0;
  solve(id > 0 && accepted_loop_closures() == loops_before && !drift_update && !linked ? id : -1);
  return id;
}

bool KeyframeSlam::link_heading(int id) {
  if (config_.heading_link_s <= 0.0) return false;
  const int from = heading_link_anchor_;
  const double dt = seconds_between(from, id);
  if (dt < config_.heading_link_s) return false;
  heading_link_anchor_ = id;
  const SE2 a = se2_from_se3(keyframes_[static_cast<size_t>(from)].T_W_V_dr);
  const SE2 b = se2_from_se3(keyframes_[static_cast<size_t>(id)].T_W_V_dr);
  const double walk = config_.heading_link_walk_dps * kRadPerDeg, white = config_.heading_link_white_deg * kRadPerDeg;
  Factor f{FactorKind::kHeadingLink, from, id, a.inverse() * b, {1.0, 1.0, std::sqrt(walk * walk * dt + 2.0 * white * white)},
           true, "heading link over " + std::to_string(static_cast<int>(std::lround(dt))) + " s"};
  f.mix = Eigen::Vector3d(0.0, 0.0, 1.0).asDiagonal();  // yaw only: x and y carry no residual
  f.weakened = 2;
  factors_.push_back(std::move(f));
  return true;
}

std::vector<Eigen::Vector2d> KeyframeSlam::aggregate(const std::vector<int>& ids, int frame) const {
  std::vector<Eigen::Vector2d> out;
  const SE2 T_frame_W = poses_[static_cast<size_t>(frame)].inverse();
  for (int k : ids) {
    const SE2 T_frame_k = T_frame_W * poses_[static_cast<size_t>(k)];
    for (const auto& p : keyframes_[static_cast<size_t>(k)].cloud_V) out.push_back(T_frame_k * p);
  }
  return out;
}

std::vector<Eigen::Vector2d> KeyframeSlam::seen_from(const std::vector<Eigen::Vector2d>& cloud_V,
                                                     const SE2& T_W_V,
                                                     const std::vector<int>& ids) const {
  std::vector<SE2> T_k_V;
  for (int k : ids) T_k_V.push_back(poses_[static_cast<size_t>(k)].inverse() * T_W_V);
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : cloud_V) {
    for (const SE2& T : T_k_V) {
      if (in_sonar_view(T * p, gate_range_m(), gate_fov_deg(), config_.sonar_x_m)) {
        out.push_back(p);
        break;
      }
    }
  }
  return out;
}

void KeyframeSlam::sequential_match(int id) {
  const auto& cur = keyframes_[static_cast<size_t>(id)];
  const int prev = id - 1;
  const SE2 T_dr = se2_from_se3(keyframes_[static_cast<size_t>(prev)].T_W_V_dr).inverse() *
                   se2_from_se3(cur.T_W_V_dr);
  // DR's motion as the graph expects it (less the estimated heading drift): the ICP guess,
  // the gate, and the new pose's starting value. The factor keeps the measurement.
  SE2 T_dr_expected = T_dr;
  T_dr_expected.theta -= heading_drift_rad_s_ * seconds_between(prev, id);
  std::vector<int> targets;
  for (int k = std::max(0, id - config_.ssm_target_frames); k < id; ++k) targets.push_back(k);
  // Both clouds cropped to what the other side could have seen (initial guess = DR), so
  // structure seen by only one of them does not pull the fit.
  const auto target = gate_to_sonar_view(aggregate(targets, prev), T_dr_expected.inverse(),
                                         gate_range_m(), gate_fov_deg(), config_.sonar_x_m);
  const auto source = seen_from(cur.cloud_V, poses_[static_cast<size_t>(prev)] * T_dr_expected, targets);
  Factor f{FactorKind::kOdometryDr, prev, id, T_dr, sigma_dr_, true, "dead reckoning"};
  if (source.size() < config_.ssm_min_points || target.size() < config_.ssm_min_points) {
    f.reason = "dead reckoning: too few points for icp";
  } else {
    const IcpResult icp = icp_2d(source, target, T_dr_expected, config_.icp);
    Factor m{FactorKind::kSequentialIcp, prev, id, icp.T_target_source, config_.sigma_icp, false, ""};
    if (icp.converged) shape(m, source, target);
    const SE2 diff = T_dr_expected.inverse() * icp.T_target_source;
    bool close = std::hypot(diff.x, diff.y) <= config_.ssm_max_translation_m &&
                 std::abs(diff.theta) <= config_.ssm_max_rotation_deg * kRadPerDeg;
    if (close && config_.ssm_max_mahalanobis > 0.0) {
      // ICP and DR measure the same motion: a disagreement beyond their joint noise is a
      // scan-match failure (a slide along a wall, a viewpoint-dependent outline). Directions
      // the fit does not observe carry a large ICP variance, so they are not judged.
      const Eigen::Matrix3d joint = covariance(sigma_dr_) + m.covariance();
      const Eigen::Vector3d d(diff.x, diff.y, diff.theta);
      close = squared_mahalanobis(d, joint) <= config_.ssm_max_mahalanobis;
    }
    // A match that adds little to what DR already knows (a fibre-optic gyro's heading and a
    // DVL's translation: a few per cent of the information in every direction) is left out:
    // its errors are biased on one-sided structure (docs/SLAM.md "SSM and DR together"), and a
    // small bias repeated at every keyframe adds up where the little information does not.
    bool informative = true;
    if (icp.converged && close && config_.ssm_min_information_ratio > 0.0) {
      const Eigen::DiagonalMatrix<double, 3> s(sigma_dr_);
      const Eigen::Matrix3d gain = s * m.information() * s;
      informative = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(gain, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() >=
                    config_.ssm_min_information_ratio;
    }
    if (icp.converged && close && !informative) {
      m.reason = "icp adds under " + std::to_string(static_cast<int>(config_.ssm_min_information_ratio * 100.0 + 0.5)) +
                 " % of dead reckoning's information" + m.reason;
      factors_.push_back(std::move(m));
      f.reason = "dead reckoning: icp adds little";
    } else if (icp.converged && close) {
      m.accepted = true;
      m.reason = "icp converged" + m.reason;
      f = std::move(m);
    } else {
      // Keep the failed match on record, then fall back to DR so the graph never breaks.
      m.reason = (icp.converged ? "icp disagrees with dead reckoning" : "icp not converged") + m.reason;
      factors_.push_back(std::move(m));
      f.reason = "dead reckoning: icp rejected";
    }
  }
  poses_.push_back(poses_[static_cast<size_t>(prev)] *
                   (f.kind == FactorKind::kOdometryDr ? T_dr_expected : f.T_from_to));
  const bool icp_accepted = f.kind == FactorKind::kSequentialIcp;
  sequential_factor_.push_back(static_cast<int>(factors_.size()));
  factors_.push_back(std::move(f));
  if (icp_accepted && config_.ssm_keep_dr_factor) {
    // DR and the sonar are independent measurements of the same motion: keep both, so a
    // biased scan match (a wall seen end-on, a hull outline that changes with viewpoint)
    // is weighed against DR instead of replacing it (docs/SLAM.md "SSM and DR together").
    factors_.push_back({FactorKind::kOdometryDr, prev, id, T_dr, sigma_dr_, true,
                        "dead reckoning (beside icp)"});
  }
  // The motion prev -> id as the graph knows it (PCM's odometry chain): ICP and the DR
  // factor beside it, informations added.
  const size_t first = static_cast<size_t>(sequential_factor_.back());
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  int n = 0;
  for (size_t q = first; q < factors_.size(); ++q) {
    if (!factors_[q].accepted) continue;
    info += factors_[q].information();
    ++n;
  }
  sequential_cov_.push_back(n > 1 ? Eigen::Matrix3d(info.inverse()) : factors_[first].covariance());
}

void KeyframeSlam::solve(int leaf) {
  std::vector<GraphEdge> edges;
  edges.reserve(factors_.size());
  const bool drifting = drift_sigma_dps() > 0.0;
  std::vector<size_t> loops;  // factor index of each loop edge in `edges`, in order
  for (size_t i = 0; i < factors_.size(); ++i) {
    Factor& f = factors_[i];
    if (!f.accepted || f.kind == FactorKind::kPrior) continue;
    GraphEdge e{f.from, f.to, f.T_from_to, f.sigma, f.mix};
    if (drifting && (f.kind == FactorKind::kOdometryDr || f.kind == FactorKind::kHeadingLink)) {
      e.dt_s = seconds_between(f.from, f.to);
    }
    if (f.kind == FactorKind::kLoopClosure && config_.loop_loss != GraphEdge::Loss::kNone) {
      // One IRLS step per full solve: the weight at the previous optimum (the warm start).
      if (leaf < 0 && f.solved)
        f.robust_weight = robust_weight(config_.loop_loss, config_.loop_loss_scale,
                                        edge_whitened_norm(poses_, e, heading_drift_rad_s_));
      e.mix *= std::sqrt(f.robust_weight);
      if (leaf < 0) loops.push_back(i);
    }
    if (f.kind == FactorKind::kLoopClosure) e.mix /= std::sqrt(f.shared);
    edges.push_back(e);
  }
  if (leaf >= 0) {
    // The drift rate is held with the rest of the graph (the next full solve moves it).
    last_solve_ = solve_leaf_pose(poses_, leaf, edges, config_.solver, heading_drift_rad_s_);
  } else {
    HeadingDrift drift{heading_drift_rad_s_, drift_sigma_dps() * kRadPerDeg};
    last_solve_ = solve_pose_graph(poses_, factors_.front().T_from_to, config_.sigma_prior, edges,
                                   config_.solver, &drift);
    heading_drift_rad_s_ = drift.rate_rad_s;
    for (size_t i : loops) factors_[i].solved = true;
  }
  for (size_t k = leaf >= 0 ? static_cast<size_t>(leaf) : 0; k < keyframes_.size(); ++k) {
    Keyframe& kf = keyframes_[k];
    const Vec3 rpy = rpy_from_rotation(kf.T_W_V_dr.rotation());
    kf.T_W_V_slam = se3_from_se2(poses_[k], kf.T_W_V_dr.translation().z(), rpy.x(), rpy.y());
  }
}

int64_t KeyframeSlam::cloud_bytes() const {
  int64_t n = heap_bytes(keyframes_);
  for (const auto& k : keyframes_) n += heap_bytes(k.cloud_V);
  return n;
}

int64_t KeyframeSlam::graph_bytes() const {
  int64_t n = heap_bytes(factors_) + heap_bytes(poses_) + heap_bytes(path_m_) + heap_bytes(sequential_factor_) +
              heap_bytes(sequential_cov_) + heap_bytes(pcm_queue_) + heap_bytes(accepted_loops_);
  for (const auto& f : factors_) n += heap_bytes(f.reason);
  return n;
}

}  // namespace orthosonar::slam
