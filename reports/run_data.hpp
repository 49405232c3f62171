#pragma once
// What the report reads from an output directory (shared output contract): trajectories
// (TUM), the ground-truth mesh, per-system maps and metrics, summary.json, digest.json,
// and a sweep's grid.json. Every part is optional; what is missing is listed in `notes`.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/mesh.hpp"
#include "core/result.hpp"
#include "replay/outputs/ping_pair_io.hpp"

namespace orthosonar::reports {

struct TumPose {
  double t_s = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector4d q_xyzw{0.0, 0.0, 0.0, 1.0};
};
using Trajectory = std::vector<TumPose>;

// TUM format: "t x y z qx qy qz qw" per line; '#' comments and blank lines skipped.
Result<Trajectory> read_tum(const std::string& path);
Status write_tum(const std::string& path, const Trajectory& poses);

// Numbers absent or null in the JSON are NaN (reports print "n/a").
struct RuntimeStat {
  std::string stage;
  double mean_ms = 0.0;
  double sd_ms = 0.0;
  double count = 0.0;
};

struct SystemOutput {
  std::string name;                        // fusion, submap, inference, inference_submap
  std::vector<Eigen::Vector3f> map_W;      // map.ply points, world frame
  bool has_map = false;
  bool has_metrics = false;
  double coverage_voxels = 0.0, mae_m = 0.0, rmse_m = 0.0, ate_dr_m = 0.0, ate_slam_m = 0.0;
  std::vector<RuntimeStat> runtime;        // sorted by stage name
  std::vector<std::pair<std::string, std::string>> counts;
};

struct GridCell {
  std::string system;
  double distance_m = 0.0;
  double rotation_deg = 0.0;
  double coverage_voxels = 0.0;
  double mae_m = 0.0;
  double rmse_m = 0.0;
  double ate_slam_m = 0.0;
};
struct Grid {
  std::string scene;
  std::vector<GridCell> cells;
};
Result<Grid> read_grid(const std::string& path);

struct RunData {
  std::string dir;
  std::optional<TriangleMesh> mesh;
  std::optional<Trajectory> truth, dr, slam;
  std::vector<SystemOutput> systems;                          // in contract order
  std::vector<std::pair<std::string, std::string>> summary;   // flattened summary.json ("a.b" -> value)
  std::string software_version;
  std::string scene;
  std::string digest_overall;
  std::vector<std::pair<std::string, std::string>> digest_outputs;
  std::optional<Grid> grid;
  std::optional<outputs::PingPairRecord> ping_pair;           // ping_pair/ (the pair with the most fused points)
  std::vector<std::string> notes;                             // what was missing or unreadable
  std::string input_cut;  // summary.json says the input fixture was cut short: what it held ("" otherwise)
};

// Fails only when `dir` does not exist or holds nothing the report understands.
Result<RunData> load_run(const std::string& dir);

// The systems of the contract, in display order.
const std::vector<std::string>& system_names();

}  // namespace orthosonar::reports
