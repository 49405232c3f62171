#include "replay/run/perception_check.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <utility>

#include "hal/event_source.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/simulator.hpp"
#include "replay/run/run.hpp"

namespace orthosonar::run {
namespace {

using nlohmann::json;
using mapping::ratio;

// Pulls `src` to its end through a PerceptionMeter.
Status measure_source(hal::EventSource& src, const perception::FusionConfig& cfg, const TriangleMesh& mesh,
                      int every, const std::string& what, MeasuredProfile& out, bool keep_points) {
  mapping::PerceptionMeter meter(cfg, mesh, every, keep_points);
  for (;;) {
    hal::Pulled p = src.next();
    if (p.error) return Error{p.error->message};
    if (p.end_of_stream || !p.event) break;
    meter.add(std::move(*p.event));
  }
  Status s = meter.finish(what);
  out.m = meter.take();
  return s;
}

json num(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json intensity_json(const mapping::IntensityHistogram& h, double gate) {
  return {{"pixels", h.n},          {"p50", num(h.quantile(0.5))}, {"p90", num(h.quantile(0.9))},
          {"p99", num(h.quantile(0.99))}, {"mean", num(h.mean())},
          {"above_gate", num(h.n ? h.fraction_above(gate) : std::nan(""))}};
}

json label_free_json(const mapping::IntensityHistogram& h, double gate) {
  const mapping::OtsuSplit s = mapping::otsu(h);
  return {{"all", intensity_json(h, gate)},
          {"otsu",
           {{"threshold", num(s.threshold)},
            {"dark", {{"fraction", num(s.dark_fraction)}, {"p50", num(s.dark_p50)}}},
            {"bright", {{"fraction", num(s.bright_fraction)}, {"p50", num(s.bright_p50)}}}}}};
}

json mount_json(const mapping::MountTally& t, double gate) {
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

json slope_bands_json(const std::vector<double>& err, const std::vector<float>& surface_deg) {
  json bands = json::array();
  for (const auto& b : mapping::fusion_figures_by_slope(err, surface_deg))
    bands.push_back({{"from_deg", b.lo_deg},
                     {"to_deg", b.hi_deg},
                     {"points", b.points},
                     {"median", num(b.figures.median)},
                     {"p90", num(b.figures.p90)},
                     {"mae", num(b.figures.mae)},
                     {"rmse", num(b.figures.rmse)}});
  return bands;
}

json calibration_json(const mapping::SigmaCalibration& c) {
  return {{"points", c.points},
          {"rms_error_deg", num(c.rms_error_deg)},
          {"rms_sigma_deg", num(c.rms_sigma_deg)},
          {"z_rms", num(c.z_rms)},
          {"within_1_sigma", num(c.within_1sigma)},
          {"within_2_sigma", num(c.within_2sigma)}};
}

json measured_json(const MeasuredProfile& r) {
  const mapping::FusionTally& f = r.m.fusion;
  const mapping::FusionFigures ff = mapping::fusion_figures(f.err);
  const mapping::MappedPoints mp = mapping::mapped_points(f, r.max_elevation_sigma_deg);
  const mapping::FusionFigures mf = mapping::fusion_figures(mp.err);
  return {{"label", r.label},
          {"profile", r.profile},
          {"note", r.note},
          {"mounts", {{"h", mount_json(r.m.h, r.m.gate_h)}, {"v", mount_json(r.m.v, r.m.gate_v)}}},
          {"fusion",
           {{"pairs", f.pairs},
            {"fused_pairs", f.fused},
            {"points", f.err.size()},
            {"points_per_pair", ratio(static_cast<double>(f.err.size()), static_cast<double>(f.fused))},
            {"subproblems", f.subproblems},
            {"matches", f.matches},
            {"culled_low_confidence", f.culled},
            {"sloped_face", f.sloped_face},
            {"distance_to_mesh_m",
             {{"median", num(ff.median)}, {"p90", num(ff.p90)}, {"mae", num(ff.mae)}, {"rmse", num(ff.rmse)}},
            },
            {"within_0_1m", num(ff.within)},
            {"by_surface_angle_from_vertical", slope_bands_json(f.err, f.surface_deg)},
            {"elevation_sigma",
             {{"v_return", calibration_json(mapping::sigma_calibration(f, false))},
              {"sloped_face", calibration_json(mapping::sigma_calibration(f, true))}}},
            {"mapped",
             {{"max_elevation_sigma_deg", r.max_elevation_sigma_deg},
              {"points", mp.err.size()},
              {"share", ratio(static_cast<double>(mp.err.size()), static_cast<double>(f.err.size()))},
              {"distance_to_mesh_m",
               {{"median", num(mf.median)}, {"p90", num(mf.p90)}, {"mae", num(mf.mae)}, {"rmse", num(mf.rmse)}}},
              {"within_0_1m", num(mf.within)},
              {"by_surface_angle_from_vertical", slope_bands_json(mp.err, mp.surface_deg)}}},
            {"association_bound", [&f] {
               const mapping::AssociationBound b = mapping::association_bound(f);
               return json{{"mae_fused", num(b.mae_fused)},
                           {"mae_best_candidate_of_bin", num(b.mae_best_candidate)},
                           {"mae_best_elevation_in_overlap", num(b.mae_best_elevation)},
                           {"single_candidate_points", b.single_candidate_points},
                           {"single_candidate_mae", num(b.single_candidate_mae)}};
             }()}}}};
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

}  // namespace

Result<RealPing> load_real_ping(const std::string& path) {
  auto f = hal::drivers::oculus::read_oculus_ping_file(path, "--real-ping");
  if (!f) return f.error();
  RealPing rp{path, std::move(f->raw), std::move(f->ping), {}};
  rp.all.add(rp.ping);
  return rp;
}

Result<PerceptionCheck> PerceptionCheck::open(
    const PerceptionCheckOptions& options,
    const std::function<void(const std::string& path, const replay::RecoveryReport&)>& on_fixture_open) {
  PerceptionCheck c;
  c.o_ = options;
  for (const std::string& path : options.real_pings) {
    auto r = load_real_ping(path);
    if (!r) return r.error();
    c.real_.push_back(std::move(*r));
  }
  std::string run_yaml;
  if (!options.run_config.empty()) {
    auto text = read_config_text(options.run_config);
    if (!text) return text.error();
    run_yaml = *text;
    if (Status s = load_config_file(options.run_config, c.run_); !s.ok()) return s.error();
  }
  if (options.fixture.empty()) {
    if (options.profile == "both") {
      c.profiles_ = {sim::SonarProfile::kField, sim::SonarProfile::kClean};
    } else {
      auto p = sim::parse_profile(options.profile);
      if (!p) return Error{"--profile: " + p.error().message + " (field, clean or both)"};
      c.profiles_ = {*p};
    }
  }
  c.gate_real_ = c.run_.pipeline.fusion.cfar_v.gate;  // the M1200d is the vertical head
  if (!options.fixture.empty()) {
    const std::string& path = options.fixture;
    auto src = replay::FixtureSource::open(path);
    if (!src) return src.error();
    c.fixture_ = std::move(*src);
    if (on_fixture_open) on_fixture_open(path, c.fixture_->recovery());
    if (c.fixture_metadata("labels") != "true")
      return Error{path + ": the fixture has no per-pixel labels (record it with `orthosonar simulate --labels`)"};
    auto scene = sim::scene_from_fixture(c.fixture_->metadata(), replay::attachment_files(c.fixture_->attachments()));
    if (!scene) return Error{path + ": no scene for the mesh distance: " + scene.error().message};
    c.scene_ = std::move(*scene);
    RunOptions run_options;
    run_options.config_yaml = run_yaml;
    run_options.config_origin = options.run_config;
    auto resolved = effective_config(c.fixture_->metadata(), run_options, nullptr, c.fixture_->attachments());
    if (!resolved) return Error{path + ": " + resolved.error().message};
    c.fixture_fusion_ = resolved->pipeline.fusion;
    c.gate_real_ = c.fixture_fusion_.cfar_v.gate;
  } else {
    auto scene = options.scene_file.empty() ? sim::builtin_scene(options.scene, 1) : sim::load_scene_file(options.scene_file);
    if (!scene) return scene.error();
    c.scene_ = std::move(*scene);
    auto resolution = sim::parse_resolution(options.resolution);
    if (!resolution) return resolution.error();
    c.resolution_ = *resolution;
  }
  return c;
}

std::string PerceptionCheck::fixture_metadata(const std::string& key) const {
  if (!fixture_) return {};
  const auto& md = fixture_->metadata();
  const auto it = md.find(key);
  return it == md.end() ? std::string() : it->second;
}

Status PerceptionCheck::measure() {
  results_.clear();
  return fixture_ ? measure_fixture() : measure_profiles();
}

Status PerceptionCheck::measure_fixture() {
  MeasuredProfile m;
  m.profile = fixture_metadata("profile").empty() ? "unknown" : fixture_metadata("profile");
  m.label = "fixture";
  m.max_elevation_sigma_deg = run_.pipeline.max_elevation_sigma_deg;
  m.heading = "fixture " + o_.fixture + " (profile " + m.profile + ", as recorded)";
  if (Status s = measure_source(*fixture_, fixture_fusion_, scene_.mesh, o_.every, o_.fixture, m, o_.keep_points); !s)
    return s;
  results_.push_back(std::move(m));
  return {};
}

Status PerceptionCheck::measure_profiles() {
  for (sim::SonarProfile profile : profiles_) {
    sim::SimConfig sc;
    sc.profile = profile;  // before the sim config file, whose keys refine the profile
    sim::apply_profile(sc.sonar, profile);
    sc.duration_s = o_.duration_s;
    sc.seed = o_.seed;
    sc.labels = true;
    sc.render_threads = 2;
    sc.resolution = resolution_;
    if (!o_.sim_config.empty())
      if (Status s = sim::load_sim_config_file(o_.sim_config, sc); !s) return s;
    sc.labels = true;
    if (Status s = sim::validate(sc); !s) return s;
    perception::FusionConfig cfg = run_.pipeline.fusion;
    cfg.T_V_h = sc.T_V_h;
    cfg.T_V_v = sc.T_V_v;
    MeasuredProfile m;
    m.label = sim::profile_name(profile);
    m.max_elevation_sigma_deg = run_.pipeline.max_elevation_sigma_deg;
    m.heading = std::string("profile ") + m.label;
    m.profile = sim::profile_name(sc.profile);
    if (sc.profile != profile) m.note = "(the sim config sets profile: " + m.profile + ")";
    sim::Scene copy = scene_;
    if (Status s = sim::select_route(copy, sc.route); !s) return s;
    const TriangleMesh mesh = copy.mesh;
    sim::Simulator simulator(std::move(copy), sc);
    if (Status s = measure_source(simulator, cfg, mesh, o_.every, simulator.describe(), m, o_.keep_points); !s)
      return s;
    results_.push_back(std::move(m));
  }
  return {};
}

json PerceptionCheck::to_json() const {
  json doc;
  if (fixture_) {
    doc["source"] = {{"fixture", o_.fixture},
                     {"scene", scene_.name},
                     {"scene_origin", scene_.origin},
                     {"seed", fixture_metadata("seed")},
                     {"resolution", fixture_metadata("resolution")},
                     {"duration_s", fixture_metadata("duration_s")},
                     {"profile", results_.empty() ? std::string() : results_.front().profile},
                     {"complete", fixture_->recovery().complete}};
  } else {
    doc["source"] = {{"scene", scene_.name},
                     {"scene_origin", o_.scene_file.empty() ? scene_.origin : sim::portable_origin(scene_)},
                     {"seed", o_.seed},
                     {"resolution", sim::resolution_name(resolution_)},
                     {"duration_s", o_.duration_s},
                     {"sim_config", o_.sim_config}};
  }
  doc["every"] = o_.every;
  doc["notes"] = {
      {"label_based", "simulator only: per-pixel labels (0 water, 1 seabed, >= 2 structure), detection precision"},
      {"label_free", "all pixels and Otsu's dark/bright split: comparable with real pings"},
      {"quantiles", "8-bit intensity; quantile q = sorted value at floor(q (n - 1)); above_gate: share > gate"},
      {"fusion", "fused points placed with the true vehicle pose, distance to the scene mesh"}};
  doc["profiles"] = json::array();
  for (const MeasuredProfile& m : results_) doc["profiles"].push_back(measured_json(m));
  doc["real_pings"] = json::array();
  for (const RealPing& r : real_) doc["real_pings"].push_back(real_ping_json(r, gate_real_));
  return doc;
}

Status PerceptionCheck::write_json(const std::string& path) const {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << to_json().dump(2) << "\n";
  out.close();
  if (!out) return Error{"cannot write '" + path + "'"};
  return {};
}

std::string cloud_path_for(const std::string& path, const std::string& label, size_t n_results) {
  if (n_results <= 1) return path;
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + "_" + label;
  return path.substr(0, dot) + "_" + label + path.substr(dot);
}

Status write_cloud(const std::string& path, const mapping::FusionTally& f) {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<sim::PlyScalar> scalars = {{"distance_m", {}},    {"range_m", {}},    {"bearing_deg", {}},
                                         {"elevation_deg", {}}, {"confidence", {}}, {"stamp_s", {}},
                                         {"surface_deg", {}}, {"sloped_face", {}},
                                         {"elevation_error_deg", {}}, {"elevation_sigma_deg", {}},
                                         {"run_m", {}}, {"bin_spread_deg", {}}, {"bin_candidates", {}}};
  constexpr double kDeg = 180.0 / std::numbers::pi;
  for (size_t i = 0; i < f.points.size(); ++i) {
    const mapping::FusionTally::Point& p = f.points[i];
    xyz.push_back(p.p_W);
    const double values[] = {f.err[i],   p.range_m, p.bearing_rad * kDeg, p.elevation_rad * kDeg,
                             p.confidence, p.stamp_s, f.surface_deg[i], p.sloped_face ? 1.0 : 0.0,
                             f.elevation_error_rad[i] * kDeg, f.elevation_sigma_rad[i] * kDeg, p.run_m,
                             p.bin_spread_rad * kDeg, static_cast<double>(f.bin_candidates_v[i])};
    for (size_t k = 0; k < scalars.size(); ++k) scalars[k].values.push_back(static_cast<float>(values[k]));
  }
  return sim::write_ply_points(xyz, scalars, "orthosonar perception-check: fused points placed with the true pose",
                               path);
}

}  // namespace orthosonar::run
