#pragma once
// The interface every mapping system implements (SPEC §6): sonar fusion mapping,
// submapping, inference mapping, inference submapping. The pipeline feeds each system
// every fused pair in stamp order, tells it when a keyframe was created, and hands it all
// keyframe poses after each SLAM re-solve. A system never reads images again after
// on_pair returns (the pointers in PairInput are valid only during the call).
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/time.hpp"

namespace orthosonar::perception {
struct FusionResult;  // core/perception/fusion.hpp
}

namespace orthosonar::mapping {

// Mean and standard deviation of a stage's duration. Durations come from a StageClock the
// tool injects (core has no clock); they never reach the digest.
struct RuntimeStats {
  int64_t count = 0;
  double sum_ms = 0.0;
  double sum_sq_ms = 0.0;

  void add(double ms) {
    ++count;
    sum_ms += ms;
    sum_sq_ms += ms * ms;
  }
  void merge(const RuntimeStats& o) {
    count += o.count;
    sum_ms += o.sum_ms;
    sum_sq_ms += o.sum_sq_ms;
  }
  double mean_ms() const { return count > 0 ? sum_ms / static_cast<double>(count) : 0.0; }
  double sd_ms() const {
    if (count < 2) return 0.0;
    const double n = static_cast<double>(count);
    const double var = (sum_sq_ms - sum_ms * sum_ms / n) / (n - 1.0);
    return var > 0.0 ? std::sqrt(var) : 0.0;
  }
};

// A monotonic clock in milliseconds, provided by the tool. Core code only takes
// differences of two readings; a null clock means "do not measure".
class StageClock {
 public:
  virtual ~StageClock() = default;
  virtual double now_ms() const = 0;
};

// Times one stage into `stats` for the lifetime of the object (no-op without a clock).
class ScopedStage {
 public:
  ScopedStage(const StageClock* clock, RuntimeStats& stats)
      : clock_(clock), stats_(stats), start_(clock ? clock->now_ms() : 0.0) {}
  ~ScopedStage() {
    if (clock_) stats_.add(clock_->now_ms() - start_);
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  const StageClock* clock_;
  RuntimeStats& stats_;
  double start_;
};

struct PairInput {
  Time stamp;                               // the pair's stamp (the horizontal ping's)
  const SonarPing* h = nullptr;
  const SonarPing* v = nullptr;
  const perception::FusionResult* fused = nullptr;
  SE3 T_W_V_dr = SE3::Identity();           // dead-reckoning pose at `stamp`
};

struct KeyframeInput {
  int keyframe_id = 0;                      // 0, 1, 2, ... in creation order
  Time stamp;
  SE3 T_W_V_dr = SE3::Identity();
};

class MappingSystem {
 public:
  virtual ~MappingSystem() = default;
  virtual std::string name() const = 0;
  // Every fused pair, in stamp order. A pair at a keyframe's stamp arrives after
  // on_keyframe for that keyframe.
  virtual void on_pair(const PairInput& pair) = 0;
  // A new keyframe was created (after SLAM added it).
  virtual void on_keyframe(const KeyframeInput& keyframe) = 0;
  // All keyframe poses T_W_K (index = keyframe id) after a SLAM re-solve.
  virtual void on_poses_updated(const std::vector<SE3>& T_W_K_slam) = 0;
  // The map in W, in a deterministic order.
  virtual std::vector<Eigen::Vector3f> map_points_W() const = 0;
  // The same map with the keyframes placed by `T_W_K` (index = keyframe id) instead of
  // the SLAM poses, e.g. the true poses of a simulated run, to separate what navigation
  // costs the map from what perception does. nullopt for a system whose map does not
  // follow the keyframe poses alone (the default).
  virtual std::optional<std::vector<Eigen::Vector3f>> map_points_W_with(const std::vector<SE3>& T_W_K) const {
    (void)T_W_K;
    return std::nullopt;
  }
  // Per-stage runtime, e.g. {"submap_construction", stats}.
  virtual std::vector<std::pair<std::string, RuntimeStats>> runtime() const = 0;
  // System-specific counters for metrics.json (e.g. inference's clusters and Bayes
  // updates); none by default. Deterministic; never part of the digest.
  virtual std::vector<std::pair<std::string, int64_t>> system_counts() const { return {}; }
  // Heap bytes the system holds for its map (core/memory.hpp; replay --memory-report).
  virtual int64_t memory_bytes() const { return 0; }
  // The clock used to time stages; optional, may be null.
  virtual void set_clock(const StageClock* clock) { (void)clock; }
};

}  // namespace orthosonar::mapping
