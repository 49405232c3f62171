#pragma once
// results.mcap: a run's outputs as one MCAP file that Foxglove opens beside the input
// fixture (docs/RESULTS.md). JSON messages ("json") described by the official Foxglove
// JSON schemas ("jsonschema"), written with replay/mcap/mcap_generic.hpp's GenericWriter:
//
//   /orthosonar/<system>/map        foxglove.PointCloud     one, at the end of the stream;
//                                                           x y z float32, stride 12, frame world
//   /orthosonar/trajectory/truth    foxglove.PosesInFrame   one each (when the run has it), at the
//   /orthosonar/trajectory/dr       foxglove.PosesInFrame   end: every truth pose / every keyframe
//   /orthosonar/trajectory/slam     foxglove.PosesInFrame   pose (DR and SLAM estimates)
//   /orthosonar/tf                  foxglove.FrameTransform world -> vehicle_slam and vehicle_dr at
//                                                           every keyframe, world -> vehicle_truth at
//                                                           most every 100 ms, so the timeline animates
//   /orthosonar/scene               foxglove.SceneUpdate    the truth mesh (when known) at the start:
//                                                           one entity "truth_mesh", one indexed
//                                                           TriangleListPrimitive of a single colour
//
// and a Metadata record "orthosonar" (software version, output digests, fixture metadata,
// configuration, counts, accuracy). The bytes are a pure function of the RunOutput (no
// clocks: stage timings and wall time are left out). The file is a rendering of the
// outputs, like the report's PNGs: it is not a digest input.
#include <string>

#include "core/result.hpp"

namespace orthosonar::run {

struct RunOutput;

inline constexpr const char* kResultsMcapFile = "results.mcap";

// Writes `path` (replacing it). Errors name the path; an invalid truth mesh (an index out
// of range) is an error rather than a file Foxglove cannot draw.
Status write_results_mcap(const RunOutput& run, const std::string& path);

}  // namespace orthosonar::run
