#pragma once
// Keyframe pose SLAM (SPEC §5, paper §IV): keyframes by DR distance/rotation; sequential
// scan matching (SSM) by 2D ICP against the previous keyframes, with a DR odometry factor
// as fallback so the graph never breaks; loop closures (NSSM) against older keyframes in
// sonar range and field of view, filtered by PCM; a Ceres SE(2) pose graph re-solved
// warm-started after every keyframe. 6-DoF keyframe poses = SE(2) + DR z, roll, pitch.
// Deterministic; not thread-safe.
#include <cstddef>
#include <string>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"
#include "core/slam/icp.hpp"
#include "core/slam/pcm.hpp"
#include "core/slam/planar_cloud.hpp"
#include "core/slam/pose_graph.hpp"
#include "core/time.hpp"

namespace orthosonar::slam {

struct SlamConfig {
  // Keyframe selection.
  double kf_distance_m = 3.0;
  double kf_rotation_deg = 30.0;
  // Planar cloud.
  // Addition (docs/SLAM.md "Keyframe clouds over the interval", issue 34): 0 = a keyframe's
  // cloud is its own pair's horizontal detections (SPEC §5). > 0: a keyframe's cloud may
  // gather the horizontal detections of every pair after the previous keyframe's and at most
  // this many seconds before it, each placed in the keyframe's frame by dead reckoning (a
  // thin or sparse structure gives a single pair too few points for scan matching).
  double keyframe_cloud_s = 0.0;
  // With keyframe_cloud_s > 0: false = the gathered cloud only for a keyframe whose own
  // pair's prepared cloud has fewer than ssm_min_points points (too few for a scan match),
  // its own pair's otherwise; true = the gathered cloud for every keyframe.
  bool keyframe_cloud_always = false;
  double voxel_m = 0.5;
  double outlier_radius_m = 1.0;
  // SPEC §5 says >= 5; pilings are 1-3 voxels of 0.5 m, so 5 removes every piling and SSM
  // starves on marinas. 2 is sonar-SLAM's feature.yaml value (docs/SLAM.md).
  size_t outlier_min_neighbours = 2;
  // Scan matching.
  IcpConfig icp;
  int ssm_target_frames = 3;
  // SPEC §5 says 50. 0.5 m voxels of a wreck, a row of pilings or a far wall are often
  // 25-50 points, and a keyframe below the threshold falls back to DR (docs/SLAM.md).
  size_t ssm_min_points = 25;
  double ssm_max_translation_m = 3.0;  // max ICP-vs-DR disagreement
  double ssm_max_rotation_deg = 30.0;
  // SPEC §5 adds the DR odometry factor only when ICP is rejected; true also keeps it beside
  // an accepted ICP factor (a deviation, docs/SLAM.md): DR is an independent measurement.
  bool ssm_keep_dr_factor = true;
  // Addition: reject an ICP result whose squared Mahalanobis distance from DR (joint noise
  // sigma_odometry^2 + sigma_icp^2) exceeds this (chi-square 0.99, 3 dof, as PCM); 0 = off
  // (SPEC: only the 3 m / 30 deg gate).
  double ssm_max_mahalanobis = 11.34;
  // Addition (docs/SLAM.md "The DR factor from the sensors' noise figures"): a scan match
  // whose information, whitened by the DR factor's sigmas, is below this ratio in every
  // direction is recorded but not added (DR alone is as good; its bias would add up). With
  // sigma_odometry and sigma_icp as set, ratio 0.25: every match is kept; with a FOG heading
  // and the DVL's translation sigma about 0.02. 0 = off.
  double ssm_min_information_ratio = 0.1;
  // Loop closures.
  int nssm_min_separation = 8;        // keyframes older than the newest by at least this
  double nssm_min_travel_m = 20.0;    // ...and at least this far back along the DR path (addition)
  double nssm_range_m = 30.0;         // sonar range: gating of candidate keyframes and points
  double nssm_fov_deg = 130.0;        // horizontal sonar swath
  double sonar_x_m = 0.35;            // horizontal sonar position along V x (T_V_h)
  // Field-of-view gating of ICP inputs (SSM and NSSM) can widen the sonar's view by these
  // margins. Measured on the simulated harbor, widening made SSM worse (docs/SLAM.md).
  double gate_margin_deg = 0.0;
  double gate_margin_m = 0.0;
  size_t nssm_min_points = 25;        // source, gated target points and ICP inliers (as SSM's)
  int nssm_max_target_frames = 10;    // nearest candidate keyframes aggregated (bounds the cost)
  // Addition (docs/SLAM.md): a loop candidate whose squared Mahalanobis distance from the
  // graph's estimate of the same relative pose (joint covariance: the odometry chain between
  // the two keyframes + the loop's own) exceeds this is not a candidate. 0 = off.
  double nssm_max_mahalanobis = 30.0;
  // Addition (docs/SLAM.md "The DR factor from the sensors' noise figures"): when the DR
  // factor is the sensors' (a FOG heading), a loop candidate whose heading differs from the
  // odometry chain's by more than this is not a candidate either. 0 = off.
  double nssm_max_heading_diff_gyro_deg = 0.5;
  // Addition (docs/SLAM.md "Heading drift on the AHRS"): when the DR factor is not the
  // sensors' (an AHRS heading), a loop candidate whose heading differs from the odometry
  // chain's by more than this many sigmas (the chain's heading sigma and sigma_icp's, in
  // quadrature) is not a candidate either. 0 = off.
  double nssm_max_heading_sigmas = 3.0;
  // Addition (docs/SLAM.md "Loops at the FOG's heading"): when the DR factor is the
  // sensors' (a FOG heading), a loop candidate's ICP solves for translation only, at the
  // graph's relative heading, and the loop factor carries no heading information of its own.
  bool nssm_fixed_heading_gyro = false;
  // Addition (docs/SLAM.md "Loop targets from one pass"): a loop's target aggregates only
  // the candidate keyframes within nssm_min_travel_m of the anchor along the DR path (the
  // anchor's own pass), not keyframes of other passes whose relative poses carry the drift
  // between them.
  bool nssm_target_same_pass = false;
  // Addition (docs/SLAM.md "Loops from the same side"): when the DR factor is not the
  // sensors' (an AHRS heading), loop candidates are only the older keyframes whose heading
  // (the graph's estimate) is within this of the new keyframe's, so that the anchor and the
  // target see the place from the same side: the sonar's 2D outline of a 3D structure
  // changes with the view, and loops across it are biased in heading. 0 = off (tried for
  // issue 33, not a default: routes that pass a structure from both sides lose the loops
  // that held their heading).
  double nssm_max_view_change_deg = 0.0;
  // ...and when none is, the other keyframes in range: kNone never; kTranslation for a loop
  // fitted in translation only at the chain's heading; kFull for a loop as any other (the
  // only loops some routes have).
  enum class OtherSide : uint8_t { kNone, kTranslation, kFull };
  static constexpr OtherSide kOtherSides[] = {OtherSide::kNone, OtherSide::kTranslation, OtherSide::kFull};
  static constexpr const char* other_side_name(OtherSide o) {
    return o == OtherSide::kNone ? "none" : o == OtherSide::kTranslation ? "translation" : "full";
  }
  OtherSide nssm_other_side = OtherSide::kTranslation;
  // Addition (docs/SLAM.md "Loop sources from several keyframes"): a loop's source
  // aggregates the new keyframe and the nssm_source_frames - 1 before it, placed by the
  // graph's estimates (the sequential chain), in the new keyframe's frame: a longer outline
  // for the loop's heading. 1 = the new keyframe's cloud alone (SPEC).
  int nssm_source_frames = 1;
  double nssm_max_rmse_m = 1.0;       // an ICP fit worse than this is not a candidate (PCM judges the rest)
  int pcm_queue = 5;
  double pcm_threshold = 11.34;       // chi-square 0.99, 3 dof (squared Mahalanobis)
  int min_pcm = 2;
  // Noise sigmas (x m, y m, theta rad).
  Eigen::Vector3d sigma_prior{0.1, 0.1, 0.01};
  // SPEC §5 says 0.2, 0.2, 0.02 (sonar-SLAM's vehicle); these match the DVL/IMU of SPEC §10 over
  // one keyframe interval (docs/SLAM.md "Noise models").
  Eigen::Vector3d sigma_odometry{0.05, 0.05, 0.005};
  // With a fibre-optic gyro the DR factor's heading sigma is what the gyro accumulated
  // between the keyframes (add_keyframe's DrSigma::heading_rad), at least this.
  double gyro_heading_sigma_min_deg = 0.01;
  // The DR factor's translation sigma (docs/SLAM.md "The DR factor from the sensors' noise
  // figures"): kConstant sigma_odometry's; kSensors what the DVL accumulated between the
  // keyframes (DrSigma::translation_m, at least dr_translation_sigma_min_m); kAuto the
  // sensors' when the heading is a fibre-optic gyro's, the constant otherwise (a drifting
  // AHRS needs scan matches' translations with its headings: measured there).
  enum class DrSigmaModel : uint8_t { kAuto, kConstant, kSensors };
  static constexpr DrSigmaModel kDrSigmaModels[] = {DrSigmaModel::kAuto, DrSigmaModel::kConstant,
                                                    DrSigmaModel::kSensors};
  static constexpr const char* dr_sigma_model_name(DrSigmaModel m) {
    return m == DrSigmaModel::kAuto ? "auto" : m == DrSigmaModel::kConstant ? "constant" : "sensors";
  }
  DrSigmaModel dr_sigma_model = DrSigmaModel::kAuto;
  double dr_translation_sigma_min_m = 0.005;
  Eigen::Vector3d sigma_icp{0.1, 0.1, 0.01};
  // Loop-closure factors (SPEC: the ICP noise above). A loop match between views minutes
  // apart is less certain than a sequential one (docs/SLAM.md "Noise models").
  Eigen::Vector3d sigma_loop{0.5, 0.5, 0.05};
  // The same when the DR factor comes from the sensors' noise figures (dr_sigma_model; with
  // a fibre-optic gyro under kAuto): a loop match started from a heading that does not drift
  // is as good as its fit, and the tighter noise lets the odometry-chain gate
  // (nssm_max_mahalanobis) refuse the metre-off matches that 0.5 m let in (docs/SLAM.md).
  Eigen::Vector3d sigma_loop_gyro{0.2, 0.2, 0.005};
  // Addition (docs/SLAM.md "Degenerate scan matches"): a scan-match factor (sequential or
  // loop) constrains only what its fit observes. Its information, diag(1/sigma²) as above,
  // is weakened along each eigen-direction of the fit's Hessian (icp_fit_information, in
  // sigma-whitened coordinates) whose eigenvalue is below degeneracy_ratio × the largest,
  // in proportion (a straight wall: translation along it). PCM and the SSM gate use the
  // resulting covariances. 0 = off (every factor diag(1/sigma²), as SPEC §5).
  double degeneracy_ratio = 0.1;
  // Addition (docs/SLAM.md "Heading drift"): sigma (deg/s) of a zero-mean prior on a steady
  // drift of the DR heading (gyro bias, AHRS drift), estimated in the graph at every full
  // solve and taken out of each DR factor's yaw (rate × the keyframes' time apart). A
  // scan-match chain and DR disagree about heading at that rate; loop closures tell which
  // is right. 0 = off (DR yaw increments as measured). This one applies when the DR factor
  // is not the sensors' (an AHRS heading, dr_sigma_model): 0.005 °/s, a MEMS AHRS's steady
  // drift (~18 °/h); on by default since 2026-12-08 (docs/SLAM.md "Heading drift on the AHRS").
  double heading_drift_sigma_dps = 0.005;
  // The same when the DR factor is the sensors' (a fibre-optic gyro's heading, whose bias is
  // in the DR factor's heading sigma already: dr.gyro_bias_dph). 0 = off.
  double heading_drift_sigma_gyro_dps = 0.0;
  // With the drift estimated: also re-solve the whole graph (and the rate) every this many
  // keyframes when no loop closure has, so a drift is taken out before the first loop
  // closes (0 = only at loop closures).
  int heading_drift_every_keyframes = 0;
  // Addition (docs/SLAM.md "Heading links"): the DR heading is the AHRS's, whose error is a
  // slow random walk, not white noise per keyframe. Every heading_link_s seconds of keyframe
  // time, a yaw-only factor joins the new keyframe to the last one linked: their DR yaw
  // difference, sigma² = walk² × dt + 2 × white² (walk in deg/√s, white in deg), and the
  // whole graph is re-solved. The odometry factors alone let a chain of biased one-sided
  // scan matches turn the heading by degrees in a minute the AHRS turns by tenths. 0 = off.
  double heading_link_s = 0.0;
  double heading_link_walk_dps = 0.05;   // deg/√s
  double heading_link_white_deg = 0.2;   // deg
  // Addition (docs/SLAM.md "Robust losses"): the loss of loop-closure factors in the graph,
  // on the whitened residual: "none" (least squares, SPEC), "huber" or "cauchy", bending at
  // a whitened norm of loop_loss_scale. A loop that passed the gate and PCM but is wrong
  // then pulls with a bounded force. Solved by reweighting (IRLS), one step per full solve:
  // each loop's weight comes from its residual at the previous full solve's optimum, so a
  // re-solve costs what a least-squares one does.
  GraphEdge::Loss loop_loss = GraphEdge::Loss::kCauchy;
  double loop_loss_scale = 3.37;  // sqrt of chi-square(0.99, 3): inliers stay quadratic
  // Option (docs/SLAM.md "Loop closures that share an error"): loops close to one another
  // match much the same clouds and share most of their error (measured correlation about
  // exp(-d / 7 m), d the larger of the distances between their anchors and between their new
  // keyframes), yet each enters the graph as an independent measurement, so a revisit's
  // weight grows with how densely keyframes are taken. Each accepted loop's information is
  // divided by sum_j exp(-d_ij / loop_correlation_m) over the accepted loops (itself
  // included): n loops sharing one error weigh as one. 0 = off (each loop independent), the
  // default: measured, it changed little (docs/SLAM.md).
  double loop_correlation_m = 0.0;
  // Addition (docs/SLAM.md "Loop error against baseline"): with a gyro (the DR factor from
  // the sensors), a loop's x/y sigma grows with the distance between the keyframes it joins,
  // sigma_xy = hypot(sigma_loop_gyro, this x |t|): two clouds seen from 15 m apart overlap
  // less, and their match errs more (measured: 0.06 m RMS under 2 m, 0.13-0.14 m at 5-20 m).
  // Without a gyro the long loops are what corrects the heading, and every loop keeps
  // sigma_loop. 0 = off.
  double sigma_loop_per_m = 0.02;
  FitInformationConfig fit_information;
  PoseGraphConfig solver;
};

enum class FactorKind { kPrior, kOdometryDr, kSequentialIcp, kLoopClosure, kHeadingLink };
// "prior", "odometry_dr", "ssm_icp", "loop_closure", "heading_link"
const char* factor_kind_name(FactorKind k);

struct Factor {
  FactorKind kind = FactorKind::kPrior;
  int from = 0;  // for the prior, from == to == 0
  int to = 0;
  SE2 T_from_to;
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();
  bool accepted = false;  // in the graph
  std::string reason;     // why accepted or rejected, e.g. "pcm clique 3", "icp not converged"
  // Residual mixing of a scan match with weakly observed directions (GraphEdge::mix);
  // identity otherwise. weakened: how many of the 3 directions were weakened.
  Eigen::Matrix3d mix = Eigen::Matrix3d::Identity();
  int weakened = 0;
  // Loop closures under slam.loop_loss: the reweighting of the residual (1 = least squares),
  // from the loop's residual at the optimum of the last full solve it took part in, and
  // whether it has taken part in one (a new loop enters at 1: docs/SLAM.md "Robust losses").
  double robust_weight = 1.0;
  bool solved = false;
  // Accepted loop closures: how many accepted loops share this one's error (SlamConfig::
  // loop_correlation_m; 1 = none). The graph divides its information by this.
  double shared = 1.0;
  // Loop closures: the largest distance along the DR path between the anchor and a keyframe
  // aggregated into the target (0: the anchor alone; slam.nssm_target_same_pass bounds it).
  double target_span_m = 0.0;
  // Loop closures: how many keyframes the source aggregates (slam.nssm_source_frames).
  int source_frames = 1;
  // Scan matches fitted in translation only, at the odometry chain's heading (their heading
  // row carries no information): the reason says so at every stage.
  bool heading_from_chain = false;
  Eigen::Matrix3d information() const;  // diag(1/sigma) mixᵀ mix diag(1/sigma)
  Eigen::Matrix3d covariance() const;   // its inverse (unobserved directions: 1e6 × sigma²)
};

struct Keyframe {
  int id = 0;
  Time stamp;
  SE3 T_W_V_dr;
  SE3 T_W_V_slam;
  std::vector<Eigen::Vector2d> cloud_V;  // prepared planar cloud (voxelised, outliers removed)
};

class KeyframeSlam {
 public:
  explicit KeyframeSlam(SlamConfig config = {});

  // True for the first keyframe, then when the DR distance or yaw change since the last
  // keyframe reaches the thresholds.
  bool should_add(const SE3& T_W_V_dr) const;
  // Adds a keyframe (SSM vs the previous keyframes, NSSM + PCM, warm-started re-solve of
  // the whole graph when a loop closure joined it, of the new pose alone otherwise).
  // planar_points_V: horizontal-sonar detections in V with elevation 0 (x, y). Returns its id.
  // dr_sigma: the DR's own sigmas since the previous keyframe (DeadReckoning's
  // heading_sigma_rad, set when the heading is a fibre-optic gyro's, and translation_sigma_m);
  // what SlamConfig::dr_sigma_model does with them is there. Empty: sigma_odometry.
  struct DrSigma {
    std::optional<double> translation_m;
    std::optional<double> heading_rad;
  };
  int add_keyframe(Time stamp, const SE3& T_W_V_dr, std::vector<Eigen::Vector2d> planar_points_V,
                   DrSigma dr_sigma = {});

  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  const std::vector<Factor>& factors() const { return factors_; }
  size_t accepted_loop_closures() const;
  // The heading-drift prior in use (deg/s): heading_drift_sigma_dps, or its gyro form when
  // the DR factor is the sensors' (known from the first keyframe on).
  double drift_sigma_dps() const;
  const SlamConfig& config() const { return config_; }
  const PoseGraphSummary& last_solve() const { return last_solve_; }
  // The estimated drift of the DR heading (rad/s; 0 when drift_sigma_dps() is 0).
  double heading_drift_rad_s() const { return heading_drift_rad_s_; }
  // Heap bytes (core/memory.hpp) of the keyframes' planar clouds, and of the pose graph
  // (factors, estimates, per-keyframe bookkeeping).
  int64_t cloud_bytes() const;
  int64_t graph_bytes() const;

 private:
  void sequential_match(int id);
  void loop_closure(int id);
  void run_pcm();
  bool disagrees_with_chain(const Factor& loop) const;  // nssm_max_mahalanobis
  void accept_loop(size_t factor, size_t clique_size);   // and count the errors it shares
  UncertainSE2 odometry_between(int i, int j) const;  // current estimate + chain covariance
  // The mix of a scan-match factor with these sigmas, from its fit (identity when off).
  // translation_only: the fit did not solve for the heading (a loop at the FOG's heading):
  // its heading carries no information and only the translation block is analysed.
  void shape(Factor& f, const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target,
             bool translation_only = false) const;
  // Points of cloud_V (keyframe at T_W_V) inside the sonar view of any of the keyframes `ids`.
  std::vector<Eigen::Vector2d> seen_from(const std::vector<Eigen::Vector2d>& cloud_V, const SE2& T_W_V,
                                         const std::vector<int>& ids) const;
  std::vector<Eigen::Vector2d> aggregate(const std::vector<int>& ids, int frame) const;
  // The whole graph (leaf < 0), or only keyframe `leaf` when nothing else can have moved.
  void solve(int leaf);
  // Adds the heading link (heading_link_s) that keyframe `id` is due, if any; true if added.
  bool link_heading(int id);
  // Time from keyframe `from` to keyframe `to` (s): a DR factor's dt for the heading drift.
  double seconds_between(int from, int to) const {
    return (keyframes_[static_cast<size_t>(to)].stamp - keyframes_[static_cast<size_t>(from)].stamp).seconds();
  }
  double gate_range_m() const { return config_.nssm_range_m + config_.gate_margin_m; }
  double gate_fov_deg() const { return config_.nssm_fov_deg + 2.0 * config_.gate_margin_deg; }

  SlamConfig config_;
  std::vector<Keyframe> keyframes_;
  std::vector<Factor> factors_;
  std::vector<SE2> poses_;                 // SE(2) estimates, one per keyframe
  std::vector<double> path_m_;             // DR path length (x, y) from the first keyframe
  std::vector<int> sequential_factor_;     // per keyframe k >= 1: factor linking k-1 -> k
  // per keyframe k >= 1: covariance of the motion k-1 -> k as the graph knows it (every
  // accepted sequential factor between them, informations added); fixed once k is added.
  std::vector<Eigen::Matrix3d> sequential_cov_;
  std::vector<int> pcm_queue_;             // factor indices of the last loop candidates
  std::vector<size_t> accepted_loops_;     // factor indices of the accepted loop closures
  PoseGraphSummary last_solve_;
  double heading_drift_rad_s_ = 0.0;
  Eigen::Vector3d sigma_dr_ = Eigen::Vector3d::Zero();  // the newest keyframe's DR factor sigma
  bool dr_from_sensors_ = false;           // sigma_dr_'s translation is the DVL's (dr_sigma_model)
  int heading_link_anchor_ = 0;            // the keyframe the next heading link starts from
};

}  // namespace orthosonar::slam
