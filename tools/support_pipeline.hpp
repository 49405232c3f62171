#pragma once
// Running the pipeline from the command line (replay, verify, sweep, demo, run): a thread
// pool for fusion, a steady clock for stage timings, metrics against the ground-truth
// mesh, the output directory of the outputs contract, and its digest (SPEC §9).
#include <atomic>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/metrics.hpp"
#include "core/mapping/pipeline.hpp"
#include "core/mesh.hpp"
#include "hal/event_source.hpp"
#include "replay/digest.hpp"
#include "tools/cli.hpp"
#include "tools/support_config.hpp"

namespace orthosonar::inference {
struct InferenceFrameCache;
}  // namespace orthosonar::inference

namespace orthosonar::cli {

// Runs tasks on N threads (the caller's thread is one of them). N = 1 runs inline.
class ThreadPool final : public mapping::Executor {
 public:
  explicit ThreadPool(int threads);
  ~ThreadPool() override;
  void run(size_t n, const std::function<void(size_t)>& task) override;
  int threads() const { return static_cast<int>(workers_.size()) + 1; }

 private:
  void work();
  void drain();
  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable cv_, done_cv_;
  const std::function<void(size_t)>* task_ = nullptr;
  size_t n_ = 0;
  std::atomic<size_t> next_{0};
  size_t finished_ = 0;
  uint64_t generation_ = 0;
  bool stop_ = false;
};

class SteadyClock final : public mapping::StageClock {
 public:
  double now_ms() const override;
};


struct RunOptions {
  RunConfig config;
  std::vector<std::string> systems = {"fusion", "submap"};
  double rate = 0.0;        // > 0: pace the replay at R x sensor time (changes no output)
  std::string mesh_path;    // ground-truth mesh file; empty: from the fixture's scene
  std::string model_path;   // classifier model for the inference systems
  // Sweeps: fill / reuse the per-pair clouds of inference_submap (core/inference
  // InferenceFrameCache). Not owned; must outlive the run.
  inference::InferenceFrameCache* inference_record = nullptr;
  const inference::InferenceFrameCache* inference_replay = nullptr;
};

struct SystemOutput {
  std::string name;
  std::vector<Eigen::Vector3f> map_W;
  int64_t coverage_voxels = 0;
  std::optional<mapping::AccuracyStats> accuracy;  // when a mesh is known
  std::vector<std::pair<std::string, mapping::RuntimeStats>> runtime;
  std::vector<std::pair<std::string, int64_t>> system_counts;  // MappingSystem::system_counts
};

struct RunOutput {
  std::map<std::string, std::string> metadata;
  mapping::PipelineCounts counts;
  std::unique_ptr<mapping::Pipeline> pipeline;  // keyframes, factors, DR counts
  std::vector<TruthPose> truth;
  std::optional<double> ate_dr_m, ate_slam_m;
  std::vector<SystemOutput> systems;
  std::vector<std::pair<std::string, mapping::RuntimeStats>> runtime;
  std::optional<TriangleMesh> mesh;
  std::string mesh_note;    // where the mesh came from, or why there is none
  Time stream_span;         // last - first event stamp
  double wall_s = 0.0;
  replay::DigestResult digest;  // replay/digest.hpp: SHA-256 per output and overall
};

// The dead-reckoning start from the mission plan (the scene's first waypoint): fixtures
// record the launch point, not a truth stream. Leaves the config alone when unknown.
void apply_mission_start(const std::map<std::string, std::string>& metadata, RunConfig& config);

// The ground-truth mesh: `mesh_path` when given, else the fixture's scene (metadata).
std::optional<TriangleMesh> load_truth_mesh(const std::map<std::string, std::string>& metadata,
                                            const std::string& mesh_path, std::string& note);

// Builds the systems by name. Errors name an unknown system.
Result<std::vector<std::unique_ptr<mapping::MappingSystem>>> make_systems(const RunOptions& o);

// Feeds every event of `source` through a pipeline, then computes metrics and the digest.
// `fuse` (optional) replaces fusion (a cache). `progress(stamp)` is called now and then.
Result<RunOutput> run_pipeline(hal::EventSource& source, const std::map<std::string, std::string>& metadata,
                               const RunOptions& options, const std::optional<TriangleMesh>& mesh,
                               const mapping::FuseFn& fuse = {},
                               const std::function<void(Time)>& progress = {});
// Named deterministic counts (pipeline and DR), in a fixed order.
std::vector<std::pair<std::string, int64_t>> count_fields(const mapping::PipelineCounts& c, const slam::DrCounts& dr);
// metrics.json of one system (the outputs contract).
nlohmann::json system_metrics_json(const RunOutput& run, const SystemOutput& s);
// Writes the whole output directory (maps, metrics, trajectories, summary, digest).
Status write_run_outputs(const RunOutput& run, const RunOptions& options, const std::string& out_dir);

// Opens a fixture, sets the DR start from its mission plan, loads the truth mesh and runs
// the pipeline; a progress bar on stderr when `progress` is set.
Result<RunOutput> replay_file(const std::string& fixture_path, RunOptions options, bool progress);

// Adds the options shared by replay, verify and run to a subcommand.
struct CommonRunArgs {
  std::string systems = "fusion,submap";
  int threads = 0;           // 0: from the config (default 1)
  std::string config_path;
  double rate = 0.0;
  std::string mesh_path;
  std::string model_path;
};
void add_run_options(CLI::App& sub, CommonRunArgs& args);
// RunOptions from the parsed arguments (loads --config). Errors name the file or value.
Result<RunOptions> run_options_from(const CommonRunArgs& args);

// A fixed-width progress bar on stderr ("label [#####.....] 52%  detail").
void print_progress(const std::string& label, double fraction, const std::string& detail);

}  // namespace orthosonar::cli
