// `orthosonar verify f.mcap --expect digest.json`: replays the fixture and compares every
// output's digest. Exit 0 when identical, 1 when any differs (naming them), 2 on bad input.
// Without --systems the systems are the ones the expected digest names.
#include <iostream>
#include <set>

#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

struct VerifyArgs {
  std::string fixture;
  std::string expect;
  std::string out_dir;
  CommonRunArgs run;
  bool systems_given = false;
};

int run_verify(VerifyArgs a) {
  auto expected = replay::read_digest_json(a.expect);
  if (!expected.ok()) {
    std::cerr << "orthosonar verify: " << expected.error().message << "\n";
    return 2;
  }
  if (!a.systems_given) {
    std::set<std::string> names;
    for (const auto& [k, v] : expected->outputs)
      if (const auto slash = k.find('/'); slash != std::string::npos) names.insert(k.substr(0, slash));
    a.run.systems.clear();
    for (const auto& n : names) a.run.systems += (a.run.systems.empty() ? "" : ",") + n;
    if (a.run.systems.empty()) a.run.systems = "fusion,submap";
  }
  auto options = run_options_from(a.run);
  if (!options.ok()) {
    std::cerr << "orthosonar verify: " << options.error().message << "\n";
    return 2;
  }
  if (!a.out_dir.empty())
    if (Status s = clear_run_verdicts(a.out_dir); !s.ok()) {
      std::cerr << "orthosonar verify: " << s.error().message << "\n";
      return 2;
    }
  std::string warning;
  auto r = run_fixture(a.fixture, *options, {}, &warning);
  if (!warning.empty()) note_cut_input_warning(warning);
  if (!r.ok()) {
    std::cerr << "orthosonar verify: " << r.error().message << "\n";
    return 2;
  }
  if (!a.out_dir.empty())
    if (Status s = write_run_outputs(*r, *options, a.out_dir); !s.ok()) {
      std::cerr << "orthosonar verify: " << s.error().message << "\n";
      return 2;
    }
  const auto diff = replay::differing_outputs(*expected, r->digest);
  if (diff.empty() && expected->overall_hex == r->digest.overall_hex) {
    std::cout << "identical: " << r->digest.overall_hex << "\n";
    return 0;
  }
  std::cout << "DIFFERENT: expected " << expected->overall_hex << ", got " << r->digest.overall_hex << "\n";
  for (const auto& name : diff) {
    const auto e = expected->outputs.find(name);
    const auto g = r->digest.outputs.find(name);
    std::cout << "  " << name << ": expected " << (e == expected->outputs.end() ? "(absent)" : e->second)
              << ", got " << (g == r->digest.outputs.end() ? "(absent)" : g->second) << "\n";
  }
  if (diff.empty()) std::cout << "  (per-output hashes agree; the overall hash differs)\n";
  return 1;
}

const bool registered_verify = register_command(
    {"verify", "Replay a fixture and compare its outputs with an expected digest.json",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<VerifyArgs>();
       sub.add_option("fixture", a->fixture, "Fixture (.mcap)")->required();
       sub.add_option("--expect", a->expect, "Expected digest.json")->required();
       sub.add_option("-o,--out", a->out_dir, "Also write the output directory here");
       add_run_options(sub, a->run);
       return [a, &sub] {
         a->systems_given = sub.count("--systems") > 0;
         return run_verify(*a);
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
