#include "replay/recording.hpp"

#include <catch2/catch.hpp>

#include "hal/fake_source.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;

TEST_CASE("recording passes events through unchanged and replays them identically", "[unit]") {
  const auto events = synthetic_events(11);
  const std::string path = testing::test_dir("recording") + "/rec.mcap";
  auto rec = RecordingSource::open(std::make_unique<hal::FakeSource>(events), path, {{"scene", "rec"}});
  REQUIRE(rec.ok());
  std::vector<Event> seen;
  for (;;) {
    auto p = (*rec)->next();
    REQUIRE_FALSE(p.error);
    if (p.end_of_stream) break;
    seen.push_back(*p.event);
  }
  CHECK(seen == events);
  CHECK((*rec)->recorded() == events.size());
  const auto back = testing::read_fixture(path);
  REQUIRE(back.error.empty());
  CHECK(back.recovery.complete);
  CHECK(back.events == events);
  CHECK(back.metadata.at("scene") == "rec");
}

TEST_CASE("recording passes an inner fault on and keeps recording", "[unit]") {
  const auto events = synthetic_events(12);
  const std::string path = testing::test_dir("recording") + "/fault.mcap";
  auto rec = RecordingSource::open(std::make_unique<hal::FakeSource>(events, size_t{5}), path, {});
  REQUIRE(rec.ok());
  int faults = 0;
  size_t n = 0;
  for (;;) {
    auto p = (*rec)->next();
    if (p.error) {
      ++faults;
      continue;
    }
    if (p.end_of_stream) break;
    ++n;
  }
  CHECK(faults == 1);
  CHECK(n == events.size());
  CHECK(testing::read_fixture(path).events == events);
}
