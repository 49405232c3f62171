// Running one task of a plan into its result folder (see run.hpp).
#include "replay/batch/run.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>

#include "hal/sim/sim_config.hpp"
#include "replay/batch/files.hpp"
#include "replay/batch/process.hpp"
#include "replay/batch/state.hpp"
#include "replay/batch/sweep_outputs.hpp"
#include "replay/digest/digest.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::batch {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---- sweep ----

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
  auto options =
      run_options_for(common.value("systems", std::string("fusion,submap")), common.value("model", std::string()));
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

Status run_golden_task(const Plan& plan, const Task& task, int threads, const std::string& executable,
                       const std::string& out, json& result) {
  std::vector<std::string> argv = {executable, "golden", "--check", task.spec.at("scenario").get<std::string>(),
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

}  // namespace

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

int default_task_threads() {
  if (const char* c = std::getenv("SLURM_CPUS_PER_TASK"); c && std::atoi(c) > 0) return std::atoi(c);
  return 1;
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
    else st = run_golden_task(plan, task, o.threads, o.executable.empty() ? self_executable() : o.executable,
                              tmp.string(), result);
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

}  // namespace orthosonar::batch
