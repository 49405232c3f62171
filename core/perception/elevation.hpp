#pragma once
// Issue 34, inside fusion (docs/PERCEPTION.md "Sloped faces"): the pieces of a fused point's
// elevation that come from the h return's run. Internal to orthosonar_perception (fusion.cpp);
// the public ones, sloped_face_elevation, elevation_sigma and elevation_mappable, are declared
// in fusion.hpp.
#include <optional>
#include <vector>

#include "core/perception/fusion.hpp"

namespace orthosonar::perception {

// The run of an h return along its beam: the ranges of its ends.
struct RunExtent {
  double near_m = 0, far_m = 0;
};

// The run of the h return at (row, col), raw intensity `intensity`: the rows of its beam on
// both sides at least FusionConfig::slope_run_floor of it and above the noise-floor gate,
// bridging gaps of up to slope_run_max_gap rows. Measured for every fused point: its length
// also sets the point's elevation σ.
RunExtent measure_run(const SonarPing& h, int row, int col, double intensity, RowMedians& medians_h,
                      const FusionConfig& config);

// The elevation the run gives when it is a sloped face filling the aperture
// (FusionConfig::slope_run_ratio, slope_v_span_deg, slope_top_from_v); nullopt otherwise.
// `row` is the h return's, `range` Eq. 3's, `lim` the half-aperture, `dets_v` the v
// detections, row-major.
std::optional<double> elevation_from_run(const SonarPing& h, const SonarPing& v, const std::vector<Detection>& dets_v,
                                         int row, const RunExtent& run, double range, double lim,
                                         const FusionConfig& config);

}  // namespace orthosonar::perception
