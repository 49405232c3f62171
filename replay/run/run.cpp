#include "replay/run/run.hpp"
#include "replay/run/truth_spill.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>


#include "core/canonical.hpp"
#include "core/inference/inference_mapping.hpp"
#include "core/inference/numeric_pins.hpp"
#include "core/mapping/systems.hpp"
#include "hal/config/pose6.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"
#include "orthosonar/version.hpp"
#include "replay/digest/digest.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/outputs/map_writers.hpp"
#include "replay/run/trajectory.hpp"

namespace orthosonar::run {

// ---------------------------------------------------------------- executor, clock

struct TbbExecutor::Arena {
  // TBB caps its workers at the machine's cores unless told otherwise; a run asked for
  // more threads gets them (outputs do not depend on the count either way).
  explicit Arena(int threads)
      : limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads)), arena(threads) {}
  tbb::global_control limit;
  tbb::task_arena arena;
};

TbbExecutor::TbbExecutor(int threads) : threads_(std::max(1, threads)) {
  if (threads_ > 1) arena_ = std::make_unique<Arena>(threads_);
}

TbbExecutor::~TbbExecutor() = default;

void TbbExecutor::run(size_t n, const std::function<void(size_t)>& task) {
  if (n == 0) return;
  if (!arena_ || n == 1) {
    for (size_t i = 0; i < n; ++i) task(i);
    return;
  }
  // Each index is a pure function of its input (fusion of one pair): which thread runs it
  // cannot change a result, so any partitioner gives identical outputs. TBB cancels the
  // remaining work and rethrows a task's exception here, in the caller's thread.
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) task(i);
    });
  });
}

double SteadyClock::now_ms() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// ---------------------------------------------------------------- setup

void apply_mission_start(const std::map<std::string, std::string>& metadata, RunConfig& config,
                         const std::vector<replay::Attachment>& attachments) {
  const auto scene = sim::scene_from_fixture(metadata, replay::attachment_files(attachments));
  if (scene.ok() && !scene->route.empty())
    config.pipeline.dr.initial_xy_m = Vec2(scene->route.front().x_m, scene->route.front().y_m);
}

std::optional<TriangleMesh> load_truth_mesh(const std::map<std::string, std::string>& metadata,
                                            const std::string& mesh_path, std::string& note,
                                            const std::vector<replay::Attachment>& attachments) {
  if (!mesh_path.empty()) {
    auto m = sim::read_mesh(mesh_path);
    if (!m.ok()) {
      note = m.error().message;
      return std::nullopt;
    }
    note = "file:" + mesh_path;
    return std::move(*m);
  }
  bool embedded = false;
  auto scene = sim::scene_from_fixture(metadata, replay::attachment_files(attachments), &embedded);
  if (!scene.ok()) {
    note = "no ground-truth mesh: " + scene.error().message;
    return std::nullopt;
  }
  note = (embedded ? "embedded:" : "scene:") + scene->origin;
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
          {"fused_points", c.fused_points}, {"fused_sloped_face", c.fused_sloped_face},
          {"withheld_uncertain", c.withheld_uncertain},
          {"keyframes", c.keyframes},
          {"loop_closures", c.loop_closures},
          {"dvl_rejected_invalid", static_cast<int64_t>(dr.dvl_invalid)},
          {"dvl_rejected_nonfinite", static_cast<int64_t>(dr.dvl_nonfinite)},
          {"dvl_rejected_too_fast", static_cast<int64_t>(dr.dvl_too_fast)},
          {"dvl_dropouts", static_cast<int64_t>(dr.dropouts)}};
}

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
    mt.put_i64(s.true_pose_accuracy ? s.true_pose_accuracy->count : 0);
    mt.put_f64(s.true_pose_accuracy ? s.true_pose_accuracy->mae_m : std::numeric_limits<double>::quiet_NaN());
    mt.put_f64(s.true_pose_accuracy ? s.true_pose_accuracy->rmse_m : std::numeric_limits<double>::quiet_NaN());
    out[s.name + "/metrics"] = mt.take();
  }
  return out;
}

namespace {

Result<RunOutput> run_source_unguarded(hal::EventSource& source, const std::map<std::string, std::string>& metadata,
                                       const RunOptions& options, const std::optional<TriangleMesh>& mesh,
                                       const RunControl& control, const mapping::FuseFn& fuse) {
  inference::apply_numeric_pins();  // cross-machine determinism (docs/ARCHITECTURE.md); idempotent
  auto systems = make_systems(options);
  if (!systems.ok()) return systems.error();
  RunOutput r;
  r.metadata = metadata;
  r.config = options.config;
  r.pipeline = std::make_unique<mapping::Pipeline>(options.config.pipeline);
  TbbExecutor pool(std::max(1, options.config.threads));
  SteadyClock clock;
  r.pipeline->set_executor(&pool);
  r.pipeline->set_clock(&clock);
  if (fuse) r.pipeline->set_fusion(fuse);
  // Pairs arrive in stamp order on this thread: the pair kept is the same for any thread count.
  auto best = std::make_shared<std::optional<PingPairView>>();
  r.pipeline->set_pair_observer([best](const SonarPing& h, const SonarPing& v, const perception::FusionResult& f) {
    if (f.points.empty() || (*best && (*best)->fused.points.size() >= f.points.size())) return;
    *best = PingPairView{h, v, f};
  });
  std::vector<const inference::InferenceMapping*> cached;
  for (auto& s : *systems) {
    if (const auto* im = dynamic_cast<const inference::InferenceMapping*>(s.get()); im && options.inference_replay)
      cached.push_back(im);
    r.pipeline->add_system(std::move(s));
  }

  const auto wall0 = std::chrono::steady_clock::now();
  Time first_stamp;
  double duration_s = 0.0;
  if (const auto it = metadata.find("duration_s"); it != metadata.end()) duration_s = std::atof(it->second.c_str());
  auto report = [&](Time t, int64_t events) {
    Progress pr;
    pr.stamp = t;
    pr.events = events;
    pr.fraction = duration_s > 0.0 ? std::clamp((t - first_stamp).seconds() / duration_s, 0.0, 1.0)
                                   : std::numeric_limits<double>::quiet_NaN();
    control.progress(pr);
  };
  // The truth goes to a temporary file, not memory (issue 41): the metrics need only the
  // poses around keyframe stamps. Where no temporary file can be had, it stays in memory.
  std::shared_ptr<TruthSpill> spill;
  if (auto opened = TruthSpill::open(); opened.ok()) {
    spill = std::move(opened).value();
    r.pipeline->set_truth_observer([s = spill.get()](const TruthPose& p) { s->append(p); });
  }
  std::optional<Time> first, last, memory_at;
  const auto sample_memory = [&](const char* phase, const hal::EventSource* src) {
    if (control.memory)
      control.memory({last.value_or(Time()), phase, *r.pipeline, src, spill ? spill->memory_bytes() : 0});
  };
  int64_t n = 0;
  for (;;) {
    if (control.cancel && control.cancel->load(std::memory_order_relaxed))
      return Error{std::string(kCancelledPrefix) + ": " + source.describe() + " stopped after " + std::to_string(n) +
                   " events" + (last ? " (stamp " + std::to_string(last->ns()) + " ns)" : std::string())};
    hal::Pulled p = source.next();
    if (p.error) return Error{source.describe() + ": " + p.error->message};
    if (p.end_of_stream || !p.event) break;
    const Time t = p.event->stamp;
    if (!first) {
      first = t;
      first_stamp = t;
    }
    last = t;
    if (control.memory && (!memory_at || t - *memory_at >= control.memory_every)) {
      memory_at = t;
      sample_memory("stream", &source);
    }
    if (options.rate > 0.0) {
      const auto due = wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>((t - *first).seconds() / options.rate));
      std::this_thread::sleep_until(due);
    }
    r.pipeline->consume(std::move(*p.event));
    ++n;
    if (control.progress && control.progress_every > 0 && n % control.progress_every == 0) report(t, n);
  }
  r.pipeline->finish();
  sample_memory("end of stream", nullptr);
  r.pipeline->set_pair_observer({});
  r.ping_pair = std::move(*best);
  if (control.progress && last) report(*last, n);
  r.stream_span = first ? (*last - *first) : Time();
  for (const auto* im : cached)
    if (im->cache_misses() > 0)
      return Error{"inference cache: " + std::to_string(im->cache_misses()) + " pair(s) of " + source.describe() +
                   " were not in the cache the preparation pass filled"};

  r.counts = r.pipeline->counts();
  if (spill) {
    if (Status st = spill->finish(); !st.ok()) return st.error();
    std::vector<Time> stamps;
    for (const auto& k : r.pipeline->slam().keyframes()) stamps.push_back(k.stamp);
    auto subset = spill->subset(stamps);
    if (!subset.ok()) return subset.error();
    r.truth = std::move(subset).value();
    r.truth_all = spill;
  } else {
    r.truth = r.pipeline->take_truth();
  }
  r.runtime = r.pipeline->runtime();
  std::vector<mapping::StampedPosition> dr, sl;
  std::vector<mapping::StampedPose> dr_pose, sl_pose;
  for (const auto& k : r.pipeline->slam().keyframes()) {
    dr.push_back({k.stamp, k.T_W_V_dr.translation()});
    sl.push_back({k.stamp, k.T_W_V_slam.translation()});
    dr_pose.push_back({k.stamp, k.T_W_V_dr});
    sl_pose.push_back({k.stamp, k.T_W_V_slam});
  }
  r.ate_dr_m = mapping::absolute_trajectory_error(dr, r.truth);
  r.ate_slam_m = mapping::absolute_trajectory_error(sl, r.truth);
  r.heading_dr = mapping::heading_error(dr_pose, r.truth);
  r.heading_slam = mapping::heading_error(sl_pose, r.truth);
  r.mesh = mesh;
  std::optional<mapping::MeshDistance> md;
  if (mesh) md.emplace(*mesh);
  const mapping::VoxelConfig vc{options.config.voxel_m};
  // The keyframes' true poses, when the truth stream spans all of them.
  std::optional<std::vector<SE3>> T_W_K_true;
  if (md && !r.truth.empty()) {
    T_W_K_true.emplace();
    for (const auto& k : r.pipeline->slam().keyframes()) {
      const auto T = mapping::truth_pose_at(r.truth, k.stamp);
      if (!T) {
        T_W_K_true.reset();
        break;
      }
      T_W_K_true->push_back(*T);
    }
  }
  for (const auto& s : r.pipeline->systems()) {
    SystemOutput o;
    o.name = s->name();
    o.map_W = s->map_points_W();
    const auto centroids = mapping::voxel_centroids(o.map_W, vc);
    o.coverage_voxels = static_cast<int64_t>(centroids.size());
    if (md) o.accuracy = mapping::accuracy(centroids, *md);
    if (T_W_K_true)
      if (const auto true_map = s->map_points_W_with(*T_W_K_true))
        o.true_pose_accuracy = mapping::accuracy(mapping::voxel_centroids(*true_map, vc), *md);
    o.runtime = s->runtime();
    o.system_counts = s->system_counts();
    r.systems.push_back(std::move(o));
  }
  replay::DigestBuilder digest;
  for (const auto& [name, bytes] : canonical_outputs(r)) digest.add(name, bytes);
  r.digest = digest.finish();
  sample_memory("metrics", nullptr);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace

Result<RunOutput> run_source(hal::EventSource& source, const std::map<std::string, std::string>& metadata,
                             const RunOptions& options, const std::optional<TriangleMesh>& mesh,
                             const RunControl& control, const mapping::FuseFn& fuse) {
  // Anything thrown on the way (a fusion task on a worker thread included: TBB rethrows it
  // here) becomes an Error naming the source, never std::terminate.
  try {
    return run_source_unguarded(source, metadata, options, mesh, control, fuse);
  } catch (const std::exception& e) {
    return Error{source.describe() + ": " + e.what()};
  } catch (...) {
    return Error{source.describe() + ": unknown exception"};
  }
}

bool is_cancelled(const Error& e) { return e.message.rfind(kCancelledPrefix, 0) == 0; }

namespace {

// Flattens a config JSON into "a.b.c" -> value text.
void flatten(const nlohmann::json& j, const std::string& prefix, std::map<std::string, std::string>& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k, out);
    return;
  }
  out[prefix] = j.dump();
}

void note_changes(const RunConfig& before, const RunConfig& after, const std::string& origin, ConfigSources& sources) {
  std::map<std::string, std::string> a, b;
  flatten(config_to_json(before), "", a);
  flatten(config_to_json(after), "", b);
  for (const auto& [k, v] : b)
    if (a[k] != v) sources[k] = origin;
}

}  // namespace

Result<RunConfig> effective_config(const std::map<std::string, std::string>& metadata, const RunOptions& options,
                                   ConfigSources* sources, const std::vector<replay::Attachment>& attachments) {
  ConfigSources local;
  ConfigSources& src = sources ? *sources : local;
  src.clear();
  RunConfig c;  // 1. defaults
  // 2. the fixture's recorded values
  RunConfig from_fixture = c;
  for (const auto& [key, target] : {std::pair<const char*, SE3*>{"T_V_h", &from_fixture.pipeline.fusion.T_V_h},
                                    std::pair<const char*, SE3*>{"T_V_v", &from_fixture.pipeline.fusion.T_V_v},
                                    std::pair<const char*, SE3*>{"T_V_gyro", &from_fixture.pipeline.dr.gyro.T_V_gyro}}) {
    const auto it = metadata.find(key);
    if (it == metadata.end()) continue;
    const auto pose = config::parse_pose6(it->second);
    if (!pose.ok())
      return Error{std::string("fixture metadata '") + key + "' = '" + it->second +
                   "' is not six finite numbers 'x y z roll pitch yaw' (m, rad)"};
    *target = *pose;
  }
  if (const auto it = metadata.find("latitude_deg"); it != metadata.end()) {
    // Where the gyro's mission was (the Earth rate it senses): simulated scenes and imports record it.
    char* end = nullptr;
    const double lat = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || end != it->second.c_str() + it->second.size() || !(lat >= -90.0 && lat <= 90.0))
      return Error{"fixture metadata 'latitude_deg' = '" + it->second + "' is not a latitude in [-90, 90] degrees"};
    from_fixture.pipeline.dr.gyro.latitude_deg = lat;
  }
  apply_mission_start(metadata, from_fixture, attachments);
  note_changes(c, from_fixture, "fixture", src);
  c = from_fixture;
  // 3. the run YAML
  if (!options.config_yaml.empty()) {
    RunConfig from_yaml = c;
    if (Status s = apply_config_yaml(options.config_yaml, from_yaml); !s.ok())
      return Error{(options.config_origin.empty() ? std::string() : options.config_origin + ": ") + s.error().message};
    note_changes(c, from_yaml, "config" + (options.config_origin.empty() ? std::string() : ":" + options.config_origin),
                 src);
    c = from_yaml;
  }
  // 4. the command line
  if (options.threads_override) {
    if (*options.threads_override < 1 || *options.threads_override > kMaxThreads)
      return Error{"--threads must be in [1, " + std::to_string(kMaxThreads) + "]"};
    RunConfig from_flags = c;
    from_flags.threads = *options.threads_override;
    note_changes(c, from_flags, "command line", src);
    c = from_flags;
  }
  if (options.adjust) {
    RunConfig adjusted = c;
    options.adjust(adjusted);
    note_changes(c, adjusted, "program", src);
    c = adjusted;
  }
  return c;
}

Result<RunOutput> run_fixture(const std::string& fixture_path, const RunOptions& options, const RunControl& control,
                              std::string* warning) {
  auto src = replay::FixtureSource::open(fixture_path);
  if (!src.ok()) return src.error();
  auto& source = **src;
  if (warning)
    if (auto cut = replay::cut_input_warning(fixture_path, source.recovery())) *warning = *cut;
  const auto& meta = source.metadata();
  RunOptions resolved = options;
  ConfigSources sources;
  auto config = effective_config(meta, options, &sources, source.attachments());
  if (!config.ok()) return Error{fixture_path + ": " + config.error().message};
  resolved.config = *config;
  std::string note;
  const auto mesh = load_truth_mesh(meta, options.mesh_path, note, source.attachments());
  auto r = run_source(source, meta, resolved, mesh, control);
  if (!r.ok()) return r.error();
  r->mesh_note = note;
  r->config_sources = std::move(sources);
  r->input_path = fixture_path;
  r->input_recovery = source.recovery();
  return r;
}

}  // namespace orthosonar::run
