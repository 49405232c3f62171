// `orthosonar config [--config run.yaml]`: prints the effective run configuration (the
// defaults, overridden by the file if given) as JSON, every field, so a user can see what
// a replay will run with before running it. Same reader and printer as replay/sweep.
#include <iostream>

#include "tools/cli.hpp"
#include "tools/support_config.hpp"

namespace orthosonar::cli {
namespace {

const bool registered = register_command(
    {"config", "Print the effective run configuration (defaults, or a --config YAML applied to them) as JSON",
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       sub.add_option("--config", *path, "Run configuration YAML (docs/CONFIG.md)");
       return [path] {
         RunConfig run;
         if (!path->empty()) {
           if (Status s = load_config_file(*path, run); !s.ok()) {
             std::cerr << "orthosonar config: " << s.error().message << "\n";
             return 2;
           }
         }
         std::cout << config_to_json(run).dump(2) << "\n";
         return 0;
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
