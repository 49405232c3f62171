// Import and export (issue 18): topics.yaml, exact round trips through a ROS 1 bag and a
// ROS 2 MCAP recording, JPEG and ProjectedSonarImage round trips within their losses,
// and the errors a user meets.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "replay/fixture/fixture.hpp"
#include "replay/ros/export.hpp"
#include "replay/ros/import.hpp"
#include "replay/ros/topic_map.hpp"
#include "replay/fixture/synthetic.hpp"
#include "replay/fixture/testing.hpp"

namespace orthosonar::replay::ros {
namespace {

namespace fs = std::filesystem;

std::string dir_for(const std::string& name) { return testing::case_dir("ros_import", name, true).string(); }

std::vector<uint8_t> file_bytes(const std::string& path) { return testing::read_bytes(path); }

std::vector<Event> read_all(const std::string& path) {
  auto back = testing::read_fixture(path);
  REQUIRE(back.error.empty());
  return std::move(back.events);
}

// Synthetic events as real devices report them, so that the ROS types hold them exactly:
// int16 centidegree bearings, float32 depth, the Oculus modes' frequencies, no labels.
std::vector<Event> representable_events(uint64_t seed) {
  SyntheticOptions o;
  o.duration_ns = 1'500'000'000;
  o.labels = false;
  auto events = synthetic_events(seed, o);
  for (Event& e : events) {
    if (auto* p = std::get_if<SonarPing>(&e.payload)) {
      for (double& b : p->bearings_rad) {
        const auto c = static_cast<int16_t>(std::lround(b / (0.01 * std::numbers::pi / 180.0)));
        b = c * 0.01 * (std::numbers::pi / 180.0);
      }
      p->part_number = p->mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
      p->frequency_hz = p->mount == SonarMount::kHorizontal ? 750e3 : 1.2e6;
      p->device_id = p->mount == SonarMount::kHorizontal ? 7 : 8;
    } else if (auto* d = std::get_if<DepthReading>(&e.payload)) {
      d->depth_m = static_cast<double>(static_cast<float>(d->depth_m));
    } else if (auto* v = std::get_if<DvlReading>(&e.payload)) {
      if (!v->valid) v->velocity_V_mps = Vec3::Zero();
      if (v->altitude_m < 0) v->altitude_m = 0;
    }
  }
  return events;
}

std::string write_fixture(const std::string& path, const std::vector<Event>& events) {
  const FixtureMetadata md{{"T_V_h", "0.25 0 0.1 0 0 0"}, {"T_V_v", "0.25 0 -0.1 1.5707963267948966 0 0"}};
  REQUIRE(testing::write_fixture(path, events, md).ok());
  return path;
}

ImportOptions options_from(const std::string& yaml_path) {
  auto map = load_topic_map(yaml_path);
  INFO((map.ok() ? "" : map.error().message));
  REQUIRE(map.ok());
  ImportOptions o;
  o.map = *map;
  return o;
}

}  // namespace

TEST_CASE("topics.yaml maps topics to roles, with stamps, conventions and mounts", "[ros][import]") {
  const std::string yaml =
      "stamp: receive\n"
      "topics:\n"
      "  /oculus/h: {role: horizontal_sonar, device_id: 12, flip_bearings: true}\n"
      "  /oculus/v: vertical_sonar\n"
      "  /imu/data: {role: imu, convention: ned_frd, stamp: header}\n"
      "  /pressure: {role: depth, fluid_density: 1000, atmospheric_pressure: 100000}\n"
      "mounts:\n"
      "  horizontal: {xyz: [0.3, 0, 0.1], rpy_deg: [0, 0, 90]}\n"
      "  vertical: \"0.3 0 -0.1 1.5 0 0\"\n";
  auto m = parse_topic_map(yaml, "topics.yaml");
  INFO((m.ok() ? "" : m.error().message));
  REQUIRE(m.ok());
  const TopicRule* h = m->find("/oculus/h");
  REQUIRE(h != nullptr);
  CHECK(h->role == Role::kHorizontalSonar);
  CHECK(h->device_id == 12);
  CHECK(h->flip_bearings);
  CHECK(h->stamp == StampSource::kReceive);
  CHECK(m->find("/oculus/v")->role == Role::kVerticalSonar);
  CHECK(m->find("/imu/data")->convention == Convention::kNedFrd);
  CHECK(m->find("/imu/data")->stamp == StampSource::kHeader);
  CHECK(m->find("/pressure")->fluid_density_kg_m3 == 1000.0);
  CHECK(m->T_V_h == "0.29999999999999999 0 0.10000000000000001 0 0 1.5707963267948966");
  CHECK(m->T_V_v == "0.29999999999999999 0 -0.10000000000000001 1.5 0 0");
  // The authors' topics follow unless `defaults: false`.
  CHECK(m->find("/vn100/imu/raw") != nullptr);
  auto no_defaults = parse_topic_map("defaults: false\ntopics: {/a: imu}\n", "t.yaml");
  REQUIRE(no_defaults.ok());
  CHECK(no_defaults->find("/vn100/imu/raw") == nullptr);
  // What topic_map_yaml writes parses back to the same rules.
  auto again = parse_topic_map(topic_map_yaml(*m, false), "again.yaml");
  REQUIRE(again.ok());
  REQUIRE(again->rules.size() == m->rules.size());
  for (size_t i = 0; i < m->rules.size(); ++i) {
    CHECK(again->rules[i].topic == m->rules[i].topic);
    CHECK(again->rules[i].role == m->rules[i].role);
    CHECK(again->rules[i].stamp == m->rules[i].stamp);
    CHECK(again->rules[i].device_id == m->rules[i].device_id);
  }
  CHECK(again->T_V_h == m->T_V_h);
}

TEST_CASE("topics.yaml errors name the file and the key", "[ros][import]") {
  const std::pair<const char*, const char*> cases[] = {
      {"topics: {/a: {role: sonar}}\n", "topics./a.role: unknown role 'sonar'"},
      {"topics: {/a: {role: imu, rate: 3}}\n", "topics./a.rate: unknown key"},
      {"topics: {/a: {stamp: header}}\n", "topics./a: no role"},
      {"topics: {/a: {role: imu, stamp: sometimes}}\n", "topics./a.stamp"},
      {"mounts: {horizontal: \"1 2 3\"}\n", "mounts.horizontal"},
      {"mounts: {sideways: \"0 0 0 0 0 0\"}\n", "mounts.sideways: unknown mount"},
      {"topix: {}\n", "unknown key 'topix'"},
      {"? [a]\n: 1\n", "not a plain name"},
      {"topics: [/a, /b]\n", "topics: expected a mapping"},
      {"topics: {/a: {role: depth, fluid_density: -3}}\n", "fluid_density: must be positive"},
      {"topics: {/a: imu\n", "my.yaml: line"},
  };
  for (const auto& [text, want] : cases) {
    auto m = parse_topic_map(text, "my.yaml");
    INFO(text);
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.error().message, Catch::Contains("my.yaml") && Catch::Contains(want));
  }
  auto missing = load_topic_map("/nonexistent/topics.yaml");
  REQUIRE_FALSE(missing.ok());
  CHECK_THAT(missing.error().message, Catch::Contains("/nonexistent/topics.yaml: cannot open"));
}

TEST_CASE("export then import restores every event exactly (ROS 1 bag and ROS 2 MCAP, raw images)",
          "[ros][import][export]") {
  const std::string dir = dir_for("exact");
  const auto events = representable_events(3);
  const std::string fixture = write_fixture(dir + "/orig.mcap", events);
  for (auto target : {ExportTarget::kRos1Bag, ExportTarget::kRos2Mcap}) {
    for (const char* compression : {"", "lz4"}) {
      if (target == ExportTarget::kRos2Mcap && std::string(compression) == "lz4") continue;
      const bool bag = target == ExportTarget::kRos1Bag;
      const std::string name = std::string(bag ? "mission" : "mission_ros2") + (*compression ? "_lz4" : "");
      const std::string out = dir + "/" + name + (bag ? ".bag" : ".mcap");
      ExportOptions eo;
      eo.target = target;
      eo.jpeg = false;
      eo.compression = compression;
      auto r = export_fixture(fixture, out, eo);
      INFO((r.ok() ? "" : r.error().message));
      REQUIRE(r.ok());
      CHECK(r->topics_yaml == dir + "/" + name + ".topics.yaml");
      CHECK(r->messages.at("/sonar_oculus_node/M750d/ping") == 15);
      auto o = options_from(r->topics_yaml);
      const std::string back = dir + "/" + name + "_back.mcap";
      auto ir = import_recording(out, back, o);
      INFO((ir.ok() ? "" : ir.error().message));
      REQUIRE(ir.ok());
      CHECK(ir->warnings.empty());
      const auto got = read_all(back);
      REQUIRE(got.size() == events.size());
      for (size_t i = 0; i < events.size(); ++i) {
        INFO("event " << i << " on " << channel_topic(events[i].channel));
        CHECK(got[i] == events[i]);
      }
      auto src = FixtureSource::open(back);
      REQUIRE(src.ok());
      CHECK((*src)->metadata().at("T_V_h") == "0.25 0 0.10000000000000001 0 0 0");
      // Importing twice gives identical bytes.
      REQUIRE(import_recording(out, back + ".again", o).ok());
      CHECK(file_bytes(back) == file_bytes(back + ".again"));
    }
  }
}

TEST_CASE("JPEG and ProjectedSonarImage exports import within their losses", "[ros][import][export]") {
  const std::string dir = dir_for("lossy");
  const auto events = representable_events(5);
  const std::string fixture = write_fixture(dir + "/orig.mcap", events);
  for (bool projected : {false, true}) {
    ExportOptions eo;
    eo.sonar = projected ? SonarType::kProjected : SonarType::kOculus;
    eo.jpeg = !projected;
    const std::string out = dir + (projected ? "/projected.bag" : "/jpeg.bag");
    auto r = export_fixture(fixture, out, eo);
    INFO((r.ok() ? "" : r.error().message));
    REQUIRE(r.ok());
    auto ir = import_recording(out, out + ".mcap", options_from(r->topics_yaml));
    INFO((ir.ok() ? "" : ir.error().message));
    REQUIRE(ir.ok());
    const auto got = read_all(out + ".mcap");
    REQUIRE(got.size() == events.size());
    for (size_t i = 0; i < events.size(); ++i) {
      REQUIRE(got[i].channel == events[i].channel);
      CHECK(got[i].stamp == events[i].stamp);
      if (const auto* a = std::get_if<SonarPing>(&events[i].payload)) {
        const auto& b = std::get<SonarPing>(got[i].payload);
        REQUIRE(b.image.size() == a->image.size());
        double diff = 0;
        for (size_t k = 0; k < a->image.size(); ++k) diff += std::abs(int(a->image[k]) - int(b.image[k]));
        CHECK(diff / static_cast<double>(a->image.size()) <= (projected ? 0.0 : 12.0));
        for (size_t k = 0; k < a->bearings_rad.size(); ++k) CHECK(b.bearings_rad[k] == Approx(a->bearings_rad[k]).margin(1e-6));
        CHECK(b.range_resolution_m == Approx(a->range_resolution_m).epsilon(1e-6));
      } else if (const auto* d = std::get_if<DepthReading>(&events[i].payload)) {
        CHECK(std::get<DepthReading>(got[i].payload).depth_m == Approx(d->depth_m).margin(1e-6));
      } else if (!projected || events[i].channel != Channel::kDvl) {
        CHECK(got[i] == events[i]);
      }
    }
  }
}

TEST_CASE("import errors name the file, the topic and what is missing", "[ros][import]") {
  const std::string dir = dir_for("errors");
  const std::string fixture = write_fixture(dir + "/orig.mcap", representable_events(7));
  ExportOptions eo;
  eo.jpeg = false;
  eo.bag_chunk_bytes = 16 * 1024;  // several chunks, so that a cut keeps some
  REQUIRE(export_fixture(fixture, dir + "/m.bag", eo).ok());

  SECTION("a required role without a topic") {
    ImportOptions o;
    auto m = parse_topic_map("defaults: false\ntopics:\n  /vn100/imu/raw: imu\n", "partial.yaml");
    REQUIRE(m.ok());
    o.map = *m;
    auto r = import_recording(dir + "/m.bag", dir + "/x.mcap", o);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("m.bag: no messages for horizontal_sonar, vertical_sonar, dvl, depth"));
    CHECK_FALSE(fs::exists(dir + "/x.mcap"));
    CHECK_FALSE(fs::exists(dir + "/x.mcap.partial"));
  }
  SECTION("a topic whose type the role cannot read") {
    ImportOptions o;
    auto m = parse_topic_map("topics:\n  /vn100/imu/raw: dvl\n", "wrong.yaml");
    REQUIRE(m.ok());
    o.map = *m;
    auto r = import_recording(dir + "/m.bag", dir + "/x.mcap", o);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("/vn100/imu/raw (dvl): type sensor_msgs/Imu cannot be the dvl"));
  }
  SECTION("neither a bag nor an MCAP file") {
    std::ofstream(dir + "/junk.bag") << "hello, world";
    auto r = import_recording(dir + "/junk.bag", dir + "/x.mcap", ImportOptions{});
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("junk.bag: neither a ROS 1 bag"));
  }
  SECTION("a bag cut short imports what it holds, with a warning") {
    const auto bytes = file_bytes(dir + "/m.bag");
    std::ofstream(dir + "/cut.bag", std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size() * 3 / 4));
    ImportOptions o = options_from(dir + "/m.topics.yaml");
    auto r = import_recording(dir + "/cut.bag", dir + "/cut.mcap", o);
    INFO((r.ok() ? "" : r.error().message));
    REQUIRE(r.ok());
    REQUIRE(r->warnings.size() == 1);
    CHECK_THAT(r->warnings[0], Catch::Contains("cut.bag is truncated"));
    CHECK(r->events > 0);
    // Cut inside the first chunk: nothing to import, and the error says why.
    std::ofstream(dir + "/stub.bag", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), 4200);
    auto stub = import_recording(dir + "/stub.bag", dir + "/stub.mcap", o);
    REQUIRE_FALSE(stub.ok());
    CHECK_THAT(stub.error().message, Catch::Contains("stub.bag is truncated"));
  }
  SECTION("--list counts topics, rates and roles") {
    auto s = list_input(dir + "/m.bag", options_from(dir + "/m.topics.yaml").map);
    REQUIRE(s.ok());
    CHECK(s->format == "ros1 bag");
    bool found = false;
    for (const auto& t : s->topics) {
      if (t.topic != "/vn100/imu/raw") continue;
      found = true;
      CHECK(t.type == "sensor_msgs/Imu");
      CHECK(t.role == Role::kImu);
      CHECK(t.count == 75);
      CHECK(t.rate_hz() == Approx(50.0).epsilon(0.01));
    }
    CHECK(found);
  }
}

}  // namespace orthosonar::replay::ros
