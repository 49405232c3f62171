#pragma once
// Orthogonal sonar fusion (SPEC §4, paper §V-B): CFAR on both images of a pair, overlap
// gating, per-pair normalisation, per-range-bin subproblems solved exactly (Hungarian),
// confidence per paper Eq. 6, and 3D points per paper Eq. 3 and Eq. 1.
//
// Geometry: h image rows = range, cols = bearing θ (positive left); v image rows = range,
// cols = elevation φ (positive up), v being h rolled +90° about x. See docs/PERCEPTION.md
// for the orientation of the rotated v patch (rot90) used by the cost of Eq. 5.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/perception/cfar.hpp"

namespace orthosonar::perception {

// SPEC §1 default extrinsics.
SE3 default_T_V_h();  // translation (0.35, 0, 0)
SE3 default_T_V_v();  // translation (0.35, 0, -0.10), roll +90°

inline CfarConfig with_min_neighbours(int n) {
  CfarConfig c;
  c.min_neighbours = n;
  return c;
}

struct FusionConfig {
  double max_pair_dt_s = 0.1;           // pairing window (used by PingPairer users)
  double overlap_deg = 10.0;            // |θ| on h and |φ| on v must be within this
  int patch = 3;                        // side of the square patch (odd)
  double min_confidence = 0.05;         // Eq. 6 threshold (SPEC; docs/PERCEPTION.md "Field images")
  double normalise_percentile = 0.99;   // per-image normaliser, clamped to 1 after
  bool rotate_v_patch = true;           // Eq. 5 compares ν_h with rot90(ν_v); false: ν_v as is
  // Addition (docs/PERCEPTION.md "Field images"): a candidate in the overlap is kept only if
  // no detection of its row within ±peak_window_deg (bearing on h, elevation on v) is
  // brighter, so a target blurred across the beam's main lobe fuses at its peak beam. 0 = off.
  double peak_window_deg = 1.0;
  // Addition (docs/PERCEPTION.md "Field images"): a candidate in the overlap is kept only if
  // its intensity is at least noise_floor_factor times its image's local noise floor, the
  // largest row median within ±noise_floor_rows rows. It removes the TVG-lifted far-range
  // speckle clusters that pass CFAR and the neighbour filter. 0 = off.
  double noise_floor_factor = 3.0;
  int noise_floor_rows = 5;
  // Addition (issue 34; docs/PERCEPTION.md "Sloped faces"): an h return whose bright run
  // along its beam is at least slope_run_ratio times as long as a vertical wall facing the
  // sonar would give across the elevation aperture (R (1/cos a - 1), a = overlap_deg, the h
  // sonar's half-aperture) comes from a face sloped well away from vertical that fills the
  // aperture (8: a plane more than about 19 degrees from vertical). Its elevation is then where
  // along the run its range lies, linearly, the near end at -a (a face rising away from the
  // sonar: mounds, revetments, the seabed), not the v return's: on such a face the v return
  // of the same range comes from another part of the face. 0 = off: Eq. 6 for every point.
  double slope_run_ratio = 8.0;
  // The run: the rows of the return's beam, on both sides of it, at least slope_run_floor of
  // its intensity and above the noise-floor gate, bridging gaps of up to slope_run_max_gap rows.
  double slope_run_floor = 0.25;
  int slope_run_max_gap = 2;
  // ... and only if the v image's detections in the overlap over the run's ranges span at
  // least this much elevation: a face that fills the h sonar's elevation aperture fills the v
  // sonar's fan over the same ranges (an object seen in the lower half of the aperture only,
  // or the seabed, does not). 0 = no such check.
  double slope_v_span_deg = 10.0;
  // ... and no higher than the highest elevation at which the v image sees anything in the
  // overlap over the run's ranges: where the face ends inside the aperture (a crest at long
  // range), the run's far end is that top edge, not +a. false: the linear elevation as is.
  bool slope_top_from_v = true;
  // Addition (issue 34; docs/PERCEPTION.md "Elevation uncertainty"): each point's elevation σ
  // (FusedPoint::elevation_sigma_rad). A v-return point's is sigma_v_deg plus
  // sigma_v_per_wall_deg for each wall-length of its h run beyond the first (a run longer
  // than a wall's says the surface spans elevations at this range, and Eq. 6's v return is
  // one of them). A sloped-face point's grows linearly with its elevation from
  // sigma_slope_near_deg at -a (the run's near end, where the aperture's bottom meets the
  // face) to sigma_slope_far_deg at +a (the far end: a crest, a dimming grazing return).
  // Fitted on seed 1 of the seven scenes, checked on seeds 2-3 and the revetment.
  double sigma_v_deg = 0.8;
  double sigma_v_per_wall_deg = 0.3;
  double sigma_slope_near_deg = 0.3;
  double sigma_slope_far_deg = 1.1;
  SE3 T_V_h = default_T_V_h();
  SE3 T_V_v = default_T_V_v();
  // SPEC CFAR with the isolated-speckle filter on (3 of 8 neighbours) against the field
  // profile's TVG-lifted far-range speckle (docs/PERCEPTION.md "Field images").
  CfarConfig cfar_h = with_min_neighbours(3), cfar_v = with_min_neighbours(3);
};

struct FusedPoint {
  Eigen::Vector3f p_V = Eigen::Vector3f::Zero();  // vehicle frame, metres
  float range_m = 0;        // Eq. 3: (R_h + R_v) / 2
  float bearing_rad = 0;    // θ from h
  float elevation_rad = 0;  // φ from v
  float intensity_h = 0;    // normalised [0, 1]
  float intensity_v = 0;    // normalised [0, 1]
  float confidence = 0;     // Eq. 6
  // Where φ came from: the v return (Eq. 6), or the h return's run on a sloped face
  // (FusionConfig::slope_run_ratio), with the run's ends in range.
  enum class Elevation : uint8_t { v_return = 0, sloped_face = 1 };
  Elevation elevation_from = Elevation::v_return;
  float run_near_m = 0, run_far_m = 0;  // the h return's run (both 0 when not measured)
  // The elevation's standard uncertainty (rad, issue 34; docs/PERCEPTION.md "Elevation
  // uncertainty"): a v return's from its h run's length in wall-lengths, a sloped face's from
  // its place along the run (elevation_sigma). The maps withhold points whose σ exceeds
  // PipelineConfig::max_elevation_sigma_deg (elevation_mappable).
  float elevation_sigma_rad = 0;
  // The v candidates of this point's range bin (the alternatives Eq. 6 chose among):
  // FusionResult::bin_elevations_rad[bin_first, bin_first + bin_count). For diagnosis
  // (perception-check's association bound, issue 34); nothing downstream reads them, and
  // the sweep's fusion store (replay/run/sweep_store.hpp) does not keep them.
  uint32_t bin_first = 0;
  uint32_t bin_count = 0;
};

struct FusionResult {
  std::vector<FusedPoint> points;             // ordered by (h row, h col)
  // φ of every v candidate of each range bin that produced a point, bin after bin
  // (FusedPoint::bin_first / bin_count index it).
  std::vector<float> bin_elevations_rad;
  std::vector<Detection> detections_h;        // all CFAR detections, row-major
  std::vector<Detection> detections_v;        // inside the overlap only (the rest is never used)
  size_t candidates_h = 0;                    // detections inside the overlap
  size_t candidates_v = 0;
  size_t subproblems = 0;                     // range bins with candidates on both sides
  size_t matches = 0;                         // assigned pairs before the confidence cull
  size_t culled_low_confidence = 0;           // matches dropped by min_confidence
  size_t sloped_face = 0;                     // points whose φ came from their h run
};

FusionResult fuse_pair(const SonarPing& h, const SonarPing& v, const FusionConfig& config);

// The elevation of range `range_m` on a sloped face whose run along one beam spans
// [near_m, far_m]: the near end at -half_aperture_rad, the far end at +half_aperture_rad (a
// face rising away from the sonar), linear in range between them, clamped to the run.
// nullopt when far_m <= near_m.
std::optional<double> sloped_face_elevation(double near_m, double far_m, double range_m, double half_aperture_rad);

// A point's elevation σ (rad) under FusionConfig's sigma_* (see there): `run_m` its h run's
// length (0 when not measured: no run beyond a wall's), `range_m` Eq. 3's range, `elevation_rad`
// its elevation, `half_aperture_rad` a. Exposed for tests.
double elevation_sigma(const FusionConfig& config, FusedPoint::Elevation from, double run_m, double range_m,
                       double elevation_rad, double half_aperture_rad);

// Whether a point of elevation σ `sigma_rad` is mapped under a limit of `max_deg` degrees
// (PipelineConfig::max_elevation_sigma_deg; 0 or less: every point is). The pipeline's maps
// and perception-check's mapped figures both ask this.
bool elevation_mappable(float sigma_rad, double max_deg);

// Median intensity of each row (the lower median; raw image units), computed on demand and
// kept: the local noise floor of the fusion gate. Exposed for tests.
class RowMedians {
 public:
  explicit RowMedians(const SonarPing& p) : p_(p), median_(static_cast<size_t>(p.rows), -1.0) {}
  double operator()(int row);
  // max of the row medians over [row - half, row + half], clipped to the image.
  double local_floor(int row, int half);

 private:
  const SonarPing& p_;
  std::vector<double> median_;
  std::vector<uint16_t> scratch_;
};

// CFAR detections of the beams with |bearing| <= max_abs_bearing_rad, computed on that strip
// of the image plus the margin its windows need: the same list as cfar_detect on the whole
// image restricted to those beams.
std::vector<Detection> cfar_detect_within(const SonarPing& p, const CfarConfig& cfg, double max_abs_bearing_rad);

// Horizontal detections as planar points in V (φ = 0; SLAM, paper §IV-A): x, y of
// T_V_h * Eq.1(R, θ, 0).
std::vector<Eigen::Vector2d> planar_points_V(const SonarPing& h, const std::vector<Detection>& dets,
                                             const SE3& T_V_h);
// Horizontal detections as 3D points in V at a given elevation φ (rad).
std::vector<Eigen::Vector3d> points_V_at_elevation(const SonarPing& h,
                                                   const std::vector<Detection>& dets,
                                                   const SE3& T_V_h, double elevation_rad);

}  // namespace orthosonar::perception
