#include "replay/fixture_summary.hpp"

#include <catch2/catch.hpp>

#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;

TEST_CASE("summary reports counts rates and gaps longer than twice the nominal period", "[unit]") {
  std::vector<Event> ev;
  uint64_t seq = 0;
  for (int i = 0; i < 40; ++i) {
    if (i >= 20 && i < 25) continue;  // a 0.6 s hole in a 10 Hz stream
    const Time t = Time::from_ms(100 * i);
    ev.push_back({t, Channel::kDepth, seq++, DepthReading{t, 2.0}});
  }
  const std::string path = testing::test_dir("summary") + "/gap.mcap";
  REQUIRE(testing::write_fixture(path, ev, {{"scene", "gap"}}).ok());
  const auto s = summarize_fixture(path);
  REQUIRE(s.ok());
  CHECK(s->messages == 35);
  CHECK(s->duration() == Time::from_ms(3900));
  CHECK(s->metadata.at("scene") == "gap");
  REQUIRE(s->channels.size() == 1);
  const auto& c = s->channels[0];
  CHECK(c.topic == "/depth");
  CHECK(c.schema == "orthosonar_msgs/Depth");
  CHECK(c.nominal_period == Time::from_ms(100));
  CHECK(c.rate_hz == Approx(34.0 / 3.9));
  REQUIRE(c.gaps.size() == 1);
  CHECK(c.gaps[0].from == Time::from_ms(1900));
  CHECK(c.gaps[0].to == Time::from_ms(2500));
  CHECK(has_mcap_magic(path));
}

TEST_CASE("summary of a non-MCAP file is an error naming it", "[unit]") {
  const std::string path = testing::test_dir("summary") + "/text.bin";
  testing::write_bytes(path, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
  CHECK_FALSE(has_mcap_magic(path));
  const auto s = summarize_fixture(path);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find(path) != std::string::npos);
}
