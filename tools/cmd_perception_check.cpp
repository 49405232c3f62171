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
// perception numbers in docs/PERCEPTION.md. What it measures and how: replay/run/perception_check.hpp
// and core/mapping/perception_metrics.hpp; this file parses the arguments and prints.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>
#include <utility>

#include "replay/run/perception_check.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {

using mapping::ratio;
using run::MeasuredProfile;
using run::RealPing;

struct CheckArgs {
  run::PerceptionCheckOptions check;
  std::string json_path;
  std::string cloud_path;  // --cloud: the true-pose fused points with their mesh distance
};

int check_fail(const std::string& msg) {
  std::cerr << "orthosonar perception-check: " << msg << "\n";
  return 2;
}

void print_class_row(const char* name, const mapping::IntensityHistogram& h, double gate) {
  if (h.n == 0) {
    std::printf("    %-20s %12s\n", name, "0 (none)");
    return;
  }
  std::printf("    %-20s %12llu %5.0f %5.0f %5.0f %7.2f %8.4f\n", name, static_cast<unsigned long long>(h.n),
              h.quantile(0.5), h.quantile(0.9), h.quantile(0.99), h.mean(),
              ratio(static_cast<double>(h.above(gate)), static_cast<double>(h.n)));
}

void print_label_free_row(const std::string& name, const mapping::IntensityHistogram& h, double gate) {
  const mapping::OtsuSplit s = mapping::otsu(h);
  std::printf("  %-34s %5.0f %5.0f %5.0f %7.2f %8.4f | %4.0f  %6.4f %4.0f   %6.4f %4.0f\n", name.c_str(),
              h.quantile(0.5), h.quantile(0.9), h.quantile(0.99), h.mean(),
              ratio(static_cast<double>(h.above(gate)), static_cast<double>(h.n)), s.threshold, s.dark_fraction,
              s.dark_p50, s.bright_fraction, s.bright_p50);
}

void print_label_free_header() {
  std::printf("  %-34s %5s %5s %5s %7s %8s | %4s  %6s %4s   %6s %4s\n", "", "p50", "p90", "p99", "mean", ">gate",
              "otsu", "dark", "p50", "bright", "p50");
}

void print_measured(const MeasuredProfile& r) {
  const mapping::PerceptionMeasurement& m = r.m;
  const auto d = [](size_t n) { return static_cast<double>(n); };
  std::printf("== %s%s%s\n", r.heading.c_str(), r.note.empty() ? "" : " ", r.note.c_str());
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
  const mapping::FusionTally& f = m.fusion;
  const mapping::FusionFigures ff = mapping::fusion_figures(f.err);
  std::printf("  subproblems %zu, matches %zu, culled by confidence %zu, elevation from a sloped face's run %zu\n",
              f.subproblems, f.matches, f.culled, f.sloped_face);
  std::printf("  fused %zu of %zu pairs: %zu points (%.1f/pair), distance to mesh with true poses: median %.3f p90 %.3f "
              "MAE %.3f RMSE %.3f, within 0.1 m %.3f\n",
              f.fused, f.pairs, f.err.size(), ratio(d(f.err.size()), d(f.fused)), ff.median, ff.p90, ff.mae, ff.rmse,
              ff.within);
  // The same by the nearest surface's angle from vertical (issue 34: sloped faces).
  std::printf("  by surface angle from vertical:");
  for (const auto& b : mapping::fusion_figures_by_slope(f.err, f.surface_deg))
    std::printf(" %s%.0f-%.0f deg: %zu points MAE %.3f RMSE %.3f p90 %.3f", b.lo_deg > 0 ? "| " : "", b.lo_deg,
                b.hi_deg, b.points, b.figures.mae, b.figures.rmse, b.figures.p90);
  std::printf("\n");
  // What the maps take, and how honest the elevation σ is (issue 34).
  const mapping::MappedPoints mp = mapping::mapped_points(f, r.max_elevation_sigma_deg);
  const mapping::FusionFigures mf = mapping::fusion_figures(mp.err);
  std::printf("  mapped (elevation sigma <= %.2f deg): %zu points (%.3f of fused), MAE %.3f RMSE %.3f p90 %.3f\n",
              r.max_elevation_sigma_deg, mp.err.size(), ratio(d(mp.err.size()), d(f.err.size())), mf.mae, mf.rmse, mf.p90);
  for (const bool sloped : {false, true}) {
    const mapping::SigmaCalibration c = mapping::sigma_calibration(f, sloped);
    std::printf("  elevation sigma, %s points: %zu with an error, RMS error %.2f deg, RMS sigma %.2f deg, RMS error/sigma "
                "%.2f, within 1 sigma %.3f, 2 sigma %.3f\n",
                sloped ? "sloped-face" : "v-return", c.points, c.rms_error_deg, c.rms_sigma_deg, c.z_rms, c.within_1sigma,
                c.within_2sigma);
  }
  // How much of the error the choice among candidates explains (issue 34).
  const mapping::AssociationBound ab = mapping::association_bound(f);
  std::printf("  association bound: MAE as fused %.3f | with the best v candidate of each point's range bin %.3f | "
              "with the best elevation in the overlap %.3f | points whose bin had one v candidate: %zu, MAE %.3f\n",
              ab.mae_fused, ab.mae_best_candidate, ab.mae_best_elevation, ab.single_candidate_points,
              ab.single_candidate_mae);
}

int run_check(CheckArgs a) {
  a.check.keep_points = !a.cloud_path.empty();
  const run::PerceptionCheckOptions& o = a.check;
  auto opened = run::PerceptionCheck::open(o, [](const std::string& path, const replay::RecoveryReport& r) {
    note_input(path, r);
  });
  if (!opened) return check_fail(opened.error().message);
  run::PerceptionCheck& c = *opened;
  if (!c.is_fixture())
    std::printf("perception-check: scene %s, %.1f s, seed %llu, %s resolution, 1 pair in %d fused\n",
                c.scene().name.c_str(), o.duration_s, static_cast<unsigned long long>(o.seed),
                sim::resolution_name(c.resolution()), o.every);
  if (Status s = c.measure(); !s) return check_fail(s.error().message);
  if (c.is_fixture())
    std::printf("perception-check: fixture %s: scene %s, %s resolution, 1 pair in %d fused\n", o.fixture.c_str(),
                c.scene().name.c_str(), c.fixture_metadata("resolution").c_str(), o.every);
  const std::vector<MeasuredProfile>& results = c.results();
  for (const MeasuredProfile& r : results) print_measured(r);
  if (!a.cloud_path.empty())
    for (const MeasuredProfile& r : results) {
      const std::string path = run::cloud_path_for(a.cloud_path, r.label, results.size());
      if (Status s = run::write_cloud(path, r.m.fusion); !s) return check_fail(s.error().message);
      std::printf("  wrote %zu true-pose fused points with their mesh distance -> %s\n", r.m.fusion.points.size(),
                  path.c_str());
    }
  std::printf("== label-free (no labels needed: comparable between simulated and real images)\n");
  std::printf("  8-bit intensity of all pixels; >gate: share above the CFAR gate; Otsu's threshold splits the\n"
              "  pooled histogram into dark (<= threshold) and bright pixels (share, p50 of each)\n");
  print_label_free_header();
  for (const MeasuredProfile& r : results) {
    const std::string name = o.fixture.empty() ? r.label : std::string("fixture (") + r.profile + ")";
    print_label_free_row(name + " h", r.m.h.all, r.m.gate_h);
    print_label_free_row(name + " v", r.m.v.all, r.m.gate_v);
  }
  const double gate_real = c.gate_real();
  for (const RealPing& r : c.real_pings()) {
    const std::string base = r.path.substr(r.path.find_last_of('/') + 1);
    print_label_free_row("real " + base, r.all, gate_real);
  }
  for (const RealPing& r : c.real_pings())
    std::printf("  real %s: device %u, ping %u, %.1f kHz, range %.2f m, resolution %.4f m, %u ranges x %u beams, "
                "%d-bit, gain %.0f %% (gate %.0f: the vertical head's)\n",
                r.path.c_str(), r.raw.header.src_device_id, r.raw.ping_id, r.raw.frequency_hz / 1e3, r.raw.fire.range,
                r.raw.range_resolution_m, r.raw.n_ranges, r.raw.n_beams, 8 * r.raw.bytes_per_pixel(),
                r.raw.fire.gain_percent, gate_real);
  if (!a.json_path.empty())
    if (Status s = c.write_json(a.json_path); !s) return check_fail(s.error().message);
  return 0;
}

const bool registered_perception_check = register_command(
    {"perception-check",
     "Measure CFAR and fusion against simulator truth (labels, true poses, mesh distance), per image profile",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<CheckArgs>();
       auto* scene = sub.add_option("--scene", a->check.scene, "Built-in scene")->capture_default_str();
       auto* scene_file = sub.add_option("--scene-file", a->check.scene_file, "User scene YAML (docs/SCENES.md)")->excludes(scene);
       add_allow_incomplete_flag(sub);
       auto* fixture = sub.add_option("--fixture", a->check.fixture,
                                      "Measure a recorded fixture with labels (simulate --labels) as recorded")
                           ->excludes(scene)
                           ->excludes(scene_file);
       auto* profile = sub.add_option("--profile", a->check.profile, "Image formation: field, clean or both")
                           ->capture_default_str();
       sub.add_option("--real-ping", a->check.real_pings,
                      "Raw Oculus SimplePingResult to compare with (label-free figures); repeatable");
       sub.add_option("--json", a->json_path, "Write every figure as JSON");
       sub.add_option("--cloud", a->cloud_path,
                      "Write the true-pose fused points with their mesh distance (PLY; one file per profile)");
       auto* duration = sub.add_option("--duration", a->check.duration_s, "Mission length, seconds")->capture_default_str();
       auto* seed = sub.add_option("--seed", a->check.seed, "Noise seed")->capture_default_str();
       auto* res = sub.add_option("--resolution", a->check.resolution, "full or reduced")->capture_default_str();
       auto* sim_config = sub.add_option("--sim-config", a->check.sim_config, "Simulator config YAML (fields of SimConfig; refines the profile)");
       sub.add_option("--config", a->check.run_config, "Run configuration YAML (its fusion: section applies)");
       sub.add_option("--every", a->check.every, "Fuse every n-th pair")->capture_default_str()->check(CLI::PositiveNumber);
       for (CLI::Option* o : {profile, duration, seed, res, sim_config}) fixture->excludes(o);
       return [a] { return run_check(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
