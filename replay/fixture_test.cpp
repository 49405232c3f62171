#include "replay/fixture.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>

#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;

namespace {
FixtureMetadata meta() { return {{"scene", "harbor"}, {"seed", "7"}, {"T_V_h", "0.1 0 0.2 0 0 0"}}; }
}  // namespace

TEST_CASE("fixture round trip is exact for every payload type zstd chunks", "[unit]") {
  const auto events = synthetic_events(1);
  const std::string path = test_dir("roundtrip") + "/zstd.mcap";
  REQUIRE(write_fixture(path, events, meta()).ok());
  const auto back = read_fixture(path);
  REQUIRE(back.error.empty());
  CHECK(back.recovery.complete);
  CHECK(back.recovery.messages_recovered == events.size());
  CHECK(back.metadata == meta());
  REQUIRE(back.events.size() == events.size());
  CHECK(back.events == events);
  std::array<int, kChannelCount> seen{};
  for (const auto& e : back.events) ++seen[static_cast<size_t>(e.channel)];
  for (int n : seen) CHECK(n > 0);
}

TEST_CASE("fixture round trip is exact uncompressed with 16-bit images and tiny chunks", "[unit]") {
  SyntheticOptions so;
  so.bytes_per_pixel = 2;
  const auto events = synthetic_events(2, so);
  WriterOptions o;
  o.compress = false;
  o.chunk_max_bytes = 4096;
  const std::string path = test_dir("roundtrip") + "/raw16.mcap";
  REQUIRE(write_fixture(path, events, {}, o).ok());
  const auto back = read_fixture(path);
  REQUIRE(back.error.empty());
  CHECK(back.events == events);
}

TEST_CASE("fixture replays in stamp channel sequence order whatever the recording order", "[unit]") {
  auto events = synthetic_events(3);
  std::reverse(events.begin(), events.end());
  const std::string path = test_dir("order") + "/reversed.mcap";
  WriterOptions o;
  o.chunk_max_stream_ns = 200'000'000;
  REQUIRE(write_fixture(path, events, {}, o).ok());
  const auto back = read_fixture(path);
  REQUIRE(back.error.empty());
  std::sort(events.begin(), events.end(), event_before);
  CHECK(back.events == events);
}

TEST_CASE("a chunk is closed at least every second of stream time", "[unit]") {
  SyntheticOptions so;
  so.duration_ns = 5'000'000'000;
  so.ping_rate_hz = 0;
  const auto events = synthetic_events(4, so);
  const std::string dir = test_dir("chunks");
  REQUIRE(write_fixture(dir + "/a.mcap", events).ok());
  // Cut the file in the middle of its last second: at least 4 seconds must remain.
  auto bytes = read_bytes(dir + "/a.mcap");
  const auto full = read_fixture(dir + "/a.mcap");
  REQUIRE(full.error.empty());
  bytes.resize(bytes.size() * 9 / 10);
  write_bytes(dir + "/cut.mcap", bytes);
  const auto cut = read_fixture(dir + "/cut.mcap");
  REQUIRE(cut.error.empty());
  CHECK_FALSE(cut.recovery.complete);
  REQUIRE_FALSE(cut.events.empty());
  CHECK(cut.events.back().stamp >= Time::from_s(3));
  CHECK(cut.recovery.messages_recovered == cut.events.size());
  CHECK(cut.recovery.bytes_recovered < bytes.size());
  CHECK(cut.recovery.detail.find("byte offset") != std::string::npos);
}

TEST_CASE("a recording killed mid-write stays readable up to its last complete chunk", "[unit]") {
  const std::string path = test_dir("sigkill") + "/killed.mcap";
  std::filesystem::remove(path);
  int pipefd[2];
  REQUIRE(::pipe(pipefd) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    // Child: record an endless stream, telling the parent after every 50 events.
    ::close(pipefd[0]);
    WriterOptions o;
    o.chunk_max_stream_ns = 100'000'000;
    auto w = FixtureWriter::open(path, {{"scene", "killed"}}, o);
    if (!w) ::_exit(3);
    SyntheticOptions so;
    so.duration_ns = 1'000'000'000;
    uint64_t round = 0;
    std::array<uint64_t, kChannelCount> seq{};
    for (;;) {
      for (auto e : synthetic_events(round, so)) {
        e.stamp = e.stamp + Time::from_s(static_cast<int64_t>(round));
        std::visit([&](auto& x) { x.stamp = e.stamp; }, e.payload);
        e.sequence = seq[static_cast<size_t>(e.channel)]++;
        if (!(*w)->write(e).ok()) ::_exit(4);
      }
      const char c = 'x';
      if (::write(pipefd[1], &c, 1) != 1) ::_exit(5);
      ++round;
    }
  }
  ::close(pipefd[1]);
  char c = 0;
  for (int i = 0; i < 3; ++i) REQUIRE(::read(pipefd[0], &c, 1) == 1);
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(pipefd[0]);
  REQUIRE(WIFSIGNALED(status));
  const auto back = read_fixture(path);
  INFO(back.error);
  REQUIRE(back.error.empty());
  CHECK_FALSE(back.recovery.complete);
  CHECK(back.metadata.at("scene") == "killed");
  // Three whole seconds were handed to the writer; chunks close every 0.1 s.
  CHECK(back.events.size() >= 100);
  CHECK(back.events.back().stamp >= Time::from_ms(2500));
  CHECK(back.recovery.messages_recovered == back.events.size());
}

TEST_CASE("the writer rejects events it cannot store exactly", "[unit]") {
  const std::string path = test_dir("reject") + "/r.mcap";
  auto w = FixtureWriter::open(path, {});
  REQUIRE(w.ok());
  Event e{Time::from_ms(1), Channel::kDvl, 0, DepthReading{Time::from_ms(1), 1.0}};
  auto s = (*w)->write(e);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find(path) != std::string::npos);
  // A rejected event writes nothing: the file stays valid and closes cleanly.
  CHECK((*w)->close().ok());
  const auto back = read_fixture(path);
  CHECK(back.error.empty());
  CHECK(back.events.empty());
  Event neg{Time::from_ns(-5), Channel::kDepth, 0, DepthReading{Time::from_ns(-5), 1.0}};
  auto w2 = FixtureWriter::open(path, {});
  REQUIRE(w2.ok());
  CHECK_FALSE((*w2)->write(neg).ok());
}
