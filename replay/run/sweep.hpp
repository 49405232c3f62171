#pragma once
// The paper's keyframe-density experiment (SPEC §7): pairs are fused once (fusion does not
// depend on keyframes), then each cell replays the image-free stream with the cached
// fusion results, so a cell costs DR + SLAM + mapping + metrics only. Results are a pure
// function of the fixture and config: cells run in any order on any number of threads.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/pipeline.hpp"
#include "core/mesh.hpp"
#include "replay/run/run.hpp"
#include "replay/run/sweep_store.hpp"

namespace orthosonar::run {

struct GridCell {
  double distance_m = 1.0;
  double rotation_deg = 30.0;
};
// Distances 1..5 m x rotations 30/60/90 deg, rotation-major.
std::vector<GridCell> paper_grid();
// "all" (the paper grid) or a comma-separated list of DISTANCE/ROTATION cells such as
// "1/30,3/30,5/90", returned in paper-grid order without duplicates. Errors name the item.
Result<std::vector<GridCell>> parse_cells(const std::string& spec);
// "3m30" for 3 m / 30 deg: a cell's name in files and messages.
std::string cell_name(const GridCell& cell);
// Seeds as "1-5", "1,3,7" or "2": ascending, no duplicates. Errors name the item.
Result<std::vector<uint64_t>> parse_seeds(const std::string& spec);

struct PreparedSweep {
  std::map<std::string, std::string> metadata;
  RunConfig config;           // the effective configuration (every cell starts from it)
  // Every event, sonar images removed, and every pair's fusion result, both held compactly
  // (replay/run/sweep_store.hpp; issue 41). unique_ptr: SweepEventSource and the cells'
  // fusion refer to them while a PreparedSweep may move.
  std::unique_ptr<SweepEvents> events = std::make_unique<SweepEvents>();
  std::unique_ptr<FusionCache> fused = std::make_unique<FusionCache>();
  std::optional<TriangleMesh> mesh;
  mapping::RuntimeStats fusion_runtime;
  double stream_s = 0.0;
  double fuse_wall_s = 0.0;
  // inference_submap runs the classifier on every pair in stamp order whatever the
  // keyframe setting, so its per-pair clouds are computed once here and replayed by every
  // cell (same outputs, 15 times less classifier work).
  std::shared_ptr<inference::InferenceFrameCache> inference_cache;
  mapping::RuntimeStats inference_runtime;  // inference per frame, in that single pass
  replay::RecoveryReport recovery;  // whether the fixture was whole (replay::cut_input_warning)
};
Result<PreparedSweep> prepare_sweep(const std::string& fixture, const RunOptions& options, int threads,
                                    const std::function<void(double)>& progress);

struct CellSystem {
  std::string system;
  int64_t coverage_voxels = 0;
  int64_t accuracy_count = 0;
  double mae_m = 0.0, rmse_m = 0.0;
  // The same map with the keyframes at their true poses (SystemOutput::true_pose_accuracy);
  // count 0 when unknown.
  int64_t true_pose_count = 0;
  double true_pose_mae_m = 0.0, true_pose_rmse_m = 0.0;
  mapping::RuntimeStats runtime;  // the system's own stage (map update / submap construction)
};
struct CellResult {
  GridCell cell;
  int64_t keyframes = 0;
  std::optional<double> ate_dr_m, ate_slam_m;
  // RMS keyframe heading error against truth, degrees (issue 33); nullopt without truth.
  std::optional<double> heading_rms_dr_deg, heading_rms_slam_deg;
  mapping::RuntimeStats slam_runtime;
  std::vector<CellSystem> systems;
  std::string digest;
  double wall_s = 0.0;
};
Result<CellResult> run_cell(const PreparedSweep& prepared, const RunOptions& options, const GridCell& cell);
// Every cell on `threads` threads (oneTBB task arena); results in the order of `cells`,
// whatever order they finish in. `progress(done, total)` is called after each cell (from
// the thread that ran it, one call at a time). The first failing cell's error is returned,
// naming the cell; an exception in any cell becomes an Error too.
Result<std::vector<CellResult>> run_cells(const PreparedSweep& prepared, const RunOptions& options,
                                          const std::vector<GridCell>& cells, int threads,
                                          const std::function<void(size_t, size_t)>& progress = {});

struct SweepReport {
  std::string scene;
  std::map<std::string, std::string> metadata;
  std::vector<CellResult> cells;
  mapping::RuntimeStats fusion_runtime;
  double stream_s = 0.0;
  double fuse_wall_s = 0.0;
  mapping::RuntimeStats inference_runtime;  // inference per frame (the preparation pass)
  // Empty when the fixture was whole; else the warning naming it, the byte offset and what
  // was recovered (replay::cut_input_warning): grid.json and tables.md record it (issue 40).
  std::string input_cut;
};
SweepReport make_sweep_report(const PreparedSweep& prepared, std::vector<CellResult> cells);
// The deterministic tables (coverage grid, Table II, ATE per cell): a pure function of the
// fixture, the configuration and the cells, byte-identical on every machine.
std::string sweep_tables_markdown(const SweepReport& report);
// Timings (paper Table III layout): machine-dependent, kept apart from the tables.
std::string sweep_runtime_markdown(const SweepReport& report);
// Writes grid.json, grid.csv and tables.md (deterministic: the same bytes however the cells
// were run, one machine or a batch of shards), and runtime.json + runtime.md (timings).
Status write_sweep_outputs(const SweepReport& report, const std::string& out_dir);

// A cell's result as JSON and back (exact: doubles round-trip), for batch shards.
nlohmann::json cell_result_to_json(const CellResult& c);
Result<CellResult> cell_result_from_json(const nlohmann::json& j);
nlohmann::json runtime_stats_to_json(const mapping::RuntimeStats& s);
mapping::RuntimeStats runtime_stats_from_json(const nlohmann::json& j);

// Several (scene, seed) sweeps: each in <out>/<scene>/seed<N>/ (write_sweep_outputs), and
// seeds.json + seeds.md in <out>: per scene, per seed and pooled over seeds, each system's
// MAE/RMSE pooled over the cells, and the SLAM/DR ATE ratio (median, share of cells with
// SLAM <= DR). Deterministic bytes. `seeds` holds one entry per report, same order.
std::string sweep_set_dir(const std::string& scene, uint64_t seed);
std::string seeds_markdown(const std::vector<SweepReport>& reports, const std::vector<uint64_t>& seeds);
Status write_sweep_set(const std::vector<SweepReport>& reports, const std::vector<uint64_t>& seeds,
                       const std::string& out_dir);

}  // namespace orthosonar::run
