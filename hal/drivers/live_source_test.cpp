#include <catch2/catch.hpp>
#include <atomic>
#include <thread>

#include "hal/drivers/emulator.hpp"
#include "hal/drivers/live_source.hpp"
#include "hal/drivers/test_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;
using testing::count_channel;

namespace {

// Runs a live source against a started emulator until the emulator finished and the queue
// drained (bounded by `limit`); returns the consumed events.
std::vector<Event> consume(LiveSource& live, MissionEmulator& emu, std::chrono::milliseconds limit) {
  std::vector<Event> out;
  const auto until = std::chrono::steady_clock::now() + limit;
  std::atomic<int64_t> last_event_ns{std::chrono::steady_clock::now().time_since_epoch().count()};
  // Stops once the emulator sent everything and nothing arrived for 500 ms (or at the limit).
  std::thread stopper([&] {
    while (std::chrono::steady_clock::now() < until) {
      const int64_t quiet = std::chrono::steady_clock::now().time_since_epoch().count() - last_event_ns.load();
      if (emu.finished() && quiet > 500'000'000) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    live.stop();
  });
  for (;;) {
    auto p = live.next();
    if (p.end_of_stream) break;
    if (p.event) {
      out.push_back(std::move(*p.event));
      last_event_ns.store(std::chrono::steady_clock::now().time_since_epoch().count());
    }
  }
  stopper.join();
  return out;
}

void check_contract(const std::vector<Event>& events) {
  std::array<uint64_t, kChannelCount> seq{};
  for (size_t i = 0; i < events.size(); ++i) {
    if (i > 0) REQUIRE(event_before(events[i - 1], events[i]));
    REQUIRE(events[i].sequence == seq[static_cast<size_t>(events[i].channel)]++);
    REQUIRE(stamp_of(events[i].payload) == events[i].stamp);
    REQUIRE(channel_of(events[i].payload) == events[i].channel);
  }
}

struct Rig {
  std::unique_ptr<MissionEmulator> emu;
  std::unique_ptr<LiveSource> live;
};

Rig make_rig(const std::vector<Event>& mission, EmulatorOptions eo, uint16_t h_part_from_config) {
  Rig r;
  r.emu = std::make_unique<MissionEmulator>(mission, eo);
  REQUIRE(r.emu->start().ok());
  LiveConfig lc = r.emu->live_config();
  lc.reconnect.initial_backoff_ms = 20;
  lc.reconnect.max_backoff_ms = 200;
  lc.reconnect.connect_timeout_ms = 500;
  for (auto& d : lc.devices)
    if (d.name == "sonar_h") d.part_number = h_part_from_config;  // 0: learn it from the status message
  r.live = std::make_unique<LiveSource>(lc);
  REQUIRE(r.live->start().ok());
  for (const char* s : {"sonar_h", "sonar_v"}) {
    const uint16_t port = r.live->status_port(s);
    REQUIRE(port != 0);
    r.emu->set_status_port(s, port);
  }
  return r;
}

}  // namespace

TEST_CASE("live run through emulators delivers every event and its recording replays identically", "[hal]") {
  const auto mission = testing::synthetic_mission(1000);
  EmulatorOptions eo;
  eo.rate = 4.0;
  eo.status_period_ms = 50;
  Rig rig = make_rig(mission, eo, 0);
  const auto consumed = consume(*rig.live, *rig.emu, std::chrono::milliseconds(8000));
  const LiveReport report = rig.live->report();
  INFO(report_json(report));
  std::string emu_stats;
  for (const auto& s : rig.emu->stats())
    emu_stats += s.name + " sent " + std::to_string(s.sent) + " unsent " + std::to_string(s.unsent) + " of " +
                 std::to_string(s.frames) + " clients " + std::to_string(s.clients) + "; ";
  INFO(emu_stats);
  check_contract(consumed);
  for (Channel c : {Channel::kSonarHorizontal, Channel::kSonarVertical, Channel::kImu, Channel::kDvl, Channel::kDepth})
    CHECK(count_channel(consumed, c) == count_channel(mission, c));
  // Payload content survives the wire (images exactly, navigation to float precision).
  size_t pings = 0;
  for (const auto& e : consumed) {
    if (const auto* p = std::get_if<SonarPing>(&e.payload)) {
      const auto want = testing::small_ping(p->mount, p->ping_id, Time(), 40, 32);
      CHECK(p->image == want.image);
      CHECK(p->rows == 40);
      CHECK(p->cols == 32);
      CHECK(p->part_number == (p->mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d));
      ++pings;
    }
  }
  CHECK(pings == 12);
  for (const auto& s : rig.emu->stats())
    if (s.name.rfind("sonar", 0) == 0) CHECK(s.last_fire_version == 2);
  // The recording is exactly the consumed stream: replaying it yields the same events.
  hal::FakeSource replay(consumed);
  std::vector<Event> replayed;
  for (auto p = replay.next(); !p.end_of_stream; p = replay.next()) replayed.push_back(*p.event);
  CHECK(replayed == consumed);
  for (const auto& d : report.devices) CHECK(d.health.messages_malformed == 0);
}

TEST_CASE("a device restart is survived with backoff and the gap is reported", "[hal]") {
  const auto mission = testing::synthetic_mission(2000);
  EmulatorOptions eo;
  eo.rate = 4.0;
  eo.oculus_version = 1;
  eo.outages.push_back({"imu", Time::from_ms(600), Time::from_ms(600)});
  Rig rig = make_rig(mission, eo, kPartM750d);
  const auto consumed = consume(*rig.live, *rig.emu, std::chrono::milliseconds(10000));
  check_contract(consumed);
  const LiveReport report = rig.live->report();
  INFO(report_json(report));
  const DeviceReport* imu = nullptr;
  for (const auto& d : report.devices)
    if (d.name == "imu") imu = &d;
  REQUIRE(imu != nullptr);
  CHECK(imu->health.reconnects >= 1);
  REQUIRE_FALSE(imu->gaps.empty());
  CHECK(imu->gaps.front().to != Time::max());
  CHECK(imu->gaps.front().to > imu->gaps.front().from);
  // IMU data resumed after the restart, and the stream shows the hole (> 100 ms wall at 50 Hz / 4x).
  Time last, biggest;
  bool first = true;
  for (const auto& e : consumed) {
    if (e.channel != Channel::kImu) continue;
    if (!first && e.stamp - last > biggest) biggest = e.stamp - last;
    last = e.stamp;
    first = false;
  }
  CHECK(biggest > Time::from_ms(100));
  CHECK(count_channel(consumed, Channel::kImu) < count_channel(mission, Channel::kImu));
  size_t after_gap = 0;
  for (const auto& e : consumed) after_gap += e.channel == Channel::kImu && e.stamp > imu->gaps.front().to;
  CHECK(after_gap > 0);
  CHECK(imu->connect_failures >= 1);
  for (const auto& s : rig.emu->stats())
    if (s.name.rfind("sonar", 0) == 0) CHECK(s.last_fire_version == 1);
}

TEST_CASE("queue drops the oldest sonar ping on overflow and never navigation", "[hal]") {
  int64_t t = 0;
  LiveQueue q([&t] { return Time::from_ns(t); }, QueuePolicy{3, 1000});
  for (uint32_t i = 0; i < 10; ++i) {
    q.push(testing::small_ping(SonarMount::kHorizontal, i, Time(), 2, 2));
    q.push(DepthReading{Time(), 1.0 * i});
  }
  const QueueStats st = q.stats();
  CHECK(st.dropped[static_cast<size_t>(Channel::kSonarHorizontal)] == 7);
  CHECK(st.dropped[static_cast<size_t>(Channel::kDepth)] == 0);
  std::vector<Event> out;
  while (auto e = q.pop(std::chrono::milliseconds(0))) out.push_back(*e);
  REQUIRE(out.size() == 13);
  std::vector<uint32_t> ids;
  for (size_t i = 0; i < out.size(); ++i) {
    if (i > 0) CHECK(out[i - 1].stamp < out[i].stamp);  // same clock reading: still strictly increasing
    if (const auto* p = std::get_if<SonarPing>(&out[i].payload)) ids.push_back(p->ping_id);
  }
  CHECK(ids == std::vector<uint32_t>{7, 8, 9});
  CHECK(out.back().sequence == 9);
}
