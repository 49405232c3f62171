#pragma once
// The pipeline (issue 7): one object that owns every stage — dead reckoning, ping pairing,
// orthogonal fusion, keyframes and SLAM, and the mapping systems — fed events one at a
// time from any EventSource. Ground truth is collected for metrics only and never reaches
// an estimate; label channels are ignored.
//
// Pairs wait until DR covers their stamp, then are fused in batches through an injected
// Executor (the tool may run the batch on N threads; fusion is a pure function of the
// pair, and everything after it runs sequentially in stamp order, so outputs are
// identical for any thread count). Stage durations come from an injected StageClock.
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/events.hpp"
#include "core/memory.hpp"
#include "core/mapping/mapping_system.hpp"
#include "core/perception/fusion.hpp"
#include "core/perception/pairing.hpp"
#include "core/slam/dead_reckoning.hpp"
#include "core/slam/keyframe_slam.hpp"

namespace orthosonar::mapping {

// Runs task(0) ... task(n-1), possibly in parallel, and returns when all are done.
class Executor {
 public:
  virtual ~Executor() = default;
  virtual void run(size_t n, const std::function<void(size_t)>& task) = 0;
};

class SerialExecutor final : public Executor {
 public:
  void run(size_t n, const std::function<void(size_t)>& task) override {
    for (size_t i = 0; i < n; ++i) task(i);
  }
};

struct PipelineConfig {
  perception::FusionConfig fusion;
  slam::DrConfig dr;
  slam::SlamConfig slam;
  size_t fusion_batch_pairs = 8;  // pairs fused together (in parallel when the executor allows)
  // Issue 34 (docs/PERCEPTION.md "Elevation uncertainty"): fused points whose elevation σ
  // (FusedPoint::elevation_sigma_rad) exceeds this are withheld from the maps (counted in
  // PipelineCounts::withheld_uncertain; observers still see every point). An angle, not a
  // distance: range × σ grows with range for every point alike, and a distance cut empties
  // the far field. 0 = keep every point.
  double max_elevation_sigma_deg = 2.0;
};

struct PipelineCounts {
  int64_t events = 0;
  int64_t sonar_h = 0, sonar_v = 0, imu = 0, dvl = 0, depth = 0, truth = 0, labels = 0;
  int64_t pairs = 0;              // pairs fused
  int64_t unpaired_h = 0, unpaired_v = 0;
  int64_t pairs_without_dr = 0;   // pairs outside the DR span (dropped)
  int64_t detections_h = 0, detections_v = 0;
  int64_t matches = 0, culled_low_confidence = 0, fused_points = 0;
  int64_t fused_sloped_face = 0;  // fused points whose elevation came from their h run
  int64_t withheld_uncertain = 0; // fused points not mapped: elevation σ over max_elevation_sigma_deg
  int64_t keyframes = 0;
  int64_t loop_closures = 0;      // accepted
};

// Fuses one pair. The default is perception::fuse_pair with the pipeline's config; a tool
// may supply a cache of earlier results (the sweep fuses each pair once for every cell).
// Must be a pure function of the pair and safe to call from several threads.
using FuseFn = std::function<perception::FusionResult(const SonarPing& h, const SonarPing& v)>;

// Sees every pair the pipeline places (after fusion, in stamp order, on the thread that
// feeds the pipeline): what perception saw, for a tool's view (the report's ping pair).
// It must not change what the pipeline computes.
using PairObserver =
    std::function<void(const SonarPing& h, const SonarPing& v, const perception::FusionResult& fused)>;

class Pipeline {
 public:
  explicit Pipeline(PipelineConfig config = {});
  // Adds a mapping system (before the first event). Systems are fed in the order added.
  void add_system(std::unique_ptr<MappingSystem> system);
  void set_executor(Executor* executor) { executor_ = executor ? executor : &serial_; }
  void set_clock(const StageClock* clock);
  void set_fusion(FuseFn fuse) { fuse_ = std::move(fuse); }
  void set_pair_observer(PairObserver observer) { observer_ = std::move(observer); }
  // Hands every truth pose to `observer` (in stream order, on the feeding thread) instead of
  // keeping it in truth(): a tool that keeps a long mission's truth elsewhere (issue 41).
  void set_truth_observer(std::function<void(const TruthPose&)> observer) { truth_observer_ = std::move(observer); }

  void consume(const Event& event);
  // The same, taking a sonar ping's image instead of copying it (a replay's events are its
  // own: 1.8 GB of copies in a 600 s full-resolution replay).
  void consume(Event&& event);
  // End of stream: pairs every pending ping and processes every pair DR can place.
  void finish();

  const std::vector<std::unique_ptr<MappingSystem>>& systems() const { return systems_; }
  const slam::KeyframeSlam& slam() const { return slam_; }
  const slam::DeadReckoning& dead_reckoning() const { return dr_; }
  PipelineCounts counts() const;
  // Ground truth seen on the truth channel, in stamp order (metrics only).
  const std::vector<TruthPose>& truth() const { return truth_; }
  // Moves the collected ground truth out (after finish(): one copy per run, not two).
  std::vector<TruthPose> take_truth() { return std::move(truth_); }
  // Per-stage runtime: "fusion" (one pair), "slam_update" (one keyframe), and each
  // system's own stages prefixed by nothing (their names are unique).
  std::vector<std::pair<std::string, RuntimeStats>> runtime() const;
  const PipelineConfig& config() const { return config_; }
  // Where the pipeline's memory is (issue 41), heap bytes by part in a fixed order:
  // "truth" (metrics only), "dead_reckoning", "ping_queue" (pings waiting to pair and pairs
  // waiting for DR), "keyframe_clouds", "pose_graph", then "map:<system>" per system.
  MemoryParts memory() const;

 private:
  struct PendingPair {
    SonarPing h, v;
  };
  void drain_pairer();
  void take_ping(SonarPing ping);  // counts it, pairs it
  void process_ready(bool final);
  void process_batch(size_t n);
  void process_fused(const PendingPair& p, const perception::FusionResult& fused);
  void release_dr_history();  // after a DVL reading: DR states no later lookup can need

  PipelineConfig config_;
  slam::DeadReckoning dr_;
  perception::PingPairer pairer_;
  slam::KeyframeSlam slam_;
  std::vector<std::unique_ptr<MappingSystem>> systems_;
  SerialExecutor serial_;
  Executor* executor_ = &serial_;
  const StageClock* clock_ = nullptr;
  FuseFn fuse_;
  PairObserver observer_;
  std::function<void(const TruthPose&)> truth_observer_;
  std::deque<PendingPair> pending_;
  // slam.keyframe_cloud_s > 0: the horizontal detections (in V, elevation 0) and DR pose of
  // the pairs since the previous keyframe, the next keyframe's cloud.
  struct CloudPair {
    Time stamp;
    SE3 T_W_V;
    std::vector<Eigen::Vector3d> p_V;
  };
  std::deque<CloudPair> cloud_window_;
  std::vector<Eigen::Vector2d> keyframe_cloud_V(const SE3& T_W_V, const SonarPing& h,
                                                const perception::FusionResult& fused);
  std::vector<TruthPose> truth_;
  PipelineCounts counts_;
  RuntimeStats fusion_stats_, slam_stats_;
};

}  // namespace orthosonar::mapping
