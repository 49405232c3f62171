// Replay order (SPEC §9): whatever order events were recorded in, a fixture yields them
// in (stamp, channel, sequence) order. Seeds printed by rapidcheck.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>

#include "property_tests/replay_event_gen.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/fixture/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;

TEST_CASE("any recording order replays in stamp channel sequence order", "[property]") {
  const std::string dir = testing::test_dir("property_order");
  rc::prop("a permutation of the input gives the same yielded order", [&] {
    // Few distinct stamps, so ties on stamp (and on stamp and channel) are common.
    const auto sorted = orthosonar::replay_gen::any_events(60, 5'000'000'000, 250'000'000);
    std::vector<Event> shuffled = sorted;
    for (size_t i = shuffled.size(); i > 1; --i)  // Fisher-Yates with rapidcheck's draws
      std::swap(shuffled[i - 1], shuffled[*rc::gen::inRange<size_t>(0, i)]);
    WriterOptions o;
    o.compress = *rc::gen::arbitrary<bool>();
    o.chunk_max_stream_ns = *rc::gen::inRange<int64_t>(1, 2'000'000'000);
    o.chunk_max_bytes = *rc::gen::inRange<uint64_t>(1, 4000);
    const std::string path = dir + "/perm.mcap";
    RC_ASSERT(testing::write_fixture(path, shuffled, {}, o).ok());
    const auto back = testing::read_fixture(path);
    RC_ASSERT(back.error.empty());
    RC_ASSERT(back.events == sorted);
  });
}
