// The keyframe sweep (replay/run/sweep.hpp): one preparation pass that fuses every pair once,
// the grid's cells run in parallel from it, the cell and seed lists a user gives, and a
// cell's result as JSON (shards). The report it makes is sweep_report.cpp.
#include "replay/run/sweep.hpp"

#include "core/inference/inference_mapping.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/perception/fusion.hpp"
#include "replay/fixture/fixture.hpp"

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
  return [&cache = *prepared.fused](const SonarPing& h, const SonarPing& v) {
    auto r = cache.get(h.stamp, v.stamp);
    return r ? std::move(*r) : perception::FusionResult{};
  };
}

}  // namespace

Result<PreparedSweep> prepare_sweep(const std::string& fixture, const RunOptions& options_in, int threads,
                                    const std::function<void(double)>& progress) {
  auto src = replay::FixtureSource::open(fixture);
  if (!src.ok()) return src.error();
  PreparedSweep p;
  p.metadata = (*src)->metadata();
  p.recovery = (*src)->recovery();
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
  const auto& fcfg = options.config.pipeline.fusion;
  pipeline.set_fusion([&](const SonarPing& h, const SonarPing& v) {
    auto r = perception::fuse_pair(h, v, fcfg);
    p.fused->put(h.stamp, v.stamp, r);
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
    p.events->push_back(std::move(light));
    if (progress && duration_s > 0.0 && (++n % 4096) == 0) progress(p.stream_s / duration_s);
  }
  pipeline.finish();
  p.events->finish();
  for (const auto& [name, s] : pipeline.runtime())
    if (name == "fusion") p.fusion_runtime = s;
  if (std::find(options.systems.begin(), options.systems.end(), "inference_submap") != options.systems.end()) {
    // One inference_submap pass over the stream, fusion from the cache, recording clouds.
    RunOptions once = options;
    once.systems = {"inference_submap"};
    once.config.threads = 1;
    p.inference_cache = std::make_shared<inference::InferenceFrameCache>();
    once.inference_record = p.inference_cache.get();
    SweepEventSource source(*p.events);
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
  SweepEventSource source(*prepared.events);
  options.inference_replay = prepared.inference_cache.get();
  auto r = run_source(source, prepared.metadata, options, prepared.mesh, {}, cached_fusion(prepared));
  if (!r.ok()) return r.error();
  CellResult c;
  c.cell = cell;
  c.keyframes = r->counts.keyframes;
  c.ate_dr_m = r->ate_dr_m;
  c.ate_slam_m = r->ate_slam_m;
  if (r->heading_dr) c.heading_rms_dr_deg = r->heading_dr->rms_deg;
  if (r->heading_slam) c.heading_rms_slam_deg = r->heading_slam->rms_deg;
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

// ---- cell lists, seeds, shard results ----

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
                      {"digest", c.digest},              {"wall_s", c.wall_s},
                      {"heading_rms_dr_deg", opt(c.heading_rms_dr_deg)},
                      {"heading_rms_slam_deg", opt(c.heading_rms_slam_deg)}};
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
    // Absent in results before 2026-12-07.
    for (auto [key, dst] : {std::pair{"heading_rms_dr_deg", &c.heading_rms_dr_deg},
                            std::pair{"heading_rms_slam_deg", &c.heading_rms_slam_deg}})
      if (j.contains(key) && !j.at(key).is_null()) *dst = j.at(key).get<double>();
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

}  // namespace orthosonar::run
