// Fixture read throughput: a full-resolution fixture (600 range bins x 512 beams, 8-bit,
// both sonars at 10 Hz, navigation channels, zstd chunks) is opened and every event is
// decoded, in order, on one core. Throughput is decompressed image payload per CPU second
// (process CPU time, so a loaded machine does not distort it);
// the target is >= 500 MB/s. peak_events_held: the most decoded events the source held at
// once (bounded by the chunks in use, not the file; issue 16).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "replay/fixture.hpp"
#include "replay/synthetic.hpp"

namespace {

using namespace orthosonar;

struct BenchFixture {
  std::string path;
  uint64_t payload = 0;
  size_t events = 0;
};

const BenchFixture& full_resolution_fixture(bool compress) {
  static BenchFixture fx[2];
  BenchFixture& f = fx[compress ? 1 : 0];
  if (!f.path.empty()) return f;
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = (env != nullptr ? std::filesystem::path(env) : std::filesystem::temp_directory_path()) / "bench";
  std::filesystem::create_directories(dir);
  f.path = (dir / (compress ? "full_res_zstd.mcap" : "full_res_raw.mcap")).string();
  replay::SyntheticOptions so;
  so.duration_ns = 10'000'000'000;
  so.ping_rows = 600;
  so.ping_cols = 512;
  so.labels = false;
  const auto events = replay::synthetic_events(9, so);
  f.payload = replay::payload_bytes(events);
  f.events = events.size();
  replay::WriterOptions o;
  o.compress = compress;
  auto w = replay::FixtureWriter::open(f.path, {{"scene", "bench"}}, o);
  if (!w) std::abort();
  for (const auto& e : events)
    if (!(*w)->write(e).ok()) std::abort();
  if (!(*w)->close().ok()) std::abort();
  return f;
}

void read_all(benchmark::State& state, bool compress) {
  const auto& f = full_resolution_fixture(compress);
  size_t peak_held = 0;
  for (auto _ : state) {
    auto src = replay::FixtureSource::open(f.path);
    if (!src) {
      state.SkipWithError(src.error().message.c_str());
      return;
    }
    size_t n = 0;
    for (;;) {
      auto p = (*src)->next();
      if (p.error) {
        state.SkipWithError(p.error->message.c_str());
        return;
      }
      if (p.end_of_stream) break;
      benchmark::DoNotOptimize(p.event->payload);
      ++n;
    }
    if (n != f.events) state.SkipWithError("event count mismatch");
    peak_held = std::max(peak_held, (*src)->holding().peak_events);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * f.payload));
  state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(f.path)) / 1e6;
  state.counters["payload_MB"] = static_cast<double>(f.payload) / 1e6;
  state.counters["events"] = static_cast<double>(f.events);
  state.counters["peak_events_held"] = static_cast<double>(peak_held);
}

void BM_FixtureReadFullResolutionZstd(benchmark::State& state) { read_all(state, true); }
void BM_FixtureReadFullResolutionUncompressed(benchmark::State& state) { read_all(state, false); }

BENCHMARK(BM_FixtureReadFullResolutionZstd)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FixtureReadFullResolutionUncompressed)->Unit(benchmark::kMillisecond);

}  // namespace
