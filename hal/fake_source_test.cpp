#include "hal/fake_source.hpp"

#include <catch2/catch.hpp>

using namespace orthosonar;

TEST_CASE("fake source yields events in (stamp, channel, sequence) order then ends", "[hal]") {
  std::vector<Payload> payloads = {
      DepthReading{Time::from_ms(200), 3.0}, ImuReading{Time::from_ms(100), Quat::Identity()},
      DvlReading{Time::from_ms(100), Vec3(0.3, 0, 0), true, 5.0}, DepthReading{Time::from_ms(100), 3.1}};
  hal::FakeSource src(hal::make_events(payloads));
  std::vector<Event> got;
  for (;;) {
    auto p = src.next();
    REQUIRE_FALSE(p.error);
    if (p.end_of_stream) break;
    got.push_back(*p.event);
  }
  REQUIRE(got.size() == 4);
  CHECK(got[0].channel == Channel::kImu);
  CHECK(got[1].channel == Channel::kDvl);
  CHECK(got[2].channel == Channel::kDepth);
  CHECK(got[2].sequence == 0);
  CHECK(got[3].sequence == 1);
  CHECK(std::is_sorted(got.begin(), got.end(), event_before));
}

TEST_CASE("fake source reports an injected fault as a value, then continues", "[hal]") {
  hal::FakeSource src(hal::make_events({DepthReading{Time::from_ms(1), 1.0}}), 0);
  auto first = src.next();
  REQUIRE(first.error);
  CHECK(first.error->message.find("injected") != std::string::npos);
  auto second = src.next();
  REQUIRE(second.event);
  CHECK(src.next().end_of_stream);
}
