#pragma once
// Batch plans (docs/BATCH.md): a plan is a folder holding a manifest of independent tasks;
// any engine runs them (engine.hpp: this machine, a Slurm job array; or a Kubernetes
// Indexed Job), each task writing only its own result folder (run.hpp), and merge.hpp
// gathers the results into the outputs the one-machine command writes.
//
//   plan/manifest.json        kind, common settings, the tasks (index, name, spec)
//   plan/tasks.txt            "index name" per line, for people and shell loops
//   plan/results/<i>/         task i's result.json (+ outputs), or failed.json (state.hpp)
//   plan/logs/task-<i>.log    engine logs (every attempt appended)
//   plan/fixtures/            sweep: the simulated fixtures (shared by a scene/seed's tasks)
//   plan/slurm/               sbatch scripts and the submitted job ids
//   plan/merged/              merge's default output
//
// This file: the plan's types, planning the three kinds of work (sweep, verify, golden),
// and the manifest written and read back.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.hpp"
#include "replay/run/run.hpp"

namespace orthosonar::batch {

struct Task {
  size_t index = 0;
  std::string name;      // "harbor/seed2/1m30-5m30", a fixture's stem, a scenario's name
  nlohmann::json spec;   // kind-specific
};

struct Plan {
  std::string dir;             // absolute
  std::string kind;            // sweep | verify | golden
  nlohmann::json common;       // settings shared by every task
  std::vector<Task> tasks;
};

// ---- planning ----
struct SweepPlanSpec {
  std::vector<std::string> scenes;
  std::vector<uint64_t> seeds;
  std::string cells = "all";
  int cells_per_task = 0;  // 0: all of a (scene, seed)'s cells in one task
  double duration_s = 600.0;
  std::string resolution = "full";
  std::string sim_config_yaml;
  std::string run_config_yaml;
  std::string systems = "fusion,submap";
  std::string model_path;  // classifier for the inference systems (its bytes are in the key)
  bool report = true;
};
Result<Plan> plan_sweep(const SweepPlanSpec& spec, const std::string& dir);

// `inputs`: fixtures (.mcap, expected digest beside it as <stem>.digest.json or
// <file>.digest.json), directories (every .mcap in them with such a digest), or list files
// (.txt: "fixture.mcap expected.json" per line, paths relative to the list; # comments).
struct VerifyPlanSpec {
  std::vector<std::string> inputs;
  std::string run_config_yaml;
  std::string systems;  // empty: the ones each expected digest names
};
Result<Plan> plan_verify(const VerifyPlanSpec& spec, const std::string& dir);

struct GoldenPlanSpec {
  // Scenario files; empty is an error (the CLI defaults to golden/scenarios/*.yaml).
  std::vector<std::string> scenarios;
  bool images = true;
};
Result<Plan> plan_golden(const GoldenPlanSpec& spec, const std::string& dir);

// Writes manifest.json and tasks.txt (creates the folder; refuses a folder holding a
// different plan's results unless `replace`).
Status write_plan(const Plan& plan, bool replace);
Result<Plan> load_plan(const std::string& dir);

// The run options of a plan's tasks: `systems` comma-separated, `model` the classifier
// (may be empty). Errors name the value at fault.
Result<run::RunOptions> run_options_for(const std::string& systems, const std::string& model);

}  // namespace orthosonar::batch
