// `orthosonar perception-check --scene S [--duration s] [--sim-config sim.yaml]
// [--config run.yaml]`: simulates a mission with per-pixel labels and measures the
// perception stage against the simulator's truth, with no SLAM in the way:
//   - 8-bit intensity of water pixels (label 0) and of structure pixels, per image,
//     and the fraction of water pixels above the CFAR gate (the calibration check of
//     docs/SCENES.md: the SPEC's gate 65 assumes a dark water column);
//   - CFAR detection precision (share of detections on labelled structure), overall and
//     inside the ±overlap;
//   - fused points placed with the TRUE vehicle pose: distance to the ground-truth mesh
//     (median, p90, MAE, RMSE, share within 0.1 m).
// It is the harness behind the perception numbers in docs/PERCEPTION.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>
#include <map>
#include <numbers>

#include "core/mapping/mesh_distance.hpp"
#include "core/perception/fusion.hpp"
#include "core/perception/pairing.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/simulator.hpp"
#include "tools/cli.hpp"
#include "tools/support_run_args.hpp"
#include "core/result.hpp"

namespace orthosonar::cli {
namespace {

struct CheckArgs {
  std::string scene = "harbor";
  double duration_s = 60.0;
  uint64_t seed = 1;
  std::string resolution = "full";
  std::string sim_config;
  std::string run_config;
  int every = 1;  // fuse every n-th pair
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::floor(q * static_cast<double>(v.size() - 1)));
  return v[i];
}

struct Tally {
  std::vector<double> water, structure;  // subsampled pixel intensities
  size_t water_pixels = 0, water_above_gate = 0;
  size_t det = 0, det_true = 0, det_overlap = 0, det_overlap_true = 0;
};

void tally_image(const SonarPing& ping, const SonarLabels& labels, const std::vector<perception::Detection>& dets,
                 double gate, double overlap_rad, Tally& t) {
  const size_t n = static_cast<size_t>(ping.rows) * ping.cols;
  for (size_t i = 0; i < n; ++i) {
    const double x = ping.at(static_cast<int>(i / ping.cols), static_cast<int>(i % ping.cols));
    if (labels.semantic[i] == 0) {
      ++t.water_pixels;
      if (x > gate) ++t.water_above_gate;
      if (i % 17 == 0) t.water.push_back(x);
    } else if (i % 3 == 0) {
      t.structure.push_back(x);
    }
  }
  for (const perception::Detection& d : dets) {
    const size_t i = static_cast<size_t>(d.row) * ping.cols + static_cast<size_t>(d.col);
    const bool truth = labels.semantic[i] != 0;
    ++t.det;
    t.det_true += truth;
    if (std::abs(ping.bearings_rad[static_cast<size_t>(d.col)]) <= overlap_rad) {
      ++t.det_overlap;
      t.det_overlap_true += truth;
    }
  }
}

// a / b, or 0 when b is 0.
double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return ratio(s, static_cast<double>(v.size()));
}

void print_tally(const char* name, const Tally& t, size_t images) {
  const auto d = [](size_t n) { return static_cast<double>(n); };
  std::printf("%s: water p50 %.0f p90 %.0f p99 %.0f mean %.1f, above gate %.4f | structure p50 %.0f p90 %.0f | "
              "detections/image %.0f precision %.3f, in overlap %.1f/image precision %.3f\n",
              name, quantile(t.water, 0.5), quantile(t.water, 0.9), quantile(t.water, 0.99), mean(t.water),
              ratio(d(t.water_above_gate), d(t.water_pixels)), quantile(t.structure, 0.5), quantile(t.structure, 0.9),
              ratio(d(t.det), d(images)), ratio(d(t.det_true), d(t.det)), ratio(d(t.det_overlap), d(images)),
              ratio(d(t.det_overlap_true), d(t.det_overlap)));
}

int run_check(const CheckArgs& a) {
  auto scene = sim::builtin_scene(a.scene, 1);
  if (!scene) {
    std::cerr << "orthosonar perception-check: " << scene.error().message << "\n";
    return 2;
  }
  sim::SimConfig sc;
  sc.duration_s = a.duration_s;
  sc.seed = a.seed;
  sc.labels = true;
  sc.render_threads = 2;
  auto resolution = sim::parse_resolution(a.resolution);
  if (!resolution.ok()) {
    std::cerr << "orthosonar perception-check: " << resolution.error().message << "\n";
    return 2;
  }
  sc.resolution = *resolution;
  if (!a.sim_config.empty()) {
    if (Status s = sim::load_sim_config_file(a.sim_config, sc); !s.ok()) {
      std::cerr << "orthosonar perception-check: " << s.error().message << "\n";
      return 2;
    }
  }
  RunConfig run;
  if (!a.run_config.empty()) {
    if (Status s = load_config_file(a.run_config, run); !s.ok()) {
      std::cerr << "orthosonar perception-check: " << s.error().message << "\n";
      return 2;
    }
  }
  perception::FusionConfig cfg = run.pipeline.fusion;
  cfg.T_V_h = sc.T_V_h;
  cfg.T_V_v = sc.T_V_v;
  const double overlap = cfg.overlap_deg * std::numbers::pi / 180.0;

  const TriangleMesh mesh = scene->mesh;
  sim::Simulator simulator(std::move(*scene), sc);
  mapping::MeshDistance dist(mesh);
  perception::PingPairer pairer(Time::from_seconds(cfg.max_pair_dt_s));
  std::map<std::pair<int, uint32_t>, SonarLabels> labels;  // (mount, ping id) -> labels
  Tally th, tv;
  std::vector<double> err;
  size_t pairs = 0, fused = 0, subproblems = 0, matches = 0, culled = 0;
  auto process = [&] {
    while (auto pr = pairer.pop()) {
      const SonarPing& h = pr->first;
      const SonarPing& v = pr->second;
      const auto lh = labels.find({0, h.ping_id});
      const auto lv = labels.find({1, v.ping_id});
      if (pairs++ % static_cast<size_t>(a.every) != 0 || lh == labels.end() || lv == labels.end()) continue;
      ++fused;
      const perception::FusionResult r = perception::fuse_pair(h, v, cfg);
      subproblems += r.subproblems;
      matches += r.matches;
      culled += r.culled_low_confidence;
      tally_image(h, lh->second, r.detections_h, cfg.cfar_h.gate, overlap, th);
      tally_image(v, lv->second, r.detections_v, cfg.cfar_v.gate, overlap, tv);
      const SE3 T_W_V = simulator.trajectory().at(h.stamp).T_W_V();
      for (const perception::FusedPoint& p : r.points)
        err.push_back(dist.distance(T_W_V * p.p_V.cast<double>()));
      labels.erase(labels.begin(), labels.upper_bound({0, h.ping_id}));
    }
  };
  for (;;) {
    hal::Pulled p = simulator.next();
    if (p.error) {
      std::cerr << "orthosonar perception-check: " << p.error->message << "\n";
      return 2;
    }
    if (p.end_of_stream || !p.event) break;
    if (auto* l = std::get_if<SonarLabels>(&p.event->payload)) {
      labels[{l->mount == SonarMount::kHorizontal ? 0 : 1, l->ping_id}] = *l;
    } else if (auto* ping = std::get_if<SonarPing>(&p.event->payload)) {
      pairer.push(*ping);
      process();
    }
  }
  pairer.flush();
  process();
  print_tally("h", th, fused);
  print_tally("v", tv, fused);
  double mae = 0, sq = 0;
  size_t within = 0;
  for (double e : err) {
    mae += e;
    sq += e * e;
    within += e <= 0.1;
  }
  const double n = static_cast<double>(std::max<size_t>(err.size(), 1));
  std::printf("subproblems %zu, matches %zu, culled by confidence %zu\n", subproblems, matches, culled);
  std::printf("fused %zu of %zu pairs: %zu points (%.1f/pair), distance to mesh with true poses: median %.3f p90 %.3f "
              "MAE %.3f RMSE %.3f, within 0.1 m %.3f\n",
              fused, pairs, err.size(), static_cast<double>(err.size()) / static_cast<double>(std::max<size_t>(fused, 1)),
              quantile(err, 0.5), quantile(err, 0.9), mae / n, std::sqrt(sq / n), static_cast<double>(within) / n);
  return 0;
}

const bool registered = register_command(
    {"perception-check",
     "Measure CFAR and fusion against simulator truth (labels, true poses, mesh distance)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<CheckArgs>();
       sub.add_option("--scene", a->scene, "Built-in scene")->capture_default_str();
       sub.add_option("--duration", a->duration_s, "Mission length, seconds")->capture_default_str();
       sub.add_option("--seed", a->seed, "Noise seed")->capture_default_str();
       sub.add_option("--resolution", a->resolution, "full or reduced")->capture_default_str();
       sub.add_option("--sim-config", a->sim_config, "Simulator config YAML (fields of SimConfig)");
       sub.add_option("--config", a->run_config, "Run configuration YAML (its fusion: section applies)");
       sub.add_option("--every", a->every, "Fuse every n-th pair")->capture_default_str()->check(CLI::PositiveNumber);
       return [a] { return run_check(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
