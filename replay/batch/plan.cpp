// Batch planning: the sweep, verify and golden plans, and the manifest (see plan.hpp).
#include "replay/batch/plan.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>

#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"
#include "replay/batch/files.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::batch {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kManifestVersion = 1;

json cells_json(const std::vector<run::GridCell>& cells) {
  json a = json::array();
  for (const auto& c : cells) a.push_back(json::array({c.distance_m, c.rotation_deg}));
  return a;
}

}  // namespace

Result<run::RunOptions> run_options_for(const std::string& systems, const std::string& model) {
  run::RunOptions o;
  // The configuration without a fixture (a fixture's recorded values are layered under the
  // plan's run config when a task opens it).
  auto c = run::effective_config({}, o);
  if (!c.ok()) return c.error();
  o.config = *c;
  o.model_path = model;
  o.systems.clear();
  std::stringstream ss(systems);
  for (std::string name; std::getline(ss, name, ',');)
    if (!name.empty()) o.systems.push_back(name);
  if (o.systems.empty()) return Error{"--systems is empty"};
  return o;
}

Result<Plan> plan_sweep(const SweepPlanSpec& s, const std::string& dir) {
  if (s.scenes.empty()) return Error{"sweep plan: no scene given (--scenes)"};
  for (const auto& scene : s.scenes)
    if (auto sc = sim::builtin_scene(scene, 1); !sc.ok()) return Error{"sweep plan: --scenes: " + sc.error().message};
  if (s.seeds.empty()) return Error{"sweep plan: no seed given (--seeds)"};
  auto cells = run::parse_cells(s.cells);
  if (!cells.ok()) return Error{"sweep plan: --" + cells.error().message};
  if (auto res = sim::parse_resolution(s.resolution); !res.ok()) return Error{"sweep plan: " + res.error().message};
  if (!(s.duration_s > 0.0)) return Error{"sweep plan: --duration must be > 0"};
  if (s.cells_per_task < 0) return Error{"sweep plan: --cells-per-task must be >= 0"};
  {  // the run options must be valid before any task runs
    if (auto o = run_options_for(s.systems, s.model_path); !o.ok()) return Error{"sweep plan: " + o.error().message};
    if (!s.model_path.empty() && !fs::is_regular_file(s.model_path))
      return Error{"sweep plan: --model '" + s.model_path + "' not found"};
  }
  Plan p;
  p.dir = absolute_path(dir);
  p.kind = "sweep";
  p.common = {{"scenes", s.scenes},          {"seeds", s.seeds},
              {"cells", cells_json(*cells)}, {"duration_s", s.duration_s},
              {"resolution", s.resolution},  {"sim_config_yaml", s.sim_config_yaml},
              {"run_config_yaml", s.run_config_yaml}, {"systems", s.systems},
              {"model", s.model_path.empty() ? std::string() : absolute_path(s.model_path)}, {"report", s.report}};
  const size_t per = s.cells_per_task > 0 ? static_cast<size_t>(s.cells_per_task) : cells->size();
  for (const auto& scene : s.scenes)
    for (const uint64_t seed : s.seeds)
      for (size_t first = 0; first < cells->size(); first += per) {
        const size_t last = std::min(cells->size(), first + per);
        std::vector<run::GridCell> chunk(cells->begin() + static_cast<long>(first), cells->begin() + static_cast<long>(last));
        Task t;
        t.index = p.tasks.size();
        t.name = scene + "/seed" + std::to_string(seed);
        if (per < cells->size()) t.name += "/" + run::cell_name(chunk.front()) + "-" + run::cell_name(chunk.back());
        // The first task of a (scene, seed) also replays the reference cell in full (the
        // maps of the report), as the one-machine sweep does.
        t.spec = {{"scene", scene}, {"seed", seed}, {"cells", cells_json(chunk)}, {"reference", s.report && first == 0}};
        p.tasks.push_back(std::move(t));
      }
  return p;
}

namespace {

std::optional<std::string> expected_digest_for(const fs::path& fixture) {
  for (const fs::path& c : {fs::path(fixture).replace_extension(".digest.json"), fs::path(fixture.string() + ".digest.json"),
                            fixture.parent_path() / fixture.stem() / "digest.json"})
    if (fs::is_regular_file(c)) return c.string();
  return std::nullopt;
}

}  // namespace

Result<Plan> plan_verify(const VerifyPlanSpec& s, const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> items;  // fixture, expect
  auto add_fixture = [&](const fs::path& f) -> Status {
    const auto e = expected_digest_for(f);
    if (!e) return Error{"verify plan: no expected digest for '" + f.string() + "' (looked for " +
                         fs::path(f).replace_extension(".digest.json").string() + ", " + f.string() + ".digest.json and " +
                         (f.parent_path() / f.stem() / "digest.json").string() + ")"};
    items.emplace_back(absolute_path(f.string()), absolute_path(*e));
    return {};
  };
  for (const auto& in : s.inputs) {
    const fs::path p(in);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::recursive_directory_iterator(p, ec))
        if (e.is_regular_file() && e.path().extension() == ".mcap") found.push_back(e.path());
      if (ec) return Error{"verify plan: cannot list '" + in + "': " + ec.message()};
      std::sort(found.begin(), found.end());
      if (found.empty()) return Error{"verify plan: no .mcap fixture in '" + in + "'"};
      for (const auto& f : found)
        if (Status st = add_fixture(f); !st.ok()) return st.error();
    } else if (p.extension() == ".mcap") {
      if (!fs::is_regular_file(p, ec)) return Error{"verify plan: fixture '" + in + "' not found"};
      if (Status st = add_fixture(p); !st.ok()) return st.error();
    } else {
      auto text = read_text(in);
      if (!text.ok()) return Error{"verify plan: " + text.error().message};
      std::istringstream lines(*text);
      std::string line;
      for (int n = 1; std::getline(lines, line); ++n) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::string f, e, extra;
        if (!(words >> f)) continue;
        if (!(words >> e) || (words >> extra))
          return Error{"verify plan: " + in + " line " + std::to_string(n) + ": expected 'FIXTURE.mcap EXPECTED.json'"};
        const fs::path base = p.parent_path();
        const fs::path fp = fs::path(f).is_absolute() ? fs::path(f) : base / f;
        const fs::path ep = fs::path(e).is_absolute() ? fs::path(e) : base / e;
        if (!fs::is_regular_file(fp)) return Error{in + " line " + std::to_string(n) + ": fixture '" + fp.string() + "' not found"};
        if (!fs::is_regular_file(ep)) return Error{in + " line " + std::to_string(n) + ": expected digest '" + ep.string() + "' not found"};
        items.emplace_back(absolute_path(fp.string()), absolute_path(ep.string()));
      }
    }
  }
  if (items.empty()) return Error{"verify plan: no fixtures given"};
  Plan p;
  p.dir = absolute_path(dir);
  p.kind = "verify";
  p.common = {{"run_config_yaml", s.run_config_yaml}, {"systems", s.systems}};
  std::set<std::string> names;
  for (const auto& [f, e] : items) {
    Task t;
    t.index = p.tasks.size();
    t.name = fs::path(f).stem().string();
    for (int k = 2; names.count(t.name); ++k) t.name = fs::path(f).stem().string() + "~" + std::to_string(k);
    names.insert(t.name);
    t.spec = {{"fixture", f}, {"expect", e}};
    p.tasks.push_back(std::move(t));
  }
  return p;
}

Result<Plan> plan_golden(const GoldenPlanSpec& s, const std::string& dir) {
  const std::vector<std::string>& paths = s.scenarios;
  if (paths.empty())
    return Error{"golden plan: no scenarios given and none in golden/scenarios/ (run from the repository root)"};
  Plan p;
  p.dir = absolute_path(dir);
  p.kind = "golden";
  p.common = {{"images", s.images}};
  for (const auto& path : paths) {
    if (!fs::is_regular_file(path)) return Error{"golden plan: scenario '" + path + "' not found"};
    Task t;
    t.index = p.tasks.size();
    t.name = fs::path(path).stem().string();
    t.spec = {{"scenario", absolute_path(path)}};
    p.tasks.push_back(std::move(t));
  }
  return p;
}

Status write_plan(const Plan& plan, bool replace) {
  std::error_code ec;
  const fs::path dir(plan.dir);
  json m = {{"orthosonar_batch_plan", kManifestVersion}, {"kind", plan.kind}, {"common", plan.common}};
  m["tasks"] = json::array();
  std::ostringstream list;
  for (const auto& t : plan.tasks) {
    m["tasks"].push_back({{"index", t.index}, {"name", t.name}, {"spec", t.spec}});
    list << t.index << " " << t.name << "\n";
  }
  const std::string text = m.dump(2) + "\n";
  if (fs::exists(dir / "manifest.json")) {
    auto old = read_text((dir / "manifest.json").string());
    if (old.ok() && *old != text && !replace && fs::exists(dir / "results"))
      return Error{"'" + plan.dir + "' already holds another plan with results; use another folder or --replace"};
    if (old.ok() && *old != text) fs::remove_all(dir / "results", ec);  // results of another plan
  }
  for (const char* sub : {"", "results", "logs"}) {
    fs::create_directories(dir / sub, ec);
    if (ec) return Error{"cannot create '" + (dir / sub).string() + "': " + ec.message()};
  }
  if (Status s = write_text(dir / "manifest.json", text); !s.ok()) return s;
  return write_text(dir / "tasks.txt", list.str());
}

Result<Plan> load_plan(const std::string& dir_in) {
  const std::string dir = absolute_path(dir_in);
  const std::string path = (fs::path(dir) / "manifest.json").string();
  if (!fs::exists(path)) return Error{"'" + dir_in + "' is not a batch plan (no manifest.json; write one with `orthosonar batch plan`)"};
  auto j = read_json_file(path);
  if (!j.ok()) return j.error();
  try {
    if (j->at("orthosonar_batch_plan").get<int>() != kManifestVersion)
      return Error{path + ": plan version " + j->at("orthosonar_batch_plan").dump() + " (this orthosonar reads " +
                   std::to_string(kManifestVersion) + ")"};
    Plan p;
    p.dir = dir;
    p.kind = j->at("kind").get<std::string>();
    if (p.kind != "sweep" && p.kind != "verify" && p.kind != "golden") return Error{path + ": unknown kind '" + p.kind + "'"};
    p.common = j->at("common");
    for (const auto& t : j->at("tasks")) {
      Task task;
      task.index = t.at("index").get<size_t>();
      task.name = t.at("name").get<std::string>();
      task.spec = t.at("spec");
      if (task.index != p.tasks.size()) return Error{path + ": task " + std::to_string(p.tasks.size()) + " has index " + std::to_string(task.index)};
      p.tasks.push_back(std::move(task));
    }
    return p;
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

}  // namespace orthosonar::batch
