// `orthosonar perception-check [--scene S | --scene-file site.yaml | --fixture F.mcap]
// [--profile field|clean|both] [--real-ping capture.raw ...] [--json out.json]
// [--duration s] [--every n] [--sim-config sim.yaml] [--config run.yaml]`:
// measures the perception stage against the simulator's truth, with no SLAM in the way,
// once per image-formation profile (hal/sim SonarProfile; default both, field then clean):
//   - label-based (simulator labels, per image type h/v): 8-bit intensity p50/p90/p99/mean
//     and the fraction above the CFAR gate of water (label 0), seabed (label 1) and
//     structure (labels >= 2) pixels; CFAR detection precision (share of detections on
//     labelled non-water pixels, and on structure only), overall and inside the ±overlap;
//   - label-free (comparable with real captures): the same intensity figures over all
//     pixels, and Otsu's split of the pooled histogram into dark and bright pixels;
//   - fused points placed with the TRUE vehicle pose: distance to the ground-truth mesh
//     (median, p90, MAE, RMSE, share within 0.1 m).
// --real-ping decodes a raw Oculus SimplePingResult (hal/drivers) and prints its label-free
// figures beside the profiles. --fixture measures a recorded, labelled fixture's images as
// recorded (its own profile, its embedded scene and truth poses). --json writes every figure
// (deterministic: no timings). --cloud writes the true-pose fused points with their mesh
// distance, range, bearing, elevation and confidence (PLY). It is the harness behind the
// perception numbers in docs/PERCEPTION.md.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/mesh_distance.hpp"
#include "core/mapping/metrics.hpp"
#include "core/perception/fusion.hpp"
#include "core/perception/pairing.hpp"
#include "core/result.hpp"
#include "hal/drivers/oculus_protocol.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/simulator.hpp"
#include "replay/fixture.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_oculus_ping_file.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

using nlohmann::json;

struct CheckArgs {
  std::string scene = "harbor";
  std::string scene_file;
  std::string fixture;
  std::string profile = "both";
  std::vector<std::string> real_pings;
  std::string json_path;
  double duration_s = 60.0;
  uint64_t seed = 1;
  std::string resolution = "full";
  std::string sim_config;
  std::string run_config;
  std::string cloud_path;  // --cloud: the true-pose fused points with their mesh distance
  int every = 1;           // fuse every n-th pair
};

int check_fail(const std::string& msg) {
  std::cerr << "orthosonar perception-check: " << msg << "\n";
  return 2;
}

// a / b, or 0 when b is 0.
double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

// Exact statistics of integer intensities through a histogram (8- or 16-bit images).
// Quantile q is the sorted sample at floor(q (n - 1)), as before histograms.
struct Histogram {
  std::vector<uint64_t> count;
  uint64_t n = 0;
  double sum = 0.0;
  void add(uint32_t x) {
    if (x >= count.size()) count.resize(x + 1, 0);
    ++count[x];
    ++n;
    sum += x;
  }
  void add(const Histogram& o) {
    if (o.count.size() > count.size()) count.resize(o.count.size(), 0);
    for (size_t i = 0; i < o.count.size(); ++i) count[i] += o.count[i];
    n += o.n;
    sum += o.sum;
  }
  // Quantile of the values in [lo, hi].
  double quantile(double q, size_t lo = 0, size_t hi = SIZE_MAX) const {
    hi = std::min(hi, count.empty() ? 0 : count.size() - 1);
    uint64_t m = 0;
    for (size_t i = lo; i <= hi && i < count.size(); ++i) m += count[i];
    if (m == 0) return std::nan("");
    const auto k = static_cast<uint64_t>(std::floor(q * static_cast<double>(m - 1)));
    uint64_t c = 0;
    for (size_t i = lo; i <= hi; ++i) {
      c += count[i];
      if (c > k) return static_cast<double>(i);
    }
    return static_cast<double>(hi);
  }
  double mean() const { return n ? sum / static_cast<double>(n) : std::nan(""); }
  uint64_t above(double gate) const {
    uint64_t a = 0;
    for (size_t i = 0; i < count.size(); ++i)
      if (static_cast<double>(i) > gate) a += count[i];
    return a;
  }
};

// Otsu's threshold t of a histogram: dark = values <= t, bright = values > t.
struct OtsuSplit {
  double threshold = std::nan("");
  double dark_fraction = std::nan(""), dark_p50 = std::nan("");
  double bright_fraction = std::nan(""), bright_p50 = std::nan("");
};

OtsuSplit otsu(const Histogram& h) {
  OtsuSplit s;
  if (h.n == 0) return s;
  const double total = static_cast<double>(h.n);
  double w0 = 0.0, sum0 = 0.0, best = -1.0;
  size_t t_best = 0;
  for (size_t t = 0; t + 1 < h.count.size(); ++t) {
    w0 += static_cast<double>(h.count[t]);
    sum0 += static_cast<double>(t) * static_cast<double>(h.count[t]);
    const double w1 = total - w0;
    if (w0 == 0.0 || w1 == 0.0) continue;
    const double m0 = sum0 / w0, m1 = (h.sum - sum0) / w1;
    const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      t_best = t;
    }
  }
  if (best < 0.0) t_best = h.count.size() - 1;  // a single value: everything is "dark"
  s.threshold = static_cast<double>(t_best);
  uint64_t dark = 0;
  for (size_t i = 0; i <= t_best && i < h.count.size(); ++i) dark += h.count[i];
  s.dark_fraction = static_cast<double>(dark) / total;
  s.bright_fraction = 1.0 - s.dark_fraction;
  s.dark_p50 = h.quantile(0.5, 0, t_best);
  s.bright_p50 = h.quantile(0.5, t_best + 1);
  return s;
}

json num(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json intensity_json(const Histogram& h, double gate) {
  return {{"pixels", h.n},          {"p50", num(h.quantile(0.5))}, {"p90", num(h.quantile(0.9))},
          {"p99", num(h.quantile(0.99))}, {"mean", num(h.mean())},
          {"above_gate", num(h.n ? ratio(static_cast<double>(h.above(gate)), static_cast<double>(h.n)) : std::nan(""))}};
}

json otsu_json(const OtsuSplit& s) {
  return {{"threshold", num(s.threshold)},
          {"dark", {{"fraction", num(s.dark_fraction)}, {"p50", num(s.dark_p50)}}},
          {"bright", {{"fraction", num(s.bright_fraction)}, {"p50", num(s.bright_p50)}}}};
}

json label_free_json(const Histogram& h, double gate) {
  return {{"all", intensity_json(h, gate)}, {"otsu", otsu_json(otsu(h))}};
}

// One image type (h or v) over the measured pairs.
struct MountTally {
  Histogram water, seabed, structure, all;
  size_t images = 0;
  size_t det = 0, det_true = 0, det_structure = 0;
  size_t det_overlap = 0, det_overlap_true = 0, det_overlap_structure = 0;
};

void tally_image(const SonarPing& ping, const std::vector<uint8_t>& semantic, const std::vector<perception::Detection>& dets,
                 double overlap_rad, MountTally& t) {
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

struct FusionTally {
  size_t pairs = 0, fused = 0, subproblems = 0, matches = 0, culled = 0;
  std::vector<double> err;  // distance of each fused point to the mesh, true pose
  bool keep_points = false;  // --cloud: keep each point's fields below, in err's order
  struct Point {
    Eigen::Vector3f p_W;  // true-pose world position
    float range_m, bearing_rad, elevation_rad, confidence;
    double stamp_s;
  };
  std::vector<Point> points;
};

// What one profile (or one fixture) measured.
struct Measured {
  std::string label;           // "field", "clean", or "fixture"
  std::string heading;         // "profile field", "fixture F.mcap (profile clean, as recorded)"
  std::string profile;         // the profile of the images (effective / recorded)
  std::string note;            // e.g. "the sim config sets profile: clean"
  double gate_h = 0, gate_v = 0;
  MountTally h, v;
  FusionTally fusion;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::floor(q * static_cast<double>(v.size() - 1)));
  return v[i];
}

struct FusionFigures {
  double median, p90, mae, rmse, within;
};
FusionFigures fusion_figures(const std::vector<double>& err) {
  double mae = 0, sq = 0;
  size_t within = 0;
  for (double e : err) {
    mae += e;
    sq += e * e;
    within += e <= 0.1;
  }
  const double n = static_cast<double>(err.size());
  if (err.empty()) return {std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  return {quantile(err, 0.5), quantile(err, 0.9), mae / n, std::sqrt(sq / n), static_cast<double>(within) / n};
}

// --cloud: the true-pose fused points as a PLY (hal/sim's point writer), one vertex per
// point with its distance to the mesh and the fusion's range, bearing, elevation and
// confidence, so a user can see where on a structure the fused points leave the surface.
Status write_cloud(const std::string& path, const FusionTally& f) {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<sim::PlyScalar> scalars = {{"distance_m", {}}, {"range_m", {}},      {"bearing_deg", {}},
                                         {"elevation_deg", {}}, {"confidence", {}}, {"stamp_s", {}}};
  constexpr double kDeg = 180.0 / std::numbers::pi;
  for (size_t i = 0; i < f.points.size(); ++i) {
    const FusionTally::Point& p = f.points[i];
    xyz.push_back(p.p_W);
    const double values[] = {f.err[i], p.range_m, p.bearing_rad * kDeg, p.elevation_rad * kDeg, p.confidence, p.stamp_s};
    for (size_t k = 0; k < scalars.size(); ++k) scalars[k].values.push_back(static_cast<float>(values[k]));
  }
  return sim::write_ply_points(xyz, scalars, "orthosonar perception-check: fused points placed with the true pose",
                               path);
}

// The --cloud file of one measured profile: the path itself when one profile was measured,
// else "<stem>_<label><ext>".
std::string cloud_path_for(const std::string& path, const std::string& label, size_t n_results) {
  if (n_results <= 1) return path;
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + "_" + label;
  return path.substr(0, dot) + "_" + label + path.substr(dot);
}

// Replays `src` (simulator or fixture): pairs h and v pings, fuses every n-th pair with
// labels for both, tallies its images and places its points with the truth pose at the h
// stamp (TruthPose events, interpolated between neighbours when not exact).
Status measure(hal::EventSource& src, const perception::FusionConfig& cfg, const TriangleMesh& mesh, int every,
               const std::string& what, Measured& out) {
  const double overlap = cfg.overlap_deg * std::numbers::pi / 180.0;
  out.gate_h = cfg.cfar_h.gate;
  out.gate_v = cfg.cfar_v.gate;
  mapping::MeshDistance dist(mesh);
  perception::PingPairer pairer(Time::from_seconds(cfg.max_pair_dt_s));
  std::map<std::pair<int, uint32_t>, std::vector<uint8_t>> labels;  // (mount, ping id) -> semantic
  std::map<int64_t, SE3> truth;                                     // stamp ns -> T_W_V
  std::deque<std::pair<SonarPing, SonarPing>> pending;
  size_t label_events = 0, truth_events = 0;
  Time latest = Time::min();
  FusionTally& f = out.fusion;

  const auto pose_at = [&](Time t) -> std::optional<SE3> {
    if (truth.empty()) return std::nullopt;
    auto it = truth.lower_bound(t.ns());
    if (it != truth.end() && it->first == t.ns()) return it->second;
    if (it == truth.end()) return std::prev(it)->second;
    if (it == truth.begin()) return it->second;
    const auto prev = std::prev(it);
    const double s = static_cast<double>(t.ns() - prev->first) / static_cast<double>(it->first - prev->first);
    return interpolate(prev->second, it->second, s);
  };
  const auto process_one = [&](const SonarPing& h, const SonarPing& v) {
    const auto lh = labels.find({0, h.ping_id});
    const auto lv = labels.find({1, v.ping_id});
    const size_t nh = static_cast<size_t>(h.rows) * h.cols, nv = static_cast<size_t>(v.rows) * v.cols;
    const bool take = f.pairs++ % static_cast<size_t>(every) == 0 && lh != labels.end() && lv != labels.end() &&
                      lh->second.size() == nh && lv->second.size() == nv;
    if (take) {
      ++f.fused;
      const perception::FusionResult r = perception::fuse_pair(h, v, cfg);
      f.subproblems += r.subproblems;
      f.matches += r.matches;
      f.culled += r.culled_low_confidence;
      tally_image(h, lh->second, r.detections_h, overlap, out.h);
      tally_image(v, lv->second, r.detections_v, overlap, out.v);
      if (const auto T_W_V = pose_at(h.stamp))
        for (const perception::FusedPoint& p : r.points) {
          const Eigen::Vector3d p_W = *T_W_V * p.p_V.cast<double>();
          f.err.push_back(dist.distance(p_W));
          if (f.keep_points)
            f.points.push_back({p_W.cast<float>(), p.range_m, p.bearing_rad, p.elevation_rad, p.confidence,
                                h.stamp.seconds()});
        }
    }
    labels.erase(labels.begin(), labels.upper_bound({0, h.ping_id}));
    labels.erase(labels.lower_bound({1, 0}), labels.upper_bound({1, v.ping_id}));
    // Keep the truth pose at or before this stamp (interpolation of later pairs).
    auto it = truth.upper_bound(h.stamp.ns());
    if (it != truth.begin()) truth.erase(truth.begin(), std::prev(it));
  };
  // A pair waits for its labels and the truth pose at its stamp (both follow the pings in
  // the (stamp, channel) order); after 1 s of stream time, or at the end, it goes anyway.
  const auto drain = [&](bool final) {
    while (auto pr = pairer.pop()) pending.push_back(std::move(*pr));
    while (!pending.empty()) {
      const SonarPing& h = pending.front().first;
      const SonarPing& v = pending.front().second;
      const bool ready = final || (labels.count({0, h.ping_id}) && labels.count({1, v.ping_id}) && !truth.empty() &&
                                   truth.rbegin()->first >= h.stamp.ns()) ||
                         latest > std::max(h.stamp, v.stamp) + Time::from_s(1);
      if (!ready) break;
      process_one(h, v);
      pending.pop_front();
    }
  };
  for (;;) {
    hal::Pulled p = src.next();
    if (p.error) return Error{p.error->message};
    if (p.end_of_stream || !p.event) break;
    latest = std::max(latest, p.event->stamp);
    if (auto* l = std::get_if<SonarLabels>(&p.event->payload)) {
      ++label_events;
      labels[{l->mount == SonarMount::kHorizontal ? 0 : 1, l->ping_id}] = std::move(l->semantic);
    } else if (auto* tp = std::get_if<TruthPose>(&p.event->payload)) {
      ++truth_events;
      truth[tp->stamp.ns()] = mapping::truth_pose(*tp);
    } else if (auto* ping = std::get_if<SonarPing>(&p.event->payload)) {
      pairer.push(std::move(*ping));
    }
    drain(false);
  }
  pairer.flush();
  drain(true);
  if (label_events == 0) return Error{what + ": has no per-pixel labels (simulate --labels writes them)"};
  if (truth_events == 0) return Error{what + ": has no truth poses"};
  if (f.fused == 0) return Error{what + ": no h/v pair with labels to measure"};
  return {};
}

// ---------------------------------------------------------------- real pings

struct RealPing {
  std::string path;
  hal::drivers::oculus::PingResult raw;
  SonarPing ping;
  Histogram all;
};

Result<RealPing> load_real_ping(const std::string& path) {
  auto f = read_oculus_ping_file(path, "--real-ping");
  if (!f) return f.error();
  RealPing rp{path, std::move(f->raw), std::move(f->ping), {}};
  for (int row = 0; row < rp.ping.rows; ++row)
    for (int col = 0; col < rp.ping.cols; ++col) rp.all.add(rp.ping.at(row, col));
  return rp;
}

// ---------------------------------------------------------------- output

void print_class_row(const char* name, const Histogram& h, double gate) {
  if (h.n == 0) {
    std::printf("    %-20s %12s\n", name, "0 (none)");
    return;
  }
  std::printf("    %-20s %12llu %5.0f %5.0f %5.0f %7.2f %8.4f\n", name, static_cast<unsigned long long>(h.n),
              h.quantile(0.5), h.quantile(0.9), h.quantile(0.99), h.mean(),
              ratio(static_cast<double>(h.above(gate)), static_cast<double>(h.n)));
}

void print_label_free_row(const std::string& name, const Histogram& h, double gate) {
  const OtsuSplit s = otsu(h);
  std::printf("  %-34s %5.0f %5.0f %5.0f %7.2f %8.4f | %4.0f  %6.4f %4.0f   %6.4f %4.0f\n", name.c_str(),
              h.quantile(0.5), h.quantile(0.9), h.quantile(0.99), h.mean(),
              ratio(static_cast<double>(h.above(gate)), static_cast<double>(h.n)), s.threshold, s.dark_fraction,
              s.dark_p50, s.bright_fraction, s.bright_p50);
}

void print_label_free_header() {
  std::printf("  %-34s %5s %5s %5s %7s %8s | %4s  %6s %4s   %6s %4s\n", "", "p50", "p90", "p99", "mean", ">gate",
              "otsu", "dark", "p50", "bright", "p50");
}

void print_measured(const Measured& m) {
  const auto d = [](size_t n) { return static_cast<double>(n); };
  std::printf("== %s%s%s\n", m.heading.c_str(), m.note.empty() ? "" : " ", m.note.c_str());
  std::printf("  label-based (simulator labels), 8-bit intensity per class over %zu image pairs:\n", m.h.images);
  std::printf("    %-20s %12s %5s %5s %5s %7s %8s\n", "", "pixels", "p50", "p90", "p99", "mean", ">gate");
  for (const auto& [name, t, gate] : {std::tuple{"h", &m.h, m.gate_h}, std::tuple{"v", &m.v, m.gate_v}}) {
    print_class_row((std::string(name) + " water (0)").c_str(), t->water, gate);
    print_class_row((std::string(name) + " seabed (1)").c_str(), t->seabed, gate);
    print_class_row((std::string(name) + " structure (>=2)").c_str(), t->structure, gate);
  }
  // One summary line per image type (its form is what the calibration ctest matches).
  for (const auto& [name, t] : {std::pair{"h", &m.h}, std::pair{"v", &m.v}}) {
    const double gate = *name == 'h' ? m.gate_h : m.gate_v;
    std::printf("  %s: water p50 %.0f p90 %.0f p99 %.0f mean %.1f, above gate %.4f | structure p50 %.0f p90 %.0f | "
                "detections/image %.0f precision %.3f, in overlap %.1f/image precision %.3f | on structure only: "
                "precision %.3f, in overlap %.3f\n",
                name, t->water.quantile(0.5), t->water.quantile(0.9), t->water.quantile(0.99), t->water.mean(),
                ratio(d(t->water.above(gate)), d(t->water.n)), t->structure.quantile(0.5), t->structure.quantile(0.9),
                ratio(d(t->det), d(t->images)), ratio(d(t->det_true), d(t->det)), ratio(d(t->det_overlap), d(t->images)),
                ratio(d(t->det_overlap_true), d(t->det_overlap)), ratio(d(t->det_structure), d(t->det)),
                ratio(d(t->det_overlap_structure), d(t->det_overlap)));
  }
  const FusionTally& f = m.fusion;
  const FusionFigures ff = fusion_figures(f.err);
  std::printf("  subproblems %zu, matches %zu, culled by confidence %zu\n", f.subproblems, f.matches, f.culled);
  std::printf("  fused %zu of %zu pairs: %zu points (%.1f/pair), distance to mesh with true poses: median %.3f p90 %.3f "
              "MAE %.3f RMSE %.3f, within 0.1 m %.3f\n",
              f.fused, f.pairs, f.err.size(), ratio(d(f.err.size()), d(f.fused)), ff.median, ff.p90, ff.mae, ff.rmse,
              ff.within);
}

json mount_json(const MountTally& t, double gate) {
  const auto d = [](size_t n) { return static_cast<double>(n); };
  return {{"images", t.images},
          {"gate", gate},
          {"label_based",
           {{"water", intensity_json(t.water, gate)},
            {"seabed", intensity_json(t.seabed, gate)},
            {"structure", intensity_json(t.structure, gate)}}},
          {"label_free", label_free_json(t.all, gate)},
          {"detections",
           {{"total", t.det},
            {"per_image", ratio(d(t.det), d(t.images))},
            {"precision", ratio(d(t.det_true), d(t.det))},
            {"precision_structure", ratio(d(t.det_structure), d(t.det))},
            {"in_overlap", t.det_overlap},
            {"in_overlap_per_image", ratio(d(t.det_overlap), d(t.images))},
            {"in_overlap_precision", ratio(d(t.det_overlap_true), d(t.det_overlap))},
            {"in_overlap_precision_structure", ratio(d(t.det_overlap_structure), d(t.det_overlap))}}}};
}

json measured_json(const Measured& m) {
  const FusionTally& f = m.fusion;
  const FusionFigures ff = fusion_figures(f.err);
  return {{"label", m.label},
          {"profile", m.profile},
          {"note", m.note},
          {"mounts", {{"h", mount_json(m.h, m.gate_h)}, {"v", mount_json(m.v, m.gate_v)}}},
          {"fusion",
           {{"pairs", f.pairs},
            {"fused_pairs", f.fused},
            {"points", f.err.size()},
            {"points_per_pair", ratio(static_cast<double>(f.err.size()), static_cast<double>(f.fused))},
            {"subproblems", f.subproblems},
            {"matches", f.matches},
            {"culled_low_confidence", f.culled},
            {"distance_to_mesh_m",
             {{"median", num(ff.median)}, {"p90", num(ff.p90)}, {"mae", num(ff.mae)}, {"rmse", num(ff.rmse)}},
            },
            {"within_0_1m", num(ff.within)}}}};
}

json real_ping_json(const RealPing& r, double gate) {
  return {{"path", r.path},
          {"device_id", r.raw.header.src_device_id},
          {"ping_id", r.raw.ping_id},
          {"frequency_hz", r.raw.frequency_hz},
          {"range_m", r.raw.fire.range},
          {"range_resolution_m", r.raw.range_resolution_m},
          {"ranges", r.raw.n_ranges},
          {"beams", r.raw.n_beams},
          {"bits", 8 * r.raw.bytes_per_pixel()},
          {"gain_percent", r.raw.fire.gain_percent},
          {"label_free", label_free_json(r.all, gate)}};
}

// ---------------------------------------------------------------- the command

int run_check(const CheckArgs& a) {
  // Inputs first: every bad one is an error before any simulation.
  std::vector<RealPing> real;
  for (const std::string& path : a.real_pings) {
    auto r = load_real_ping(path);
    if (!r) return check_fail(r.error().message);
    real.push_back(std::move(*r));
  }
  RunConfig run;
  std::string run_yaml;
  if (!a.run_config.empty()) {
    auto text = read_config_text(a.run_config);
    if (!text) return check_fail(text.error().message);
    run_yaml = *text;
    if (Status s = load_config_file(a.run_config, run); !s.ok()) return check_fail(s.error().message);
  }
  std::vector<sim::SonarProfile> profiles;
  if (a.fixture.empty()) {
    if (a.profile == "both") {
      profiles = {sim::SonarProfile::kField, sim::SonarProfile::kClean};
    } else {
      auto p = sim::parse_profile(a.profile);
      if (!p) return check_fail("--profile: " + p.error().message + " (field, clean or both)");
      profiles = {*p};
    }
  }

  json doc;
  std::vector<Measured> results;
  double gate_real = run.pipeline.fusion.cfar_v.gate;  // the M1200d is the vertical head
  if (!a.fixture.empty()) {
    auto src = replay::FixtureSource::open(a.fixture);
    if (!src) return check_fail(src.error().message);
    note_input(a.fixture, (*src)->recovery());
    const auto& md = (*src)->metadata();
    const auto get = [&](const char* k) {
      const auto it = md.find(k);
      return it == md.end() ? std::string() : it->second;
    };
    if (get("labels") != "true")
      return check_fail(a.fixture + ": the fixture has no per-pixel labels (record it with `orthosonar simulate --labels`)");
    auto scene = sim::scene_from_fixture(md, replay::attachment_files((*src)->attachments()));
    if (!scene) return check_fail(a.fixture + ": no scene for the mesh distance: " + scene.error().message);
    RunOptions options;
    options.config_yaml = run_yaml;
    options.config_origin = a.run_config;
    auto resolved = effective_config(md, options, nullptr, (*src)->attachments());
    if (!resolved) return check_fail(a.fixture + ": " + resolved.error().message);
    const perception::FusionConfig cfg = resolved->pipeline.fusion;
    gate_real = cfg.cfar_v.gate;
    Measured m;
    m.profile = get("profile").empty() ? "unknown" : get("profile");
    m.label = "fixture";
    m.heading = "fixture " + a.fixture + " (profile " + m.profile + ", as recorded)";
    m.fusion.keep_points = !a.cloud_path.empty();
    if (Status s = measure(**src, cfg, scene->mesh, a.every, a.fixture, m); !s) return check_fail(s.error().message);
    std::printf("perception-check: fixture %s: scene %s, %s resolution, 1 pair in %d fused\n", a.fixture.c_str(),
                scene->name.c_str(), get("resolution").c_str(), a.every);
    doc["source"] = {{"fixture", a.fixture},
                     {"scene", scene->name},
                     {"scene_origin", scene->origin},
                     {"seed", get("seed")},
                     {"resolution", get("resolution")},
                     {"duration_s", get("duration_s")},
                     {"profile", m.profile},
                     {"complete", (*src)->recovery().complete}};
    results.push_back(std::move(m));
  } else {
    auto scene = a.scene_file.empty() ? sim::builtin_scene(a.scene, 1) : sim::load_scene_file(a.scene_file);
    if (!scene) return check_fail(scene.error().message);
    auto resolution = sim::parse_resolution(a.resolution);
    if (!resolution) return check_fail(resolution.error().message);
    std::printf("perception-check: scene %s, %.1f s, seed %llu, %s resolution, 1 pair in %d fused\n",
                scene->name.c_str(), a.duration_s, static_cast<unsigned long long>(a.seed),
                sim::resolution_name(*resolution), a.every);
    doc["source"] = {{"scene", scene->name},
                     {"scene_origin", a.scene_file.empty() ? scene->origin : sim::portable_origin(*scene)},
                     {"seed", a.seed},
                     {"resolution", sim::resolution_name(*resolution)},
                     {"duration_s", a.duration_s},
                     {"sim_config", a.sim_config}};
    for (sim::SonarProfile profile : profiles) {
      sim::SimConfig sc;
      sc.profile = profile;  // before the sim config file, whose keys refine the profile
      sim::apply_profile(sc.sonar, profile);
      sc.duration_s = a.duration_s;
      sc.seed = a.seed;
      sc.labels = true;
      sc.render_threads = 2;
      sc.resolution = *resolution;
      if (!a.sim_config.empty())
        if (Status s = sim::load_sim_config_file(a.sim_config, sc); !s) return check_fail(s.error().message);
      sc.labels = true;
      if (Status s = sim::validate(sc); !s) return check_fail(s.error().message);
      perception::FusionConfig cfg = run.pipeline.fusion;
      cfg.T_V_h = sc.T_V_h;
      cfg.T_V_v = sc.T_V_v;
      Measured m;
      m.label = sim::profile_name(profile);
      m.heading = std::string("profile ") + m.label;
      m.profile = sim::profile_name(sc.profile);
      if (sc.profile != profile) m.note = "(the sim config sets profile: " + m.profile + ")";
      m.fusion.keep_points = !a.cloud_path.empty();
      sim::Scene copy = *scene;
      const TriangleMesh mesh = copy.mesh;
      sim::Simulator simulator(std::move(copy), sc);
      if (Status s = measure(simulator, cfg, mesh, a.every, simulator.describe(), m); !s) return check_fail(s.error().message);
      results.push_back(std::move(m));
    }
  }

  for (const Measured& m : results) print_measured(m);
  if (!a.cloud_path.empty())
    for (const Measured& m : results) {
      const std::string path = cloud_path_for(a.cloud_path, m.label, results.size());
      if (Status s = write_cloud(path, m.fusion); !s) return check_fail(s.error().message);
      std::printf("  wrote %zu true-pose fused points with their mesh distance -> %s\n", m.fusion.points.size(),
                  path.c_str());
    }
  std::printf("== label-free (no labels needed: comparable between simulated and real images)\n");
  std::printf("  8-bit intensity of all pixels; >gate: share above the CFAR gate; Otsu's threshold splits the\n"
              "  pooled histogram into dark (<= threshold) and bright pixels (share, p50 of each)\n");
  print_label_free_header();
  for (const Measured& m : results) {
    const std::string name = a.fixture.empty() ? m.label : std::string("fixture (") + m.profile + ")";
    print_label_free_row(name + " h", m.h.all, m.gate_h);
    print_label_free_row(name + " v", m.v.all, m.gate_v);
  }
  for (const RealPing& r : real) {
    const std::string base = r.path.substr(r.path.find_last_of('/') + 1);
    print_label_free_row("real " + base, r.all, gate_real);
  }
  for (const RealPing& r : real)
    std::printf("  real %s: device %u, ping %u, %.1f kHz, range %.2f m, resolution %.4f m, %u ranges x %u beams, "
                "%d-bit, gain %.0f %% (gate %.0f: the vertical head's)\n",
                r.path.c_str(), r.raw.header.src_device_id, r.raw.ping_id, r.raw.frequency_hz / 1e3, r.raw.fire.range,
                r.raw.range_resolution_m, r.raw.n_ranges, r.raw.n_beams, 8 * r.raw.bytes_per_pixel(),
                r.raw.fire.gain_percent, gate_real);

  if (!a.json_path.empty()) {
    doc["every"] = a.every;
    doc["notes"] = {
        {"label_based", "simulator only: per-pixel labels (0 water, 1 seabed, >= 2 structure), detection precision"},
        {"label_free", "all pixels and Otsu's dark/bright split: comparable with real pings"},
        {"quantiles", "8-bit intensity; quantile q = sorted value at floor(q (n - 1)); above_gate: share > gate"},
        {"fusion", "fused points placed with the true vehicle pose, distance to the scene mesh"}};
    doc["profiles"] = json::array();
    for (const Measured& m : results) doc["profiles"].push_back(measured_json(m));
    doc["real_pings"] = json::array();
    for (const RealPing& r : real) doc["real_pings"].push_back(real_ping_json(r, gate_real));
    std::ofstream out(a.json_path, std::ios::binary | std::ios::trunc);
    out << doc.dump(2) << "\n";
    out.close();
    if (!out) return check_fail("cannot write '" + a.json_path + "'");
  }
  return 0;
}

const bool registered_perception_check = register_command(
    {"perception-check",
     "Measure CFAR and fusion against simulator truth (labels, true poses, mesh distance), per image profile",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<CheckArgs>();
       auto* scene = sub.add_option("--scene", a->scene, "Built-in scene")->capture_default_str();
       auto* scene_file = sub.add_option("--scene-file", a->scene_file, "User scene YAML (docs/SCENES.md)")->excludes(scene);
       add_allow_incomplete_flag(sub);
       auto* fixture = sub.add_option("--fixture", a->fixture,
                                      "Measure a recorded fixture with labels (simulate --labels) as recorded")
                           ->excludes(scene)
                           ->excludes(scene_file);
       auto* profile = sub.add_option("--profile", a->profile, "Image formation: field, clean or both")
                           ->capture_default_str();
       sub.add_option("--real-ping", a->real_pings,
                      "Raw Oculus SimplePingResult to compare with (label-free figures); repeatable");
       sub.add_option("--json", a->json_path, "Write every figure as JSON");
       sub.add_option("--cloud", a->cloud_path,
                      "Write the true-pose fused points with their mesh distance (PLY; one file per profile)");
       auto* duration = sub.add_option("--duration", a->duration_s, "Mission length, seconds")->capture_default_str();
       auto* seed = sub.add_option("--seed", a->seed, "Noise seed")->capture_default_str();
       auto* res = sub.add_option("--resolution", a->resolution, "full or reduced")->capture_default_str();
       auto* sim_config = sub.add_option("--sim-config", a->sim_config, "Simulator config YAML (fields of SimConfig; refines the profile)");
       sub.add_option("--config", a->run_config, "Run configuration YAML (its fusion: section applies)");
       sub.add_option("--every", a->every, "Fuse every n-th pair")->capture_default_str()->check(CLI::PositiveNumber);
       for (CLI::Option* o : {profile, duration, seed, res, sim_config}) fixture->excludes(o);
       return [a] { return run_check(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
