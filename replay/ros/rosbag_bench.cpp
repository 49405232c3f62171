// Bag read throughput: BagReader::open and for_each over a ~64 MB bag of 100 KB messages
// (sonar-ping sized), uncompressed and lz4, on one core. The callback folds every payload
// word, as a consumer reads each byte once (for an uncompressed bag that faults the mapped
// pages in). Throughput is message payload bytes per CPU second.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "replay/ros/rosbag.hpp"

namespace {

using namespace orthosonar;
using namespace orthosonar::replay::rosbag;

constexpr size_t kMessageBytes = 100 * 1000;
constexpr size_t kMessages = 640;

const std::string& bench_bag(const std::string& compression) {
  static std::map<std::string, std::string> paths;
  auto& path = paths[compression];
  if (!path.empty()) return path;
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = (env != nullptr ? std::filesystem::path(env) : std::filesystem::temp_directory_path()) / "bench";
  std::filesystem::create_directories(dir);
  path = (dir / ("rosbag_" + compression + ".bag")).string();
  auto w = BagWriter::open(path, {compression, 768 * 1024});
  if (!w) std::abort();
  auto conn = (*w)->add_connection("/sonar/ping", "orthosonar_msgs/Ping", std::string(32, '0'), "uint8[] data\n");
  if (!conn) std::abort();
  // Ping-like bytes: each 600-bin beam is noise out to a third of its range, an echo, then
  // silence, so lz4 has something to find (about 2.5:1) and work to do.
  std::vector<uint8_t> data(kMessageBytes);
  uint32_t x = 12345;
  for (size_t i = 0; i < kMessages; ++i) {
    for (size_t j = 0; j < data.size(); ++j) {
      x = x * 1664525u + 1013904223u;
      const size_t bin = j % 600;
      data[j] = static_cast<uint8_t>(bin < 200 ? (x >> 24) & 0x1f : bin < 240 ? 180 + ((x >> 24) & 0x3) : 0);
    }
    if (!(*w)->write(*conn, 1'700'000'000'000'000'000ull + i * 100'000'000ull, data.data(), data.size()).ok()) std::abort();
  }
  if (!(*w)->close().ok()) std::abort();
  return path;
}

void read_bag(benchmark::State& state, const std::string& compression) {
  const std::string& path = bench_bag(compression);
  uint64_t payload = 0;
  for (auto _ : state) {
    auto bag = BagReader::open(path);
    if (!bag) {
      state.SkipWithError(bag.error().message.c_str());
      return;
    }
    uint64_t fold = 0, n = 0;
    payload = 0;
    auto s = (*bag)->for_each([&](const Connection&, const MessageView& m) -> Status {
      for (size_t i = 0; i + 8 <= m.size; i += 8) {
        uint64_t w;
        std::memcpy(&w, m.data + i, 8);
        fold ^= w;
      }
      payload += m.size;
      ++n;
      return {};
    });
    if (!s || n != kMessages) {
      state.SkipWithError(s ? "message count mismatch" : s.error().message.c_str());
      return;
    }
    benchmark::DoNotOptimize(fold);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * payload));
  state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
}

void BM_RosbagReadUncompressed(benchmark::State& state) { read_bag(state, "none"); }
void BM_RosbagReadLz4(benchmark::State& state) { read_bag(state, "lz4"); }
BENCHMARK(BM_RosbagReadUncompressed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RosbagReadLz4)->Unit(benchmark::kMillisecond);

}  // namespace
