#include "reports/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>


#include "hal/codec/image_codec.hpp"
#include "reports/error_plot.hpp"
#include "reports/heatmap.hpp"
#include "reports/html.hpp"
#include "reports/image_compare.hpp"
#include "reports/map_views.hpp"
#include "reports/ping_pair_figure.hpp"
#include "reports/trajectory_plot.hpp"

namespace orthosonar::reports {
namespace fs = std::filesystem;

namespace {

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// The PNG's bytes, also written to `path` (every figure is a file beside the report too).
Result<std::vector<uint8_t>> save_png(const fs::path& path, const cv::Mat& image) {
  auto png = codec::encode_png(image);
  if (!png) return png.error();
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(png->data()), static_cast<std::streamsize>(png->size()));
  if (!f) return Error{"cannot write '" + path.string() + "'"};
  return png;
}

struct Builder {
  const RunData& run;
  const ReportOptions& options;
  fs::path out;
  HtmlDoc& doc;
  RenderConfig render;
  Bounds bounds;
  bool can_render = false;

  // Renders into `name` (PNG), adds a figure. Render faults become notes, write faults
  // errors. A photo (sonar speckle: megabytes as PNG) is embedded as JPEG.
  Status figure(const Result<cv::Mat>& image, const std::string& name, const std::string& caption,
                std::vector<std::string>& notes, cv::Mat* keep = nullptr, bool photo = false) {
    if (!image) {
      notes.push_back(name + ": " + image.error().message);
      return Status::Ok();
    }
    auto png = save_png(out / name, *image);
    if (!png) return png.error();
    if (keep) *keep = *image;
    if (photo) {
      auto jpeg = codec::encode_jpeg(*image, 88);
      if (!jpeg) return jpeg.error();
      doc.figure(*jpeg, "image/jpeg", name, caption);
    } else {
      doc.figure(*png, "image/png", name, caption);
    }
    return Status::Ok();
  }
};

void metrics_tables(const RunData& run, HtmlDoc& doc) {
  std::vector<std::vector<std::string>> rows, runtime;
  for (const auto& s : run.systems) {
    if (!s.has_metrics) continue;
    rows.push_back({s.name, fixed(s.coverage_voxels, 0), fixed(s.mae_m, 3), fixed(s.rmse_m, 3), fixed(s.ate_dr_m, 3),
                    fixed(s.ate_slam_m, 3), std::to_string(s.map_W.size())});
    for (const auto& r : s.runtime)
      runtime.push_back({s.name, r.stage, fixed(r.mean_ms, 3), fixed(r.sd_ms, 3), fixed(r.count, 0)});
  }
  if (rows.empty()) return;
  doc.heading("Metrics");
  doc.table({"system", "coverage (voxels, 0.1 m)", "MAE (m)", "RMSE (m)", "ATE DR (m)", "ATE SLAM (m)", "map points"},
            rows);
  if (!runtime.empty()) {
    doc.heading("Runtime");
    doc.table({"system", "stage", "mean (ms)", "sd (ms)", "count"}, runtime);
  }
}

Status map_section(Builder& b, std::vector<std::string>& notes) {
  if (!b.can_render) return Status::Ok();
  bool any_map = false;
  for (const auto& s : b.run.systems) any_map = any_map || s.has_map;
  if (!any_map && !b.run.mesh && !b.run.truth) return Status::Ok();
  b.doc.heading("Maps");
  b.doc.paragraph("Points coloured by height; ground-truth mesh translucent; trajectories: ground truth (white), "
                  "dead reckoning (orange), SLAM (magenta). The camera is fixed per scene (from the mesh and the truth "
                  "trajectory), so images of different runs compare directly.",
                  "meta");
  b.doc.begin_gallery();
  for (const auto& s : b.run.systems) {
    if (!s.has_map) continue;
    for (View v : {View::kTop, View::kOblique}) {
      const std::string name = "map_" + s.name + "_" + view_name(v) + ".png";
      const std::string title = s.name + " map, " + view_name(v) + " view (" + std::to_string(s.map_W.size()) + " points)";
      if (auto st = b.figure(render_map_view(b.run, s.map_W, v, b.bounds, title, b.render), name, title, notes); !st)
        return st;
    }
  }
  if (!any_map) {
    for (View v : {View::kTop, View::kOblique}) {
      const std::string name = std::string("scene_") + view_name(v) + ".png";
      const std::string title = std::string("scene, ") + view_name(v) + " view (no map in this run)";
      if (auto st = b.figure(render_map_view(b.run, {}, v, b.bounds, title, b.render), name, title, notes); !st)
        return st;
    }
  }
  b.doc.end_gallery();
  return Status::Ok();
}

// Where the map is wrong: each system's map coloured by its distance to the truth mesh.
Status error_map_section(Builder& b, std::vector<std::string>& notes) {
  if (!b.can_render || !b.run.mesh) return Status::Ok();
  bool any_map = false;
  for (const auto& s : b.run.systems) any_map = any_map || (s.has_map && !s.map_W.empty());
  if (!any_map) return Status::Ok();
  b.doc.heading("Where the map is wrong");
  b.doc.paragraph("Each map point coloured by its distance to the ground-truth mesh (exact point to triangle, in "
                  "metres; the scale saturates at " + fixed(b.options.diff_max_m, 2) + " m). The MAE and RMSE above "
                  "are these distances, from the map's voxel centroids.",
                  "meta");
  b.doc.begin_gallery();
  for (const auto& s : b.run.systems) {
    if (!s.has_map || s.map_W.empty()) continue;
    const std::string name = "error_" + s.name + "_top.png";
    const std::string title = s.name + " map: distance to the mesh (m)";
    if (auto st = b.figure(render_mesh_error_view(b.run, s.map_W, b.options.diff_max_m, View::kTop, b.bounds, title,
                                                  b.render),
                           name, title + ", top view", notes);
        !st)
      return st;
  }
  b.doc.end_gallery();
  return Status::Ok();
}

// What the sonars saw: the pair with the most fused points.
Status ping_pair_section(Builder& b, std::vector<std::string>& notes) {
  if (!b.run.ping_pair) return Status::Ok();
  const auto& pp = *b.run.ping_pair;
  b.doc.heading("What the sonars saw");
  b.doc.paragraph("The ping pair with the most fused points (stamp " + fixed(pp.h.stamp.seconds(), 2) +
                      " s): the horizontal image from above (forward up), the vertical one from the side (forward "
                      "right, up up), speckle stretched for display. Dots: CFAR detections; circles: the fused points, "
                      "each where it came from on both images.",
                  "meta");
  return b.figure(draw_ping_pair(pp), "ping_pair.png", "Ping pair with its CFAR detections and fused points", notes,
                  nullptr, true);
}

Status trajectory_section(Builder& b, std::vector<std::string>& notes) {
  std::vector<PlotSeries> series;
  auto add = [&](const std::optional<Trajectory>& t, const char* label, Rgb colour) {
    if (!t || t->size() < 2) return;
    PlotSeries s{label, {}, colour};
    for (const auto& p : *t) s.xy_m.push_back(p.position.head<2>());
    series.push_back(std::move(s));
  };
  add(b.run.truth, "ground truth", {0.1, 0.1, 0.1});
  add(b.run.dr, "dead reckoning", dr_colour());
  add(b.run.slam, "SLAM", {0.75, 0.1, 0.75});
  if (series.empty()) return Status::Ok();
  b.doc.heading("Trajectories");
  if (auto st = b.figure(draw_trajectory_plot(series), "trajectories.png", "Top view (x-y) of the trajectories", notes);
      !st)
    return st;
  if (!b.run.truth) return Status::Ok();
  std::vector<ErrorSeries> errors;
  if (b.run.dr) errors.push_back(trajectory_error_series(*b.run.dr, *b.run.truth, "dead reckoning", dr_colour(), true));
  if (b.run.slam)
    errors.push_back(trajectory_error_series(*b.run.slam, *b.run.truth, "SLAM", {0.75, 0.1, 0.75}, true));
  if (errors.empty()) return Status::Ok();
  return b.figure(draw_error_over_time(errors), "trajectory_error.png",
                  "Keyframe position error against the ground truth over time (unaligned, as the ATE; RMS over keyframes)",
                  notes);
}

Status sweep_section(Builder& b, std::vector<std::string>& notes) {
  if (!b.run.grid) return Status::Ok();
  b.doc.heading("Keyframe sweep");
  b.doc.paragraph("Rows: keyframe rotation (deg); columns: keyframe distance (m); one panel per system, one colour "
                  "scale per figure (blue low, orange high).",
                  "meta");
  for (auto [metric, name] : {std::pair{HeatmapMetric::kCoverage, "heatmap_coverage.png"},
                              std::pair{HeatmapMetric::kMae, "heatmap_mae.png"}}) {
    auto hm = draw_heatmap(*b.run.grid, {metric});
    const Result<cv::Mat> image = hm ? Result<cv::Mat>(hm->image) : Result<cv::Mat>(hm.error());
    if (auto st = b.figure(image, name, std::string(metric_label(metric)) + " per keyframe setting", notes); !st)
      return st;
  }
  return Status::Ok();
}

Status golden_section(Builder& b, std::vector<std::string>& notes) {
  if (b.options.golden_dir.empty()) return Status::Ok();
  auto golden = load_run(b.options.golden_dir);
  if (!golden) return Error{"golden: " + golden.error().message};
  b.doc.heading("Comparison with golden");
  b.doc.paragraph("Golden: " + b.options.golden_dir + ". Both rendered with this run's camera. Image difference = "
                  "mean absolute grayscale difference at 160x120 (0 identical, 1 black vs white).",
                  "meta");
  if (!b.can_render) {
    notes.push_back("golden comparison images skipped: no display");
    return Status::Ok();
  }
  std::vector<std::vector<std::string>> scores;
  b.doc.begin_gallery();
  for (const auto& s : b.run.systems) {
    const SystemOutput* g = nullptr;
    for (const auto& gs : golden->systems)
      if (gs.name == s.name && gs.has_map) g = &gs;
    if (!s.has_map || !g) {
      notes.push_back("no golden comparison for " + s.name + " (map missing on one side)");
      continue;
    }
    for (View v : {View::kTop, View::kOblique}) {
      // The same title on both, so the score measures the maps only (captions say which is which).
      const std::string title = s.name + ", " + view_name(v) + " view";
      auto cur = render_map_view(b.run, s.map_W, v, b.bounds, title, b.render);
      auto gold = render_map_view(b.run, g->map_W, v, b.bounds, title, b.render);
      if (!cur || !gold) {
        notes.push_back(s.name + ": " + (!cur ? cur.error().message : gold.error().message));
        continue;
      }
      const double score = image_difference(*gold, *cur);
      scores.push_back({s.name, view_name(v), fixed(score, 4), std::to_string(g->map_W.size()),
                        std::to_string(s.map_W.size())});
      const std::string name = "compare_" + s.name + "_" + view_name(v) + ".png";
      const Result<cv::Mat> pair = side_by_side(*gold, "golden", *cur, "current");
      if (auto st = b.figure(pair, name, s.name + " " + view_name(v) + ": golden (left) vs current (right)", notes); !st)
        return st;
    }
    const std::string d1 = "diff_" + s.name + "_current_to_golden.png";
    if (auto st = b.figure(render_difference_view(b.run, s.map_W, g->map_W, b.options.diff_max_m, View::kOblique,
                                                  b.bounds, s.name + ": current points, distance to golden", b.render),
                           d1, s.name + ": each current point coloured by its distance to the golden map", notes);
        !st)
      return st;
    const std::string d2 = "diff_" + s.name + "_golden_to_current.png";
    if (auto st = b.figure(render_difference_view(b.run, g->map_W, s.map_W, b.options.diff_max_m, View::kOblique,
                                                  b.bounds, s.name + ": golden points, distance to current", b.render),
                           d2, s.name + ": each golden point coloured by its distance to the current map (lost coverage)",
                           notes);
        !st)
      return st;
  }
  b.doc.end_gallery();
  if (!scores.empty()) b.doc.table({"system", "view", "image difference", "golden points", "current points"}, scores);
  return Status::Ok();
}

}  // namespace

std::vector<std::string> referenced_files(const std::string& html) {
  // Every src="..." and href="..." value, in order (a plain scan: GCC 12 reports a false
  // -Wmaybe-uninitialized inside <regex> under the sanitizers, issue 16).
  std::vector<std::string> out;
  size_t pos = 0;
  while (true) {
    const size_t s = html.find("src=\"", pos);
    const size_t h = html.find("href=\"", pos);
    if (s == std::string::npos && h == std::string::npos) break;
    const size_t value_begin = s < h ? s + 5 : h + 6;
    const size_t value_end = html.find('"', value_begin);
    if (value_end == std::string::npos) break;
    pos = value_end + 1;
    const std::string v = html.substr(value_begin, value_end - value_begin);
    if (v.empty() || v[0] == '#' || v[0] == '/' || v.find(':') != std::string::npos) continue;
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  }
  return out;
}

Status write_report(const std::string& run_dir, const std::string& report_dir, const ReportOptions& options) {
  auto run = load_run(run_dir);
  if (!run) return run.error();
  std::error_code ec;
  fs::create_directories(report_dir, ec);
  if (ec) return Error{"cannot create report directory '" + report_dir + "': " + ec.message()};

  const std::string scene = run->scene.empty() ? std::string("unnamed scene") : run->scene;
  HtmlDoc doc(options.title.empty() ? "orthosonar report: " + scene : options.title);
  std::vector<std::string> notes = run->notes;
  Builder b{*run, options, fs::path(report_dir), doc, {}, run_bounds(*run), false};
  b.render.width_px = options.width_px;
  b.render.height_px = options.height_px;
  if (auto d = check_display(); d) {
    b.can_render = true;
  } else if (options.require_renders) {
    return d.error();
  } else {
    notes.push_back("3D renders skipped: " + d.error().message);
  }

  doc.paragraph("scene: " + scene + " | software version: " +
                    (run->software_version.empty() ? std::string("unknown") : run->software_version) +
                    " | digest: " + (run->digest_overall.empty() ? std::string("none") : run->digest_overall),
                "meta");
  doc.paragraph("run directory: " + run_dir, "meta");
  if (!run->input_cut.empty()) doc.paragraph("INCOMPLETE INPUT: " + run->input_cut, "note");
  metrics_tables(*run, doc);
  for (auto section : {map_section, error_map_section, ping_pair_section, trajectory_section, sweep_section,
                       golden_section})
    if (auto st = section(b, notes); !st) return st;

  if (!run->summary.empty()) {
    doc.heading("Fixture and run summary");
    std::vector<std::vector<std::string>> rows, config;
    for (const auto& [k, v] : run->summary) (k.rfind("config.", 0) == 0 ? config : rows).push_back({k, v});
    doc.table({"key", "value"}, rows);
    if (!config.empty()) {
      doc.begin_details("configuration used (" + std::to_string(config.size()) + " values)");
      doc.table({"key", "value"}, config);
      doc.end_details();
    }
  }
  if (!run->digest_overall.empty() || !run->digest_outputs.empty()) {
    doc.heading("Digest");
    std::vector<std::vector<std::string>> rows{{"overall", run->digest_overall}};
    for (const auto& [k, v] : run->digest_outputs) rows.push_back({k, v});
    doc.table({"output", "sha256"}, rows);
  }
  if (!notes.empty()) {
    doc.heading("Notes");
    doc.list(notes);
  }
  const fs::path html_path = fs::path(report_dir) / "report.html";
  std::ofstream html(html_path, std::ios::binary);
  html << doc.finish();
  if (!html) return Error{"cannot write '" + html_path.string() + "'"};
  return Status::Ok();
}

}  // namespace orthosonar::reports
