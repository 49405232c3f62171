// `orthosonar config [--fixture f.mcap] [--config run.yaml] [--threads N]`: prints the
// effective run configuration as JSON, every field, so a user sees what a replay will run
// with before running it. Same resolution as replay (run::effective_config), in order of
// precedence, lowest first: defaults, the fixture's recorded values (sonar extrinsics,
// DR start), the --config file, command-line flags. With --sources, a second JSON object
// names where each non-default value came from. `--ranges` lists every key's valid range.
#include <iostream>

#include "replay/fixture/fixture.hpp"
#include "tools/cli.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

struct ConfigArgs {
  std::string config_path;
  std::string fixture;
  int threads = 0;
  bool sources = false;
  bool ranges = false;
};

int run_config(const ConfigArgs& a) {
  if (a.ranges) {
    for (const auto& r : config_key_ranges()) std::cout << r.key << "\t" << r.range << "\n";
    return 0;
  }
  RunOptions options;
  if (!a.config_path.empty()) {
    auto text = read_config_text(a.config_path);
    if (!text.ok()) {
      std::cerr << "orthosonar config: " << text.error().message << "\n";
      return 2;
    }
    options.config_yaml = *text;
    options.config_origin = a.config_path;
  }
  if (a.threads != 0) options.threads_override = a.threads;
  replay::FixtureMetadata metadata;
  std::vector<replay::Attachment> attachments;  // the embedded scene gives the DR start
  if (!a.fixture.empty()) {
    auto src = replay::FixtureSource::open(a.fixture);
    if (!src.ok()) {
      std::cerr << "orthosonar config: " << src.error().message << "\n";
      return 2;
    }
    metadata = (*src)->metadata();
    attachments = (*src)->attachments();
  }
  ConfigSources sources;
  auto config = effective_config(metadata, options, &sources, attachments);
  if (!config.ok()) {
    std::cerr << "orthosonar config: " << (a.fixture.empty() ? std::string() : a.fixture + ": ")
              << config.error().message << "\n";
    return 2;
  }
  std::cout << config_to_json(*config).dump(2) << "\n";
  if (a.sources) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [k, v] : sources) j[k] = v;
    std::cout << nlohmann::json{{"sources", j}}.dump(2) << "\n";
  }
  return 0;
}

const bool registered_config = register_command(
    {"config",
     "Print the effective run configuration as JSON (defaults < --fixture's recorded values < --config < flags)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<ConfigArgs>();
       sub.add_option("--config", a->config_path, "Run configuration YAML (docs/CONFIG.md)");
       sub.add_option("--fixture", a->fixture, "Resolve against this fixture's recorded extrinsics and mission start");
       sub.add_option("--threads", a->threads, "As replay's --threads");
       sub.add_flag("--sources", a->sources, "Also print where each non-default value came from");
       sub.add_flag("--ranges", a->ranges, "List every key with its valid range, and exit");
       return [a] { return run_config(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
