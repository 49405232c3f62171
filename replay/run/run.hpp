#pragma once
// The run API (library orthosonar_run): open a source, configure, run the pipeline with
// progress and cancellation, and get the outputs and their digest (SPEC §9). The CLI's
// replay, verify, run, sweep, demo and golden commands and the golden tests all call it
// in-process; so can any other program (find_package(orthosonar), target orthosonar::run).
//
//   orthosonar::run::RunOptions options;                 // defaults: fusion + submap
//   options.config_yaml = "slam: {kf_distance_m: 2}";    // optional, over the fixture's values
//   std::atomic<bool> cancel{false};
//   orthosonar::run::RunControl control;
//   control.cancel = &cancel;
//   control.progress = [](const orthosonar::run::Progress& p) { /* p.fraction */ };
//   auto out = orthosonar::run::run_fixture("mission.mcap", options, control);
//   if (!out) { std::cerr << out.error().message; return 2; }
//   std::cout << out->digest.overall_hex;                // same bytes on every machine
//   orthosonar::run::write_run_outputs(*out, options, "out/");
//
// Fusion runs on oneTBB inside a task arena of `config.threads` threads; outputs are
// identical for any thread count. An exception thrown anywhere in the run (a worker thread
// included) comes back as an Error, never std::terminate. The library reads the steady
// clock for stage timings only (summary.json), never for anything that reaches an output.
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/metrics.hpp"
#include "core/mapping/pipeline.hpp"
#include "core/mesh.hpp"
#include "hal/event_source.hpp"
#include "replay/digest/digest.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/run/run_config.hpp"

namespace orthosonar::inference {
struct InferenceFrameCache;
}  // namespace orthosonar::inference

namespace orthosonar::run {

// Runs each batch with tbb::parallel_for inside its own task arena of N threads (the
// caller's thread is one of them); N = 1 runs inline. An exception from a task is rethrown
// in the caller's thread once the batch has stopped.
class TbbExecutor final : public mapping::Executor {
 public:
  explicit TbbExecutor(int threads);
  ~TbbExecutor() override;
  void run(size_t n, const std::function<void(size_t)>& task) override;
  int threads() const { return threads_; }

 private:
  struct Arena;  // a tbb::task_arena (TBB headers stay out of this header)
  int threads_;
  std::unique_ptr<Arena> arena_;
};

class SteadyClock final : public mapping::StageClock {
 public:
  double now_ms() const override;
};

struct RunOptions {
  // The configuration a run uses. run_fixture() recomputes it with effective_config():
  // defaults < the fixture's recorded values < config_yaml < threads_override.
  RunConfig config;
  std::string config_yaml;              // the user's run YAML (docs/CONFIG.md), may be empty
  std::string config_origin;            // where config_yaml came from, for messages ("c.yaml")
  std::optional<int> threads_override;  // --threads
  // A program's own settings, applied last (e.g. a sweep cell's keyframe distance).
  std::function<void(RunConfig&)> adjust;
  std::vector<std::string> systems = {"fusion", "submap"};
  double rate = 0.0;        // > 0: pace the replay at R x sensor time (changes no output)
  std::string mesh_path;    // ground-truth mesh file; empty: the fixture's embedded scene
  std::string model_path;   // classifier model for the inference systems
  // Sweeps: fill / reuse the per-pair clouds of inference_submap (core/inference
  // InferenceFrameCache). Not owned; must outlive the run.
  inference::InferenceFrameCache* inference_record = nullptr;
  const inference::InferenceFrameCache* inference_replay = nullptr;
};

// Where each configuration value came from: flattened key ("fusion.T_V_h") -> "fixture",
// "config:<origin>" or "command line". Keys left at their defaults are not listed.
using ConfigSources = std::map<std::string, std::string>;

// The configuration for a fixture with these metadata. Precedence, lowest first:
//   1. built-in defaults (docs/CONFIG.md);
//   2. the fixture's recorded values: sonar extrinsics (metadata T_V_h, T_V_v) and the DR
//      start from its mission plan (the scene's first waypoint; the scene embedded in
//      `attachments` when the fixture has one, else the one its metadata names);
//   3. options.config_yaml (--config);
//   4. options.threads_override (--threads), then options.adjust.
// Errors name the metadata key or the config key at fault.
Result<RunConfig> effective_config(const std::map<std::string, std::string>& metadata, const RunOptions& options,
                                   ConfigSources* sources = nullptr,
                                   const std::vector<replay::Attachment>& attachments = {});

// What run progress reports: the stamp reached, the fraction of the recording when its
// duration is known (else NaN), and the events consumed so far.
struct Progress {
  Time stamp;
  double fraction = 0.0;
  int64_t events = 0;
};

class TruthSpill;

struct RunControl {
  std::function<void(const Progress&)> progress;  // called every `progress_every` events
  int64_t progress_every = 2048;
  // Set to true from any thread to stop the run; it then returns an Error whose message
  // starts with kCancelledPrefix. Checked before every event.
  const std::atomic<bool>* cancel = nullptr;
  // Memory sampling (issue 41, replay --memory-report): called on the feeding thread at the
  // first event ("stream"), then whenever the stream has gone `memory_every` of sensor time
  // past the previous call ("stream"), after the last event ("end of stream", pairs
  // flushed), and after the metrics ("metrics"), with what the pipeline and the source hold
  // (source null once the stream is over). Changes no output.
  struct MemoryView {
    Time stamp;          // the stream's last event stamp
    const char* phase;
    const mapping::Pipeline& pipeline;
    const hal::EventSource* source;
    int64_t truth_spill_bytes;  // what the run's TruthSpill holds in memory (0 without one)
  };
  std::function<void(const MemoryView&)> memory;
  Time memory_every = Time::from_s(60);
};
inline constexpr const char* kCancelledPrefix = "cancelled";
bool is_cancelled(const Error& e);

struct SystemOutput {
  std::string name;
  std::vector<Eigen::Vector3f> map_W;
  int64_t coverage_voxels = 0;
  std::optional<mapping::AccuracyStats> accuracy;  // when a mesh is known
  // The same map with every keyframe at its true pose (MappingSystem::map_points_W_with):
  // the map error perception alone leaves. When a mesh is known, the truth stream spans
  // every keyframe and the system follows keyframe poses (fusion, submap).
  std::optional<mapping::AccuracyStats> true_pose_accuracy;
  std::vector<std::pair<std::string, mapping::RuntimeStats>> runtime;
  std::vector<std::pair<std::string, int64_t>> system_counts;  // MappingSystem::system_counts
};

// One ping pair as perception saw it: both images, every CFAR detection, the fused points.
struct PingPairView {
  SonarPing h, v;
  perception::FusionResult fused;
};

struct RunOutput {
  std::map<std::string, std::string> metadata;
  RunConfig config;                   // the configuration the run used
  ConfigSources config_sources;       // where its non-default values came from
  mapping::PipelineCounts counts;
  std::unique_ptr<mapping::Pipeline> pipeline;  // keyframes, factors, DR counts
  // The ground truth the metrics use: every pose seen, or (when the run kept the truth in a
  // TruthSpill, truth_all) the first and last poses and those either side of every keyframe
  // stamp, which give every keyframe's truth exactly as the whole stream does.
  std::vector<TruthPose> truth;
  // Every truth pose, on disk (replay/run/truth_spill.hpp): traj_truth.tum and results.mcap's
  // view read it. Null when the run kept the whole truth in `truth`.
  std::shared_ptr<const TruthSpill> truth_all;
  std::optional<double> ate_dr_m, ate_slam_m;
  // Keyframe heading against truth (issue 33), DR's and SLAM's; nullopt without truth.
  std::optional<mapping::HeadingErrorStats> heading_dr, heading_slam;
  std::vector<SystemOutput> systems;
  std::vector<std::pair<std::string, mapping::RuntimeStats>> runtime;
  std::optional<TriangleMesh> mesh;
  std::string mesh_note;    // where the mesh came from, or why there is none
  Time stream_span;         // last - first event stamp
  double wall_s = 0.0;
  replay::DigestResult digest;  // replay/digest/digest.hpp: SHA-256 per output and overall
  // The input fixture (run_fixture) and whether it was whole (replay::cut_input_warning):
  // summary.json's "input" records both. Live runs leave the path empty.
  std::string input_path;
  replay::RecoveryReport input_recovery;
  // The pair with the most fused points (the first of equals): the report's "what the
  // sonars saw" (ping_pair/ in the output directory). Empty when no pair fused a point.
  std::optional<PingPairView> ping_pair;
};

// The dead-reckoning start from the mission plan (the scene's first waypoint): fixtures
// record the launch point, not a truth stream. The scene is the one embedded in the
// fixture's `attachments` (sim::scene_from_fixture; fixtures written before scenes were
// embedded: the one the metadata names). Leaves the config alone when unknown.
void apply_mission_start(const std::map<std::string, std::string>& metadata, RunConfig& config,
                         const std::vector<replay::Attachment>& attachments = {});

// The ground-truth mesh: `mesh_path` when given, else the fixture's scene (embedded in
// `attachments`, else named by the metadata). `note` says which ("embedded:<origin>",
// "scene:<origin>", "file:<path>") or why there is none.
std::optional<TriangleMesh> load_truth_mesh(const std::map<std::string, std::string>& metadata,
                                            const std::string& mesh_path, std::string& note,
                                            const std::vector<replay::Attachment>& attachments = {});

// Builds the systems by name. Errors name an unknown system.
Result<std::vector<std::unique_ptr<mapping::MappingSystem>>> make_systems(const RunOptions& o);

// Feeds every event of `source` through a pipeline configured with `options.config` as it
// is (call effective_config() first for a fixture), then computes metrics and the digest.
// `fuse` (optional) replaces fusion (a cache).
Result<RunOutput> run_source(hal::EventSource& source, const std::map<std::string, std::string>& metadata,
                             const RunOptions& options, const std::optional<TriangleMesh>& mesh,
                             const RunControl& control = {}, const mapping::FuseFn& fuse = {});

// Opens a fixture, resolves the configuration (effective_config), finds the truth mesh
// and runs the pipeline over it. A truncated fixture runs on what was recovered,
// RunOutput::input_recovery records it and `warning` (when given) is
// replay::cut_input_warning's text (the caller decides the exit code, issue 40).
Result<RunOutput> run_fixture(const std::string& fixture_path, const RunOptions& options,
                              const RunControl& control = {}, std::string* warning = nullptr);

// Named deterministic counts (pipeline and DR), in a fixed order.
std::vector<std::pair<std::string, int64_t>> count_fields(const mapping::PipelineCounts& c, const slam::DrCounts& dr);
// The canonical bytes of every output (SPEC §9): the digest is SHA-256 over these.
std::map<std::string, std::vector<uint8_t>> canonical_outputs(const RunOutput& run);
// metrics.json of one system (the outputs contract).
nlohmann::json system_metrics_json(const RunOutput& run, const SystemOutput& s);
// Removes an earlier run's summary.json and digest.json from `out_dir` (call before a run
// starts): a run that then fails or is killed leaves no file that reads as a finished run.
Status clear_run_verdicts(const std::string& out_dir);
// Writes the whole output directory (maps, metrics, trajectories, summary, digest);
// summary.json and digest.json last, each through a temporary file and a rename.
Status write_run_outputs(const RunOutput& run, const RunOptions& options, const std::string& out_dir);

}  // namespace orthosonar::run
