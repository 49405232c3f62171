// `orthosonar golden`: golden scenarios (issue 8). A scenario file (golden/scenarios/*.yaml)
// names a simulated mission and the pipeline settings, and holds what it is expected to
// produce: the digest (per output and overall) and metrics with tolerances.
//
//   golden --run S.yaml [-o DIR] [--threads N]     simulate + map, print "digest: <hex>"
//   golden --check S.yaml... [--threads N] [--repeat K]
//                                                  exit 0 when every run matches, 1 when not
//   golden --update [S.yaml...]                    rewrite expectations, print what changed
//
// The fixture is generated in-process by the simulator (deterministic from the seed), so a
// scenario needs no stored recording.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "hal/sim/scene.hpp"
#include "hal/sim/simulator.hpp"
#include "tools/cli.hpp"
#include "tools/support_pipeline.hpp"

namespace orthosonar::cli {
namespace {

struct Tolerances {
  double coverage_rel = 0.0;   // relative change of coverage_voxels allowed
  double mae_abs_m = 0.0;
  double rmse_abs_m = 0.0;
  double ate_abs_m = 0.0;
};

struct Scenario {
  std::string path;
  std::string name, scene;
  uint64_t seed = 1;
  double duration_s = 40.0;
  std::string resolution = "reduced";
  double kf_distance_m = 3.0, kf_rotation_deg = 30.0;
  std::vector<std::string> systems = {"fusion", "submap"};
  Tolerances tol;
  YAML::Node expected;  // may be null before the first --update
};

Result<Scenario> load_scenario(const std::string& path) {
  Scenario s;
  s.path = path;
  try {
    const YAML::Node n = YAML::LoadFile(path);
    s.name = n["name"].as<std::string>();
    s.scene = n["scene"].as<std::string>();
    s.seed = n["seed"].as<uint64_t>();
    s.duration_s = n["duration_s"].as<double>();
    s.resolution = n["resolution"].as<std::string>();
    s.kf_distance_m = n["keyframes"]["distance_m"].as<double>();
    s.kf_rotation_deg = n["keyframes"]["rotation_deg"].as<double>();
    s.systems = n["systems"].as<std::vector<std::string>>();
    const YAML::Node t = n["tolerances"];
    s.tol = {t["coverage_rel"].as<double>(), t["mae_abs_m"].as<double>(), t["rmse_abs_m"].as<double>(),
             t["ate_abs_m"].as<double>()};
    if (n["expected"]) s.expected = n["expected"];
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  return s;
}

// The metrics a scenario pins, flattened to "system.metric" -> value.
std::map<std::string, double> scenario_metrics(const RunOutput& run) {
  std::map<std::string, double> m;
  for (const auto& s : run.systems) {
    m[s.name + ".coverage_voxels"] = static_cast<double>(s.coverage_voxels);
    if (s.accuracy) {
      m[s.name + ".mae_m"] = s.accuracy->mae_m;
      m[s.name + ".rmse_m"] = s.accuracy->rmse_m;
    }
  }
  if (run.ate_dr_m) m["ate_dr_m"] = *run.ate_dr_m;
  if (run.ate_slam_m) m["ate_slam_m"] = *run.ate_slam_m;
  m["keyframes"] = static_cast<double>(run.counts.keyframes);
  m["loop_closures"] = static_cast<double>(run.counts.loop_closures);
  return m;
}

// Allowed absolute difference for one metric.
double tolerance_for(const std::string& key, double expected, const Tolerances& t) {
  if (key.ends_with("coverage_voxels")) return t.coverage_rel * std::abs(expected);
  if (key.ends_with("mae_m")) return t.mae_abs_m;
  if (key.ends_with("rmse_m")) return t.rmse_abs_m;
  if (key.starts_with("ate_")) return t.ate_abs_m;
  return 0.0;  // counts are exact
}

Result<RunOutput> run_scenario(const Scenario& s, int threads) {
  auto scene = sim::builtin_scene(s.scene, s.seed);
  if (!scene) return Error{s.path + ": scene: " + scene.error().message};
  auto res = sim::parse_resolution(s.resolution);
  if (!res) return Error{s.path + ": resolution: " + res.error().message};
  sim::SimConfig sc;
  sc.duration_s = s.duration_s;
  sc.seed = s.seed;
  sc.resolution = *res;
  std::optional<TriangleMesh> mesh = scene->mesh;
  sim::Simulator simulator(std::move(*scene), sc);
  const auto metadata = simulator.metadata();

  RunOptions o;
  o.systems = s.systems;
  o.config.threads = threads;
  o.config.pipeline.slam.kf_distance_m = s.kf_distance_m;
  o.config.pipeline.slam.kf_rotation_deg = s.kf_rotation_deg;
  apply_mission_start(metadata, o.config);
  return run_pipeline(simulator, metadata, o, mesh);
}

void print_metrics(const std::map<std::string, double>& m) {
  for (const auto& [k, v] : m) std::cout << "  " << std::left << std::setw(26) << k << " " << std::setprecision(6) << v << "\n";
}

int do_run(const std::string& path, const std::string& out_dir, int threads) {
  auto s = load_scenario(path);
  if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
  auto run = run_scenario(*s, threads);
  if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
  if (!out_dir.empty()) {
    RunOptions o;
    o.systems = s->systems;
    if (auto st = write_run_outputs(*run, o, out_dir); !st) {
      std::cerr << "orthosonar golden: " << st.error().message << "\n";
      return 2;
    }
  }
  std::cout << "scenario " << s->name << " (" << s->scene << ", seed " << s->seed << ", " << s->duration_s << " s, "
            << s->resolution << ", " << threads << " thread(s))\n";
  print_metrics(scenario_metrics(*run));
  std::cout << "digest: " << run->digest.overall_hex << "\n";
  return 0;
}

// Compares one run with the scenario's expectations; prints every difference.
bool matches(const Scenario& s, const RunOutput& run, std::ostream& out) {
  bool ok = true;
  if (!s.expected || !s.expected["digest"]) {
    out << "  no expectations recorded: run `orthosonar golden --update " << s.path << "`\n";
    return false;
  }
  const std::string want = s.expected["digest"].as<std::string>();
  if (want != run.digest.overall_hex) {
    ok = false;
    out << "  digest differs: expected " << want << ", got " << run.digest.overall_hex << "\n";
    const YAML::Node outs = s.expected["outputs"];
    for (const auto& [name, hash] : run.digest.outputs) {
      if (!outs[name]) out << "    new output " << name << "\n";
      else if (outs[name].as<std::string>() != hash) out << "    output differs: " << name << "\n";
    }
    for (const auto& kv : outs)
      if (!run.digest.outputs.count(kv.first.as<std::string>())) out << "    missing output " << kv.first.as<std::string>() << "\n";
  }
  const auto got = scenario_metrics(run);
  for (const auto& kv : s.expected["metrics"]) {
    const std::string key = kv.first.as<std::string>();
    const double want_v = kv.second.as<double>();
    auto it = got.find(key);
    if (it == got.end()) { ok = false; out << "  metric missing: " << key << "\n"; continue; }
    const double tol = tolerance_for(key, want_v, s.tol);
    if (!(std::abs(it->second - want_v) <= tol)) {
      ok = false;
      out << "  metric out of tolerance: " << key << " expected " << want_v << " +- " << tol << ", got " << it->second << "\n";
    }
  }
  return ok;
}

int do_check(const std::vector<std::string>& paths, int threads, int repeat) {
  int failures = 0;
  for (const auto& path : paths) {
    auto s = load_scenario(path);
    if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
    for (int r = 0; r < repeat; ++r) {
      auto run = run_scenario(*s, threads);
      if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
      std::ostringstream diff;
      const bool ok = matches(*s, *run, diff);
      std::cout << (ok ? "PASS " : "FAIL ") << s->name << " (threads " << threads << ", run " << r + 1 << "/" << repeat
                << ") digest " << run->digest.overall_hex << "\n" << diff.str();
      if (!ok) ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}

Status write_expectations(const Scenario& s, const RunOutput& run) {
  YAML::Emitter e;
  e << YAML::Comment("Golden scenario. Expectations are written by `orthosonar golden --update`; review the diff.");
  e << YAML::BeginMap;
  e << YAML::Key << "name" << YAML::Value << s.name;
  e << YAML::Key << "scene" << YAML::Value << s.scene;
  e << YAML::Key << "seed" << YAML::Value << s.seed;
  e << YAML::Key << "duration_s" << YAML::Value << s.duration_s;
  e << YAML::Key << "resolution" << YAML::Value << s.resolution;
  e << YAML::Key << "keyframes" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "distance_m"
    << YAML::Value << s.kf_distance_m << YAML::Key << "rotation_deg" << YAML::Value << s.kf_rotation_deg << YAML::EndMap;
  e << YAML::Key << "systems" << YAML::Value << YAML::Flow << s.systems;
  e << YAML::Key << "tolerances" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "coverage_rel"
    << YAML::Value << s.tol.coverage_rel << YAML::Key << "mae_abs_m" << YAML::Value << s.tol.mae_abs_m << YAML::Key
    << "rmse_abs_m" << YAML::Value << s.tol.rmse_abs_m << YAML::Key << "ate_abs_m" << YAML::Value << s.tol.ate_abs_m
    << YAML::EndMap;
  e << YAML::Key << "expected" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "digest" << YAML::Value << run.digest.overall_hex;
  e << YAML::Key << "outputs" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : run.digest.outputs) e << YAML::Key << k << YAML::Value << v;
  e << YAML::EndMap;
  e << YAML::Key << "metrics" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : scenario_metrics(run)) {
    std::ostringstream num;
    num << std::setprecision(17) << v;
    e << YAML::Key << k << YAML::Value << num.str();
  }
  e << YAML::EndMap << YAML::EndMap << YAML::EndMap;
  const std::string tmp = s.path + ".tmp";
  {
    std::ofstream f(tmp);
    f << e.c_str() << "\n";
    if (!f) return Error{tmp + ": cannot write"};
  }
  std::error_code ec;
  std::filesystem::rename(tmp, s.path, ec);
  if (ec) return Error{s.path + ": " + ec.message()};
  return {};
}

int do_update(const std::vector<std::string>& paths) {
  for (const auto& path : paths) {
    auto s = load_scenario(path);
    if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
    auto run = run_scenario(*s, 1);
    if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
    const std::string old = s->expected && s->expected["digest"] ? s->expected["digest"].as<std::string>() : "(none)";
    std::cout << s->name << ": digest " << old << " -> " << run->digest.overall_hex
              << (old == run->digest.overall_hex ? "  (unchanged)" : "  (CHANGED)") << "\n";
    const auto now = scenario_metrics(*run);
    for (const auto& [k, v] : now) {
      const bool had = s->expected && s->expected["metrics"] && s->expected["metrics"][k];
      const double before = had ? s->expected["metrics"][k].as<double>() : std::nan("");
      if (!had || before != v)
        std::cout << "  " << std::left << std::setw(26) << k << " " << (had ? std::to_string(before) : "(new)") << " -> " << v << "\n";
    }
    if (auto st = write_expectations(*s, *run); !st) {
      std::cerr << "orthosonar golden: " << st.error().message << "\n";
      return 2;
    }
  }
  return 0;
}

std::vector<std::string> default_scenarios() {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("golden/scenarios", ec))
    if (e.path().extension() == ".yaml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

struct GoldenArgs {
  std::string run;
  bool check = false, update = false;
  std::vector<std::string> scenarios;
  std::string out_dir;
  int threads = 1;
  int repeat = 1;
};

int run_golden(GoldenArgs a) {
  if (!a.run.empty()) return do_run(a.run, a.out_dir, a.threads);
  if (a.scenarios.empty()) a.scenarios = default_scenarios();
  if (a.scenarios.empty()) {
    std::cerr << "orthosonar golden: no scenarios given and none in golden/scenarios/ (run from the repository root)\n";
    return 2;
  }
  if (a.update) return do_update(a.scenarios);
  if (a.check) return do_check(a.scenarios, a.threads, a.repeat);
  std::cerr << "orthosonar golden: say --run S.yaml, --check or --update\n";
  return 2;
}

const bool registered = register_command(
    {"golden", "Run, check or update golden scenarios (simulated missions with expected digests and metrics)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<GoldenArgs>();
       sub.add_option("--run", a->run, "Run one scenario and print its digest");
       sub.add_flag("--check", a->check, "Check scenarios against their expectations (exit 1 on a difference)");
       sub.add_flag("--update", a->update, "Regenerate expectations and print what changed");
       sub.add_option("scenarios", a->scenarios, "Scenario files (default: golden/scenarios/*.yaml)");
       sub.add_option("-o,--out", a->out_dir, "With --run: write the run's outputs here");
       sub.add_option("--threads", a->threads, "Fusion threads")->check(CLI::Range(1, 64));
       sub.add_option("--repeat", a->repeat, "With --check: runs per scenario")->check(CLI::Range(1, 100));
       return [a] { return run_golden(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
