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

#include "core/mapping/pipeline.hpp"
#include "core/mesh.hpp"
#include "replay/run/run.hpp"

namespace orthosonar::run {

struct GridCell {
  double distance_m = 1.0;
  double rotation_deg = 30.0;
};
// Distances 1..5 m x rotations 30/60/90 deg, rotation-major.
std::vector<GridCell> paper_grid();

struct PreparedSweep {
  std::map<std::string, std::string> metadata;
  RunConfig config;           // the effective configuration (every cell starts from it)
  std::vector<Event> events;  // every event, sonar images removed
  std::map<std::pair<int64_t, int64_t>, std::shared_ptr<const perception::FusionResult>> fused;
  std::optional<TriangleMesh> mesh;
  mapping::RuntimeStats fusion_runtime;
  double stream_s = 0.0;
  double fuse_wall_s = 0.0;
  // inference_submap runs the classifier on every pair in stamp order whatever the
  // keyframe setting, so its per-pair clouds are computed once here and replayed by every
  // cell (same outputs, 15 times less classifier work).
  std::shared_ptr<inference::InferenceFrameCache> inference_cache;
  mapping::RuntimeStats inference_runtime;  // inference per frame, in that single pass
};
Result<PreparedSweep> prepare_sweep(const std::string& fixture, const RunOptions& options, int threads,
                                    const std::function<void(double)>& progress);

struct CellSystem {
  std::string system;
  int64_t coverage_voxels = 0;
  int64_t accuracy_count = 0;
  double mae_m = 0.0, rmse_m = 0.0;
  mapping::RuntimeStats runtime;  // the system's own stage (map update / submap construction)
};
struct CellResult {
  GridCell cell;
  int64_t keyframes = 0;
  std::optional<double> ate_dr_m, ate_slam_m;
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
};
SweepReport make_sweep_report(const PreparedSweep& prepared, std::vector<CellResult> cells);
std::string sweep_tables_markdown(const SweepReport& report);
Status write_sweep_outputs(const SweepReport& report, const std::string& out_dir);

}  // namespace orthosonar::run
