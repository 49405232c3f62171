// `orthosonar replay f.mcap -o out/`: runs the pipeline over a fixture, writes the output
// directory (maps, metrics, trajectories, summary, digest) and prints the overall digest.
#include <iostream>

#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "replay/run/truth_spill.hpp"
#include "tools/support_memory_report.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

struct ReplayArgs {
  std::string fixture;
  std::string out_dir = "out/replay";
  bool quiet = false;
  std::string memory_report;  // CSV path; empty: no sampling
  CommonRunArgs run;
};

int run_replay(const ReplayArgs& a) {
  auto options = run_options_from(a.run);
  if (!options.ok()) {
    std::cerr << "orthosonar replay: " << options.error().message << "\n";
    return 2;
  }
  // An earlier run's verdicts go before this run starts (issue 40).
  if (Status s = clear_run_verdicts(a.out_dir); !s.ok()) {
    std::cerr << "orthosonar replay: " << s.error().message << "\n";
    return 2;
  }
  std::string warning;
  RunControl control = progress_bar_control("replay", !a.quiet);
  MemoryReport memory;
  if (!a.memory_report.empty()) control.memory = [&memory](const RunControl::MemoryView& v) { memory.sample(v); };
  auto r = run_fixture(a.fixture, *options, control, &warning);
  if (!warning.empty()) note_cut_input_warning(warning);
  if (!r.ok()) {
    std::cerr << "orthosonar replay: " << r.error().message << "\n";
    return 2;
  }
  if (Status s = write_run_outputs(*r, *options, a.out_dir); !s.ok()) {
    std::cerr << "orthosonar replay: " << s.error().message << "\n";
    return 2;
  }
  if (!a.memory_report.empty()) {
    memory.sample_outputs(*r->pipeline, r->truth_all ? r->truth_all->memory_bytes() : 0);
    if (Status s = memory.write_csv(a.memory_report); !s.ok()) {
      std::cerr << "orthosonar replay: --memory-report: " << s.error().message << "\n";
      return 2;
    }
    std::cerr << "memory budget (samples in " << a.memory_report << "):\n" << memory.budget();
  }
  if (!a.quiet) {
    std::cerr << "replayed " << r->stream_span.seconds() << " s of sensor time in " << r->wall_s << " s ("
              << (r->wall_s > 0 ? r->stream_span.seconds() / r->wall_s : 0.0) << "x real time); pairs "
              << r->counts.pairs << ", keyframes " << r->counts.keyframes << "; outputs in " << a.out_dir << "\n";
  }
  std::cout << r->digest.overall_hex << "\n";
  return 0;
}

const bool registered_replay = register_command(
    {"replay", "Replay a fixture through the pipeline, write maps, metrics and the output digest",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<ReplayArgs>();
       sub.add_option("fixture", a->fixture, "Fixture (.mcap)")->required();
       sub.add_option("-o,--out", a->out_dir, "Output directory")->capture_default_str();
       sub.add_flag("-q,--quiet", a->quiet, "Print only the digest");
       sub.add_option("--memory-report", a->memory_report,
                      "Sample resident memory and each part's bytes every minute of sensor time into this CSV, "
                      "and print the memory budget (changes no output)");
       add_run_options(sub, a->run);
       return [a] { return run_replay(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
