#include "tools/support_batch.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "hal/sim/scene.hpp"
#include "reports/html.hpp"
#include "replay/digest.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/sweep.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_golden_images.hpp"
#include "tools/support_process.hpp"
#include "tools/support_run_args.hpp"
#include "tools/support_sweep_report.hpp"

namespace orthosonar::cli::batch {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kManifestVersion = 1;

std::string absolute(const std::string& p) {
  std::error_code ec;
  const auto a = fs::absolute(p, ec);
  return (ec ? fs::path(p) : a).lexically_normal().string();
}

}  // namespace

Result<std::string> read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{"cannot open '" + path + "'"};
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

namespace {

Status write_text(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::trunc | std::ios::binary);
  if (!f) return Error{"cannot open '" + path.string() + "' for writing"};
  f << text;
  f.close();
  return f ? Status{} : Status{Error{"write failed for '" + path.string() + "'"}};
}

Result<json> read_json_file(const std::string& path) {
  auto text = read_text(path);
  if (!text.ok()) return text.error();
  try {
    return json::parse(*text);
  } catch (const std::exception& e) {
    return Error{path + ": not valid JSON: " + e.what()};
  }
}

std::string utc_now() {
  const auto t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char buf[32];
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string host_name() {
  char buf[256] = {};
  ::gethostname(buf, sizeof buf - 1);
  return buf;
}

std::string sha256_text(const std::string& s) {
  return replay::sha256_hex(reinterpret_cast<const uint8_t*>(s.data()), s.size());
}

// ---- sweep ----

json cells_json(const std::vector<run::GridCell>& cells) {
  json a = json::array();
  for (const auto& c : cells) a.push_back(json::array({c.distance_m, c.rotation_deg}));
  return a;
}

std::vector<run::GridCell> cells_from_json(const json& a) {
  std::vector<run::GridCell> out;
  for (const auto& c : a) out.push_back({c.at(0).get<double>(), c.at(1).get<double>()});
  return out;
}

std::string sweep_fixture(const Plan& plan, const json& spec) {
  return (fs::path(plan.dir) / "fixtures" /
          (spec.at("scene").get<std::string>() + "-seed" + std::to_string(spec.at("seed").get<uint64_t>()) + ".mcap"))
      .string();
}

Result<run::RunOptions> options_from_common(const json& common) {
  CommonRunArgs args;
  args.systems = common.value("systems", std::string("fusion,submap"));
  args.model_path = common.value("model", std::string());
  auto options = run_options_from(args);
  if (!options.ok()) return options.error();
  options->config_yaml = common.value("run_config_yaml", std::string());
  options->config_origin = "the plan's run config";
  return options;
}

Status run_sweep_task(const Plan& plan, const Task& task, int threads, const std::string& out, json& result) {
  const json& spec = task.spec;
  run::MissionSpec mission;
  mission.scene = spec.at("scene").get<std::string>();
  mission.seed = spec.at("seed").get<uint64_t>();
  mission.duration_s = plan.common.at("duration_s").get<double>();
  auto res = sim::parse_resolution(plan.common.at("resolution").get<std::string>());
  if (!res.ok()) return res.error();
  mission.resolution = *res;
  mission.render_threads = threads;
  mission.sim_config_yaml = plan.common.value("sim_config_yaml", std::string());
  const std::string fixture = sweep_fixture(plan, spec);
  auto made = run::ensure_mission_fixture(mission, fixture);
  if (!made.ok()) return Error{"simulating " + fixture + ": " + made.error().message};
  std::cerr << "batch: " << (*made ? "simulated " : "reusing ") << fixture << "\n";
  auto options = options_from_common(plan.common);
  if (!options.ok()) return options.error();
  auto prepared = run::prepare_sweep(fixture, *options, threads, {});
  if (!prepared.ok()) return prepared.error();
  // A cut input is recorded with the result; merge names the task (issue 40).
  if (auto cut = replay::cut_input_warning(fixture, prepared->recovery)) result["input_cut"] = *cut;
  const auto cells = cells_from_json(spec.at("cells"));
  auto done = run::run_cells(*prepared, *options, cells, threads, [&](size_t d, size_t n) {
    std::cerr << "batch: " << task.name << ": cell " << d << "/" << n << "\n";
  });
  if (!done.ok()) return done.error();
  result["metadata"] = prepared->metadata;
  result["stream_s"] = prepared->stream_s;
  result["fuse_wall_s"] = prepared->fuse_wall_s;
  result["fusion_runtime"] = run::runtime_stats_to_json(prepared->fusion_runtime);
  result["inference_runtime"] = run::runtime_stats_to_json(prepared->inference_runtime);
  result["cells"] = json::array();
  for (const auto& c : *done) result["cells"].push_back(run::cell_result_to_json(c));
  if (spec.value("reference", false)) {
    if (Status s = write_reference_outputs(fixture, *options, threads, (fs::path(out) / "reference").string()); !s.ok())
      return Error{"reference cell: " + s.error().message};
  }
  return {};
}

// ---- verify ----

Status run_verify_task(const Plan& plan, const Task& task, int threads, const std::string& out, json& result) {
  const std::string fixture = task.spec.at("fixture").get<std::string>();
  const std::string expect = task.spec.at("expect").get<std::string>();
  auto expected = replay::read_digest_json(expect);
  if (!expected.ok()) return expected.error();
  json common = plan.common;
  if (common.value("systems", std::string()).empty()) {
    std::set<std::string> names;
    for (const auto& [k, v] : expected->outputs)
      if (const auto slash = k.find('/'); slash != std::string::npos) names.insert(k.substr(0, slash));
    std::string systems;
    for (const auto& n : names) systems += (systems.empty() ? "" : ",") + n;
    common["systems"] = systems.empty() ? "fusion,submap" : systems;
  }
  auto options = options_from_common(common);
  if (!options.ok()) return options.error();
  options->threads_override = threads;
  std::string warning;
  auto r = run::run_fixture(fixture, *options, {}, &warning);
  if (!r.ok()) return r.error();
  if (!warning.empty()) result["warning"] = warning;
  if (!r->input_recovery.complete) result["input_cut"] = warning;
  const auto diff = replay::differing_outputs(*expected, r->digest);
  const bool same = diff.empty() && expected->overall_hex == r->digest.overall_hex;
  result["passed"] = same;
  result["expected"] = expected->overall_hex;
  result["got"] = r->digest.overall_hex;
  std::ostringstream msg;
  if (!same) {
    msg << "expected " << expected->overall_hex << ", got " << r->digest.overall_hex << "\n";
    for (const auto& name : diff) {
      const auto e = expected->outputs.find(name);
      const auto g = r->digest.outputs.find(name);
      msg << "  " << name << ": expected " << (e == expected->outputs.end() ? "(absent)" : e->second) << ", got "
          << (g == r->digest.outputs.end() ? "(absent)" : g->second) << "\n";
    }
    if (diff.empty()) msg << "  (per-output hashes agree; the overall hash differs)\n";
  }
  result["differing_outputs"] = diff;
  result["message"] = msg.str();
  return replay::write_digest_json((fs::path(out) / "digest.json").string(), r->digest);
}

// ---- golden: `orthosonar golden --check` in a child process (its own output, verdict) ----

Status run_golden_task(const Plan& plan, const Task& task, int threads, const std::string& out, json& result) {
  std::vector<std::string> argv = {self_executable(), "golden", "--check", task.spec.at("scenario").get<std::string>(),
                                   "--threads", std::to_string(threads), "-o", (fs::path(out) / "runs").string()};
  if (!plan.common.value("images", true)) argv.push_back("--no-images");
  auto c = run_captured(argv);
  if (!c.ok()) return c.error();
  if (Status s = write_text(fs::path(out) / "golden.log", c->out); !s.ok()) return s;
  if (c->exit_code != 0 && c->exit_code != 1)
    return Error{"golden --check exited " + std::to_string(c->exit_code) + ": " + c->out};
  result["passed"] = c->exit_code == 0;
  result["message"] = c->out;
  return {};
}

std::string plan_files_note(const Plan& plan) { return "plan " + plan.dir; }

}  // namespace

// ---------------------------------------------------------------- planning

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
    CommonRunArgs args;
    args.systems = s.systems;
    args.model_path = s.model_path;
    if (auto o = run_options_from(args); !o.ok()) return Error{"sweep plan: " + o.error().message};
    if (!s.model_path.empty() && !fs::is_regular_file(s.model_path))
      return Error{"sweep plan: --model '" + s.model_path + "' not found"};
  }
  Plan p;
  p.dir = absolute(dir);
  p.kind = "sweep";
  p.common = {{"scenes", s.scenes},          {"seeds", s.seeds},
              {"cells", cells_json(*cells)}, {"duration_s", s.duration_s},
              {"resolution", s.resolution},  {"sim_config_yaml", s.sim_config_yaml},
              {"run_config_yaml", s.run_config_yaml}, {"systems", s.systems},
              {"model", s.model_path.empty() ? std::string() : absolute(s.model_path)}, {"report", s.report}};
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
    items.emplace_back(absolute(f.string()), absolute(*e));
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
        items.emplace_back(absolute(fp.string()), absolute(ep.string()));
      }
    }
  }
  if (items.empty()) return Error{"verify plan: no fixtures given"};
  Plan p;
  p.dir = absolute(dir);
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
  const std::vector<std::string> paths = s.scenarios.empty() ? default_golden_scenarios() : s.scenarios;
  if (paths.empty())
    return Error{"golden plan: no scenarios given and none in golden/scenarios/ (run from the repository root)"};
  Plan p;
  p.dir = absolute(dir);
  p.kind = "golden";
  p.common = {{"images", s.images}};
  for (const auto& path : paths) {
    if (!fs::is_regular_file(path)) return Error{"golden plan: scenario '" + path + "' not found"};
    Task t;
    t.index = p.tasks.size();
    t.name = fs::path(path).stem().string();
    t.spec = {{"scenario", absolute(path)}};
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
  const std::string dir = absolute(dir_in);
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

// ---------------------------------------------------------------- running

Result<size_t> task_index(const Plan& plan, std::optional<long> given) {
  long index = -1;
  std::string from;
  if (given) {
    index = *given;
    from = "--task";
  } else {
    for (const char* var : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
      const char* v = std::getenv(var);
      if (!v || !*v) continue;
      char* end = nullptr;
      index = std::strtol(v, &end, 10);
      if (*end != '\0') return Error{std::string("$") + var + " is '" + v + "', not a task index"};
      from = std::string("$") + var;
      break;
    }
    if (from.empty()) return Error{"no task index: give --task I, or run as a Slurm array task ($SLURM_ARRAY_TASK_ID) or a Kubernetes Indexed Job ($JOB_COMPLETION_INDEX)"};
  }
  if (index < 0 || static_cast<size_t>(index) >= plan.tasks.size())
    return Error{from + " = " + std::to_string(index) + ": the plan has tasks 0.." + std::to_string(plan.tasks.size()) + "-1"};
  return static_cast<size_t>(index);
}

std::string result_dir(const Plan& plan, size_t index) {
  return (fs::path(plan.dir) / "results" / std::to_string(index)).string();
}

std::string log_path(const Plan& plan, size_t index) {
  return (fs::path(plan.dir) / "logs" / ("task-" + std::to_string(index) + ".log")).string();
}

const std::string& executable_digest() {
  static const std::string digest = [] {
    auto d = replay::sha256_file_hex(self_executable());
    return d.ok() ? *d : std::string("unknown");
  }();
  return digest;
}

Result<std::string> task_key(const Plan& plan, const Task& task, const json* known, json* inputs) {
  json k = {{"kind", plan.kind}, {"common", plan.common}, {"task", task.spec}, {"orthosonar", executable_digest()}};
  // The bytes of every input file, not its name: an edited fixture or scenario is new work.
  auto add_file = [&](const std::string& label, const std::string& path) -> Status {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) return Error{"cannot read '" + path + "': " + ec.message()};
    const auto mtime = static_cast<int64_t>(fs::last_write_time(path, ec).time_since_epoch().count());
    std::string digest;
    if (known && known->is_object() && known->contains(label)) {
      const json& r = (*known)[label];
      if (r.value("path", std::string()) == path && r.value("size", uint64_t{0}) == size &&
          r.value("mtime_ns", int64_t{0}) == mtime)
        digest = r.value("sha256", std::string());
    }
    if (digest.empty()) {
      auto d = replay::sha256_file_hex(path);
      if (!d.ok()) return d.error();
      digest = *d;
    }
    k["inputs"][label] = digest;
    if (inputs) (*inputs)[label] = {{"path", path}, {"size", size}, {"mtime_ns", mtime}, {"sha256", digest}};
    return {};
  };
  if (plan.kind == "verify") {
    if (Status s = add_file("fixture", task.spec.at("fixture").get<std::string>()); !s.ok()) return s.error();
    if (Status s = add_file("expect", task.spec.at("expect").get<std::string>()); !s.ok()) return s.error();
  } else if (plan.kind == "golden") {
    const std::string scenario = task.spec.at("scenario").get<std::string>();
    if (Status s = add_file("scenario", scenario); !s.ok()) return s.error();
    // Its stored images: <dir>/<name>/*.png
    std::error_code ec;
    std::vector<fs::path> pngs;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(scenario).parent_path() / fs::path(scenario).stem(), ec))
      if (e.is_regular_file() && e.path().extension() == ".png") pngs.push_back(e.path());
    std::sort(pngs.begin(), pngs.end());
    for (const auto& png : pngs)
      if (Status s = add_file("image:" + png.filename().string(), png.string()); !s.ok()) return s.error();
  }
  if (const std::string model = plan.common.value("model", std::string()); !model.empty())
    if (Status s = add_file("model", model); !s.ok()) return s.error();
  // Sweep fixtures are simulated from the spec by this executable: the spec and the
  // executable's digest determine them.
  return sha256_text(k.dump());
}

int run_task(const Plan& plan, size_t index, const RunTaskOptions& o) {
  const Task& task = plan.tasks.at(index);
  const std::string label = "task " + std::to_string(index) + " (" + task.name + ")";
  const fs::path dir = result_dir(plan, index);
  std::error_code ec;
  json earlier;  // the result of an earlier run, if any
  if (auto old = read_json_file((dir / "result.json").string()); old.ok() && old->is_object()) earlier = std::move(*old);
  const json old_inputs = earlier.is_object() ? earlier.value("inputs", json()) : json();
  json inputs = json::object();
  auto key = task_key(plan, task, &old_inputs, &inputs);
  auto fail = [&](const std::string& message) {
    std::cerr << "orthosonar batch run: " << label << ": " << message << "\n";
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    const json f = {{"task", index},       {"name", task.name}, {"error", message}, {"attempt", o.attempt},
                    {"host", host_name()}, {"at", utc_now()},   {"key", key.ok() ? *key : std::string()}};
    (void)write_text(dir / "failed.json", f.dump(2) + "\n");
    return 2;
  };
  if (!key.ok()) return fail(key.error().message);
  if (!o.force && earlier.is_object() && earlier.value("key", std::string()) == *key) {
    std::cerr << "batch: " << label << ": result is current (same inputs), skipped\n";
    return 0;
  }
  std::cerr << "batch: " << label << ": attempt " << o.attempt << " on " << host_name() << ", " << o.threads
            << " thread(s)\n";
  // Written beside the final folder and renamed when complete: a killed task leaves no
  // half result that could be merged.
  const fs::path tmp = dir.string() + ".partial." + std::to_string(::getpid());
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp, ec);
  if (ec) return fail("cannot create '" + tmp.string() + "': " + ec.message());
  json result = {{"task", index}, {"name", task.name}, {"kind", plan.kind}, {"key", *key}, {"inputs", inputs}};
  const auto t0 = std::chrono::steady_clock::now();
  Status st;
  try {
    if (plan.kind == "sweep") st = run_sweep_task(plan, task, o.threads, tmp.string(), result);
    else if (plan.kind == "verify") st = run_verify_task(plan, task, o.threads, tmp.string(), result);
    else st = run_golden_task(plan, task, o.threads, tmp.string(), result);
  } catch (const std::exception& e) {
    st = Error{std::string("exception: ") + e.what()};
  }
  if (!st.ok()) {
    fs::remove_all(tmp, ec);
    return fail(st.error().message);
  }
  result["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result["attempt"] = o.attempt;
  result["host"] = host_name();
  result["finished_at"] = utc_now();
  if (Status s = write_text(tmp / "result.json", result.dump(2) + "\n"); !s.ok()) return fail(s.error().message);
  fs::remove_all(dir, ec);
  fs::rename(tmp, dir, ec);
  if (ec) return fail("cannot rename '" + tmp.string() + "' to '" + dir.string() + "': " + ec.message());
  std::cerr << "batch: " << label << ": done in " << result["wall_s"].get<double>() << " s\n";
  return 0;
}

// ---------------------------------------------------------------- state, merge

std::string state_name(TaskState s) {
  switch (s) {
    case TaskState::kDone: return "done";
    case TaskState::kFailed: return "failed";
    case TaskState::kStale: return "stale";
    case TaskState::kMissing: break;
  }
  return "missing";
}

TaskStatus task_status(const Plan& plan, const Task& task, bool check_keys) {
  const fs::path dir = result_dir(plan, task.index);
  if (fs::exists(dir / "result.json")) {
    auto r = read_json_file((dir / "result.json").string());
    if (!r.ok()) return {TaskState::kMissing, r.error().message};
    if (check_keys) {
      const json known = r->value("inputs", json());
      auto key = task_key(plan, task, &known);
      if (!key.ok()) return {TaskState::kStale, "cannot compute its key: " + key.error().message};
      if (r->value("key", std::string()) != *key)
        return {TaskState::kStale, "the result was made from other inputs or another orthosonar build"};
    }
    return {TaskState::kDone, ""};
  }
  if (fs::exists(dir / "failed.json")) {
    auto f = read_json_file((dir / "failed.json").string());
    if (f.ok())
      return {TaskState::kFailed, f->value("error", std::string("?")) + " (attempt " +
                                      std::to_string(f->value("attempt", 0)) + " on " + f->value("host", std::string("?")) + ")"};
    return {TaskState::kFailed, f.error().message};
  }
  return {TaskState::kMissing, "no result"};
}

std::string xml_escape(const std::string& s) {
  // XML 1.0 allows tab, newline, carriage return and nothing else below 0x20; the five
  // markup characters are escaped as for HTML (&#39; is XML's too).
  std::string text = s;
  for (char& ch : text)
    if (static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\n' && ch != '\r') ch = '?';
  return reports::html_escape(text);
}

namespace {

struct Gathered {
  std::vector<std::optional<json>> results;  // per task, when done and current
  std::vector<std::string> problems;         // one line per missing/failed/stale task
};

Gathered gather(const Plan& plan) {
  Gathered g;
  for (const auto& t : plan.tasks) {
    TaskStatus st = task_status(plan, t, true);
    if (st.state == TaskState::kDone) {
      auto r = read_json_file((fs::path(result_dir(plan, t.index)) / "result.json").string());
      if (r.ok()) {
        g.results.push_back(std::move(*r));
        continue;
      }
      st = {TaskState::kMissing, r.error().message};  // removed or rewritten meanwhile
    }
    g.results.push_back(std::nullopt);
    g.problems.push_back("task " + std::to_string(t.index) + " (" + t.name + "): " + state_name(st.state) + ": " +
                         st.detail + "; log " + log_path(plan, t.index));
  }
  return g;
}

// The tasks whose inputs were cut short (a result's "input_cut"), named on stderr and
// noted as cut inputs: merge exits 1 for them unless --allow-incomplete (issue 40).
json note_cut_tasks(const Plan& plan, const Gathered& g) {
  json named = json::array();
  for (const auto& t : plan.tasks) {
    const auto& r = g.results[t.index];
    if (!r || !r->contains("input_cut")) continue;
    const std::string why = r->value("input_cut", std::string());
    named.push_back({{"index", t.index}, {"name", t.name}, {"input_cut", why}});
    note_cut_input_warning("batch task " + std::to_string(t.index) + " (" + t.name + "): " + why);
  }
  return named;
}

void report_problems(const Plan& plan, const Gathered& g) {
  std::cerr << "orthosonar batch merge: " << g.problems.size() << " of " << plan.tasks.size()
            << " task results missing (" << plan_files_note(plan) << "):\n";
  for (const auto& p : g.problems) std::cerr << "  " << p << "\n";
  std::cerr << "re-run them (a re-submitted plan skips the tasks already done), then merge again\n";
}

Status copy_tree(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_directories(to, ec);
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::overwrite_existing, ec);
  if (ec) return Error{"cannot copy '" + from.string() + "' to '" + to.string() + "': " + ec.message()};
  return {};
}

int merge_sweep(const Plan& plan, const Gathered& g, const fs::path& out) {
  if (!g.problems.empty()) {
    report_problems(plan, g);
    return 2;
  }
  note_cut_tasks(plan, g);
  // One report per (scene, seed), in the plan's order; cells in task order = grid order.
  std::vector<run::SweepReport> reports;
  std::vector<uint64_t> seeds;
  std::vector<std::optional<size_t>> reference_task;
  std::map<std::pair<std::string, uint64_t>, size_t> slot;
  for (const auto& t : plan.tasks) {
    const auto key = std::make_pair(t.spec.at("scene").get<std::string>(), t.spec.at("seed").get<uint64_t>());
    const json& r = *g.results[t.index];
    auto [it, fresh] = slot.emplace(key, reports.size());
    if (fresh) {
      run::SweepReport rep;
      rep.metadata = r.at("metadata").get<std::map<std::string, std::string>>();
      const auto sc = rep.metadata.find("scene");
      rep.scene = sc == rep.metadata.end() ? "?" : sc->second;
      rep.fusion_runtime = run::runtime_stats_from_json(r.at("fusion_runtime"));
      rep.inference_runtime = run::runtime_stats_from_json(r.at("inference_runtime"));
      rep.stream_s = r.at("stream_s").get<double>();
      rep.fuse_wall_s = r.at("fuse_wall_s").get<double>();
      rep.input_cut = r.value("input_cut", std::string());
      reports.push_back(std::move(rep));
      seeds.push_back(key.second);
      reference_task.push_back(std::nullopt);
    }
    for (const auto& c : r.at("cells")) {
      auto cell = run::cell_result_from_json(c);
      if (!cell.ok()) {
        std::cerr << "orthosonar batch merge: " << result_dir(plan, t.index) << "/result.json: " << cell.error().message << "\n";
        return 2;
      }
      reports[it->second].cells.push_back(std::move(*cell));
    }
    if (t.spec.value("reference", false)) reference_task[it->second] = t.index;
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::cerr << "orthosonar batch merge: cannot create '" << out.string() << "': " << ec.message() << "\n";
    return 2;
  }
  const bool set = reports.size() > 1;
  Status st = set ? run::write_sweep_set(reports, seeds, out.string()) : run::write_sweep_outputs(reports[0], out.string());
  if (!st.ok()) {
    std::cerr << "orthosonar batch merge: " << st.error().message << "\n";
    return 2;
  }
  for (size_t k = 0; k < reports.size(); ++k) {
    if (!reference_task[k]) continue;
    const fs::path dir = set ? out / run::sweep_set_dir(reports[k].scene, seeds[k]) : out;
    if (Status s = copy_tree(fs::path(result_dir(plan, *reference_task[k])) / "reference", dir); !s.ok()) {
      std::cerr << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
    if (Status s = write_sweep_report(dir.string(), "orthosonar sweep: " + reports[k].scene); !s.ok()) {
      std::cerr << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
  }
  std::cout << (set ? run::seeds_markdown(reports, seeds) : run::sweep_tables_markdown(reports[0]));
  std::cerr << "batch merge: " << plan.tasks.size() << " tasks merged into " << out.string() << "\n";
  return 0;
}

// verify / golden: a summary (markdown + JSON) and JUnit XML, one test case per task.
int merge_verdicts(const Plan& plan, const Gathered& g, const fs::path& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::cerr << "orthosonar batch merge: cannot create '" << out.string() << "': " << ec.message() << "\n";
    return 2;
  }
  const std::string suite = "orthosonar " + plan.kind;
  size_t failures = 0, errors = 0;
  double total_s = 0.0;
  std::ostringstream cases, md;
  json summary = {{"kind", plan.kind}, {"tasks", json::array()}};
  const json cut_tasks = note_cut_tasks(plan, g);
  md << "# " << suite << "\n\n| Task | Result |\n|---|---|\n";
  for (const auto& t : plan.tasks) {
    const auto& r = g.results[t.index];
    const double time_s = r ? r->value("wall_s", 0.0) : 0.0;
    total_s += time_s;
    char tbuf[32];
    std::snprintf(tbuf, sizeof tbuf, "%.3f", time_s);
    cases << "    <testcase classname=\"" << xml_escape("orthosonar." + plan.kind) << "\" name=\"" << xml_escape(t.name)
          << "\" time=\"" << tbuf << "\"";
    std::string verdict;
    if (!r) {
      ++errors;
      const TaskStatus st = task_status(plan, t, false);
      const std::string msg = state_name(st.state) + ": " + st.detail;
      cases << ">\n      <error message=\"" << xml_escape("no result: " + msg) << "\" type=\"missing\">"
            << xml_escape("log: " + log_path(plan, t.index)) << "</error>\n    </testcase>\n";
      verdict = "MISSING (" + msg + ")";
    } else if (!r->value("passed", false)) {
      ++failures;
      const std::string message = r->value("message", std::string());
      const std::string first_line = message.substr(0, message.find('\n'));
      cases << ">\n      <failure message=\"" << xml_escape(first_line) << "\" type=\""
            << (plan.kind == "verify" ? "digest" : "golden") << "\">" << xml_escape(message) << "</failure>\n    </testcase>\n";
      verdict = plan.kind == "verify" ? "DIFFERENT: " + first_line : "FAIL";
    } else {
      cases << "/>\n";
      verdict = plan.kind == "verify" ? "identical: " + r->value("got", std::string()) : "PASS";
    }
    if (r && r->contains("input_cut")) verdict += " (INPUT CUT SHORT)";
    md << "| " << t.name << " | " << verdict << " |\n";
    summary["tasks"].push_back({{"index", t.index}, {"name", t.name}, {"verdict", verdict},
                                {"passed", r && r->value("passed", false)}});
  }
  char tot[32];
  std::snprintf(tot, sizeof tot, "%.3f", total_s);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"" << xml_escape(suite) << "\" tests=\""
      << plan.tasks.size() << "\" failures=\"" << failures << "\" errors=\"" << errors << "\" time=\"" << tot << "\">\n"
      << "  <testsuite name=\"" << xml_escape(suite) << "\" tests=\"" << plan.tasks.size() << "\" failures=\"" << failures
      << "\" errors=\"" << errors << "\" skipped=\"0\" time=\"" << tot << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  const size_t passed = plan.tasks.size() - failures - errors;
  md << "\n" << passed << " of " << plan.tasks.size() << " passed, " << failures << " failed, " << errors << " missing.\n";
  summary["passed"] = passed;
  summary["failed"] = failures;
  summary["missing"] = errors;
  summary["input_cut_tasks"] = cut_tasks;
  if (!cut_tasks.empty()) md << cut_tasks.size() << " task(s) ran on an input cut short: see summary.json input_cut_tasks.\n";
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"junit.xml", xml.str()},
                                   {"summary.md", md.str()}, {"summary.json", summary.dump(2) + "\n"}})
    if (Status s = write_text(out / name, text); !s.ok()) {
      std::cerr << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
  std::cout << md.str();
  std::cerr << "batch merge: JUnit XML " << (out / "junit.xml").string() << "\n";
  if (errors) {
    report_problems(plan, g);
    return 2;
  }
  return failures ? 1 : 0;
}

}  // namespace

int merge(const Plan& plan, const std::string& out_dir) {
  const fs::path out = out_dir.empty() ? fs::path(plan.dir) / "merged" : fs::path(out_dir);
  const Gathered g = gather(plan);
  return plan.kind == "sweep" ? merge_sweep(plan, g, out) : merge_verdicts(plan, g, out);
}

}  // namespace orthosonar::cli::batch
