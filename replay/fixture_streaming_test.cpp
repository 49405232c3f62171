// Streaming replay (issue 16): what FixtureSource holds is bounded by the chunks in use,
// not by the recording's length, and file bytes are not kept resident once consumed.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;

namespace {

struct Replayed {
  std::vector<Event> events;
  FixtureSource::Holding holding;
  uint64_t peak_mapped_kb = 0;  // resident pages of the fixture's mapping, at most (Linux)
};

// Resident kB of this process's mappings of `path` (/proc/self/smaps; 0 elsewhere).
uint64_t mapped_resident_kb(const std::string& path) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool ours = false;
  uint64_t kb = 0;
  while (std::getline(smaps, line)) {
    if (line.empty()) continue;
    const auto colon = line.find(':');
    const bool field = colon != std::string::npos && line.find(' ') > colon;  // "Rss:    12 kB"
    if (!field) {
      // A mapping header: "start-end perms offset dev inode [path]".
      const auto slash = line.find('/');
      ours = slash != std::string::npos && line.compare(slash, std::string::npos, path) == 0;
    } else if (ours && line.rfind("Rss:", 0) == 0) {
      kb += std::stoull(line.substr(4));
    }
  }
  return kb;
}

Replayed replay_all(const std::string& path, size_t sample_every = 0) {
  Replayed r;
  auto src = FixtureSource::open(path);
  REQUIRE(src.ok());
  for (size_t i = 0;; ++i) {
    auto p = (*src)->next();
    REQUIRE_FALSE(p.error);
    if (p.end_of_stream) break;
    r.events.push_back(std::move(*p.event));
    if (sample_every > 0 && i % sample_every == 0)
      r.peak_mapped_kb = std::max(r.peak_mapped_kb, mapped_resident_kb(path));
  }
  if (sample_every > 0) r.peak_mapped_kb = std::max(r.peak_mapped_kb, mapped_resident_kb(path));
  r.holding = (*src)->holding();
  return r;
}

// The most events any one-second stretch of `events` holds (the writer's chunk span).
size_t max_events_per_second(const std::vector<Event>& events) {
  size_t best = 0;
  size_t lo = 0;
  for (size_t hi = 0; hi < events.size(); ++hi) {
    while (events[hi].stamp - events[lo].stamp >= Time::from_s(1)) ++lo;
    best = std::max(best, hi - lo + 1);
  }
  return best;
}

uint64_t le(const std::vector<uint8_t>& b, size_t at, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(b[at + static_cast<size_t>(i)]) << (8 * i);
  return v;
}

void put_le(std::vector<uint8_t>& b, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// The same recording with every (uncompressed) chunk unwrapped into Message records in
// the data section, and no summary: every message is a loose one.
std::vector<uint8_t> unchunked(const std::vector<uint8_t>& in) {
  std::vector<uint8_t> out(in.begin(), in.begin() + 8);
  size_t pos = 8;
  for (;;) {
    const uint8_t op = in[pos];
    const size_t len = static_cast<size_t>(le(in, pos + 1, 8));
    const size_t body = pos + 9;
    if (op == static_cast<uint8_t>(mcap::Op::kDataEnd)) break;
    if (op == static_cast<uint8_t>(mcap::Op::kChunk)) {
      size_t p = body + 8 + 8 + 8 + 4;
      const size_t clen = static_cast<size_t>(le(in, p, 4));
      REQUIRE(clen == 0);  // uncompressed
      p += 4 + clen;
      const size_t rlen = static_cast<size_t>(le(in, p, 8));
      p += 8;
      out.insert(out.end(), in.begin() + static_cast<ptrdiff_t>(p), in.begin() + static_cast<ptrdiff_t>(p + rlen));
    } else if (op != static_cast<uint8_t>(mcap::Op::kMessageIndex)) {
      out.insert(out.end(), in.begin() + static_cast<ptrdiff_t>(pos), in.begin() + static_cast<ptrdiff_t>(body + len));
    }
    pos = body + len;
  }
  out.push_back(static_cast<uint8_t>(mcap::Op::kDataEnd));
  put_le(out, 4, 8);
  put_le(out, 0, 4);  // no data section CRC
  out.push_back(static_cast<uint8_t>(mcap::Op::kFooter));
  put_le(out, 20, 8);
  put_le(out, 0, 8);  // no summary
  put_le(out, 0, 8);
  put_le(out, 0, 4);
  out.insert(out.end(), mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  return out;
}

}  // namespace

TEST_CASE("replay holds decoded events of the chunks in use only, whatever the recording length", "[unit]") {
  const std::string dir = test_dir("streaming");
  size_t peak_short = 0;
  for (const int64_t seconds : {5, 40}) {
    SyntheticOptions so;
    so.duration_ns = seconds * 1'000'000'000;
    const auto events = synthetic_events(11, so);
    const std::string path = dir + "/s" + std::to_string(seconds) + ".mcap";
    REQUIRE(write_fixture(path, events).ok());
    const auto r = replay_all(path);
    CHECK(r.events == events);
    INFO(seconds << " s: " << events.size() << " events, at most " << r.holding.peak_events << " held");
    CHECK(r.holding.events == 0);
    CHECK(r.holding.chunks_read >= static_cast<size_t>(seconds));
    // Chunks close every second of stream time: the source holds about one chunk.
    CHECK(r.holding.peak_events <= 2 * max_events_per_second(events));
    if (seconds == 5) peak_short = r.holding.peak_events;
    else CHECK(r.holding.peak_events <= peak_short + peak_short / 4);
  }
}

TEST_CASE("a replayed fixture's bytes are not kept resident once consumed", "[unit]") {
  SyntheticOptions so;
  so.duration_ns = 4'000'000'000;
  so.ping_rows = 600;
  so.ping_cols = 512;
  so.labels = false;
  const auto events = synthetic_events(12, so);
  const std::string path = std::filesystem::absolute(test_dir("streaming") + "/full_res_raw.mcap").string();
  WriterOptions o;
  o.compress = false;  // the largest file for the stream
  o.chunk_max_stream_ns = 250'000'000;
  REQUIRE(write_fixture(path, events, {}, o).ok());
  const uint64_t file_kb = std::filesystem::file_size(path) / 1024;
  const auto r = replay_all(path, 16);
  CHECK(r.events == events);
  INFO("file " << file_kb << " kB, mapping resident at most " << r.peak_mapped_kb << " kB");
#ifdef __linux__
  // Each chunk is ~1/16 of the file; a whole-file map that keeps every touched page
  // would show the whole file here.
  CHECK(r.peak_mapped_kb <= file_kb / 4);
#endif
}

TEST_CASE("messages outside chunks replay in order and are read lazily", "[unit]") {
  SyntheticOptions so;
  so.duration_ns = 12'000'000'000;
  const auto events = synthetic_events(13, so);
  const std::string dir = test_dir("streaming");
  WriterOptions o;
  o.compress = false;
  REQUIRE(write_fixture(dir + "/chunked.mcap", events, {}, o).ok());
  write_bytes(dir + "/loose.mcap", unchunked(read_bytes(dir + "/chunked.mcap")));
  const auto r = replay_all(dir + "/loose.mcap");
  CHECK(r.events == events);
  INFO(events.size() << " loose messages, at most " << r.holding.peak_events << " held");
  CHECK(r.holding.peak_events <= 2 * max_events_per_second(events));
  CHECK(r.holding.events == 0);
}
