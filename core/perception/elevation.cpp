// Issue 34: the elevation fusion gives a point besides Eq. 6's, and how well it is known
// (docs/PERCEPTION.md "Sloped faces" and "Elevation uncertainty"): the h return's run along its
// beam, the elevation a sloped face's run gives, the point's elevation σ, and which points the
// maps take. fuse_pair (fusion.cpp) calls these for each fused point.
#include "core/perception/elevation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace orthosonar::perception {
namespace {

constexpr double kElevationDeg = std::numbers::pi / 180.0;

// The run a vertical wall facing the sonar gives at `range_m` across the h sonar's elevation
// aperture ±half_aperture_rad: R (1/cos a - 1). Sloped faces and the elevation σ count runs in it.
double wall_run_m(double range_m, double half_aperture_rad) { return range_m * (1.0 / std::cos(half_aperture_rad) - 1.0); }

// The elevations [lo, hi] at which the v image sees anything in the overlap (|φ| <= lim) over
// the ranges [near, far]; lo > hi when it sees nothing there.
std::pair<double, double> v_span(const SonarPing& v, const std::vector<Detection>& dets_v, double near, double far,
                                 double lim) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const auto first = std::lower_bound(dets_v.begin(), dets_v.end(), near,
                                      [&](const Detection& d, double r) { return v.range_of_row(d.row) < r; });
  for (auto it = first; it != dets_v.end() && v.range_of_row(it->row) <= far; ++it) {
    const double e = v.bearings_rad[static_cast<size_t>(it->col)];
    if (std::abs(e) > lim) continue;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  return {lo, hi};
}

}  // namespace

RunExtent measure_run(const SonarPing& h, int row, int col, double intensity, RowMedians& medians_h,
                      const FusionConfig& config) {
  const double floor = std::max(config.noise_floor_factor > 0.0
                                    ? config.noise_floor_factor * medians_h.local_floor(row, config.noise_floor_rows)
                                    : 0.0,
                                config.slope_run_floor * intensity);
  const int gap = std::max(0, config.slope_run_max_gap);
  int r0 = row, r1 = row;
  for (int r = row - 1, g = 0; r >= 0 && g <= gap; --r) {
    if (h.at(r, col) >= floor) { r0 = r; g = 0; } else { ++g; }
  }
  for (int r = row + 1, g = 0; r < h.rows && g <= gap; ++r) {
    if (h.at(r, col) >= floor) { r1 = r; g = 0; } else { ++g; }
  }
  return {h.range_of_row(r0), h.range_of_row(r1)};
}


std::optional<double> elevation_from_run(const SonarPing& h, const SonarPing& v, const std::vector<Detection>& dets_v,
                                         int row, const RunExtent& run, double range, double lim,
                                         const FusionConfig& config) {
  const double near = run.near_m, far = run.far_m;
  if (far - near < config.slope_run_ratio * wall_run_m(range, lim)) return std::nullopt;
  const auto [lo, hi] = v_span(v, dets_v, near, far, lim);
  // A face that fills the h sonar's aperture fills the v sonar's fan over the same ranges.
  if (config.slope_v_span_deg > 0.0 && !(hi - lo >= config.slope_v_span_deg * kElevationDeg)) return std::nullopt;
  std::optional<double> e = sloped_face_elevation(near, far, h.range_of_row(row), lim);
  // No higher than the v image sees the face over the run: where the face ends inside the
  // aperture (a crest at long range), the run's far end is that top, not +a.
  if (e && config.slope_top_from_v && hi >= lo) e = std::min(*e, hi);
  return e;
}

std::optional<double> sloped_face_elevation(double near_m, double far_m, double range_m, double half_aperture_rad) {
  if (!(far_m > near_m) || !(half_aperture_rad > 0.0) || !std::isfinite(range_m)) return std::nullopt;
  // Linear in range across the aperture. The plane through the run's ends (r(φ) = D / (cos φ -
  // τ sin φ)) was measured worse: 0.236 m MAE against 0.126 m on the breakwater, seed 1
  // (docs/PERCEPTION.md "Sloped faces").
  const double t = std::clamp((range_m - near_m) / (far_m - near_m), 0.0, 1.0);
  return -half_aperture_rad + 2.0 * half_aperture_rad * t;
}

double elevation_sigma(const FusionConfig& config, FusedPoint::Elevation from, double run_m, double range_m,
                       double elevation_rad, double half_aperture_rad) {
  if (from == FusedPoint::Elevation::sloped_face) {
    const double t =
        half_aperture_rad > 0.0 ? std::clamp((elevation_rad + half_aperture_rad) / (2.0 * half_aperture_rad), 0.0, 1.0) : 0.0;
    return (config.sigma_slope_near_deg + (config.sigma_slope_far_deg - config.sigma_slope_near_deg) * t) * kElevationDeg;
  }
  const double wall = wall_run_m(range_m, half_aperture_rad);
  const double walls = wall > 0.0 && run_m > 0.0 ? run_m / wall : 0.0;
  return (config.sigma_v_deg + config.sigma_v_per_wall_deg * std::max(0.0, walls - 1.0)) * kElevationDeg;
}

bool elevation_mappable(float sigma_rad, double max_deg) {
  return max_deg <= 0.0 || sigma_rad <= static_cast<float>(max_deg * kElevationDeg);
}

}  // namespace orthosonar::perception
