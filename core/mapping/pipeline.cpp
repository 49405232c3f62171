#include "core/mapping/pipeline.hpp"

#include <algorithm>
#include <variant>

#include "core/slam/planar_cloud.hpp"

namespace orthosonar::mapping {
namespace {

// DR states this long before the oldest stamp the pipeline can still look up are kept too
// (release_dr_history): a margin for sources that deliver a ping a little out of order.
constexpr int64_t kDrHistoryMarginNs = 30'000'000'000;

}  // namespace

Pipeline::Pipeline(PipelineConfig config)
    : config_(std::move(config)),
      dr_(config_.dr),
      pairer_(Time::from_seconds(config_.fusion.max_pair_dt_s)),
      slam_(config_.slam) {}

void Pipeline::add_system(std::unique_ptr<MappingSystem> system) {
  system->set_clock(clock_);
  systems_.push_back(std::move(system));
}

void Pipeline::set_clock(const StageClock* clock) {
  clock_ = clock;
  for (auto& s : systems_) s->set_clock(clock);
}

void Pipeline::consume(Event&& event) {
  if (event.channel == Channel::kSonarHorizontal || event.channel == Channel::kSonarVertical)
    if (auto* p = std::get_if<SonarPing>(&event.payload)) {
      ++counts_.events;
      take_ping(std::move(*p));
      process_ready(false);
      return;
    }
  consume(static_cast<const Event&>(event));
}

void Pipeline::take_ping(SonarPing ping) {
  ++(ping.mount == SonarMount::kHorizontal ? counts_.sonar_h : counts_.sonar_v);
  pairer_.push(std::move(ping));
  drain_pairer();
}

void Pipeline::consume(const Event& event) {
  ++counts_.events;
  switch (event.channel) {
    case Channel::kSonarHorizontal:
    case Channel::kSonarVertical:
      if (const auto* p = std::get_if<SonarPing>(&event.payload)) take_ping(*p);
      break;
    case Channel::kImu:
      if (const auto* r = std::get_if<ImuReading>(&event.payload)) {
        ++counts_.imu;
        dr_.add(*r);
      }
      break;
    case Channel::kDvl:
      if (const auto* r = std::get_if<DvlReading>(&event.payload)) {
        ++counts_.dvl;
        dr_.add(*r);
      }
      break;
    case Channel::kDepth:
      if (const auto* r = std::get_if<DepthReading>(&event.payload)) {
        ++counts_.depth;
        dr_.add(*r);
      }
      break;
    case Channel::kTruthPose:
      // Metrics only: never read by any estimator.
      if (const auto* r = std::get_if<TruthPose>(&event.payload)) {
        ++counts_.truth;
        if (truth_observer_) {
          truth_observer_(*r);
        } else {
          truth_.push_back(*r);
        }
      }
      break;
    case Channel::kLabelsHorizontal:
    case Channel::kLabelsVertical:
      ++counts_.labels;
      break;
    case Channel::kGyro:
      if (const auto* r = std::get_if<GyroReading>(&event.payload)) dr_.add(*r);
      break;
  }
  process_ready(false);
  if (event.channel == Channel::kDvl) release_dr_history();
}

// DR is looked up at the stamps of pairs (each pair's h ping: those pending, those the
// pairer still holds, and later ones, at or after the newest event) and, for a keyframe's
// odometry sigma, at the last keyframe's stamp. States before the oldest of these (less a
// margin) are never asked for again, so releasing them changes no pose and no digest; the
// trajectory's memory then stays bounded on a mission of any length (issue 41).
void Pipeline::release_dr_history() {
  if (dr_.empty()) return;
  Time oldest = dr_.last_time();
  if (!pending_.empty()) oldest = std::min(oldest, pending_.front().h.stamp);
  if (const auto h = pairer_.oldest_h()) oldest = std::min(oldest, *h);
  if (!slam_.keyframes().empty()) oldest = std::min(oldest, slam_.keyframes().back().stamp);
  dr_.forget_before(oldest - Time::from_ns(kDrHistoryMarginNs));
}

void Pipeline::finish() {
  pairer_.flush();
  drain_pairer();
  process_ready(true);
}

void Pipeline::drain_pairer() {
  while (auto pair = pairer_.pop()) pending_.push_back({std::move(pair->first), std::move(pair->second)});
}

void Pipeline::process_ready(bool final) {
  // A pair is ready once DR has a state at or after its stamp (its pose is then final).
  // Pairs are fused in batches of fusion_batch_pairs; at the end whatever remains.
  const size_t batch = config_.fusion_batch_pairs > 0 ? config_.fusion_batch_pairs : 1;
  while (!pending_.empty()) {
    size_t ready = 0;
    while (ready < pending_.size() && !dr_.empty() && pending_[ready].h.stamp <= dr_.last_time()) ++ready;
    if (final) ready = pending_.size();
    if (ready == 0 || (!final && ready < batch)) return;
    process_batch(ready < batch ? ready : batch);
  }
}

void Pipeline::process_batch(size_t n) {
  std::vector<perception::FusionResult> fused(n);
  std::vector<RuntimeStats> stats(n);
  executor_->run(n, [&](size_t i) {
    ScopedStage timer(clock_, stats[i]);
    fused[i] = fuse_ ? fuse_(pending_[i].h, pending_[i].v)
                     : perception::fuse_pair(pending_[i].h, pending_[i].v, config_.fusion);
  });
  for (size_t i = 0; i < n; ++i) {
    fusion_stats_.merge(stats[i]);
    process_fused(pending_[i], fused[i]);
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
}

void Pipeline::process_fused(const PendingPair& p, const perception::FusionResult& fused) {
  const Time stamp = p.h.stamp;
  const auto pose = dr_.pose_at(stamp);
  if (!pose.ok()) {
    ++counts_.pairs_without_dr;
    return;
  }
  ++counts_.pairs;
  counts_.detections_h += static_cast<int64_t>(fused.detections_h.size());
  counts_.detections_v += static_cast<int64_t>(fused.detections_v.size());
  counts_.matches += static_cast<int64_t>(fused.matches);
  counts_.culled_low_confidence += static_cast<int64_t>(fused.culled_low_confidence);
  counts_.fused_points += static_cast<int64_t>(fused.points.size());
  counts_.fused_sloped_face += static_cast<int64_t>(fused.sloped_face);
  if (observer_) observer_(p.h, p.v, fused);
  const SE3& T_W_V = *pose;
  if (config_.slam.keyframe_cloud_s > 0.0) {
    // Kept in the pair's own frame: placed by DR only if a keyframe gathers it.
    cloud_window_.push_back(
        {stamp, T_W_V, perception::points_V_at_elevation(p.h, fused.detections_h, config_.fusion.T_V_h, 0.0)});
    const Time oldest = stamp - Time::from_seconds(config_.slam.keyframe_cloud_s);
    while (cloud_window_.front().stamp < oldest) cloud_window_.pop_front();
  }
  if (slam_.should_add(T_W_V)) {
    int id = 0;
    {
      ScopedStage timer(clock_, slam_stats_);
      const auto& kfs = slam_.keyframes();
      slam::KeyframeSlam::DrSigma dr_sigma;
      if (!kfs.empty()) {
        dr_sigma.heading_rad = dr_.heading_sigma_rad(kfs.back().stamp, stamp);
        dr_sigma.translation_m = dr_.translation_sigma_m(kfs.back().stamp, stamp);
      }
      id = slam_.add_keyframe(stamp, T_W_V, keyframe_cloud_V(T_W_V, p.h, fused), dr_sigma);
    }
    std::vector<SE3> poses;
    poses.reserve(slam_.keyframes().size());
    for (const auto& k : slam_.keyframes()) poses.push_back(k.T_W_V_slam);
    for (auto& s : systems_) {
      s->on_keyframe({id, stamp, T_W_V});
      s->on_poses_updated(poses);
    }
  }
  // The maps take the points whose elevation is known well enough (issue 34).
  const perception::FusionResult* mapped = &fused;
  perception::FusionResult kept;
  if (config_.max_elevation_sigma_deg > 0.0) {
    const auto uncertain = [max_deg = config_.max_elevation_sigma_deg](const perception::FusedPoint& q) {
      return !perception::elevation_mappable(q.elevation_sigma_rad, max_deg);
    };
    if (const auto n = std::count_if(fused.points.begin(), fused.points.end(), uncertain); n > 0) {
      counts_.withheld_uncertain += n;
      kept = fused;  // detections and all: a mapping system may read them (inference does)
      std::erase_if(kept.points, uncertain);
      mapped = &kept;
    }
  }
  const PairInput in{stamp, &p.h, &p.v, mapped, T_W_V};
  for (auto& s : systems_) s->on_pair(in);
}

std::vector<Eigen::Vector2d> Pipeline::keyframe_cloud_V(const SE3& T_W_V, const SonarPing& h,
                                                      const perception::FusionResult& fused) {
  const slam::SlamConfig& s = config_.slam;
  if (s.keyframe_cloud_s <= 0.0) return perception::planar_points_V(h, fused.detections_h, config_.fusion.T_V_h);
  // process_fused has just added this pair to the window: its points are the keyframe's own
  // (x, y of them: planar_points_V's cloud).
  std::vector<Eigen::Vector2d> own;
  own.reserve(cloud_window_.back().p_V.size());
  for (const Eigen::Vector3d& q : cloud_window_.back().p_V) own.emplace_back(q.x(), q.y());
  if (!s.keyframe_cloud_always &&
      slam::prepare_planar_cloud(own, {s.voxel_m, s.outlier_radius_m, s.outlier_min_neighbours}).size() >=
          s.ssm_min_points) {
    cloud_window_.clear();
    return own;
  }
  // The window holds this pair and the earlier ones since the previous keyframe: each
  // detection to the world by its pair's DR pose, back into this keyframe's frame V, as
  // x, y (the SPEC's planar cloud).
  const SE3 T_V_W = T_W_V.inverse();
  std::vector<Eigen::Vector2d> out;
  size_t n = 0;
  for (const CloudPair& c : cloud_window_) n += c.p_V.size();
  out.reserve(n);
  for (const CloudPair& c : cloud_window_)
    for (const Eigen::Vector3d& q : c.p_V) {
      const Eigen::Vector3d p_W = c.T_W_V * q;
      const Eigen::Vector3d p_K = T_V_W * p_W;
      out.emplace_back(p_K.x(), p_K.y());
    }
  cloud_window_.clear();
  return out;
}

PipelineCounts Pipeline::counts() const {
  PipelineCounts c = counts_;
  c.unpaired_h = static_cast<int64_t>(pairer_.unpaired_h());
  c.unpaired_v = static_cast<int64_t>(pairer_.unpaired_v());
  c.keyframes = static_cast<int64_t>(slam_.keyframes().size());
  c.loop_closures = static_cast<int64_t>(slam_.accepted_loop_closures());
  return c;
}

std::vector<std::pair<std::string, RuntimeStats>> Pipeline::runtime() const {
  std::vector<std::pair<std::string, RuntimeStats>> out = {{"fusion", fusion_stats_},
                                                           {"slam_update", slam_stats_}};
  for (const auto& s : systems_)
    for (auto& r : s->runtime()) out.push_back(std::move(r));
  return out;
}

MemoryParts Pipeline::memory() const {
  int64_t queued = pairer_.memory_bytes() + heap_bytes(pending_);
  for (const auto& p : pending_) queued += heap_bytes(p.h) + heap_bytes(p.v);
  int64_t window = heap_bytes(cloud_window_);
  for (const auto& c : cloud_window_) window += heap_bytes(c.p_V);
  MemoryParts parts = {{"truth", heap_bytes(truth_)},
                       {"dead_reckoning", dr_.memory_bytes()},
                       {"ping_queue", queued},
                       {"keyframe_clouds", slam_.cloud_bytes() + window},
                       {"pose_graph", slam_.graph_bytes()}};
  for (const auto& s : systems_) parts.emplace_back("map:" + s->name(), s->memory_bytes());
  return parts;
}

}  // namespace orthosonar::mapping
