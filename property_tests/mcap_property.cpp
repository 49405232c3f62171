// MCAP fixture properties: exact round trips of random events, and a reader that never
// crashes on corrupted files (run under the asan preset too). Seeds printed by rapidcheck;
// RC_PARAMS="seed=..." replays a failure.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>

#include "property_tests/replay_event_gen.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/fixture/fixture_summary.hpp"
#include "replay/fixture/synthetic.hpp"
#include "replay/fixture/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;

namespace {

WriterOptions any_writer_options() {
  WriterOptions o;
  o.compress = *rc::gen::arbitrary<bool>();
  o.chunk_max_bytes = *rc::gen::inRange<uint64_t>(1, 20000);
  o.chunk_max_stream_ns = *rc::gen::inRange<int64_t>(1, 3'000'000'000);
  o.zstd_level = *rc::gen::inRange(1, 4);
  return o;
}

// Finds an event of `original` (sorted, unique keys) with the same key; nullptr if none.
const Event* find_key(const std::vector<Event>& original, const Event& e) {
  auto it = std::lower_bound(original.begin(), original.end(), e, event_before);
  if (it == original.end() || event_before(e, *it)) return nullptr;
  return &*it;
}

}  // namespace

TEST_CASE("N random events written and read back are identical", "[property]") {
  const std::string dir = testing::test_dir("property_roundtrip");
  rc::prop("write then read is the identity on events and metadata", [&] {
    const auto events = orthosonar::replay_gen::any_events(40, int64_t{4'000'000'000} * 1'000'000'000);
    const FixtureMetadata meta = *rc::gen::container<std::map<std::string, std::string>>(
        rc::gen::string<std::string>(), rc::gen::string<std::string>());
    const std::string path = dir + "/rt.mcap";
    RC_ASSERT(testing::write_fixture(path, events, meta, any_writer_options()).ok());
    const auto back = testing::read_fixture(path);
    RC_ASSERT(back.error.empty());
    RC_ASSERT(back.recovery.complete);
    RC_ASSERT(back.recovery.messages_recovered == events.size());
    RC_ASSERT(back.metadata == meta);
    RC_ASSERT(back.events == events);
  });
}

TEST_CASE("random corruption of a valid fixture never crashes the reader", "[property]") {
  const std::string dir = testing::test_dir("property_corrupt");
  SyntheticOptions so;
  so.duration_ns = 600'000'000;
  so.ping_rows = 8;
  so.ping_cols = 6;
  const auto events = synthetic_events(77, so);
  std::vector<std::vector<uint8_t>> originals;
  for (bool compress : {true, false}) {
    WriterOptions o;
    o.compress = compress;
    o.chunk_max_stream_ns = 150'000'000;
    const std::string path = dir + "/valid.mcap";
    REQUIRE(testing::write_fixture(path, events, {{"scene", "corrupt"}}, o).ok());
    originals.push_back(testing::read_bytes(path));
  }
  rc::prop("flips, truncation and insertion give events, a recovery or an error", [&] {
    auto bytes = originals[*rc::gen::inRange<size_t>(0, originals.size())];
    const int mutations = *rc::gen::inRange(1, 4);
    for (int m = 0; m < mutations && !bytes.empty(); ++m) {
      const int kind = *rc::gen::inRange(0, 3);
      const size_t at = *rc::gen::inRange<size_t>(0, bytes.size());
      if (kind == 0) {
        bytes[at] ^= *rc::gen::inRange<uint8_t>(1, 255);
      } else if (kind == 1) {
        bytes.resize(at);
      } else {
        const auto ins = *rc::gen::nonEmpty(rc::gen::container<std::vector<uint8_t>>(rc::gen::arbitrary<uint8_t>()));
        bytes.insert(bytes.begin() + static_cast<ptrdiff_t>(at), ins.begin(), ins.end());
      }
    }
    const std::string path = dir + "/corrupt.mcap";
    testing::write_bytes(path, bytes);
    const auto back = testing::read_fixture(path);
    if (!back.error.empty()) {
      RC_ASSERT(back.error.find(path) != std::string::npos);
    } else if (back.recovery.complete) {
      RC_ASSERT(back.events == events);  // every byte is covered by a CRC: no silent change
    }
    for (const auto& e : back.events) {
      const Event* o = find_key(events, e);
      RC_ASSERT(o != nullptr);
      RC_ASSERT(*o == e);
    }
    (void)summarize_fixture(path);
  });
}
