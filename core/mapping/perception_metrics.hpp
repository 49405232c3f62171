#pragma once
// Perception measured against simulator truth, with no SLAM in the way (the measuring unit
// behind `orthosonar perception-check`, docs/PERCEPTION.md): per image type, intensity
// statistics per labelled class (water 0, seabed 1, structure >= 2) and over all pixels,
// CFAR detections per image and their precision against the labels; fused points placed
// with the true vehicle pose (TruthTrack, i.e. truth_pose_at) and their distance to the
// scene mesh. PerceptionMeter takes a source's events in stream order.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/events.hpp"
#include "core/mapping/intensity_histogram.hpp"
#include "core/mapping/mesh_distance.hpp"
#include "core/mapping/metrics.hpp"
#include "core/mesh.hpp"
#include "core/perception/fusion.hpp"
#include "core/perception/pairing.hpp"
#include "core/result.hpp"
#include "core/time.hpp"

namespace orthosonar::mapping {

// One image type (h or v) over the measured pairs.
struct MountTally {
  IntensityHistogram water, seabed, structure, all;
  size_t images = 0;
  size_t det = 0, det_true = 0, det_structure = 0;  // detections; on label != 0; on label >= 2
  size_t det_overlap = 0, det_overlap_true = 0, det_overlap_structure = 0;  // the same within ±overlap
};

// Adds one image with its per-pixel labels (semantic, rows * cols) and its detections;
// a detection is "in the overlap" when its beam's |bearing| <= overlap_rad.
void tally_image(const SonarPing& ping, const std::vector<uint8_t>& semantic,
                 const std::vector<perception::Detection>& dets, double overlap_rad, MountTally& t);

struct FusionTally {
  size_t pairs = 0, fused = 0, subproblems = 0, matches = 0, culled = 0;
  size_t sloped_face = 0;  // points whose elevation came from their h run (FusionConfig::slope_run_ratio)
  std::vector<double> err;   // distance of each fused point to the mesh, true pose
  // In err's order: the angle (deg) of the nearest mesh surface from vertical (0 a wall, 90
  // a flat bottom): the error split by surface slope (issue 34).
  std::vector<float> surface_deg;
  // The association bound (issue 34), in err's order: the distance had the point taken the
  // best of its range bin's v candidates (the alternatives Eq. 6 chose among), and the best
  // elevation anywhere in the overlap (every 0.2°; how far the h return's arc passes from
  // the surface); and how many v candidates its bin had.
  std::vector<double> err_best_candidate, err_best_elevation;
  std::vector<uint32_t> bin_candidates_v;
  // The elevation error (rad, signed), in err's order: the point's elevation less the
  // nearest elevation on the h return's arc at which the arc meets a surface (the grid
  // samples of the association bound within one grid step of the arc's closest pass; the
  // one nearest the point's own elevation). NaN when the arc passes no surface within
  // kArcSurfaceTolM. Beside it the elevation σ the fusion gave the point
  // (FusedPoint::elevation_sigma_rad): their ratio is the σ's calibration (issue 34).
  std::vector<double> elevation_error_rad;
  std::vector<float> elevation_sigma_rad;
  std::vector<uint8_t> from_sloped_face;
  bool keep_points = false;  // keep each point's fields below, in err's order
  struct Point {
    Eigen::Vector3f p_W;  // true-pose world position
    float range_m, bearing_rad, elevation_rad, confidence;
    double stamp_s;
    bool sloped_face;  // elevation from the h return's run (FusedPoint::elevation_from)
    float run_m;       // the h return's run along its beam (FusedPoint::run_far_m - run_near_m)
    float bin_spread_rad;  // RMS of the bin's v candidates about the chosen elevation
  };
  std::vector<Point> points;
};

// Distance statistics (NaN each when there is no distance): quantiles are the sorted
// sample at floor(q (n - 1)); within: share <= 0.1 m.
struct FusionFigures {
  double median, p90, mae, rmse, within;
};
FusionFigures fusion_figures(const std::vector<double>& err);

// The association bound's figures (FusionTally): MAE as fused, with the best v candidate of
// each point's range bin, with the best elevation in the overlap; and the points whose bin
// had a single v candidate (nothing to choose: Eq. 6 cannot be the cause) with their MAE.
struct AssociationBound {
  double mae_fused = 0, mae_best_candidate = 0, mae_best_elevation = 0;
  size_t single_candidate_points = 0;
  double single_candidate_mae = 0;
};
// NaN MAEs when the tally has no point.
AssociationBound association_bound(const FusionTally& f);

// The same per band of the nearest surface's angle from vertical: [0, 10) walls and piles,
// [10, 30) steep slopes (the example breakwater's 25° armour faces, a hull's side), [30, 60)
// slopes (a 1:1.5 rubble mound is 56°, a bilge), [60, 90] near-flat faces and the bottom;
// with each band's point count.
struct SlopeBand {
  double lo_deg, hi_deg;
  size_t points;
  FusionFigures figures;
};
std::vector<SlopeBand> fusion_figures_by_slope(const std::vector<double>& err, const std::vector<float>& surface_deg);

// Issue 34 (docs/PERCEPTION.md "Elevation uncertainty"). The points the maps take: err and
// surface_deg of the points perception::elevation_mappable keeps under max_sigma_deg (0:
// every point).
struct MappedPoints {
  std::vector<double> err;
  std::vector<float> surface_deg;
};
MappedPoints mapped_points(const FusionTally& f, double max_sigma_deg);

// How well the elevation σ predicts the elevation error, over the points of one source
// (sloped_face: the run's; otherwise the v return's) that have an elevation error: their count,
// RMS error and RMS σ (deg), RMS of error / σ (1 for an honest σ of a normal error), and the
// shares within 1 σ and 2 σ (0.68 and 0.95 for one). NaNs when there is no such point.
struct SigmaCalibration {
  size_t points = 0;
  double rms_error_deg, rms_sigma_deg, z_rms, within_1sigma, within_2sigma;
};
SigmaCalibration sigma_calibration(const FusionTally& f, bool sloped_face);

// A unit normal's surface angle from vertical (deg): asin(|n_z|); 0 for a zero normal.
double surface_angle_from_vertical_deg(const Eigen::Vector3d& normal);

struct PerceptionMeasurement {
  double gate_h = 0, gate_v = 0;  // the CFAR gates of the configuration measured
  MountTally h, v;
  FusionTally fusion;
};

// Pairs h and v pings, fuses every n-th pair that has labels for both, tallies its images
// and places its points with the truth pose at the h stamp. A pair waits for its labels and
// the truth pose at its stamp (both follow the pings in the (stamp, channel) order); after
// 1 s of stream time, or at finish(), it is measured anyway.
class PerceptionMeter {
 public:
  // keep_points: keep every fused point's fields (FusionTally::points).
  PerceptionMeter(const perception::FusionConfig& config, const TriangleMesh& mesh, int every, bool keep_points);
  // The next event of the stream; pings, labels and truth poses are used, the rest ignored.
  void add(Event event);
  // End of the stream. An error (naming `what`, the source) when the stream had no labels,
  // no truth poses or no labelled h/v pair.
  Status finish(const std::string& what);
  const PerceptionMeasurement& measurement() const { return out_; }
  PerceptionMeasurement take() { return std::move(out_); }

 private:
  void drain(bool final);
  void measure_pair(const SonarPing& h, const SonarPing& v);

  perception::FusionConfig cfg_;
  double overlap_rad_;
  MeshDistance dist_;
  size_t every_;
  perception::PingPairer pairer_;
  std::map<std::pair<int, uint32_t>, std::vector<uint8_t>> labels_;  // (mount, ping id) -> semantic
  TruthTrack truth_;
  std::deque<std::pair<SonarPing, SonarPing>> pending_;
  size_t label_events_ = 0, truth_events_ = 0;
  Time latest_ = Time::min();
  PerceptionMeasurement out_;
};

}  // namespace orthosonar::mapping
