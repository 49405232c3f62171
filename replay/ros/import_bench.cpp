// Import throughput (issue 18: >= 100 MB/s of bag on one core): a ROS 1 bag of
// full-resolution pings (512 beams x 600 ranges, 10 Hz per sonar, the authors' types) with
// navigation at the usual rates, imported to a fixture. Bytes/s counts the bag's size.
// Variants: uncompressed images (OculusPingUncompressed) in an uncompressed bag and in
// an lz4 bag, and JPEG (OculusPing, quality 80), whose cost is the JPEG decoder's.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "replay/fixture/fixture.hpp"
#include "replay/ros/export.hpp"
#include "replay/ros/import.hpp"
#include "replay/fixture/synthetic.hpp"

namespace orthosonar::replay::ros {
namespace {

namespace fs = std::filesystem;

struct BagFixture {
  std::string bag;
  uint64_t bytes = 0;
};

const BagFixture& bag_for(const std::string& name, bool jpeg, const std::string& compression) {
  static std::map<std::string, BagFixture> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  const fs::path dir = fs::temp_directory_path() / "orthosonar_import_bench";
  fs::create_directories(dir);
  const std::string fixture = (dir / "source.mcap").string();
  if (!fs::exists(fixture)) {
    SyntheticOptions o;
    o.duration_ns = 10'000'000'000;
    o.ping_rows = 600;
    o.ping_cols = 512;
    o.labels = false;
    auto w = FixtureWriter::open(fixture, {{"T_V_h", "0.35 0 0 0 0 0"}});
    if (!w) throw std::runtime_error(w.error().message);
    for (const Event& e : synthetic_events(1, o))
      if (!(*w)->write(e)) throw std::runtime_error("write");
    (void)(*w)->close();
  }
  BagFixture f;
  f.bag = (dir / (name + ".bag")).string();
  ExportOptions eo;
  eo.jpeg = jpeg;
  eo.compression = compression;
  auto r = export_fixture(fixture, f.bag, eo);
  if (!r) throw std::runtime_error(r.error().message);
  f.bytes = fs::file_size(f.bag);
  return cache.emplace(name, f).first->second;
}

void run_import(benchmark::State& state, const BagFixture& f) {
  const std::string out = f.bag + ".imported.mcap";
  ImportOptions o;
  o.map.T_V_h = "0.35 0 0 0 0 0";
  if (const char* l = std::getenv("IMPORT_ZSTD_LEVEL")) o.writer.zstd_level = std::atoi(l);
  for (auto _ : state) {
    auto r = import_recording(f.bag, out, o);
    if (!r) state.SkipWithError(r.error().message.c_str());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * f.bytes));
  state.counters["bag_MB"] = static_cast<double>(f.bytes) / 1e6;
}

void BM_ImportBagRawImages(benchmark::State& state) { run_import(state, bag_for("raw", false, "none")); }
void BM_ImportBagRawImagesLz4(benchmark::State& state) { run_import(state, bag_for("raw_lz4", false, "lz4")); }
void BM_ImportBagJpeg(benchmark::State& state) { run_import(state, bag_for("jpeg", true, "none")); }

BENCHMARK(BM_ImportBagRawImages)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ImportBagRawImagesLz4)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ImportBagJpeg)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace orthosonar::replay::ros
