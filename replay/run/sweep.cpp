#include "replay/run/sweep.hpp"

#include "core/inference/inference_mapping.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/perception/fusion.hpp"
#include "hal/fake_source.hpp"
#include "replay/fixture.hpp"

namespace orthosonar::run {

std::vector<GridCell> paper_grid() {
  std::vector<GridCell> g;
  for (double r : {30.0, 60.0, 90.0})
    for (int d = 1; d <= 5; ++d) g.push_back({static_cast<double>(d), r});
  return g;
}

namespace {

// Fusion served from the preparation pass's results (a pair it did not fuse gets none).
mapping::FuseFn cached_fusion(const PreparedSweep& prepared) {
  return [&cache = prepared.fused](const SonarPing& h, const SonarPing& v) {
    const auto it = cache.find({h.stamp.ns(), v.stamp.ns()});
    return it == cache.end() ? perception::FusionResult{} : *it->second;
  };
}

}  // namespace

Result<PreparedSweep> prepare_sweep(const std::string& fixture, const RunOptions& options_in, int threads,
                                    const std::function<void(double)>& progress) {
  auto src = replay::FixtureSource::open(fixture);
  if (!src.ok()) return src.error();
  PreparedSweep p;
  p.metadata = (*src)->metadata();
  RunOptions options = options_in;
  auto config = effective_config(p.metadata, options_in, nullptr, (*src)->attachments());
  if (!config.ok()) return Error{fixture + ": " + config.error().message};
  options.config = *config;
  p.config = *config;
  std::string note;
  p.mesh = load_truth_mesh(p.metadata, options.mesh_path, note, (*src)->attachments());
  double duration_s = 0.0;
  if (const auto it = p.metadata.find("duration_s"); it != p.metadata.end()) duration_s = std::atof(it->second.c_str());

  // A pipeline without mapping systems pairs and fuses every pair exactly as a cell would;
  // its fusion hook records each result.
  mapping::Pipeline pipeline(options.config.pipeline);
  TbbExecutor pool(threads);
  SteadyClock clock;
  pipeline.set_executor(&pool);
  pipeline.set_clock(&clock);
  std::mutex mu;
  const auto& fcfg = options.config.pipeline.fusion;
  pipeline.set_fusion([&](const SonarPing& h, const SonarPing& v) {
    auto r = perception::fuse_pair(h, v, fcfg);
    auto keep = std::make_shared<perception::FusionResult>(r);
    std::lock_guard lock(mu);
    p.fused[{h.stamp.ns(), v.stamp.ns()}] = std::move(keep);
    return r;
  });
  const bool needs_h_images = std::any_of(options.systems.begin(), options.systems.end(), [](const std::string& s) {
    return s == "inference" || s == "inference_submap";
  });
  const auto wall0 = std::chrono::steady_clock::now();
  std::optional<Time> first;
  int64_t n = 0;
  for (;;) {
    auto e = (*src)->next();
    if (e.error) return Error{fixture + ": " + e.error->message};
    if (e.end_of_stream || !e.event) break;
    if (!first) first = e.event->stamp;
    pipeline.consume(*e.event);
    Event light = std::move(*e.event);
    // Cells reuse the cached fusion, so images can go, except the horizontal ones when an
    // inference system will crop them.
    if (auto* ping = std::get_if<SonarPing>(&light.payload);
        ping && !(needs_h_images && ping->mount == SonarMount::kHorizontal)) {
      ping->image.clear();
      ping->image.shrink_to_fit();
    }
    if (std::holds_alternative<SonarLabels>(light.payload)) continue;
    p.stream_s = (light.stamp - *first).seconds();
    p.events.push_back(std::move(light));
    if (progress && duration_s > 0.0 && (++n % 4096) == 0) progress(p.stream_s / duration_s);
  }
  pipeline.finish();
  for (const auto& [name, s] : pipeline.runtime())
    if (name == "fusion") p.fusion_runtime = s;
  if (std::find(options.systems.begin(), options.systems.end(), "inference_submap") != options.systems.end()) {
    // One inference_submap pass over the stream, fusion from the cache, recording clouds.
    RunOptions once = options;
    once.systems = {"inference_submap"};
    once.config.threads = 1;
    p.inference_cache = std::make_shared<inference::InferenceFrameCache>();
    once.inference_record = p.inference_cache.get();
    hal::FakeSource source(p.events);
    auto r = run_source(source, p.metadata, once, p.mesh, {}, cached_fusion(p));
    if (!r.ok()) return Error{"inference pass: " + r.error().message};
    for (const auto& s : r->systems)
      for (const auto& [name, st] : s.runtime)
        if (name == "inference_per_frame") p.inference_runtime = st;
  }
  p.fuse_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return p;
}

Result<CellResult> run_cell(const PreparedSweep& prepared, const RunOptions& options_in, const GridCell& cell) {
  RunOptions options = options_in;
  options.config = prepared.config;  // defaults < fixture < --config (effective_config)
  options.config.threads = 1;  // fusion is cached; cells run in parallel instead
  options.config.pipeline.slam.kf_distance_m = cell.distance_m;
  options.config.pipeline.slam.kf_rotation_deg = cell.rotation_deg;
  hal::FakeSource source(prepared.events);
  options.inference_replay = prepared.inference_cache.get();
  auto r = run_source(source, prepared.metadata, options, prepared.mesh, {}, cached_fusion(prepared));
  if (!r.ok()) return r.error();
  CellResult c;
  c.cell = cell;
  c.keyframes = r->counts.keyframes;
  c.ate_dr_m = r->ate_dr_m;
  c.ate_slam_m = r->ate_slam_m;
  for (const auto& [name, s] : r->runtime)
    if (name == "slam_update") c.slam_runtime = s;
  for (const auto& s : r->systems) {
    CellSystem cs;
    cs.system = s.name;
    cs.coverage_voxels = s.coverage_voxels;
    if (s.accuracy) {
      cs.accuracy_count = s.accuracy->count;
      cs.mae_m = s.accuracy->mae_m;
      cs.rmse_m = s.accuracy->rmse_m;
    }
    for (const auto& [name, st] : s.runtime) cs.runtime.merge(st);
    c.systems.push_back(cs);
  }
  c.digest = r->digest.overall_hex;
  c.wall_s = r->wall_s;
  return c;
}

Result<std::vector<CellResult>> run_cells(const PreparedSweep& prepared, const RunOptions& options,
                                          const std::vector<GridCell>& cells, int threads,
                                          const std::function<void(size_t, size_t)>& progress) {
  std::vector<std::optional<Result<CellResult>>> results(cells.size());
  std::atomic<size_t> done{0};
  std::mutex progress_mu;
  auto one = [&](size_t i) {
    try {
      results[i] = run_cell(prepared, options, cells[i]);
    } catch (const std::exception& e) {
      results[i] = Result<CellResult>(Error{e.what()});
    }
    const size_t d = ++done;
    if (progress) {
      std::lock_guard lock(progress_mu);
      progress(d, cells.size());
    }
  };
  if (threads <= 1) {
    for (size_t i = 0; i < cells.size(); ++i) one(i);
  } else {
    tbb::task_arena arena(threads);
    arena.execute([&] { tbb::parallel_for(size_t{0}, cells.size(), one); });
  }
  std::vector<CellResult> out;
  out.reserve(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!results[i]->ok()) {
      char name[64];
      std::snprintf(name, sizeof name, "cell %.1f m / %.0f deg: ", cells[i].distance_m, cells[i].rotation_deg);
      return Error{name + results[i]->error().message};
    }
    out.push_back(std::move(results[i]->value()));
  }
  return out;
}

SweepReport make_sweep_report(const PreparedSweep& prepared, std::vector<CellResult> cells) {
  SweepReport r;
  r.metadata = prepared.metadata;
  const auto it = prepared.metadata.find("scene");
  r.scene = it == prepared.metadata.end() ? "?" : it->second;
  r.cells = std::move(cells);
  r.fusion_runtime = prepared.fusion_runtime;
  r.inference_runtime = prepared.inference_runtime;
  r.stream_s = prepared.stream_s;
  r.fuse_wall_s = prepared.fuse_wall_s;
  return r;
}

namespace {

std::vector<std::string> system_names(const SweepReport& r) {
  std::vector<std::string> names;
  if (!r.cells.empty())
    for (const auto& s : r.cells.front().systems) names.push_back(s.system);
  return names;
}

const CellSystem* find(const CellResult& c, const std::string& name) {
  for (const auto& s : c.systems)
    if (s.system == name) return &s;
  return nullptr;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

std::string sweep_tables_markdown(const SweepReport& r) {
  std::ostringstream md;
  const auto names = system_names(r);
  md << "## " << r.scene << "\n\n";
  md << "Coverage (occupied 0.1 m voxels); rows: keyframe rotation, columns: keyframe distance.\n\n";
  for (const auto& name : names) {
    md << "**" << name << "**\n\n| rotation \\ distance | 1 m | 2 m | 3 m | 4 m | 5 m |\n|---|---|---|---|---|---|\n";
    for (double rot : {30.0, 60.0, 90.0}) {
      md << "| " << fmt("%.0f", rot) << "° |";
      for (int d = 1; d <= 5; ++d)
        for (const auto& c : r.cells)
          if (c.cell.rotation_deg == rot && c.cell.distance_m == d)
            if (const auto* s = find(c, name)) md << " " << s->coverage_voxels << " |";
      md << "\n";
    }
    md << "\n";
  }
  md << "Mapping error (m), pooled over the 15 cells (paper Table II layout).\n\n| System | MAE | RMSE |\n|---|---|---|\n";
  for (const auto& name : names) {
    double sum = 0, sum_sq = 0;
    int64_t n = 0;
    for (const auto& c : r.cells)
      if (const auto* s = find(c, name)) {
        sum += s->mae_m * static_cast<double>(s->accuracy_count);
        sum_sq += s->rmse_m * s->rmse_m * static_cast<double>(s->accuracy_count);
        n += s->accuracy_count;
      }
    md << "| " << name << " | " << (n ? fmt("%.3f", sum / static_cast<double>(n)) : "n/a") << " | "
       << (n ? fmt("%.3f", std::sqrt(sum_sq / static_cast<double>(n))) : "n/a") << " |\n";
  }
  md << "\nRuntime in seconds (paper Table III layout; mean and SD).\n\n| Stage | Mean | SD | Count |\n|---|---|---|---|\n";
  auto row = [&](const std::string& label, const mapping::RuntimeStats& s) {
    md << "| " << label << " | " << fmt("%.3g", s.mean_ms() / 1000.0) << " | " << fmt("%.3g", s.sd_ms() / 1000.0)
       << " | " << s.count << " |\n";
  };
  row("Orthogonal sensor fusion (one pair)", r.fusion_runtime);
  if (r.inference_runtime.count > 0) row("Mapping inference (one frame, every pair once)", r.inference_runtime);
  for (const auto& name : names) {
    mapping::RuntimeStats s;
    for (const auto& c : r.cells)
      if (const auto* cs = find(c, name)) s.merge(cs->runtime);
    row(name == "submap" ? "Submap construction (per timestep)" : name + " map update", s);
  }
  mapping::RuntimeStats slam;
  for (const auto& c : r.cells) slam.merge(c.slam_runtime);
  row("SLAM update (per keyframe)", slam);
  md << "\nATE per cell (m), DR / SLAM: ";
  for (const auto& c : r.cells)
    md << fmt("%.0f", c.cell.distance_m) << "m/" << fmt("%.0f", c.cell.rotation_deg) << "° "
       << (c.ate_dr_m ? fmt("%.2f", *c.ate_dr_m) : "n/a") << "/" << (c.ate_slam_m ? fmt("%.2f", *c.ate_slam_m) : "n/a")
       << (&c == &r.cells.back() ? "\n" : "; ");
  md << "\nMission: " << fmt("%.0f", r.stream_s) << " s of sensor data; fusing every pair once took "
     << fmt("%.1f", r.fuse_wall_s) << " s wall.\n";
  return md.str();
}

Status write_sweep_outputs(const SweepReport& r, const std::string& out_dir) {
  namespace fs = std::filesystem;
  nlohmann::json j;
  j["scene"] = r.scene;
  nlohmann::json fixture = nlohmann::json::object();
  for (const auto& [k, v] : r.metadata) fixture[k] = v;
  j["fixture"] = fixture;
  j["cells"] = nlohmann::json::array();
  std::ostringstream csv;
  csv << "system,distance_m,rotation_deg,coverage_voxels,mae_m,rmse_m,ate_dr_m,ate_slam_m,keyframes\n";
  auto num = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  for (const auto& c : r.cells)
    for (const auto& s : c.systems) {
      j["cells"].push_back({{"system", s.system}, {"distance_m", c.cell.distance_m},
                            {"rotation_deg", c.cell.rotation_deg}, {"coverage_voxels", s.coverage_voxels},
                            {"mae_m", s.accuracy_count ? nlohmann::json(s.mae_m) : nlohmann::json(nullptr)},
                            {"rmse_m", s.accuracy_count ? nlohmann::json(s.rmse_m) : nlohmann::json(nullptr)},
                            {"ate_dr_m", num(c.ate_dr_m)}, {"ate_slam_m", num(c.ate_slam_m)},
                            {"keyframes", c.keyframes}, {"digest", c.digest}});
      csv << s.system << "," << c.cell.distance_m << "," << c.cell.rotation_deg << "," << s.coverage_voxels << ","
          << fmt("%.6f", s.mae_m) << "," << fmt("%.6f", s.rmse_m) << ","
          << (c.ate_dr_m ? fmt("%.6f", *c.ate_dr_m) : "") << "," << (c.ate_slam_m ? fmt("%.6f", *c.ate_slam_m) : "")
          << "," << c.keyframes << "\n";
    }
  j["runtime"] = {{"fusion", {{"mean_ms", r.fusion_runtime.mean_ms()}, {"sd_ms", r.fusion_runtime.sd_ms()},
                              {"count", r.fusion_runtime.count}}}};
  if (r.inference_runtime.count > 0)
    j["runtime"]["inference_per_frame"] = {{"mean_ms", r.inference_runtime.mean_ms()},
                                           {"sd_ms", r.inference_runtime.sd_ms()},
                                           {"count", r.inference_runtime.count}};
  const fs::path out(out_dir);
  auto write = [](const fs::path& p, const std::string& text) -> Status {
    std::ofstream f(p, std::ios::trunc);
    if (!f) return Error{"cannot open '" + p.string() + "' for writing"};
    f << text;
    return f ? Status{} : Status{Error{"write failed for '" + p.string() + "'"}};
  };
  if (Status s = write(out / "grid.json", j.dump(2) + "\n"); !s.ok()) return s;
  if (Status s = write(out / "grid.csv", csv.str()); !s.ok()) return s;
  return write(out / "tables.md", sweep_tables_markdown(r));
}

}  // namespace orthosonar::run
