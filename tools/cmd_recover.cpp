// `orthosonar recover IN.mcap -o OUT.mcap`: a recording cut short (a killed recorder, a
// full disk) rewritten as a whole, indexed fixture: chunks, attachments, metadata,
// summary and footer (replay/fixture/recover.hpp). Replaying OUT gives the digest of replaying IN
// with --allow-incomplete. Exit codes: 0 OUT written (IN cut or whole), 2 IN unreadable
// or OUT not writable.
#include <cstdio>
#include <iostream>

#include "replay/fixture/recover.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {
namespace {

struct RecoverArgs {
  std::string in, out;
  bool quiet = false;
};

int run_recover(const RecoverArgs& a) {
  auto r = replay::recover_fixture(a.in, a.out);
  if (!r.ok()) {
    std::cerr << "orthosonar recover: " << r.error().message << "\n";
    return 2;
  }
  if (!a.quiet) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", r->input.sensor_seconds());
    if (auto cut = replay::cut_input_warning(a.in, r->input))
      std::cerr << "recovered: " << *cut << "\n";
    else
      std::cerr << a.in << " was whole; rewritten\n";
    std::cerr << "wrote " << a.out << ": " << r->events << " messages, " << seconds << " s of sensor time, "
              << r->attachments << " attachments, summary and footer\n";
  }
  std::cout << a.out << "\n";
  return 0;
}

const bool registered_recover = register_command(
    {"recover", "Rewrite a recording cut short (no summary or footer) as a whole, indexed fixture",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<RecoverArgs>();
       sub.add_option("input", a->in, "Cut recording (.mcap)")->required();
       sub.add_option("-o,--out", a->out, "Whole fixture to write (.mcap)")->required();
       sub.add_flag("-q,--quiet", a->quiet, "Print only the output path");
       return [a] { return run_recover(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
