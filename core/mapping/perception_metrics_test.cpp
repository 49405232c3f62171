// The perception measuring unit (perception_metrics.hpp, intensity_histogram.hpp) and the
// streaming truth track (metrics.hpp TruthTrack) it places points with.
#include "core/mapping/perception_metrics.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {

SonarPing flat_ping(SonarMount mount, uint32_t id, Time stamp, uint16_t rows, uint16_t cols, uint8_t value) {
  SonarPing p;
  p.mount = mount;
  p.ping_id = id;
  p.stamp = stamp;
  p.rows = rows;
  p.cols = cols;
  p.bearings_rad.resize(cols);
  for (uint16_t c = 0; c < cols; ++c) p.bearings_rad[c] = (c - (cols - 1) / 2.0) * 0.05;
  p.image.assign(static_cast<size_t>(rows) * cols, value);
  return p;
}

Event event(Payload payload) {
  Event e;
  e.stamp = stamp_of(payload);
  e.channel = channel_of(payload);
  e.payload = std::move(payload);
  return e;
}

TruthPose truth_at(Time t, double x) {
  TruthPose p;
  p.stamp = t;
  p.p_W = Vec3(x, 0, -2);
  return p;
}

}  // namespace

TEST_CASE("intensity histogram: quantiles, mean, gate and Otsu's split", "[unit]") {
  IntensityHistogram h;
  for (uint32_t x : {10u, 10u, 10u, 12u, 200u, 210u}) h.add(x);
  CHECK(h.n == 6);
  CHECK(h.quantile(0.5) == 10.0);   // sorted[floor(0.5 * 5)] = sorted[2]
  CHECK(h.quantile(0.9) == 200.0);  // sorted[4]
  CHECK(h.quantile(1.0) == 210.0);
  CHECK(h.mean() == Approx(452.0 / 6.0));
  CHECK(h.above(12) == 2);
  CHECK(h.fraction_above(12) == Approx(2.0 / 6.0));
  const OtsuSplit s = otsu(h);
  CHECK(s.threshold == 12.0);
  CHECK(s.dark_fraction == Approx(4.0 / 6.0));
  CHECK(s.dark_p50 == 10.0);
  CHECK(s.bright_p50 == 200.0);
  IntensityHistogram sum;
  sum.add(h);
  sum.add(h);
  CHECK(sum.n == 12);
  CHECK(sum.quantile(0.5) == 10.0);
  const IntensityHistogram empty;
  CHECK(std::isnan(empty.quantile(0.5)));
  CHECK(std::isnan(empty.mean()));
  CHECK(std::isnan(otsu(empty).threshold));
  IntensityHistogram one;
  one.add(7);
  CHECK(otsu(one).threshold == 7.0);
  CHECK(otsu(one).dark_fraction == 1.0);
}

TEST_CASE("tally_image: classes by label, detection precision in and out of the overlap", "[unit]") {
  SonarPing p = flat_ping(SonarMount::kHorizontal, 1, Time::from_s(1), 2, 3, 5);
  p.image[4] = 90;  // row 1, col 1 (the centre beam, bearing 0)
  p.image[5] = 80;  // row 1, col 2 (bearing 0.05 rad)
  const std::vector<uint8_t> semantic = {0, 0, 0, 1, 2, 0};
  std::vector<perception::Detection> dets(2);
  dets[0].row = 1;
  dets[0].col = 1;  // on structure
  dets[1].row = 1;
  dets[1].col = 2;  // on water
  MountTally t;
  tally_image(p, semantic, dets, 0.01, t);
  CHECK(t.images == 1);
  CHECK(t.water.n == 4);
  CHECK(t.seabed.n == 1);
  CHECK(t.structure.n == 1);
  CHECK(t.structure.quantile(0.5) == 90.0);
  CHECK(t.all.n == 6);
  CHECK(t.det == 2);
  CHECK(t.det_true == 1);
  CHECK(t.det_structure == 1);
  CHECK(t.det_overlap == 1);  // only the centre beam is within 0.01 rad
  CHECK(t.det_overlap_structure == 1);
}

TEST_CASE("fusion figures of mesh distances", "[unit]") {
  const FusionFigures f = fusion_figures({0.3, 0.05, 0.1, 0.2});
  CHECK(f.median == 0.1);  // sorted[floor(0.5 * 3)] = sorted[1]
  CHECK(f.p90 == 0.2);     // sorted[2]
  CHECK(f.mae == Approx(0.1625));
  CHECK(f.rmse == Approx(std::sqrt((0.09 + 0.0025 + 0.01 + 0.04) / 4)));
  CHECK(f.within == 0.5);
  CHECK(std::isnan(fusion_figures({}).median));
}

TEST_CASE("fusion figures split by the nearest surface's angle from vertical", "[unit]") {
  const std::vector<double> err = {0.02, 0.04, 0.1, 0.3, 0.5, 0.2, 0.9, 0.05};
  const std::vector<float> deg = {0.0f, 9.9f, 10.0f, 29.9f, 30.0f, 59.9f, 60.0f, 90.0f};
  const auto bands = fusion_figures_by_slope(err, deg);
  REQUIRE(bands.size() == 4);
  CHECK(bands[0].lo_deg == 0.0);
  CHECK(bands[3].hi_deg == 90.0);
  CHECK(bands[0].points == 2);
  CHECK(bands[0].figures.mae == Approx(0.03));
  CHECK(bands[1].points == 2);
  CHECK(bands[1].figures.mae == Approx(0.2));
  CHECK(bands[2].points == 2);
  CHECK(bands[2].figures.mae == Approx(0.35));
  CHECK(bands[3].points == 2);
  CHECK(bands[3].figures.rmse == Approx(std::sqrt((0.81 + 0.0025) / 2)));
  // A band without points has NaN figures.
  const auto none = fusion_figures_by_slope({0.1}, {10.0f});
  CHECK(none[1].points == 1);
  CHECK(none[2].points == 0);
  CHECK(std::isnan(none[2].figures.mae));
}

TEST_CASE("association bound: MAE as fused, with the best candidate, the best elevation, single-candidate points",
          "[unit]") {
  FusionTally f;
  f.err = {0.4, 0.2, 0.6};
  f.err_best_candidate = {0.1, 0.2, 0.3};
  f.err_best_elevation = {0.0, 0.05, 0.1};
  f.bin_candidates_v = {1, 3, 1};
  const AssociationBound b = association_bound(f);
  CHECK(b.mae_fused == Approx(0.4));
  CHECK(b.mae_best_candidate == Approx(0.2));
  CHECK(b.mae_best_elevation == Approx(0.05));
  CHECK(b.single_candidate_points == 2);
  CHECK(b.single_candidate_mae == Approx(0.5));
  const AssociationBound none = association_bound(FusionTally{});
  CHECK(std::isnan(none.mae_fused));
  CHECK(std::isnan(none.mae_best_candidate));
  CHECK(none.single_candidate_points == 0);
  CHECK(std::isnan(none.single_candidate_mae));
}

TEST_CASE("mapped points and the elevation sigma's calibration", "[unit]") {
  const double deg = M_PI / 180.0;
  FusionTally f;
  f.err = {0.1, 0.2, 0.3, 0.4, 0.5};
  f.surface_deg = {0, 10, 20, 30, 40};
  f.elevation_sigma_rad = {float(1 * deg), float(3 * deg), float(1 * deg), float(2 * deg), float(0.5 * deg)};
  f.elevation_error_rad = {0.5 * deg, -4.0 * deg, std::nan(""), -3.0 * deg, 0.25 * deg};
  f.from_sloped_face = {0, 0, 0, 1, 1};
  // At most 2 deg: points 0, 2, 3, 4 (the bound is inclusive); 0 keeps every point.
  const MappedPoints m = mapped_points(f, 2.0);
  REQUIRE(m.err.size() == 4);
  CHECK(m.err[1] == 0.3);
  CHECK(m.surface_deg[3] == 40.0f);
  CHECK(mapped_points(f, 0.0).err.size() == 5);
  // v-return points with an error: 0 (z 0.5) and 1 (z 4/3); point 2 has none.
  const SigmaCalibration v = sigma_calibration(f, false);
  CHECK(v.points == 2);
  CHECK(v.rms_error_deg == Approx(std::sqrt((0.25 + 16.0) / 2)));
  CHECK(v.rms_sigma_deg == Approx(std::sqrt((1.0 + 9.0) / 2)));
  CHECK(v.z_rms == Approx(std::sqrt((0.25 + 16.0 / 9.0) / 2)));
  CHECK(v.within_1sigma == Approx(0.5));
  CHECK(v.within_2sigma == Approx(1.0));
  // Sloped: 3 (z 1.5) and 4 (z 0.5).
  const SigmaCalibration s = sigma_calibration(f, true);
  CHECK(s.points == 2);
  CHECK(s.within_1sigma == Approx(0.5));
  CHECK(s.within_2sigma == Approx(1.0));
  CHECK(s.z_rms == Approx(std::sqrt((2.25 + 0.25) / 2)));
  const SigmaCalibration none = sigma_calibration(FusionTally{}, true);
  CHECK(none.points == 0);
  CHECK(std::isnan(none.z_rms));
}

TEST_CASE("truth track: truth_pose_at inside, held at the ends, forgets only what is behind", "[unit]") {
  std::vector<TruthPose> truth = {truth_at(Time::from_s(1), 0), truth_at(Time::from_s(2), 1),
                                  truth_at(Time::from_s(3), 4)};
  truth[2].q_W_V = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
  TruthTrack track;
  CHECK_FALSE(track.at(Time::from_s(1)).has_value());
  track.add(truth[2]);  // out of order: inserted in place
  track.add(truth[0]);
  track.add(truth[1]);
  REQUIRE(track.size() == 3);
  CHECK(track.last_stamp() == Time::from_s(3));
  for (int ms : {1000, 1250, 2000, 2500, 2999, 3000}) {
    const auto a = track.at(Time::from_ms(ms));
    const auto b = truth_pose_at(truth, Time::from_ms(ms));
    REQUIRE(a.has_value());
    REQUIRE(b.has_value());
    CHECK(a->matrix() == b->matrix());
  }
  CHECK(track.at(Time::from_ms(500))->translation() == Vec3(0, 0, -2));
  CHECK(track.at(Time::from_s(9))->translation() == Vec3(4, 0, -2));
  track.forget_before(Time::from_ms(2500));  // keeps the pose at 2 s for interpolation
  CHECK(track.size() == 2);
  CHECK(track.at(Time::from_ms(2500))->matrix() == truth_pose_at(truth, Time::from_ms(2500))->matrix());
  track.forget_before(Time::from_s(3));
  CHECK(track.size() == 1);
  TruthPose moved = truth_at(Time::from_s(3), 7);
  track.add(moved);  // the same stamp replaces
  CHECK(track.size() == 1);
  CHECK(track.at(Time::from_s(3))->translation().x() == 7.0);
}

TEST_CASE("perception meter: a labelled pair is tallied, missing labels or truth are errors", "[unit]") {
  perception::FusionConfig cfg;
  const TriangleMesh mesh;
  const auto stream = [&](bool labels, bool truth) {
    PerceptionMeter meter(cfg, mesh, 1, false);
    for (uint32_t id = 0; id < 2; ++id) {
      const Time t = Time::from_ms(100 * id);
      meter.add(event(flat_ping(SonarMount::kHorizontal, id, t, 4, 5, 3)));
      meter.add(event(flat_ping(SonarMount::kVertical, id, t, 4, 5, 3)));
      if (labels)
        for (SonarMount m : {SonarMount::kHorizontal, SonarMount::kVertical}) {
          SonarLabels l;
          l.stamp = t;
          l.mount = m;
          l.ping_id = id;
          l.rows = 4;
          l.cols = 5;
          l.semantic.assign(20, id == 0 ? 0 : 1);
          meter.add(event(l));
        }
      if (truth) meter.add(event(truth_at(t, id)));
    }
    Status s = meter.finish("src");
    return std::pair{std::move(s), meter.take()};
  };
  const auto [ok, m] = stream(true, true);
  REQUIRE(ok.ok());
  CHECK(m.fusion.pairs == 2);
  CHECK(m.fusion.fused == 2);
  CHECK(m.h.images == 2);
  CHECK(m.v.images == 2);
  CHECK(m.h.water.n == 20);   // ping 0: all water
  CHECK(m.h.seabed.n == 20);  // ping 1: all seabed
  CHECK(m.h.all.quantile(0.5) == 3.0);
  CHECK(m.gate_h == cfg.cfar_h.gate);
  const auto no_labels = stream(false, true).first;
  REQUIRE_FALSE(no_labels.ok());
  CHECK(no_labels.error().message == "src: has no per-pixel labels (simulate --labels writes them)");
  const auto no_truth = stream(true, false).first;
  REQUIRE_FALSE(no_truth.ok());
  CHECK(no_truth.error().message == "src: has no truth poses");
}
