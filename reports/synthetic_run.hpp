#pragma once
// A small synthetic output directory in the shared output contract's layout, for tests
// and for trying the report without the pipeline: a seafloor, a row of round pilings and
// a floating dock (scene_mesh.ply), a loop trajectory (truth, a drifting DR, a SLAM
// estimate close to truth), per-system maps sampled from the structures' visible sides,
// metrics.json, summary.json, digest.json, a ping pair and optionally a sweep grid.json.
#include <string>

#include "core/result.hpp"

namespace orthosonar::reports {

struct SyntheticRunConfig {
  unsigned long long seed = 1;
  int points_per_piling = 150;
  double map_shift_m = 0.0;     // moves every map point along +x (a regression to detect)
  double drop_fraction = 0.0;   // drops this fraction of map points (lost coverage)
  bool with_grid = true;        // write grid.json (3 rotations x 5 distances x systems)
  bool with_mesh = true;
  bool with_ping_pair = true;   // ping_pair/: two small images with a wall seen by both
};

Status write_synthetic_run(const std::string& dir, const SyntheticRunConfig& config = {});

}  // namespace orthosonar::reports
