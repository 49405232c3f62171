// The sweep's report (replay/run/sweep.hpp): the paper's Table II/III layouts and per-cell
// ATE (tables.md, runtime.md), grid.json/grid.csv/runtime.json, and over a set of sweeps the
// seed tables pooled per scene (seeds.md, seeds.json). Running the cells is sweep.cpp.
#include "replay/run/sweep.hpp"
#include "core/slam/trajectory_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

namespace orthosonar::run {

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
    if (slam::slam_no_worse_than_dr(*c.ate_slam_m, *c.ate_dr_m)) ++slam_le_dr;
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

nlohmann::json sweep_opt_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
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
  if (!r.input_cut.empty()) md << "**INPUT CUT SHORT:** " << r.input_cut << ". These figures cover what was recovered.\n\n";
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
  // One line of DR / SLAM figures, cell by cell.
  using CellFigure = std::optional<double> CellResult::*;
  const auto per_cell = [&](const char* title, CellFigure dr, CellFigure slam) {
    md << title;
    for (const auto& c : r.cells)
      md << fmt("%.0f", c.cell.distance_m) << "m/" << fmt("%.0f", c.cell.rotation_deg) << "° "
         << opt_fmt("%.2f", c.*dr) << "/" << opt_fmt("%.2f", c.*slam) << (&c == &r.cells.back() ? "\n" : "; ");
  };
  per_cell("\nATE per cell (m), DR / SLAM: ", &CellResult::ate_dr_m, &CellResult::ate_slam_m);
  if (std::any_of(r.cells.begin(), r.cells.end(), [](const CellResult& c) { return c.heading_rms_slam_deg.has_value(); }))
    per_cell("\nKeyframe heading error per cell (°, RMS against truth), DR / SLAM: ", &CellResult::heading_rms_dr_deg,
             &CellResult::heading_rms_slam_deg);
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
  if (!r.input_cut.empty()) j["input_cut"] = r.input_cut;
  j["cells"] = nlohmann::json::array();
  std::ostringstream csv;
  csv << "system,distance_m,rotation_deg,coverage_voxels,mae_m,rmse_m,ate_dr_m,ate_slam_m,keyframes,true_pose_mae_m,"
         "true_pose_rmse_m,heading_rms_dr_deg,heading_rms_slam_deg\n";
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
                            {"heading_rms_dr_deg", num(c.heading_rms_dr_deg)},
                            {"heading_rms_slam_deg", num(c.heading_rms_slam_deg)},
                            {"keyframes", c.keyframes}, {"digest", c.digest}});
      csv << s.system << "," << c.cell.distance_m << "," << c.cell.rotation_deg << "," << s.coverage_voxels << ","
          << fmt("%.6f", s.mae_m) << "," << fmt("%.6f", s.rmse_m) << ","
          << (c.ate_dr_m ? fmt("%.6f", *c.ate_dr_m) : "") << "," << (c.ate_slam_m ? fmt("%.6f", *c.ate_slam_m) : "")
          << "," << c.keyframes << "," << (s.true_pose_count ? fmt("%.6f", s.true_pose_mae_m) : "") << ","
          << (s.true_pose_count ? fmt("%.6f", s.true_pose_rmse_m) : "") << ","
          << (c.heading_rms_dr_deg ? fmt("%.6f", *c.heading_rms_dr_deg) : "") << ","
          << (c.heading_rms_slam_deg ? fmt("%.6f", *c.heading_rms_slam_deg) : "") << "\n";
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
  return {{"mae_m", sweep_opt_json(p.mae())},
          {"rmse_m", sweep_opt_json(p.rmse())},
          {"points", p.slam.n},
          {"true_pose_mae_m", sweep_opt_json(p.truth.mae())},
          {"true_pose_rmse_m", sweep_opt_json(p.truth.rmse())}};
}

nlohmann::json ate_json(const AteStats& a) {
  return {{"median_slam_dr_ratio", sweep_opt_json(a.median())}, {"slam_le_dr", a.slam_le_dr}, {"cells", a.cells}};
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
