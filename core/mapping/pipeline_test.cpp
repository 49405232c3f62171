#include "core/mapping/pipeline.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "core/mapping/systems.hpp"
#include "hal/fake_source.hpp"

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {

// A small synthetic mission: the vehicle drives along +x at 0.5 m/s; both sonars see a
// bright blob straight ahead at 5 m, so every pair fuses to a few points.
SonarPing ping(SonarMount mount, Time t, uint32_t id) {
  SonarPing p;
  p.mount = mount;
  p.part_number = mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
  p.stamp = t;
  p.ping_id = id;
  p.range_resolution_m = 0.05;
  p.rows = 160;
  p.cols = 64;
  for (int c = 0; c < p.cols; ++c)
    p.bearings_rad.push_back((-65.0 + 130.0 * (c + 0.5) / p.cols) * M_PI / 180.0);
  p.image.assign(static_cast<size_t>(p.rows) * p.cols, 10);
  for (int r = 98; r <= 101; ++r)
    for (int c = 30; c <= 33; ++c)
      p.image[static_cast<size_t>(r) * p.cols + static_cast<size_t>(c)] =
          static_cast<uint8_t>(mount == SonarMount::kHorizontal ? 200 + r - 98 + c - 30 : 200 + (r - 98) * 2 + (c - 30));
  return p;
}

// The DVL (0.5 m/s along x) and depth (2 m) readings at t, and a level IMU at 50 Hz.
void add_dvl_and_depth(Time t, std::vector<Payload>& payloads) {
  DvlReading d;
  d.stamp = t;
  d.velocity_V_mps = Vec3(0.5, 0, 0);
  payloads.push_back(d);
  DepthReading z;
  z.stamp = t;
  z.depth_m = 2.0;
  payloads.push_back(z);
}

void add_imu(int seconds, std::vector<Payload>& payloads) {
  for (int i = 0; i <= seconds * 50; ++i) {
    ImuReading r;
    r.stamp = Time::from_ms(20 * i);
    payloads.push_back(r);
  }
}

std::vector<Event> mission(bool with_truth, int seconds) {
  std::vector<Payload> payloads;
  for (int i = 0; i <= seconds * 5; ++i) {
    const Time t = Time::from_ms(200 * i);
    payloads.push_back(ping(SonarMount::kHorizontal, t, static_cast<uint32_t>(i)));
    payloads.push_back(ping(SonarMount::kVertical, t + Time::from_ms(3), static_cast<uint32_t>(i)));
    add_dvl_and_depth(t, payloads);
    if (with_truth) {
      TruthPose tp;
      tp.stamp = t;
      tp.p_W = Vec3(0.5 * t.seconds(), 0, -2);
      payloads.push_back(tp);
    }
  }
  add_imu(seconds, payloads);
  return hal::make_events(payloads);
}

class ReverseExecutor final : public Executor {
 public:
  void run(size_t n, const std::function<void(size_t)>& task) override {
    for (size_t i = n; i > 0; --i) task(i - 1);
  }
};

struct Outcome {
  std::vector<std::vector<Eigen::Vector3f>> maps;
  PipelineCounts counts;
  std::vector<SE3> keyframes;
};

Outcome run(const std::vector<Event>& events, Executor* ex, size_t batch) {
  PipelineConfig cfg;
  cfg.fusion_batch_pairs = batch;
  cfg.slam.kf_distance_m = 2.0;
  cfg.fusion.min_confidence = 0.0;  // the synthetic blob is symmetric: keep every match
  Pipeline p(cfg);
  p.add_system(std::make_unique<FusionMapping>());
  p.add_system(std::make_unique<Submapping>());
  p.set_executor(ex);
  for (const auto& e : events) p.consume(e);
  p.finish();
  Outcome o;
  for (const auto& s : p.systems()) o.maps.push_back(s->map_points_W());
  o.counts = p.counts();
  for (const auto& k : p.slam().keyframes()) o.keyframes.push_back(k.T_W_V_slam);
  return o;
}

}  // namespace

TEST_CASE("pipeline fuses pairs places keyframes and builds both maps", "[unit]") {
  const auto events = mission(true, 12);
  const Outcome o = run(events, nullptr, 8);
  CHECK(o.counts.pairs >= 55);
  CHECK(o.counts.fused_points > 0);
  CHECK(o.counts.keyframes >= 3);
  REQUIRE(o.maps.size() == 2);
  CHECK(o.maps[0].size() > 0);
  CHECK(o.maps[1].size() > o.maps[0].size());  // submapping keeps the pairs between keyframes
  // Every map point lies about 5 m ahead of some vehicle position on the x axis.
  for (const auto& p : o.maps[1]) CHECK(std::abs(p.y()) < 1.0f);
}

TEST_CASE("pipeline outputs do not depend on truth on executor order or on batch size", "[unit]") {
  const auto with_truth = mission(true, 8);
  const auto without_truth = mission(false, 8);
  const Outcome a = run(with_truth, nullptr, 8);
  ReverseExecutor rev;
  const Outcome b = run(without_truth, &rev, 3);
  const Outcome c = run(with_truth, &rev, 1);
  CHECK(a.maps == b.maps);
  CHECK(a.maps == c.maps);
  REQUIRE(a.keyframes.size() == b.keyframes.size());
  for (size_t i = 0; i < a.keyframes.size(); ++i) CHECK(a.keyframes[i].matrix() == b.keyframes[i].matrix());
  CHECK(a.counts.truth > 0);
  CHECK(b.counts.truth == 0);
}

TEST_CASE("pipeline memory parts name where the bytes are, and a truth observer keeps truth out of it", "[unit]") {
  const auto events = mission(true, 12);
  PipelineConfig cfg;
  cfg.slam.kf_distance_m = 2.0;
  cfg.fusion.min_confidence = 0.0;
  const auto make = [&] {
    auto p = std::make_unique<Pipeline>(cfg);
    p->add_system(std::make_unique<FusionMapping>());
    p->add_system(std::make_unique<Submapping>());
    return p;
  };
  auto kept = make();
  auto observed = make();
  std::vector<TruthPose> seen;
  observed->set_truth_observer([&](const TruthPose& t) { seen.push_back(t); });
  MemoryParts halfway;
  for (size_t i = 0; i < events.size(); ++i) {
    kept->consume(events[i]);
    observed->consume(events[i]);
    if (i == events.size() / 2) halfway = kept->memory();
  }
  kept->finish();
  observed->finish();
  const MemoryParts parts = kept->memory();
  std::vector<std::string> names;
  for (const auto& [name, bytes] : parts) names.push_back(name);
  CHECK(names == std::vector<std::string>{"truth", "dead_reckoning", "ping_queue", "keyframe_clouds", "pose_graph",
                                          "map:fusion", "map:submap"});
  const auto bytes = [](const MemoryParts& m, const std::string& name) {
    for (const auto& [n, b] : m)
      if (n == name) return b;
    return int64_t{-1};
  };
  CHECK(bytes(parts, "truth") >= static_cast<int64_t>(kept->truth().size() * sizeof(TruthPose)));
  CHECK(bytes(parts, "dead_reckoning") > 0);
  CHECK(bytes(parts, "ping_queue") == 0);  // finish() drained every pair
  CHECK(bytes(parts, "keyframe_clouds") > 0);
  CHECK(bytes(parts, "pose_graph") > 0);
  // The submap store holds every fused pair's points: it grew from half way to the end.
  CHECK(bytes(parts, "map:submap") > bytes(halfway, "map:submap"));
  CHECK(bytes(parts, "map:submap") >=
        static_cast<int64_t>(dynamic_cast<const Submapping&>(*kept->systems()[1]).store().total_points() *
                             sizeof(Eigen::Vector3f)));
  // The observer saw every truth pose, the pipeline kept none, and nothing else changed.
  CHECK(seen == kept->truth());
  CHECK(observed->truth().empty());
  CHECK(bytes(observed->memory(), "truth") == 0);
  CHECK(observed->counts().truth == kept->counts().truth);
  CHECK(observed->systems()[1]->map_points_W() == kept->systems()[1]->map_points_W());
}

TEST_CASE("pipeline keeps DR states only as far back as it can still look up, with the same poses", "[unit]") {
  const int seconds = 150;
  const auto events = mission(false, seconds);
  PipelineConfig cfg;
  cfg.slam.kf_distance_m = 2.0;  // a keyframe every 4 s
  cfg.fusion.min_confidence = 0.0;
  Pipeline p(cfg);
  p.add_system(std::make_unique<FusionMapping>());
  slam::DeadReckoning whole(cfg.dr);  // the same readings, nothing released
  size_t most_kept = 0;
  for (const auto& e : events) {
    p.consume(e);
    if (const auto* r = std::get_if<DvlReading>(&e.payload)) whole.add(*r);
    if (const auto* r = std::get_if<ImuReading>(&e.payload)) whole.add(*r);
    if (const auto* r = std::get_if<DepthReading>(&e.payload)) whole.add(*r);
    most_kept = std::max(most_kept, p.dead_reckoning().states_kept());
  }
  p.finish();
  const auto& dr = p.dead_reckoning();
  // 5 DVL readings a second: 751 in all; kept: the 30 s margin and a keyframe interval.
  CHECK(p.counts().dvl == seconds * 5 + 1);
  CHECK(most_kept > 150);
  CHECK(most_kept < 200);
  CHECK(dr.first_time() == whole.first_time());
  CHECK(dr.kept_from() > whole.first_time() + Time::from_s(100));
  // Every keyframe was posed by the released DR exactly as by the whole one.
  const auto& kfs = p.slam().keyframes();
  REQUIRE(kfs.size() > 30);
  for (const auto& k : kfs) {
    const auto T = whole.pose_at(k.stamp);
    REQUIRE(T.ok());
    CHECK(T->matrix() == k.T_W_V_dr.matrix());
  }
  CHECK(p.counts().pairs == seconds * 5 + 1);
  CHECK(p.counts().pairs_without_dr == 0);
}

namespace {

// Point targets fixed in the world, seen by a horizontal sonar on a vehicle driving along +x
// at 0.5 m/s (DR and truth agree): target i shows only in the pings whose number is i mod 4,
// so one ping sees a quarter of them and the pings between two keyframes see them all.
std::vector<Event> flashing_targets_mission(int seconds, std::vector<Vec3>& targets_W) {
  targets_W.clear();
  for (int i = 0; i < 24; ++i) targets_W.emplace_back(2.0 + 0.75 * i, i % 2 == 0 ? 3.0 : -3.0, -2.0);
  const SE3 T_V_h = perception::default_T_V_h();
  std::vector<Payload> payloads;
  for (int k = 0; k <= seconds * 5; ++k) {
    const Time t = Time::from_ms(200 * k);
    const SE3 T_W_V = se3_from_xyz_rpy(0.5 * t.seconds(), 0, -2, 0, 0, 0);
    SonarPing h = ping(SonarMount::kHorizontal, t, static_cast<uint32_t>(k));
    h.cols = 256;  // 0.5° beams: a 4-beam blob is 0.14 m wide at the 8 m range
    h.bearings_rad.clear();
    for (int c = 0; c < h.cols; ++c) h.bearings_rad.push_back((-65.0 + 130.0 * (c + 0.5) / h.cols) * M_PI / 180.0);
    h.image.assign(static_cast<size_t>(h.rows) * h.cols, 10);
    for (size_t i = 0; i < targets_W.size(); ++i) {
      if (static_cast<int>(i % 4) != k % 4) continue;
      const Vec3 p_h = (T_W_V * T_V_h).inverse() * targets_W[i];
      const double range = p_h.norm(), bearing = std::atan2(p_h.y(), p_h.x());
      const int row = static_cast<int>(std::lround(range / h.range_resolution_m)) - 1;
      const auto beam = std::min_element(h.bearings_rad.begin(), h.bearings_rad.end(), [&](double a, double b) {
        return std::abs(a - bearing) < std::abs(b - bearing);
      });
      const int col = static_cast<int>(beam - h.bearings_rad.begin());
      if (row < 2 || row > h.rows - 3 || std::abs(h.bearings_rad[static_cast<size_t>(col)] - bearing) > 0.01) continue;
      for (int r = row - 1; r <= row + 2; ++r)
        for (int c = std::max(0, col - 1); c <= std::min(h.cols - 1, col + 2); ++c)
          h.image[static_cast<size_t>(r) * h.cols + static_cast<size_t>(c)] = 220;
    }
    payloads.push_back(h);
    payloads.push_back(ping(SonarMount::kVertical, t + Time::from_ms(3), static_cast<uint32_t>(k)));
    add_dvl_and_depth(t, payloads);
  }
  add_imu(seconds, payloads);
  return hal::make_events(payloads);
}

// The keyframes' prepared clouds with keyframe_cloud_s = window_s (voxels of 5 cm, no
// outlier removal: every detection blob is kept).
std::vector<slam::Keyframe> keyframes_with_window(const std::vector<Event>& events, double window_s,
                                                  bool always = true, size_t ssm_min_points = 25) {
  PipelineConfig cfg;
  cfg.slam.kf_distance_m = 2.0;  // a keyframe every 4 s, 20 pairs
  cfg.slam.keyframe_cloud_s = window_s;
  cfg.slam.keyframe_cloud_always = always;
  cfg.slam.ssm_min_points = ssm_min_points;
  cfg.slam.voxel_m = 0.05;
  cfg.slam.outlier_min_neighbours = 0;
  Pipeline p(cfg);
  for (const auto& e : events) p.consume(e);
  p.finish();
  return p.slam().keyframes();
}

// How many of the targets have a cloud point within 0.3 m of them, the cloud placed at the
// keyframe's DR pose; and the largest distance of a cloud point from its nearest target.
std::pair<size_t, double> targets_seen(const slam::Keyframe& kf, const std::vector<Vec3>& targets_W) {
  std::vector<bool> seen(targets_W.size(), false);
  double worst = 0.0;
  for (const Eigen::Vector2d& q : kf.cloud_V) {
    const Vec3 p_W = kf.T_W_V_dr * Vec3(q.x(), q.y(), 0.0);
    double nearest = 1e9;
    for (size_t i = 0; i < targets_W.size(); ++i) {
      const double d = (p_W.head<2>() - targets_W[i].head<2>()).norm();
      nearest = std::min(nearest, d);
      if (d < 0.3) seen[i] = true;
    }
    worst = std::max(worst, nearest);
  }
  return {static_cast<size_t>(std::count(seen.begin(), seen.end(), true)), worst};
}

}  // namespace

TEST_CASE("slam.keyframe_cloud_s gathers the pairs since the previous keyframe into its cloud, placed by DR",
          "[unit]") {
  std::vector<Vec3> targets_W;
  const auto events = flashing_targets_mission(24, targets_W);
  const std::vector<slam::Keyframe> own = keyframes_with_window(events, 0.0);
  const std::vector<slam::Keyframe> interval = keyframes_with_window(events, 30.0);
  const std::vector<slam::Keyframe> short_window = keyframes_with_window(events, 0.5);
  REQUIRE(own.size() >= 5);
  REQUIRE(interval.size() == own.size());
  REQUIRE(short_window.size() == own.size());
  size_t compared = 0;
  for (size_t k = 1; k < own.size(); ++k) {
    const auto [n_own, worst_own] = targets_seen(own[k], targets_W);
    const auto [n_interval, worst_interval] = targets_seen(interval[k], targets_W);
    const auto [n_short, worst_short] = targets_seen(short_window[k], targets_W);
    INFO("keyframe " << k << ": targets in its cloud, own pair " << n_own << ", 0.5 s " << n_short << ", interval "
                     << n_interval << "; farthest point from a target " << worst_own << ", " << worst_short << ", "
                     << worst_interval << " m");
    // Every point of every cloud lies on a target: the earlier pairs are placed by DR.
    CHECK(worst_own < 0.3);
    CHECK(worst_interval < 0.3);
    CHECK(worst_short < 0.3);
    if (n_own == 0) continue;
    ++compared;
    // One pair sees a quarter of the targets in view; the 20 pairs since the previous
    // keyframe see every one of them; 0.5 s holds three pairs.
    CHECK(n_interval >= 3 * n_own);
    CHECK(n_short > n_own);
    CHECK(n_short < n_interval);
    // The keyframe's own pair is in its cloud whatever the window.
    CHECK(own[k].cloud_V.size() < interval[k].cloud_V.size());
  }
  CHECK(compared >= 3);
  // The first keyframe's cloud has only its own pair: nothing came before it.
  CHECK(own[0].cloud_V.size() == interval[0].cloud_V.size());

  // Not always: the gathered cloud only where the own pair's is too small to match. Every
  // keyframe's own prepared cloud here is a few blobs of 5 cm voxels.
  size_t own_max = 0, own_min = SIZE_MAX;
  for (size_t k = 1; k < own.size(); ++k) {
    own_max = std::max(own_max, own[k].cloud_V.size());
    own_min = std::min(own_min, own[k].cloud_V.size());
  }
  REQUIRE(own_min > 0);
  const std::vector<slam::Keyframe> sparse = keyframes_with_window(events, 30.0, false, own_max + 1);
  const std::vector<slam::Keyframe> dense = keyframes_with_window(events, 30.0, false, own_min);
  REQUIRE(sparse.size() == own.size());
  REQUIRE(dense.size() == own.size());
  for (size_t k = 0; k < own.size(); ++k) {
    CHECK(sparse[k].cloud_V.size() == interval[k].cloud_V.size());  // every own cloud too small
    CHECK(dense[k].cloud_V.size() == own[k].cloud_V.size());        // every own cloud enough
  }
}

TEST_CASE("mapping.max_elevation_sigma_deg withholds uncertain points from the maps, and only from them", "[unit]") {
  const auto events = mission(true, 8);
  struct Seen {
    PipelineCounts counts;
    size_t fusion_map = 0, submap = 0, observed = 0;
  };
  // Every other fused point gets an elevation σ of 3 deg, the rest 1 deg.
  auto run_with = [&](double max_sigma_deg) {
    PipelineConfig cfg;
    cfg.slam.kf_distance_m = 2.0;
    cfg.fusion.min_confidence = 0.0;
    cfg.max_elevation_sigma_deg = max_sigma_deg;
    Pipeline p(cfg);
    p.set_fusion([fc = cfg.fusion](const SonarPing& h, const SonarPing& v) {
      perception::FusionResult r = perception::fuse_pair(h, v, fc);
      for (size_t i = 0; i < r.points.size(); ++i)
        r.points[i].elevation_sigma_rad = static_cast<float>((i % 2 ? 3.0 : 1.0) * M_PI / 180.0);
      return r;
    });
    Seen s;
    p.set_pair_observer([&s](const SonarPing&, const SonarPing&, const perception::FusionResult& f) {
      s.observed += f.points.size();
    });
    p.add_system(std::make_unique<FusionMapping>());
    p.add_system(std::make_unique<Submapping>());
    for (const auto& e : events) p.consume(e);
    p.finish();
    s.counts = p.counts();
    s.fusion_map = p.systems()[0]->map_points_W().size();
    s.submap = p.systems()[1]->map_points_W().size();
    return s;
  };
  const Seen all = run_with(0.0), kept = run_with(2.0), none = run_with(0.5);
  REQUIRE(all.counts.fused_points > 10);
  CHECK(all.counts.withheld_uncertain == 0);
  CHECK(all.submap == static_cast<size_t>(all.counts.fused_points));
  // Half the points (the odd ones of each pair) are withheld; the counts and observers still see them all.
  CHECK(kept.counts.fused_points == all.counts.fused_points);
  CHECK(kept.observed == static_cast<size_t>(all.counts.fused_points));
  CHECK(kept.counts.withheld_uncertain > 0);
  CHECK(kept.submap == static_cast<size_t>(kept.counts.fused_points - kept.counts.withheld_uncertain));
  CHECK(kept.submap < all.submap);
  CHECK(kept.fusion_map <= all.fusion_map);
  CHECK(none.submap == 0);
  CHECK(none.counts.withheld_uncertain == none.counts.fused_points);
}
