#include "reports/run_data.hpp"

#include "reports/report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hal/sim/mesh_io.hpp"
#include "replay/outputs/map_writers.hpp"

namespace orthosonar::reports {
namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<std::string>& system_names() {
  static const std::vector<std::string> names = {"fusion", "submap", "inference", "inference_submap"};
  return names;
}

Result<Trajectory> read_tum(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"TUM '" + path + "': cannot open"};
  Trajectory out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    TumPose p;
    ls >> p.t_s >> p.position.x() >> p.position.y() >> p.position.z() >> p.q_xyzw[0] >> p.q_xyzw[1] >>
        p.q_xyzw[2] >> p.q_xyzw[3];
    if (!ls) return Error{"TUM '" + path + "': line " + std::to_string(line_no) + " needs 8 numbers"};
    out.push_back(p);
  }
  return out;
}

Status write_tum(const std::string& path, const Trajectory& poses) {
  std::ofstream out(path);
  if (!out) return Error{"TUM '" + path + "': cannot create"};
  char buf[256];
  for (const auto& p : poses) {
    std::snprintf(buf, sizeof buf, "%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", p.t_s, p.position.x(),
                  p.position.y(), p.position.z(), p.q_xyzw[0], p.q_xyzw[1], p.q_xyzw[2], p.q_xyzw[3]);
    out << buf;
  }
  if (!out) return Error{"TUM '" + path + "': write failed"};
  return Status::Ok();
}

namespace {

Result<json> read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return Error{"JSON '" + path.string() + "': cannot open"};
  json j = json::parse(in, nullptr, false);
  if (j.is_discarded()) return Error{"JSON '" + path.string() + "': parse error"};
  return j;
}

// A missing or null number (e.g. MAE without a ground-truth mesh) reads as NaN, shown "n/a".
double num(const json& j, const char* key) {
  const auto it = j.find(key);
  return (it != j.end() && it->is_number()) ? it->get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::string scalar_text(const json& j) {
  if (j.is_string()) return j.get<std::string>();
  return j.dump();
}

// "a": {"b": 1} -> ("a.b", "1"); arrays of scalars stay one value. json objects iterate
// in key order, so the result is deterministic.
void flatten(const json& j, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      flatten(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), out);
  } else {
    out.emplace_back(prefix, scalar_text(j));
  }
}

std::optional<Trajectory> optional_tum(const fs::path& p, std::vector<std::string>& notes) {
  if (!fs::exists(p)) {
    notes.push_back(p.filename().string() + " not found");
    return std::nullopt;
  }
  auto t = read_tum(p.string());
  if (!t) {
    notes.push_back(t.error().message);
    return std::nullopt;
  }
  return std::move(t.value());
}

}  // namespace

Result<Grid> read_grid(const std::string& path) {
  auto j = read_json(path);
  if (!j) return j.error();
  Grid g;
  if (j->contains("scene") && (*j)["scene"].is_string()) g.scene = (*j)["scene"].get<std::string>();
  if (!j->contains("cells") || !(*j)["cells"].is_array()) return Error{"grid '" + path + "': no 'cells' array"};
  for (const auto& c : (*j)["cells"]) {
    if (!c.is_object() || !c.contains("system") || !c["system"].is_string())
      return Error{"grid '" + path + "': a cell lacks 'system'"};
    GridCell cell;
    cell.system = c["system"].get<std::string>();
    cell.distance_m = num(c, "distance_m");
    cell.rotation_deg = num(c, "rotation_deg");
    cell.coverage_voxels = num(c, "coverage_voxels");
    cell.mae_m = num(c, "mae_m");
    cell.rmse_m = num(c, "rmse_m");
    cell.ate_slam_m = num(c, "ate_slam_m");
    g.cells.push_back(cell);
  }
  return g;
}

std::optional<std::string> run_input_cut(const std::string& run_dir) {
  auto j = read_json(fs::path(run_dir) / "summary.json");
  if (!j || !j->is_object() || !j->contains("input")) return std::nullopt;
  const json& in = (*j)["input"];
  if (!in.is_object() || in.value("complete", true)) return std::nullopt;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.3f", in.value("sensor_s_recovered", 0.0));
  return "input " + in.value("path", std::string("(unnamed)")) + " was cut at byte offset " +
         std::to_string(in.value("cut_at_byte", uint64_t{0})) + " of " + std::to_string(in.value("bytes_total", uint64_t{0})) +
         " bytes: the run covers only the " + seconds + " s of sensor time and " +
         std::to_string(in.value("messages_recovered", uint64_t{0})) + " messages recovered";
}

Result<RunData> load_run(const std::string& dir) {
  const fs::path root(dir);
  if (!fs::is_directory(root)) return Error{"run directory '" + dir + "' does not exist"};
  RunData run;
  run.dir = dir;
  run.truth = optional_tum(root / "traj_truth.tum", run.notes);
  run.dr = optional_tum(root / "traj_dr.tum", run.notes);
  run.slam = optional_tum(root / "traj_slam.tum", run.notes);
  if (fs::exists(root / "scene_mesh.ply")) {
    auto m = sim::read_mesh_ply((root / "scene_mesh.ply").string());
    if (m) run.mesh = std::move(m.value());
    else run.notes.push_back(m.error().message);
  } else {
    run.notes.push_back("scene_mesh.ply not found (no ground-truth overlay)");
  }
  for (const auto& name : system_names()) {
    const fs::path sdir = root / name;
    if (!fs::is_directory(sdir)) continue;
    SystemOutput s;
    s.name = name;
    if (fs::exists(sdir / "map.ply")) {
      auto pts = outputs::read_cloud((sdir / "map.ply").string());
      if (pts) {
        s.map_W = std::move(pts.value());
        s.has_map = true;
      } else {
        run.notes.push_back(pts.error().message);
      }
    } else {
      run.notes.push_back(name + "/map.ply not found");
    }
    if (fs::exists(sdir / "metrics.json")) {
      auto j = read_json(sdir / "metrics.json");
      if (j) {
        s.has_metrics = true;
        s.coverage_voxels = num(*j, "coverage_voxels");
        s.mae_m = num(*j, "mae_m");
        s.rmse_m = num(*j, "rmse_m");
        s.ate_dr_m = num(*j, "ate_dr_m");
        s.ate_slam_m = num(*j, "ate_slam_m");
        if (j->contains("runtime") && (*j)["runtime"].is_object())
          for (auto it = (*j)["runtime"].begin(); it != (*j)["runtime"].end(); ++it)
            s.runtime.push_back({it.key(), num(it.value(), "mean_ms"), num(it.value(), "sd_ms"), num(it.value(), "count")});
        if (j->contains("counts")) flatten((*j)["counts"], "", s.counts);
      } else {
        run.notes.push_back(j.error().message);
      }
    }
    run.systems.push_back(std::move(s));
  }
  if (fs::exists(root / "summary.json")) {
    auto j = read_json(root / "summary.json");
    if (j) {
      flatten(*j, "", run.summary);
      if (auto cut = run_input_cut(dir)) run.input_cut = *cut;
      for (const auto& [k, v] : run.summary) {
        const auto leaf = k.substr(k.find_last_of('.') == std::string::npos ? 0 : k.find_last_of('.') + 1);
        if (leaf == "software_version" && run.software_version.empty()) run.software_version = v;
        if (leaf == "scene" && run.scene.empty()) run.scene = v;
      }
    } else {
      run.notes.push_back(j.error().message);
    }
  } else {
    run.notes.push_back("summary.json not found");
  }
  if (fs::exists(root / "digest.json")) {
    auto j = read_json(root / "digest.json");
    if (j) {
      if (j->contains("overall")) run.digest_overall = scalar_text((*j)["overall"]);
      if (j->contains("outputs")) flatten((*j)["outputs"], "", run.digest_outputs);
    } else {
      run.notes.push_back(j.error().message);
    }
  } else {
    run.notes.push_back("digest.json not found");
  }
  if (fs::exists(root / "grid.json")) {
    auto g = read_grid((root / "grid.json").string());
    if (g) {
      if (run.scene.empty()) run.scene = g->scene;
      run.grid = std::move(g.value());
    } else {
      run.notes.push_back(g.error().message);
    }
  }
  if (fs::exists(root / "ping_pair")) {
    auto pp = outputs::read_ping_pair((root / "ping_pair").string());
    if (pp) run.ping_pair = std::move(pp.value());
    else run.notes.push_back(pp.error().message);
  }
  const bool anything = run.truth || run.dr || run.slam || run.mesh || !run.systems.empty() ||
                        !run.summary.empty() || run.grid || !run.digest_overall.empty();
  if (!anything) return Error{"run directory '" + dir + "' holds no outputs the report understands"};
  return run;
}

}  // namespace orthosonar::reports
