// Issue 40: the one decision about whether a fixture is whole (cut_input_warning), the
// sensor time a cut file still holds, and recover_fixture making a cut recording whole.
#include <catch2/catch.hpp>

#include <filesystem>

#include "replay/fixture.hpp"
#include "replay/mcap_reader.hpp"
#include "replay/recover.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;

namespace {

std::string recover_test_dir() {
  return case_dir("recover", Catch::getResultCapture().getCurrentTestName(), true).string();
}

// A 4 s synthetic recording with an attachment, cut at 60 % of its bytes.
struct CutRecording {
  std::string whole, cut;
  std::vector<Event> events;
};
CutRecording make_cut_recording(const std::string& dir) {
  SyntheticOptions so;
  so.duration_ns = 4'000'000'000;
  CutRecording c{dir + "/whole.mcap", dir + "/cut.mcap", synthetic_events(7, so)};
  {
    auto w = FixtureWriter::open(c.whole, {{"scene", "x"}});
    REQUIRE(w.ok());
    REQUIRE((*w)->attach({"orthosonar_scene.yaml", "application/yaml", {'a', ':', ' ', '1'}, 0, 0}).ok());
    for (const auto& e : c.events) REQUIRE((*w)->write(e).ok());
    REQUIRE((*w)->close().ok());
  }
  auto bytes = read_bytes(c.whole);
  bytes.resize(bytes.size() * 6 / 10);
  write_bytes(c.cut, bytes);
  return c;
}

}  // namespace

TEST_CASE("cut_input_warning: nothing for a whole file; file, byte offset, seconds and messages for a cut one",
          "[unit][recover]") {
  const auto c = make_cut_recording(recover_test_dir());
  const auto whole = read_fixture(c.whole);
  REQUIRE(whole.error.empty());
  CHECK_FALSE(cut_input_warning(c.whole, whole.recovery).has_value());
  CHECK(whole.recovery.sensor_seconds() > 3.9);

  const auto cut = read_fixture(c.cut);
  REQUIRE(cut.error.empty());
  const auto w = cut_input_warning(c.cut, cut.recovery);
  REQUIRE(w.has_value());
  INFO(*w);
  CHECK(w->find(c.cut + ": input cut at byte offset " + std::to_string(cut.recovery.bytes_recovered) + " of ") == 0);
  CHECK(w->find(std::to_string(cut.recovery.messages_recovered) + " messages") != std::string::npos);
  // The sensor time held is that of the recovered events (chunk headers span them).
  REQUIRE_FALSE(cut.events.empty());
  const double span_s = (cut.events.back().stamp - cut.events.front().stamp).seconds();
  CHECK(cut.recovery.sensor_seconds() >= span_s - 1e-9);
  CHECK(cut.recovery.sensor_seconds() < 3.9);
  CHECK(w->find(" s of sensor time") != std::string::npos);
}

TEST_CASE("recover_fixture rewrites a cut recording whole: same events, attachments, summary and footer",
          "[unit][recover]") {
  const std::string dir = recover_test_dir();
  const auto c = make_cut_recording(dir);
  const auto cut = read_fixture(c.cut);
  REQUIRE(cut.error.empty());
  REQUIRE_FALSE(cut.recovery.complete);
  REQUIRE_FALSE(cut.events.empty());

  auto r = recover_fixture(c.cut, dir + "/out.mcap");
  REQUIRE(r.ok());
  CHECK(r->events == cut.events.size());
  CHECK(r->attachments == 1);
  CHECK_FALSE(std::filesystem::exists(dir + "/out.mcap.partial"));
  const auto back = read_fixture(dir + "/out.mcap");
  REQUIRE(back.error.empty());
  CHECK(back.recovery.complete);
  CHECK(back.events == cut.events);
  CHECK(back.metadata.at("scene") == "x");
  CHECK(back.metadata.at("recovered_from").find("byte offset " + std::to_string(cut.recovery.bytes_recovered)) !=
        std::string::npos);
  // Indexed: the summary is present and used (no linear scan), chunks are there.
  auto file = mcap::MappedFile::open(dir + "/out.mcap");
  REQUIRE(file.ok());
  auto layout = mcap::scan(**file);
  REQUIRE(layout.ok());
  CHECK(layout->read.summary_present);
  CHECK_FALSE(layout->read.read_by_linear_scan);
  CHECK(layout->read.chunk_count > 0);
  REQUIRE(layout->attachments.size() == 1);
  CHECK(layout->attachments[0].name == "orthosonar_scene.yaml");

  // A whole input is rewritten unchanged in content, without "recovered_from".
  auto again = recover_fixture(c.whole, dir + "/whole_again.mcap");
  REQUIRE(again.ok());
  const auto w = read_fixture(dir + "/whole_again.mcap");
  CHECK(w.metadata.count("recovered_from") == 0);
  CHECK(w.events.size() == c.events.size());

  // An unreadable input is an error naming it; nothing is left behind.
  write_bytes(dir + "/junk.mcap", {1, 2, 3});
  auto bad = recover_fixture(dir + "/junk.mcap", dir + "/junk_out.mcap");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("junk.mcap") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir + "/junk_out.mcap"));
  CHECK_FALSE(std::filesystem::exists(dir + "/junk_out.mcap.partial"));
}
