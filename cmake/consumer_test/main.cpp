// Uses an installed orthosonar (find_package(orthosonar); orthosonar::replay and
// orthosonar::run): writes a small fixture with replay::FixtureWriter, reads it back with
// replay::FixtureSource and checks every event survives unchanged and in order, then runs
// the pipeline over it twice with the run API and checks the digests agree. Prints
// "consumer: ok" on success; any failure exits 1.
#include <cstdio>
#include <string>
#include <vector>

#include "orthosonar/version.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/run/run.hpp"
#include "replay/fixture/synthetic.hpp"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "consumer: FAIL: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace orthosonar;
  const std::string dir = argc > 1 ? argv[1] : ".";
  const std::string path = dir + "/consumer.mcap";

  replay::SyntheticOptions options;
  options.duration_ns = 500'000'000;
  const std::vector<Event> events = replay::synthetic_events(7, options);
  if (events.empty()) return fail("no synthetic events");

  {
    auto writer = replay::FixtureWriter::open(path, {{"scene", "consumer"}, {"version", kVersion}});
    if (!writer) return fail(writer.error().message);
    for (const Event& e : events) {
      const Status s = (*writer)->write(e);
      if (!s) return fail(s.error().message);
    }
    const Status closed = (*writer)->close();
    if (!closed) return fail(closed.error().message);
  }

  auto source = replay::FixtureSource::open(path);
  if (!source) return fail(source.error().message);
  if ((*source)->metadata().count("scene") == 0 || (*source)->metadata().at("scene") != "consumer")
    return fail("metadata not read back");
  size_t n = 0;
  while (true) {
    hal::Pulled p = (*source)->next();
    if (p.error) return fail(p.error->message);
    if (p.end_of_stream) break;
    if (!p.event) return fail("neither event nor end nor error");
    if (n >= events.size()) return fail("more events read than written");
    if (!(*p.event == events[n])) return fail("event " + std::to_string(n) + " differs");
    ++n;
  }
  if (n != events.size()) return fail("read " + std::to_string(n) + " of " + std::to_string(events.size()) + " events");
  std::printf("consumer: orthosonar %s, %zu events written and read back from %s\n", kVersion, n, path.c_str());

  // The run API over the same fixture: a deterministic digest.
  run::RunOptions run_options;
  run_options.systems = {"fusion"};
  std::string digest;
  for (int attempt = 0; attempt < 2; ++attempt) {
    auto out = run::run_fixture(path, run_options);
    if (!out) return fail("run_fixture: " + out.error().message);
    if (out->digest.overall_hex.size() != 64) return fail("run_fixture: no digest");
    if (attempt == 1 && out->digest.overall_hex != digest) return fail("run_fixture: digest differs between runs");
    digest = out->digest.overall_hex;
  }
  std::printf("consumer: run_fixture digest %s\n", digest.c_str());
  std::printf("consumer: ok\n");
  return 0;
}
