#include "core/mapping/perception_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

namespace orthosonar::mapping {

void tally_image(const SonarPing& ping, const std::vector<uint8_t>& semantic,
                 const std::vector<perception::Detection>& dets, double overlap_rad, MountTally& t) {
  ++t.images;
  const size_t n = static_cast<size_t>(ping.rows) * ping.cols;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t x = ping.at(static_cast<int>(i / ping.cols), static_cast<int>(i % ping.cols));
    const uint8_t c = semantic[i];
    (c == 0 ? t.water : c == 1 ? t.seabed : t.structure).add(x);
    t.all.add(x);
  }
  for (const perception::Detection& d : dets) {
    const uint8_t c = semantic[static_cast<size_t>(d.row) * ping.cols + static_cast<size_t>(d.col)];
    ++t.det;
    t.det_true += c != 0;
    t.det_structure += c >= 2;
    if (std::abs(ping.bearings_rad[static_cast<size_t>(d.col)]) <= overlap_rad) {
      ++t.det_overlap;
      t.det_overlap_true += c != 0;
      t.det_overlap_structure += c >= 2;
    }
  }
}

namespace {

constexpr double kBoundStepRad = 0.2 * std::numbers::pi / 180.0;  // the association bound's elevation grid
// An arc passing farther than this from every surface meets none (its range is wrong, not
// its elevation): the point has no elevation error (FusionTally::elevation_error_rad).
constexpr double kArcSurfaceTolM = 0.15;

double sorted_quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(std::floor(q * static_cast<double>(v.size() - 1)))];
}

}  // namespace

AssociationBound association_bound(const FusionTally& f) {
  AssociationBound b;
  b.mae_fused = fusion_figures(f.err).mae;
  b.mae_best_candidate = fusion_figures(f.err_best_candidate).mae;
  b.mae_best_elevation = fusion_figures(f.err_best_elevation).mae;
  double s = 0;
  for (size_t i = 0; i < f.err.size() && i < f.bin_candidates_v.size(); ++i)
    if (f.bin_candidates_v[i] == 1) {
      ++b.single_candidate_points;
      s += f.err[i];
    }
  b.single_candidate_mae = b.single_candidate_points ? s / static_cast<double>(b.single_candidate_points) : std::nan("");
  return b;
}

MappedPoints mapped_points(const FusionTally& f, double max_sigma_deg) {
  MappedPoints m;
  for (size_t i = 0; i < f.err.size(); ++i)
    if (i >= f.elevation_sigma_rad.size() || perception::elevation_mappable(f.elevation_sigma_rad[i], max_sigma_deg)) {
      m.err.push_back(f.err[i]);
      m.surface_deg.push_back(f.surface_deg[i]);
    }
  return m;
}

SigmaCalibration sigma_calibration(const FusionTally& f, bool sloped_face) {
  constexpr double kToDeg = 180.0 / std::numbers::pi;
  SigmaCalibration c;
  double e2 = 0, s2 = 0, z2 = 0, in1 = 0, in2 = 0;
  for (size_t i = 0; i < f.elevation_error_rad.size(); ++i) {
    const double e = f.elevation_error_rad[i], s = f.elevation_sigma_rad[i];
    if (std::isnan(e) || (f.from_sloped_face[i] != 0) != sloped_face || !(s > 0.0)) continue;
    ++c.points;
    e2 += e * e;
    s2 += s * s;
    const double z = std::abs(e) / s;
    z2 += z * z;
    in1 += z <= 1.0;
    in2 += z <= 2.0;
  }
  const double n = static_cast<double>(c.points);
  if (c.points == 0) {
    c.rms_error_deg = c.rms_sigma_deg = c.z_rms = c.within_1sigma = c.within_2sigma = std::nan("");
    return c;
  }
  c.rms_error_deg = std::sqrt(e2 / n) * kToDeg;
  c.rms_sigma_deg = std::sqrt(s2 / n) * kToDeg;
  c.z_rms = std::sqrt(z2 / n);
  c.within_1sigma = in1 / n;
  c.within_2sigma = in2 / n;
  return c;
}

FusionFigures fusion_figures(const std::vector<double>& err) {
  if (err.empty()) return {std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  double mae = 0, sq = 0;
  size_t within = 0;
  for (double e : err) {
    mae += e;
    sq += e * e;
    within += e <= 0.1;
  }
  const double n = static_cast<double>(err.size());
  return {sorted_quantile(err, 0.5), sorted_quantile(err, 0.9), mae / n, std::sqrt(sq / n),
          static_cast<double>(within) / n};
}

double surface_angle_from_vertical_deg(const Eigen::Vector3d& normal) {
  return std::asin(std::clamp(std::abs(normal.z()), 0.0, 1.0)) * 180.0 / std::numbers::pi;
}

std::vector<SlopeBand> fusion_figures_by_slope(const std::vector<double>& err, const std::vector<float>& surface_deg) {
  std::vector<SlopeBand> bands = {{0.0, 10.0, 0, {}}, {10.0, 30.0, 0, {}}, {30.0, 60.0, 0, {}}, {60.0, 90.0, 0, {}}};
  std::vector<std::vector<double>> split(bands.size());
  for (size_t i = 0; i < err.size() && i < surface_deg.size(); ++i) {
    size_t b = 0;
    while (b + 1 < bands.size() && surface_deg[i] >= bands[b + 1].lo_deg) ++b;
    split[b].push_back(err[i]);
  }
  for (size_t b = 0; b < bands.size(); ++b) {
    bands[b].points = split[b].size();
    bands[b].figures = fusion_figures(split[b]);
  }
  return bands;
}

PerceptionMeter::PerceptionMeter(const perception::FusionConfig& config, const TriangleMesh& mesh, int every,
                                 bool keep_points)
    : cfg_(config),
      overlap_rad_(config.overlap_deg * std::numbers::pi / 180.0),
      dist_(mesh),
      every_(static_cast<size_t>(std::max(every, 1))),
      pairer_(Time::from_seconds(config.max_pair_dt_s)) {
  out_.gate_h = config.cfar_h.gate;
  out_.gate_v = config.cfar_v.gate;
  out_.fusion.keep_points = keep_points;
}

void PerceptionMeter::add(Event event) {
  latest_ = std::max(latest_, event.stamp);
  if (auto* l = std::get_if<SonarLabels>(&event.payload)) {
    ++label_events_;
    labels_[{l->mount == SonarMount::kHorizontal ? 0 : 1, l->ping_id}] = std::move(l->semantic);
  } else if (auto* tp = std::get_if<TruthPose>(&event.payload)) {
    ++truth_events_;
    truth_.add(*tp);
  } else if (auto* ping = std::get_if<SonarPing>(&event.payload)) {
    pairer_.push(std::move(*ping));
  }
  drain(false);
}

Status PerceptionMeter::finish(const std::string& what) {
  pairer_.flush();
  drain(true);
  if (label_events_ == 0) return Error{what + ": has no per-pixel labels (simulate --labels writes them)"};
  if (truth_events_ == 0) return Error{what + ": has no truth poses"};
  if (out_.fusion.fused == 0) return Error{what + ": no h/v pair with labels to measure"};
  return {};
}

void PerceptionMeter::drain(bool final) {
  while (auto pr = pairer_.pop()) pending_.push_back(std::move(*pr));
  while (!pending_.empty()) {
    const SonarPing& h = pending_.front().first;
    const SonarPing& v = pending_.front().second;
    const bool ready = final ||
                       (labels_.count({0, h.ping_id}) && labels_.count({1, v.ping_id}) && !truth_.empty() &&
                        truth_.last_stamp() >= h.stamp) ||
                       latest_ > std::max(h.stamp, v.stamp) + Time::from_s(1);
    if (!ready) break;
    measure_pair(h, v);
    pending_.pop_front();
  }
}

void PerceptionMeter::measure_pair(const SonarPing& h, const SonarPing& v) {
  FusionTally& f = out_.fusion;
  const auto lh = labels_.find({0, h.ping_id});
  const auto lv = labels_.find({1, v.ping_id});
  const size_t nh = static_cast<size_t>(h.rows) * h.cols, nv = static_cast<size_t>(v.rows) * v.cols;
  const bool take = f.pairs++ % every_ == 0 && lh != labels_.end() && lv != labels_.end() &&
                    lh->second.size() == nh && lv->second.size() == nv;
  if (take) {
    ++f.fused;
    const perception::FusionResult r = perception::fuse_pair(h, v, cfg_);
    f.subproblems += r.subproblems;
    f.matches += r.matches;
    f.culled += r.culled_low_confidence;
    f.sloped_face += r.sloped_face;
    tally_image(h, lh->second, r.detections_h, overlap_rad_, out_.h);
    tally_image(v, lv->second, r.detections_v, overlap_rad_, out_.v);
    const int bound_steps = static_cast<int>(std::floor(overlap_rad_ / kBoundStepRad));  // the elevation grid's half width
    std::vector<double> arc;
    if (const auto T_W_V = truth_.at(h.stamp))
      for (const perception::FusedPoint& p : r.points) {
        const Eigen::Vector3d p_W = *T_W_V * p.p_V.cast<double>();
        const MeshDistance::Nearest near = dist_.nearest(p_W);
        f.err.push_back(near.distance);
        f.surface_deg.push_back(static_cast<float>(surface_angle_from_vertical_deg(near.normal)));
        // The association bound: the same point with each alternative elevation.
        auto dist_at = [&](double phi) {
          const Vec3 q_V = cfg_.T_V_h * spherical_to_cartesian(p.range_m, p.bearing_rad, phi);
          return dist_.nearest(*T_W_V * q_V).distance;
        };
        // The bin's v candidates: the best of them, and their spread about the chosen elevation.
        double best_c = near.distance, spread = 0.0;
        for (uint32_t k = 0; k < p.bin_count && p.bin_first + k < r.bin_elevations_rad.size(); ++k) {
          const double e = r.bin_elevations_rad[p.bin_first + k];
          best_c = std::min(best_c, dist_at(e));
          spread += (e - p.elevation_rad) * (e - p.elevation_rad);
        }
        spread = p.bin_count > 0 ? std::sqrt(spread / p.bin_count) : 0.0;
        arc.resize(static_cast<size_t>(2 * bound_steps + 1));
        double best_e = near.distance;
        for (int k = -bound_steps; k <= bound_steps; ++k)
          best_e = std::min(best_e, arc[static_cast<size_t>(k + bound_steps)] = dist_at(k * kBoundStepRad));
        // Where the arc meets a surface: the samples within one grid step of its closest pass.
        double elev_err = std::nan("");
        if (best_e <= kArcSurfaceTolM) {
          const double tol = best_e + p.range_m * kBoundStepRad;
          for (int k = -bound_steps; k <= bound_steps; ++k) {
            const double e = p.elevation_rad - k * kBoundStepRad;
            if (arc[static_cast<size_t>(k + bound_steps)] <= tol && !(std::abs(e) >= std::abs(elev_err))) elev_err = e;
          }
        }
        const bool sloped = p.elevation_from == perception::FusedPoint::Elevation::sloped_face;
        f.err_best_candidate.push_back(best_c);
        f.err_best_elevation.push_back(best_e);
        f.bin_candidates_v.push_back(p.bin_count);
        f.elevation_error_rad.push_back(elev_err);
        f.elevation_sigma_rad.push_back(p.elevation_sigma_rad);
        f.from_sloped_face.push_back(sloped ? 1 : 0);
        if (f.keep_points)
          f.points.push_back({p_W.cast<float>(), p.range_m, p.bearing_rad, p.elevation_rad, p.confidence,
                              h.stamp.seconds(), sloped, p.run_far_m - p.run_near_m, static_cast<float>(spread)});
      }
  }
  labels_.erase(labels_.begin(), labels_.upper_bound({0, h.ping_id}));
  labels_.erase(labels_.lower_bound({1, 0}), labels_.upper_bound({1, v.ping_id}));
  // Keep the truth pose at or before this stamp (interpolation of later pairs).
  truth_.forget_before(h.stamp);
}

}  // namespace orthosonar::mapping
