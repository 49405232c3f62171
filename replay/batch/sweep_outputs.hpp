#pragma once
// The parts of a sweep's outputs shared by `orthosonar sweep` and `orthosonar batch merge`:
// the reference cell (SPEC §5 defaults, 3 m / 30 deg) replayed in full, and the HTML report
// over a sweep directory (heat maps from grid.json, maps from the reference run).
#include <string>

#include "core/result.hpp"
#include "replay/run/run.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::batch {

// The reference cell of the sweep grid.
inline constexpr run::GridCell kReferenceCell{3.0, 30.0};

// Replays `fixture` with the reference cell's keyframe settings and writes the whole output
// directory (maps, metrics, trajectories, digest) into `out_dir`.
Status write_reference_outputs(const std::string& fixture, const run::RunOptions& options, int threads,
                               const std::string& out_dir);

// Writes <sweep_dir>/report/report.html; without an X display, the report without 3D
// renders (said on stderr). Prints the report's path on stderr.
Status write_sweep_report(const std::string& sweep_dir, const std::string& title);

}  // namespace orthosonar::batch
