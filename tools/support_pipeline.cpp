#include "tools/support_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>


#include "core/canonical.hpp"
#include "core/inference/inference_mapping.hpp"
#include "core/mapping/systems.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"
#include "orthosonar/version.hpp"
#include "replay/digest.hpp"
#include "replay/fixture.hpp"
#include "replay/outputs/map_writers.hpp"
#include "tools/support_trajectory.hpp"

namespace orthosonar::cli {

// ---------------------------------------------------------------- thread pool, clock

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadPool::drain() {
  size_t done = 0;
  for (size_t i = next_.fetch_add(1); i < n_; i = next_.fetch_add(1)) {
    (*task_)(i);
    ++done;
  }
  std::lock_guard lock(mu_);
  finished_ += done;
  if (finished_ == n_) done_cv_.notify_all();
}

void ThreadPool::work() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mu_);
      cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    drain();
  }
}

void ThreadPool::run(size_t n, const std::function<void(size_t)>& task) {
  if (n == 0) return;
  if (workers_.empty() || n == 1) {
    for (size_t i = 0; i < n; ++i) task(i);
    return;
  }
  {
    std::lock_guard lock(mu_);
    task_ = &task;
    n_ = n;
    next_ = 0;
    finished_ = 0;
    ++generation_;
  }
  cv_.notify_all();
  drain();
  std::unique_lock lock(mu_);
  done_cv_.wait(lock, [&] { return finished_ == n_; });
}

double SteadyClock::now_ms() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// ---------------------------------------------------------------- setup

void apply_mission_start(const std::map<std::string, std::string>& metadata, RunConfig& config) {
  const auto scene = sim::scene_from_metadata(metadata);
  if (scene.ok() && !scene->route.empty())
    config.pipeline.dr.initial_xy_m = Vec2(scene->route.front().x_m, scene->route.front().y_m);
}

std::optional<TriangleMesh> load_truth_mesh(const std::map<std::string, std::string>& metadata,
                                            const std::string& mesh_path, std::string& note) {
  if (!mesh_path.empty()) {
    auto m = sim::read_mesh(mesh_path);
    if (!m.ok()) {
      note = m.error().message;
      return std::nullopt;
    }
    note = "file:" + mesh_path;
    return std::move(*m);
  }
  auto scene = sim::scene_from_metadata(metadata);
  if (!scene.ok()) {
    note = "no ground-truth mesh: " + scene.error().message;
    return std::nullopt;
  }
  note = "scene:" + scene->origin;
  return std::move(scene->mesh);
}

Result<std::vector<std::unique_ptr<mapping::MappingSystem>>> make_systems(const RunOptions& o) {
  std::vector<std::unique_ptr<mapping::MappingSystem>> out;
  for (const auto& name : o.systems) {
    if (auto s = mapping::make_geometric_system(name)) {
      out.push_back(std::move(s));
      continue;
    }
    if (name == "inference" || name == "inference_submap") {
      if (o.model_path.empty()) return Error{"system '" + name + "' needs --model <classifier model file>"};
      std::ifstream f(o.model_path, std::ios::binary);
      if (!f) return Error{"cannot open model '" + o.model_path + "'"};
      std::stringstream ss;
      ss << f.rdbuf();
      // Torch's threads and seed are process-wide: set them explicitly, once, here in the
      // tool (never hidden in a constructor). MC-dropout seeds derive from (seed, ping id).
      inference::InferenceRuntime::configure(1, 0);
      inference::InferenceConfig ic;
      ic.seed = 0;
      ic.T_V_h = o.config.pipeline.fusion.T_V_h;  // the extrinsics fusion uses
      auto s = inference::make_inference_system_from_model(ic, name == "inference_submap", ss.str());
      if (!s.ok()) return Error{o.model_path + ": " + s.error().message};
      if (auto* im = dynamic_cast<inference::InferenceMapping*>(s->get()); im && name == "inference_submap") {
        im->record_frames_to(o.inference_record);
        im->replay_frames_from(o.inference_replay);
      }
      out.push_back(std::move(*s));
      continue;
    }
    return Error{"unknown mapping system '" + name + "' (fusion, submap, inference, inference_submap)"};
  }
  return out;
}

// ---------------------------------------------------------------- run

namespace {

double nan_or(const std::optional<double>& v) { return v ? *v : std::numeric_limits<double>::quiet_NaN(); }

}  // namespace

std::vector<std::pair<std::string, int64_t>> count_fields(const mapping::PipelineCounts& c,
                                                          const slam::DrCounts& dr) {
  return {{"events", c.events},       {"sonar_h", c.sonar_h},
          {"sonar_v", c.sonar_v},     {"imu", c.imu},
          {"dvl", c.dvl},             {"depth", c.depth},
          {"truth", c.truth},         {"labels", c.labels},
          {"pairs", c.pairs},         {"unpaired_h", c.unpaired_h},
          {"unpaired_v", c.unpaired_v}, {"pairs_without_dr", c.pairs_without_dr},
          {"detections_h", c.detections_h}, {"detections_v", c.detections_v},
          {"matches", c.matches},     {"culled_low_confidence", c.culled_low_confidence},
          {"fused_points", c.fused_points}, {"keyframes", c.keyframes},
          {"loop_closures", c.loop_closures},
          {"dvl_rejected_invalid", static_cast<int64_t>(dr.dvl_invalid)},
          {"dvl_rejected_nonfinite", static_cast<int64_t>(dr.dvl_nonfinite)},
          {"dvl_rejected_too_fast", static_cast<int64_t>(dr.dvl_too_fast)},
          {"dvl_dropouts", static_cast<int64_t>(dr.dropouts)}};
}

namespace {

std::map<std::string, std::vector<uint8_t>> canonical_outputs(const RunOutput& r) {
  std::map<std::string, std::vector<uint8_t>> out;
  const auto& slam = r.pipeline->slam();
  CanonicalWriter kf;
  kf.put_u64(slam.keyframes().size());
  for (const auto& k : slam.keyframes()) {
    kf.put_i32(k.id);
    kf.put_i64(k.stamp.ns());
    kf.put_se3(k.T_W_V_dr);
    kf.put_se3(k.T_W_V_slam);
  }
  out["keyframes"] = kf.take();
  CanonicalWriter fw;
  fw.put_u64(slam.factors().size());
  for (const auto& f : slam.factors()) {
    fw.put_u8(static_cast<uint8_t>(f.kind));
    fw.put_i32(f.from);
    fw.put_i32(f.to);
    fw.put_f64(f.T_from_to.x);
    fw.put_f64(f.T_from_to.y);
    fw.put_f64(f.T_from_to.theta);
    fw.put_bool(f.accepted);
  }
  out["factors"] = fw.take();
  CanonicalWriter cw;
  for (const auto& [name, v] : count_fields(r.counts, r.pipeline->dead_reckoning().counts())) {
    cw.put_string(name);
    cw.put_i64(v);
  }
  out["counts"] = cw.take();
  for (const auto& s : r.systems) {
    CanonicalWriter m;
    m.put_points(s.map_W);
    out[s.name + "/map"] = m.take();
    CanonicalWriter mt;
    mt.put_i64(s.coverage_voxels);
    mt.put_i64(s.accuracy ? s.accuracy->count : 0);
    mt.put_f64(s.accuracy ? s.accuracy->mae_m : std::numeric_limits<double>::quiet_NaN());
    mt.put_f64(s.accuracy ? s.accuracy->rmse_m : std::numeric_limits<double>::quiet_NaN());
    mt.put_f64(nan_or(r.ate_dr_m));
    mt.put_f64(nan_or(r.ate_slam_m));
    out[s.name + "/metrics"] = mt.take();
  }
  return out;
}

}  // namespace

Result<RunOutput> run_pipeline(hal::EventSource& source, const std::map<std::string, std::string>& metadata,
                               const RunOptions& options, const std::optional<TriangleMesh>& mesh,
                               const mapping::FuseFn& fuse, const std::function<void(Time)>& progress) {
  auto systems = make_systems(options);
  if (!systems.ok()) return systems.error();
  RunOutput r;
  r.metadata = metadata;
  r.pipeline = std::make_unique<mapping::Pipeline>(options.config.pipeline);
  ThreadPool pool(std::max(1, options.config.threads));
  SteadyClock clock;
  r.pipeline->set_executor(&pool);
  r.pipeline->set_clock(&clock);
  if (fuse) r.pipeline->set_fusion(fuse);
  std::vector<const inference::InferenceMapping*> cached;
  for (auto& s : *systems) {
    if (const auto* im = dynamic_cast<const inference::InferenceMapping*>(s.get()); im && options.inference_replay)
      cached.push_back(im);
    r.pipeline->add_system(std::move(s));
  }

  const auto wall0 = std::chrono::steady_clock::now();
  std::optional<Time> first, last;
  int64_t n = 0;
  for (;;) {
    hal::Pulled p = source.next();
    if (p.error) return Error{source.describe() + ": " + p.error->message};
    if (p.end_of_stream || !p.event) break;
    const Time t = p.event->stamp;
    if (!first) first = t;
    last = t;
    if (options.rate > 0.0) {
      const auto due = wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>((t - *first).seconds() / options.rate));
      std::this_thread::sleep_until(due);
    }
    r.pipeline->consume(*p.event);
    if (progress && (++n % 2048) == 0) progress(t);
  }
  r.pipeline->finish();
  r.stream_span = first ? (*last - *first) : Time();
  for (const auto* im : cached)
    if (im->cache_misses() > 0)
      return Error{"inference cache: " + std::to_string(im->cache_misses()) + " pair(s) of " + source.describe() +
                   " were not in the cache the preparation pass filled"};

  r.counts = r.pipeline->counts();
  r.truth = r.pipeline->truth();
  r.runtime = r.pipeline->runtime();
  std::vector<mapping::StampedPosition> dr, sl;
  for (const auto& k : r.pipeline->slam().keyframes()) {
    dr.push_back({k.stamp, k.T_W_V_dr.translation()});
    sl.push_back({k.stamp, k.T_W_V_slam.translation()});
  }
  r.ate_dr_m = mapping::absolute_trajectory_error(dr, r.truth);
  r.ate_slam_m = mapping::absolute_trajectory_error(sl, r.truth);
  r.mesh = mesh;
  std::optional<mapping::MeshDistance> md;
  if (mesh) md.emplace(*mesh);
  const mapping::VoxelConfig vc{options.config.voxel_m};
  for (const auto& s : r.pipeline->systems()) {
    SystemOutput o;
    o.name = s->name();
    o.map_W = s->map_points_W();
    const auto centroids = mapping::voxel_centroids(o.map_W, vc);
    o.coverage_voxels = static_cast<int64_t>(centroids.size());
    if (md) o.accuracy = mapping::accuracy(centroids, *md);
    o.runtime = s->runtime();
    o.system_counts = s->system_counts();
    r.systems.push_back(std::move(o));
  }
  replay::DigestBuilder digest;
  for (const auto& [name, bytes] : canonical_outputs(r)) digest.add(name, bytes);
  r.digest = digest.finish();
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

Result<RunOutput> replay_file(const std::string& fixture_path, RunOptions options, bool progress) {
  auto src = replay::FixtureSource::open(fixture_path);
  if (!src.ok()) return src.error();
  auto& source = **src;
  if (!source.recovery().complete)
    std::cerr << "warning: " << fixture_path << " is incomplete: " << source.recovery().detail << "\n";
  const auto& meta = source.metadata();
  apply_mission_start(meta, options.config);
  std::string note;
  const auto mesh = load_truth_mesh(meta, options.mesh_path, note);
  double duration_s = 0.0;
  if (const auto it = meta.find("duration_s"); it != meta.end()) duration_s = std::atof(it->second.c_str());
  std::optional<Time> t0;
  auto on_progress = [&](Time t) {
    if (!t0) t0 = t;
    if (progress && duration_s > 0.0)
      print_progress("replay", (t - *t0).seconds() / duration_s, std::to_string(static_cast<int>((t - *t0).seconds())) + " s");
  };
  auto r = run_pipeline(source, meta, options, mesh, {}, on_progress);
  if (!r.ok()) return r.error();
  if (progress && duration_s > 0.0) print_progress("replay", 1.0, "done");
  r->mesh_note = note;
  return r;
}

void add_run_options(CLI::App& sub, CommonRunArgs& a) {
  sub.add_option("--systems", a.systems, "Mapping systems, comma separated (fusion, submap, inference, inference_submap)")
      ->capture_default_str();
  sub.add_option("--threads", a.threads, "Fusion threads (outputs identical for any count; default from config, 1)");
  sub.add_option("--config", a.config_path, "YAML configuration of every stage");
  sub.add_option("--rate", a.rate, "Pace the replay at R x sensor time (0: as fast as possible; changes no output)");
  sub.add_option("--mesh", a.mesh_path, "Ground-truth mesh (PLY/OBJ/STL); default: the fixture's scene");
  sub.add_option("--model", a.model_path, "Classifier model for the inference systems");
}

Result<RunOptions> run_options_from(const CommonRunArgs& a) {
  RunOptions o;
  if (!a.config_path.empty())
    if (Status s = load_config_file(a.config_path, o.config); !s.ok()) return s.error();
  if (a.threads > 0) o.config.threads = a.threads;
  if (a.rate < 0.0) return Error{"--rate must be >= 0"};
  o.rate = a.rate;
  o.mesh_path = a.mesh_path;
  o.model_path = a.model_path;
  o.systems.clear();
  std::stringstream ss(a.systems);
  std::string name;
  while (std::getline(ss, name, ','))
    if (!name.empty()) o.systems.push_back(name);
  if (o.systems.empty()) return Error{"--systems is empty"};
  return o;
}

void print_progress(const std::string& label, double fraction, const std::string& detail) {
  const double f = std::clamp(fraction, 0.0, 1.0);
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(f * kWidth);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r%s [%s] %3d%%  %s   ", label.c_str(), bar.c_str(), static_cast<int>(f * 100.0),
               detail.c_str());
  if (f >= 1.0) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace orthosonar::cli
