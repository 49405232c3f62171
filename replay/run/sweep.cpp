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
    if (s.true_pose_accuracy) {
      cs.true_pose_count = s.true_pose_accuracy->count;
      cs.true_pose_mae_m = s.true_pose_accuracy->mae_m;
      cs.true_pose_rmse_m = s.true_pose_accuracy->rmse_m;
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

// Point-weighted MAE and RMSE over cells.
struct PooledError {
  double sum = 0, sum_sq = 0;
  int64_t n = 0;
  void add(int64_t count, double mae, double rmse) {
    sum += mae * static_cast<double>(count);
    sum_sq += rmse * rmse * static_cast<double>(count);
    n += count;
  }
  std::optional<double> mae() const { return n ? std::optional(sum / static_cast<double>(n)) : std::nullopt; }
  std::optional<double> rmse() const {
    return n ? std::optional(std::sqrt(sum_sq / static_cast<double>(n))) : std::nullopt;
  }
};

// A system's map error pooled over cells, with the SLAM poses and with the true ones.
struct Pooled {
  PooledError slam, truth;
  void add(const CellSystem& s) {
    slam.add(s.accuracy_count, s.mae_m, s.rmse_m);
    truth.add(s.true_pose_count, s.true_pose_mae_m, s.true_pose_rmse_m);
  }
  std::optional<double> mae() const { return slam.mae(); }
  std::optional<double> rmse() const { return slam.rmse(); }
};

struct AteStats {
  std::vector<double> ratios;  // SLAM / DR per cell with both
  int64_t slam_le_dr = 0, cells = 0;
  void add(const CellResult& c) {
    if (!c.ate_dr_m || !c.ate_slam_m) return;
    ++cells;
    if (*c.ate_slam_m <= *c.ate_dr_m) ++slam_le_dr;
    if (*c.ate_dr_m > 0.0) ratios.push_back(*c.ate_slam_m / *c.ate_dr_m);
  }
  std::optional<double> median() const {
    if (ratios.empty()) return std::nullopt;
    auto v = ratios;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
  }
};

nlohmann::json opt_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
std::string opt_fmt(const char* f, const std::optional<double>& v) { return v ? fmt(f, *v) : std::string("n/a"); }


// One system's points pooled over the report's cells (Table II and the seed tables).
Pooled pooled_over_cells(const SweepReport& r, const std::string& name) {
  Pooled p;
  for (const auto& c : r.cells)
    if (const auto* s = find(c, name)) p.add(*s);
  return p;
}

mapping::RuntimeStats system_runtime(const SweepReport& r, const std::string& name) {
  mapping::RuntimeStats st;
  for (const auto& c : r.cells)
    if (const auto* cs = find(c, name)) st.merge(cs->runtime);
  return st;
}

mapping::RuntimeStats slam_runtime(const SweepReport& r) {
  mapping::RuntimeStats st;
  for (const auto& c : r.cells) st.merge(c.slam_runtime);
  return st;
}

Status write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::trunc);
  if (!f) return Error{"cannot open '" + p.string() + "' for writing"};
  f << text;
  return f ? Status{} : Status{Error{"write failed for '" + p.string() + "'"}};
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
      for (int d = 1; d <= 5; ++d) {
        const CellSystem* s = nullptr;
        for (const auto& c : r.cells)
          if (c.cell.rotation_deg == rot && c.cell.distance_m == d) s = find(c, name);
        md << " " << (s ? std::to_string(s->coverage_voxels) : std::string("–")) << " |";  // – : cell not run
      }
      md << "\n";
    }
    md << "\n";
  }
  md << "Mapping error (m), pooled over the " << r.cells.size()
     << " cells (paper Table II layout); with true poses: the same maps with every keyframe at its true pose "
        "(the error perception alone leaves; n/a without a truth stream).\n\n"
        "| System | MAE | RMSE | MAE, true poses | RMSE, true poses |\n|---|---|---|---|---|\n";
  for (const auto& name : names) {
    const Pooled p = pooled_over_cells(r, name);
    md << "| " << name << " | " << opt_fmt("%.3f", p.mae()) << " | " << opt_fmt("%.3f", p.rmse()) << " | "
       << opt_fmt("%.3f", p.truth.mae()) << " | " << opt_fmt("%.3f", p.truth.rmse()) << " |\n";
  }
  md << "\nATE per cell (m), DR / SLAM: ";
  for (const auto& c : r.cells)
    md << fmt("%.0f", c.cell.distance_m) << "m/" << fmt("%.0f", c.cell.rotation_deg) << "° "
       << (c.ate_dr_m ? fmt("%.2f", *c.ate_dr_m) : "n/a") << "/" << (c.ate_slam_m ? fmt("%.2f", *c.ate_slam_m) : "n/a")
       << (&c == &r.cells.back() ? "\n" : "; ");
  md << "\nMission: " << fmt("%.0f", r.stream_s) << " s of sensor data.\n";
  return md.str();
}

std::string sweep_runtime_markdown(const SweepReport& r) {
  std::ostringstream md;
  const auto names = system_names(r);
  md << "## " << r.scene << ": runtime\n";
  md << "\nRuntime in seconds (paper Table III layout; mean and SD).\n\n| Stage | Mean | SD | Count |\n|---|---|---|---|\n";
  auto row = [&](const std::string& label, const mapping::RuntimeStats& s) {
    md << "| " << label << " | " << fmt("%.3g", s.mean_ms() / 1000.0) << " | " << fmt("%.3g", s.sd_ms() / 1000.0)
       << " | " << s.count << " |\n";
  };
  row("Orthogonal sensor fusion (one pair)", r.fusion_runtime);
  if (r.inference_runtime.count > 0) row("Mapping inference (one frame, every pair once)", r.inference_runtime);
  for (const auto& name : names)
    row(name == "submap" ? "Submap construction (per timestep)" : name + " map update", system_runtime(r, name));
  row("SLAM update (per keyframe)", slam_runtime(r));
  md << "\nFusing every pair once took " << fmt("%.1f", r.fuse_wall_s) << " s wall.\n";
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
  csv << "system,distance_m,rotation_deg,coverage_voxels,mae_m,rmse_m,ate_dr_m,ate_slam_m,keyframes,true_pose_mae_m,"
         "true_pose_rmse_m\n";
  auto num = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  for (const auto& c : r.cells)
    for (const auto& s : c.systems) {
      j["cells"].push_back({{"system", s.system}, {"distance_m", c.cell.distance_m},
                            {"rotation_deg", c.cell.rotation_deg}, {"coverage_voxels", s.coverage_voxels},
                            {"mae_m", s.accuracy_count ? nlohmann::json(s.mae_m) : nlohmann::json(nullptr)},
                            {"rmse_m", s.accuracy_count ? nlohmann::json(s.rmse_m) : nlohmann::json(nullptr)},
                            {"true_pose_mae_m", s.true_pose_count ? nlohmann::json(s.true_pose_mae_m) : nlohmann::json(nullptr)},
                            {"true_pose_rmse_m", s.true_pose_count ? nlohmann::json(s.true_pose_rmse_m) : nlohmann::json(nullptr)},
                            {"ate_dr_m", num(c.ate_dr_m)}, {"ate_slam_m", num(c.ate_slam_m)},
                            {"keyframes", c.keyframes}, {"digest", c.digest}});
      csv << s.system << "," << c.cell.distance_m << "," << c.cell.rotation_deg << "," << s.coverage_voxels << ","
          << fmt("%.6f", s.mae_m) << "," << fmt("%.6f", s.rmse_m) << ","
          << (c.ate_dr_m ? fmt("%.6f", *c.ate_dr_m) : "") << "," << (c.ate_slam_m ? fmt("%.6f", *c.ate_slam_m) : "")
          << "," << c.keyframes << "," << (s.true_pose_count ? fmt("%.6f", s.true_pose_mae_m) : "") << ","
          << (s.true_pose_count ? fmt("%.6f", s.true_pose_rmse_m) : "") << "\n";
    }
  // Timings live apart (runtime.json): grid.json is the same bytes on every machine.
  auto stats = [](const mapping::RuntimeStats& s) {
    return nlohmann::json{{"mean_ms", s.mean_ms()}, {"sd_ms", s.sd_ms()}, {"count", s.count}};
  };
  nlohmann::json rt;
  rt["scene"] = r.scene;
  rt["fusion"] = stats(r.fusion_runtime);
  if (r.inference_runtime.count > 0) rt["inference_per_frame"] = stats(r.inference_runtime);
  rt["slam_update"] = stats(slam_runtime(r));
  for (const auto& name : system_names(r)) rt["systems"][name] = stats(system_runtime(r, name));
  rt["fuse_wall_s"] = r.fuse_wall_s;
  const fs::path out(out_dir);
  if (Status s = write_text(out / "grid.json", j.dump(2) + "\n"); !s.ok()) return s;
  if (Status s = write_text(out / "grid.csv", csv.str()); !s.ok()) return s;
  if (Status s = write_text(out / "tables.md", sweep_tables_markdown(r)); !s.ok()) return s;
  if (Status s = write_text(out / "runtime.json", rt.dump(2) + "\n"); !s.ok()) return s;
  return write_text(out / "runtime.md", sweep_runtime_markdown(r));
}

// ---- cell lists, seeds, shard results, sets of sweeps ----

namespace {

std::string trim(std::string t) {
  const auto a = t.find_first_not_of(" \t");
  const auto b = t.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
}

std::vector<std::string> split_commas(const std::string& spec) {
  std::vector<std::string> items;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) items.push_back(trim(item));
  return items;
}

// A whole non-negative number, all of `t`.
std::optional<uint64_t> whole(const std::string& t) {
  if (t.empty() || t.size() > 18 || t.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return std::stoull(t);
}

}  // namespace

Result<std::vector<GridCell>> parse_cells(const std::string& spec) {
  const auto grid = paper_grid();
  if (trim(spec) == "all") return grid;
  std::vector<bool> chosen(grid.size(), false);
  for (const auto& item : split_commas(spec)) {
    const auto slash = item.find('/');
    const auto d = slash == std::string::npos ? std::nullopt : whole(trim(item.substr(0, slash)));
    const auto r = slash == std::string::npos ? std::nullopt : whole(trim(item.substr(slash + 1)));
    bool found = false;
    for (size_t i = 0; d && r && i < grid.size(); ++i)
      if (grid[i].distance_m == static_cast<double>(*d) && grid[i].rotation_deg == static_cast<double>(*r)) {
        chosen[i] = true;
        found = true;
      }
    if (!found)
      return Error{"cells: '" + item +
                   "' is not a cell of the paper grid (DISTANCE/ROTATION with distance 1-5 m and rotation 30, 60 or "
                   "90 deg, e.g. 3/30; or 'all')"};
  }
  std::vector<GridCell> out;
  for (size_t i = 0; i < grid.size(); ++i)
    if (chosen[i]) out.push_back(grid[i]);
  if (out.empty()) return Error{"cells: no cell given (e.g. 'all' or '1/30,3/30')"};
  return out;
}

std::string cell_name(const GridCell& c) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%gm%g", c.distance_m, c.rotation_deg);
  return buf;
}

Result<std::vector<uint64_t>> parse_seeds(const std::string& spec) {
  std::set<uint64_t> seeds;
  for (const auto& item : split_commas(spec)) {
    const auto dash = item.find('-');
    if (dash == std::string::npos) {
      const auto v = whole(item);
      if (!v) return Error{"seeds: '" + item + "' is not a seed (a whole number, or a range such as 1-5)"};
      seeds.insert(*v);
      continue;
    }
    const auto a = whole(trim(item.substr(0, dash)));
    const auto b = whole(trim(item.substr(dash + 1)));
    if (!a || !b || *b < *a) return Error{"seeds: '" + item + "' is not a range FIRST-LAST with FIRST <= LAST"};
    if (*b - *a >= 10000) return Error{"seeds: '" + item + "' spans more than 10000 seeds"};
    for (uint64_t v = *a; v <= *b; ++v) seeds.insert(v);
  }
  if (seeds.empty()) return Error{"seeds: none given (e.g. 1-5)"};
  return std::vector<uint64_t>(seeds.begin(), seeds.end());
}

nlohmann::json runtime_stats_to_json(const mapping::RuntimeStats& s) {
  return {{"count", s.count}, {"sum_ms", s.sum_ms}, {"sum_sq_ms", s.sum_sq_ms}};
}

mapping::RuntimeStats runtime_stats_from_json(const nlohmann::json& j) {
  mapping::RuntimeStats s;
  if (!j.is_object()) return s;
  s.count = j.value("count", int64_t{0});
  s.sum_ms = j.value("sum_ms", 0.0);
  s.sum_sq_ms = j.value("sum_sq_ms", 0.0);
  return s;
}

nlohmann::json cell_result_to_json(const CellResult& c) {
  auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"distance_m", c.cell.distance_m}, {"rotation_deg", c.cell.rotation_deg},
                      {"keyframes", c.keyframes},        {"ate_dr_m", opt(c.ate_dr_m)},
                      {"ate_slam_m", opt(c.ate_slam_m)}, {"slam_runtime", runtime_stats_to_json(c.slam_runtime)},
                      {"digest", c.digest},              {"wall_s", c.wall_s}};
  j["systems"] = nlohmann::json::array();
  for (const auto& s : c.systems)
    j["systems"].push_back({{"system", s.system},
                            {"coverage_voxels", s.coverage_voxels},
                            {"accuracy_count", s.accuracy_count},
                            {"mae_m", s.mae_m},
                            {"rmse_m", s.rmse_m},
                            {"true_pose_count", s.true_pose_count},
                            {"true_pose_mae_m", s.true_pose_mae_m},
                            {"true_pose_rmse_m", s.true_pose_rmse_m},
                            {"runtime", runtime_stats_to_json(s.runtime)}});
  return j;
}

Result<CellResult> cell_result_from_json(const nlohmann::json& j) {
  try {
    CellResult c;
    c.cell.distance_m = j.at("distance_m").get<double>();
    c.cell.rotation_deg = j.at("rotation_deg").get<double>();
    c.keyframes = j.at("keyframes").get<int64_t>();
    if (!j.at("ate_dr_m").is_null()) c.ate_dr_m = j.at("ate_dr_m").get<double>();
    if (!j.at("ate_slam_m").is_null()) c.ate_slam_m = j.at("ate_slam_m").get<double>();
    c.slam_runtime = runtime_stats_from_json(j.value("slam_runtime", nlohmann::json()));
    c.digest = j.at("digest").get<std::string>();
    c.wall_s = j.value("wall_s", 0.0);
    for (const auto& sj : j.at("systems")) {
      CellSystem s;
      s.system = sj.at("system").get<std::string>();
      s.coverage_voxels = sj.at("coverage_voxels").get<int64_t>();
      s.accuracy_count = sj.at("accuracy_count").get<int64_t>();
      s.mae_m = sj.at("mae_m").get<double>();
      s.rmse_m = sj.at("rmse_m").get<double>();
      s.true_pose_count = sj.value("true_pose_count", int64_t{0});  // absent in results before 2026-12-03
      s.true_pose_mae_m = sj.value("true_pose_mae_m", 0.0);
      s.true_pose_rmse_m = sj.value("true_pose_rmse_m", 0.0);
      s.runtime = runtime_stats_from_json(sj.value("runtime", nlohmann::json()));
      c.systems.push_back(std::move(s));
    }
    return c;
  } catch (const std::exception& e) {
    return Error{std::string("cell result: ") + e.what()};
  }
}

std::string sweep_set_dir(const std::string& scene, uint64_t seed) {
  return scene + "/seed" + std::to_string(seed);
}

namespace {

// The seed tables' numbers, computed once for seeds.md and seeds.json: per report (one
// scene and seed) each system pooled over its cells and its ATE ratios, and per scene the
// same pooled over its seeds. Points are added cell by cell in report order, for both.
struct SeedRow {
  std::map<std::string, Pooled> systems;  // the report's systems
  AteStats ate;
};
struct SceneSeeds {
  std::string scene;
  std::vector<std::string> names;  // every system any of its reports has, first seen first
  std::vector<size_t> reports;     // indices, in report order
  std::map<std::string, Pooled> pooled;
  AteStats ate;
};
struct SeedSummary {
  std::vector<SeedRow> rows;      // one per report
  std::vector<SceneSeeds> scenes;  // first seen first
};

SeedSummary summarise_seeds(const std::vector<SweepReport>& reports) {
  SeedSummary out;
  for (size_t k = 0; k < reports.size(); ++k) {
    const auto& r = reports[k];
    auto sc = std::find_if(out.scenes.begin(), out.scenes.end(), [&](const SceneSeeds& x) { return x.scene == r.scene; });
    if (sc == out.scenes.end()) {
      out.scenes.push_back({r.scene, {}, {}, {}, {}});
      sc = std::prev(out.scenes.end());
    }
    sc->reports.push_back(k);
    SeedRow row;
    for (const auto& n : system_names(r)) {
      if (std::find(sc->names.begin(), sc->names.end(), n) == sc->names.end()) sc->names.push_back(n);
      Pooled& p = row.systems[n];
      for (const auto& c : r.cells)
        if (const auto* s = find(c, n)) {
          p.add(*s);
          sc->pooled[n].add(*s);
        }
    }
    for (const auto& c : r.cells) {
      row.ate.add(c);
      sc->ate.add(c);
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

std::string seeds_markdown(const SeedSummary& sum, const std::vector<uint64_t>& seeds) {
  std::ostringstream md;
  md << "# Sweep over seeds\n\nEach system's MAE / RMSE (m) pooled over the cells run, then the same with every "
        "keyframe at its true pose (n/a without a truth stream); ATE: median SLAM/DR ratio and the share of cells "
        "where SLAM ATE <= DR ATE.\n";
  auto cells = [&](const Pooled& p) {
    md << " " << opt_fmt("%.3f", p.mae()) << " | " << opt_fmt("%.3f", p.rmse()) << " | " << opt_fmt("%.3f", p.truth.mae())
       << " / " << opt_fmt("%.3f", p.truth.rmse()) << " |";
  };
  auto ate = [&](const AteStats& a) {
    md << " " << opt_fmt("%.2f", a.median()) << " | " << a.slam_le_dr << "/" << a.cells << " |\n";
  };
  for (const auto& sc : sum.scenes) {
    md << "\n## " << sc.scene << "\n\n| Seed |";
    for (const auto& n : sc.names) md << " " << n << " MAE | " << n << " RMSE | " << n << " true poses |";
    md << " SLAM/DR median | SLAM <= DR |\n|---|";
    for (size_t i = 0; i < sc.names.size(); ++i) md << "---|---|---|";
    md << "---|---|\n";
    for (const size_t k : sc.reports) {
      md << "| " << seeds[k] << " |";
      const auto& row = sum.rows[k];
      for (const auto& n : sc.names) {
        const auto it = row.systems.find(n);
        cells(it == row.systems.end() ? Pooled{} : it->second);
      }
      ate(row.ate);
    }
    md << "| pooled |";
    for (const auto& n : sc.names) {
      const auto it = sc.pooled.find(n);
      cells(it == sc.pooled.end() ? Pooled{} : it->second);
    }
    ate(sc.ate);
  }
  return md.str();
}

nlohmann::json pooled_json(const Pooled& p) {
  return {{"mae_m", opt_json(p.mae())},
          {"rmse_m", opt_json(p.rmse())},
          {"points", p.slam.n},
          {"true_pose_mae_m", opt_json(p.truth.mae())},
          {"true_pose_rmse_m", opt_json(p.truth.rmse())}};
}

nlohmann::json ate_json(const AteStats& a) {
  return {{"median_slam_dr_ratio", opt_json(a.median())}, {"slam_le_dr", a.slam_le_dr}, {"cells", a.cells}};
}

}  // namespace

std::string seeds_markdown(const std::vector<SweepReport>& reports, const std::vector<uint64_t>& seeds) {
  return seeds_markdown(summarise_seeds(reports), seeds);
}

Status write_sweep_set(const std::vector<SweepReport>& reports, const std::vector<uint64_t>& seeds,
                       const std::string& out_dir) {
  namespace fs = std::filesystem;
  if (reports.size() != seeds.size()) return Error{"write_sweep_set: one seed per report expected"};
  const SeedSummary sum = summarise_seeds(reports);
  nlohmann::json j;
  j["sweeps"] = nlohmann::json::array();
  for (size_t k = 0; k < reports.size(); ++k) {
    const auto& r = reports[k];
    const fs::path dir = fs::path(out_dir) / sweep_set_dir(r.scene, seeds[k]);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return Error{"cannot create '" + dir.string() + "': " + ec.message()};
    if (Status s = write_sweep_outputs(r, dir.string()); !s.ok()) return s;
    nlohmann::json e = {{"scene", r.scene}, {"seed", seeds[k]}, {"dir", sweep_set_dir(r.scene, seeds[k])}};
    for (const auto& [n, p] : sum.rows[k].systems) e["systems"][n] = pooled_json(p);
    e["ate"] = ate_json(sum.rows[k].ate);
    j["sweeps"].push_back(e);
  }
  for (const auto& sc : sum.scenes) {
    if (sc.pooled.empty()) continue;  // a scene whose reports have no cells
    for (const auto& [n, p] : sc.pooled) j["pooled"][sc.scene]["systems"][n] = pooled_json(p);
    j["pooled"][sc.scene]["ate"] = ate_json(sc.ate);
  }
  if (Status s = write_text(fs::path(out_dir) / "seeds.json", j.dump(2) + "\n"); !s.ok()) return s;
  return write_text(fs::path(out_dir) / "seeds.md", seeds_markdown(sum, seeds));
}

}  // namespace orthosonar::run
