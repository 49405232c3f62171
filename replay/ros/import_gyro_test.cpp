// The fibre-optic gyro through import and export (issue 32): the authors' kvh_gyro/gyro on
// /gyro to the gyro role, topics.yaml's mounts.gyro and latitude_deg into the fixture's
// metadata and back, export of delta angles and of rates (made angles), and the messages
// import refuses, each named by file, topic, message and field.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>

#include "replay/fixture/fixture.hpp"
#include "replay/fixture/synthetic.hpp"
#include "replay/fixture/testing.hpp"
#include "replay/ros/export.hpp"
#include "replay/ros/import.hpp"
#include "replay/ros/msg_encode.hpp"
#include "replay/ros/msg_types.hpp"
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/rosbag.hpp"
#include "replay/ros/topic_map.hpp"

namespace orthosonar::replay::ros {
namespace {

namespace fs = std::filesystem;
using rosmsg::Value;

constexpr double kGyroNaN = std::numeric_limits<double>::quiet_NaN();
const std::string kGyroSep = "\n" + std::string(80, '=') + "\n";

std::string gyro_dir(const std::string& name) { return testing::case_dir("ros_import_gyro", name, true).string(); }

std::vector<Event> gyro_read_all(const std::string& path) {
  auto back = testing::read_fixture(path);
  REQUIRE(back.error.empty());
  return std::move(back.events);
}

// Synthetic events the authors' types hold exactly (as import_test.cpp's), with or without gyro.
std::vector<Event> gyro_events(uint64_t seed, double gyro_rate_hz) {
  SyntheticOptions o;
  o.duration_ns = 1'500'000'000;
  o.ping_rows = 16;
  o.ping_cols = 8;
  o.labels = false;
  o.gyro_rate_hz = gyro_rate_hz;
  auto events = synthetic_events(seed, o);
  for (Event& e : events) {
    if (auto* p = std::get_if<SonarPing>(&e.payload)) {
      for (double& b : p->bearings_rad)
        b = static_cast<int16_t>(std::lround(b / (0.01 * std::numbers::pi / 180.0))) * 0.01 * (std::numbers::pi / 180.0);
      p->part_number = p->mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
      p->frequency_hz = p->mount == SonarMount::kHorizontal ? 750e3 : 1.2e6;
    } else if (auto* d = std::get_if<DepthReading>(&e.payload)) {
      d->depth_m = static_cast<double>(static_cast<float>(d->depth_m));
    } else if (auto* v = std::get_if<DvlReading>(&e.payload)) {
      if (!v->valid) v->velocity_V_mps = Vec3::Zero();
      if (v->altitude_m < 0) v->altitude_m = 0;
    }
  }
  return events;
}

std::string gyro_write_fixture(const std::string& path, const std::vector<Event>& events, const FixtureMetadata& md) {
  REQUIRE(testing::write_fixture(path, events, md).ok());
  return path;
}

ImportOptions gyro_options(const std::string& yaml_path) {
  auto map = load_topic_map(yaml_path);
  INFO((map.ok() ? "" : map.error().message));
  REQUIRE(map.ok());
  ImportOptions o;
  o.map = *map;
  return o;
}

// One gyro message as a bag holds it: `status` and `delta` as given (a definition of the
// file's own may make status a float64).
struct GyroMsg {
  double status = 1;
  std::vector<double> delta = {1e-4, -2e-4, 3e-3};
};

// A bag of the fixture's events (no gyro: the required roles) plus `msgs` on `topic` with
// `type` and `definition` (default: the authors' kvh_gyro/gyro), 10 ms apart from 0.2 s.
std::string bag_with_gyro(const std::string& dir, const std::vector<GyroMsg>& msgs, const std::string& topic = "/gyro",
                          const std::string& type = "kvh_gyro/gyro", std::string definition = "") {
  const std::string fixture = gyro_write_fixture(dir + "/base.mcap", gyro_events(4, 0.0), {});
  ExportOptions eo;
  eo.jpeg = false;
  eo.write_topics_yaml = false;
  REQUIRE(export_fixture(fixture, dir + "/base.bag", eo).ok());
  auto in = rosbag::BagReader::open(dir + "/base.bag");
  REQUIRE(in.ok());
  auto out = rosbag::BagWriter::open(dir + "/gyro.bag");
  REQUIRE(out.ok());
  std::map<uint32_t, uint32_t> ids;
  for (const auto& c : (*in)->connections()) {
    auto id = (*out)->add_connection(c.topic, c.type, c.md5sum, c.message_definition);
    REQUIRE(id.ok());
    ids[c.id] = *id;
  }
  REQUIRE((*in)->for_each([&](const rosbag::Connection& c, const rosbag::MessageView& m) -> Status {
                 return (*out)->write(ids.at(c.id), m.time_ns, m.data, m.size);
               }).ok());
  if (definition.empty()) definition = std::string(rosmsg::definition("kvh_gyro/gyro", rosmsg::Dialect::kRos1));
  auto schema = rosmsg::Schema::parse(type, definition, rosmsg::Dialect::kRos1);
  INFO((schema.ok() ? "" : schema.error().message));
  REQUIRE(schema.ok());
  auto conn = (*out)->add_connection(topic, type, schema->md5(), definition);
  REQUIRE(conn.ok());
  for (size_t i = 0; i < msgs.size(); ++i) {
    const int64_t ns = 200'000'000 + static_cast<int64_t>(i) * 10'000'000;
    std::vector<Value> delta;
    for (double d : msgs[i].delta) delta.push_back(Value::number(d, 0, false));
    const Value v = Value::message(
        {{"header", Value::message({{"seq", Value::number(static_cast<double>(i), static_cast<int64_t>(i), true)},
                                    {"stamp", Value::time(ns)},
                                    {"frame_id", Value::string("")}})},
         {"status", Value::number(msgs[i].status, static_cast<int64_t>(msgs[i].status == 0 ? 0 : 1), false)},
         {"delta", Value::array(std::move(delta))}});
    rosmsg::Writer w(rosmsg::Encoding::kRos1);
    REQUIRE(rosmsg::encode(*schema, v, w).ok());
    REQUIRE((*out)->write(*conn, static_cast<uint64_t>(ns), w.bytes().data(), w.bytes().size()).ok());
  }
  REQUIRE((*out)->close().ok());
  return dir + "/gyro.bag";
}

std::vector<GyroReading> gyro_readings(const std::vector<Event>& events) {
  std::vector<GyroReading> out;
  for (const Event& e : events)
    if (const auto* g = std::get_if<GyroReading>(&e.payload)) out.push_back(*g);
  return out;
}

}  // namespace

TEST_CASE("kvh_gyro/gyro is the authors' definition, with genpy's MD5", "[ros][import][gyro]") {
  const auto* k = rosmsg::known_type("kvh_gyro/gyro");
  REQUIRE(k != nullptr);
  CHECK(k->ros1.starts_with("Header header\nbool status #was there an error with the gyro?\n"
                            "float64[] delta #an array for dx, dy, dz\n\n" + std::string(80, '=') + "\nMSG: std_msgs/Header\n"));
  // genpy's _md5sum for Argonaut's kvh_gyro/msg/gyro.msg (ros:msg-genpy computes it again).
  CHECK(rosmsg::md5_of("kvh_gyro/gyro") == "7bf4a7f82fe96d9124091847a68d6212");
  auto ros2 = rosmsg::Schema::parse("kvh_gyro/gyro", std::string(k->ros2), rosmsg::Dialect::kRos2);
  REQUIRE(ros2.ok());
}

TEST_CASE("topics.yaml: the gyro role, mounts.gyro and latitude_deg, and back", "[ros][import][gyro]") {
  CHECK(role_from_name("gyro") == Role::kGyro);
  CHECK(role_name(Role::kGyro) == "gyro");
  CHECK(channel_for(Role::kGyro) == Channel::kGyro);
  const TopicMap defaults = default_topic_map();  // find() points into it: keep it alive
  const TopicRule* d = defaults.find("/gyro");
  REQUIRE(d != nullptr);
  CHECK(d->role == Role::kGyro);
  CHECK(d->from_defaults);

  auto m = parse_topic_map(
      "topics:\n  /kvh/fog: {role: gyro, stamp: receive}\n"
      "mounts:\n  gyro: {xyz: [0.1, 0, -0.05], rpy_deg: [180, 0, 90]}\n"
      "latitude_deg: -33.86\n",
      "topics.yaml");
  INFO((m.ok() ? "" : m.error().message));
  REQUIRE(m.ok());
  const TopicRule* r = m->find("/kvh/fog");
  REQUIRE(r != nullptr);
  CHECK(r->role == Role::kGyro);
  CHECK(r->stamp == StampSource::kReceive);
  CHECK_FALSE(r->from_defaults);
  CHECK(m->T_V_gyro == "0.10000000000000001 0 -0.050000000000000003 3.1415926535897931 0 1.5707963267948966");
  REQUIRE(m->latitude_deg.has_value());
  CHECK(*m->latitude_deg == -33.86);
  CHECK(m->T_V_h.empty());
  auto again = parse_topic_map(topic_map_yaml(*m, false), "again.yaml");
  INFO((again.ok() ? "" : again.error().message));
  REQUIRE(again.ok());
  CHECK(again->T_V_gyro == m->T_V_gyro);
  CHECK(again->latitude_deg == m->latitude_deg);
  REQUIRE(again->find("/kvh/fog") != nullptr);
  CHECK(again->find("/kvh/fog")->role == Role::kGyro);
  CHECK(again->find("/kvh/fog")->stamp == StampSource::kReceive);
  // Without them, nothing is written and nothing parsed.
  auto plain = parse_topic_map(topic_map_yaml(default_topic_map(), false), "plain.yaml");
  REQUIRE(plain.ok());
  CHECK(plain->T_V_gyro.empty());
  CHECK_FALSE(plain->latitude_deg.has_value());
  CHECK(plain->find("/gyro")->role == Role::kGyro);
}

TEST_CASE("topics.yaml: a bad latitude or gyro mount is an error naming the file and the key", "[ros][import][gyro]") {
  const std::pair<const char*, const char*> cases[] = {
      {"latitude_deg: 90.5\n", "latitude_deg: 90.5 is not a latitude in [-90, 90] degrees"},
      {"latitude_deg: -91\n", "latitude_deg: -91 is not a latitude"},
      {"latitude_deg: north\n", "latitude_deg: 'north' is not a number"},
      {"latitude_deg: .nan\n", "latitude_deg: '.nan' is not a finite number"},
      {"latitude_deg: [40]\n", "latitude_deg: expected a number"},
      {"mounts: {gyro: \"1 2 3\"}\n", "mounts.gyro: expected \"x y z roll pitch yaw\""},
      {"mounts: {gyro: {xyz: [1, 2]}}\n", "mounts.gyro.xyz: expected three numbers"},
      {"mounts: {fog: \"0 0 0 0 0 0\"}\n", "mounts.fog: unknown mount (horizontal, vertical, gyro)"},
      {"topics: {/a: {role: fog}}\n", "unknown role 'fog' (horizontal_sonar, vertical_sonar, imu, dvl, depth, truth, gyro)"},
  };
  for (const auto& [text, want] : cases) {
    auto m = parse_topic_map(text, "my.yaml");
    INFO(text);
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.error().message, Catch::Contains("my.yaml: ") && Catch::Contains(want));
  }
  for (const char* edge : {"latitude_deg: 90\n", "latitude_deg: -90\n", "latitude_deg: 0\n"}) {
    INFO(edge);
    CHECK(parse_topic_map(edge, "my.yaml").ok());
  }
}

TEST_CASE("export then import restores gyro events and the gyro's mounting and latitude", "[ros][import][export][gyro]") {
  const std::string dir = gyro_dir("exact");
  const auto events = gyro_events(9, 100.0);
  const FixtureMetadata md{{"T_V_gyro", "0.10000000000000001 0 -0.050000000000000003 3.1415926535897931 0 0"},
                           {"latitude_deg", "40.706000000000003"}};
  const std::string fixture = gyro_write_fixture(dir + "/orig.mcap", events, md);
  const auto orig = gyro_readings(events);
  REQUIRE(orig.size() == 150);
  REQUIRE(std::count_if(orig.begin(), orig.end(), [](const GyroReading& g) { return !g.valid; }) > 3);
  for (auto target : {ExportTarget::kRos1Bag, ExportTarget::kRos2Mcap}) {
    const bool bag = target == ExportTarget::kRos1Bag;
    const std::string out = dir + (bag ? "/m.bag" : "/m2.mcap");
    ExportOptions eo;
    eo.target = target;
    eo.jpeg = false;
    auto r = export_fixture(fixture, out, eo);
    INFO((r.ok() ? "" : r.error().message));
    REQUIRE(r.ok());
    CHECK(r->messages.at("/gyro") == 150);
    auto o = gyro_options(r->topics_yaml);
    CHECK(o.map.T_V_gyro == md.at("T_V_gyro"));
    CHECK(o.map.latitude_deg == 40.706);
    REQUIRE(o.map.find("/gyro") != nullptr);
    const std::string back = out + ".back.mcap";
    auto ir = import_recording(out, back, o);
    INFO((ir.ok() ? "" : ir.error().message));
    REQUIRE(ir.ok());
    CHECK(ir->warnings.empty());
    CHECK(ir->messages.at(Role::kGyro) == 150);
    const auto got = gyro_read_all(back);
    REQUIRE(got.size() == events.size());
    for (size_t i = 0; i < events.size(); ++i) {
      INFO("event " << i << " on " << channel_topic(events[i].channel));
      Event want = events[i];
      // kvh_gyro/gyro has no field for the device's packet counter or temperature.
      if (auto* g = std::get_if<GyroReading>(&want.payload)) g->sequence = 0, g->temperature_c = 0.0;
      CHECK(got[i] == want);
    }
    auto src = FixtureSource::open(back);
    REQUIRE(src.ok());
    CHECK((*src)->metadata().at("T_V_gyro") == md.at("T_V_gyro"));
    CHECK((*src)->metadata().at("latitude_deg") == md.at("latitude_deg"));
    CHECK((*src)->metadata().at("topic.gyro") == "/gyro");
  }
}

TEST_CASE("export makes gyro rates delta angles over the interval each covers", "[ros][export][gyro]") {
  const std::string dir = gyro_dir("rates");
  auto events = gyro_events(2, 0.0);
  // 100 Hz rates from 0.1 s, samples 20..24 lost (a gap of 60 ms), one invalid.
  std::vector<GyroReading> rates;
  for (int k = 0; k < 60; ++k) {
    if (k >= 20 && k < 25) continue;
    GyroReading g;
    g.stamp = Time::from_ns(100'000'000 + int64_t{k} * 10'000'000 + (k % 3) * 100'000);  // 0.1 ms jitter
    g.is_rate = true;
    g.value_G = Vec3(0.01 * k, -0.02, 0.5);
    g.valid = k != 33;
    g.sequence = static_cast<uint8_t>(k);
    rates.push_back(g);
  }
  for (size_t i = 0; i < rates.size(); ++i) events.push_back(Event{rates[i].stamp, Channel::kGyro, i, rates[i]});
  std::sort(events.begin(), events.end(), event_before);
  const std::string fixture = gyro_write_fixture(dir + "/rates.mcap", events, {});
  ExportOptions eo;
  eo.jpeg = false;
  auto r = export_fixture(fixture, dir + "/rates.bag", eo);
  INFO((r.ok() ? "" : r.error().message));
  REQUIRE(r.ok());
  auto ir = import_recording(dir + "/rates.bag", dir + "/back.mcap", gyro_options(r->topics_yaml));
  INFO((ir.ok() ? "" : ir.error().message));
  REQUIRE(ir.ok());
  const auto got = gyro_readings(gyro_read_all(dir + "/back.mcap"));
  REQUIRE(got.size() == rates.size());
  int64_t period = 0;
  for (size_t i = 0; i < rates.size(); ++i) {
    INFO("gyro reading " << i);
    // The first takes the interval to the second; a gap counts one period (the shortest so far).
    const int64_t dt = i == 0 ? rates[1].stamp.ns() - rates[0].stamp.ns() : rates[i].stamp.ns() - rates[i - 1].stamp.ns();
    if (i > 0 && (period == 0 || dt < period)) period = dt;
    const int64_t covered = i > 0 && dt > period + period / 2 ? period : dt;
    if (i == 20) CHECK(covered == period);  // the reading after the gap
    CHECK_FALSE(got[i].is_rate);
    CHECK(got[i].valid == rates[i].valid);
    CHECK(got[i].stamp == rates[i].stamp);
    CHECK(got[i].value_G == rates[i].value_G * (static_cast<double>(covered) * 1e-9));
  }

  SECTION("a lone rate reading has no interval: refused") {
    auto one = gyro_events(2, 0.0);
    one.push_back(Event{rates[0].stamp, Channel::kGyro, 0, rates[0]});
    std::sort(one.begin(), one.end(), event_before);
    const std::string f1 = gyro_write_fixture(dir + "/one.mcap", one, {});
    auto bad = export_fixture(f1, dir + "/one.bag", eo);
    REQUIRE_FALSE(bad.ok());
    CHECK_THAT(bad.error().message, Catch::Contains("one.mcap: gyro reading 0 is a rate and the fixture's only gyro reading"));
    CHECK_FALSE(fs::exists(dir + "/one.bag"));
    CHECK_FALSE(fs::exists(dir + "/one.bag.partial"));
  }
  SECTION("a latitude that is not one is refused before anything is written") {
    const std::string f2 = gyro_write_fixture(dir + "/lat.mcap", gyro_events(2, 0.0), {{"latitude_deg", "95"}});
    auto bad = export_fixture(f2, dir + "/lat.bag", eo);
    REQUIRE_FALSE(bad.ok());
    CHECK_THAT(bad.error().message, Catch::Contains("lat.mcap: metadata 'latitude_deg' = '95' is not a latitude"));
    CHECK_FALSE(fs::exists(dir + "/lat.bag"));
  }
}

TEST_CASE("kvh_gyro/gyro messages import as the authors' node writes them", "[ros][import][gyro]") {
  const std::string dir = gyro_dir("good");
  // A good sample, a packet the node could not parse (status false, delta empty), and an
  // invalid sample that kept its values.
  const std::string bag = bag_with_gyro(dir, {GyroMsg{}, GyroMsg{0, {}}, GyroMsg{0, {1e-3, 2e-3, -3e-3}}});
  auto r = import_recording(bag, dir + "/g.mcap", ImportOptions{});  // the default topics: /gyro
  INFO((r.ok() ? "" : r.error().message));
  REQUIRE(r.ok());
  CHECK(r->messages.at(Role::kGyro) == 3);
  const auto g = gyro_readings(gyro_read_all(dir + "/g.mcap"));
  REQUIRE(g.size() == 3);
  CHECK(g[0].valid);
  CHECK(g[0].value_G == Vec3(1e-4, -2e-4, 3e-3));
  CHECK_FALSE(g[0].is_rate);
  CHECK(g[0].stamp == Time::from_ns(200'000'000));
  CHECK(g[0].sequence == 0);
  CHECK(g[0].temperature_c == 0.0);
  CHECK_FALSE(g[1].valid);
  CHECK(g[1].value_G == Vec3::Zero());
  CHECK_FALSE(g[2].valid);
  CHECK(g[2].value_G == Vec3(1e-3, 2e-3, -3e-3));

  SECTION("another topic through topics.yaml") {
    const std::string other = bag_with_gyro(gyro_dir("good_other"), {GyroMsg{}}, "/kvh/fog");
    auto map = parse_topic_map("topics: {/kvh/fog: gyro}\n", "fog.yaml");
    REQUIRE(map.ok());
    ImportOptions o;
    o.map = *map;
    auto r2 = import_recording(other, other + ".mcap", o);
    INFO((r2.ok() ? "" : r2.error().message));
    REQUIRE(r2.ok());
    CHECK(r2->messages.at(Role::kGyro) == 1);
  }
}

TEST_CASE("bad kvh_gyro/gyro messages are errors naming the file, topic, message and field", "[ros][import][gyro]") {
  const std::string header_def = kGyroSep + "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n";
  struct Case {
    const char* name;
    GyroMsg bad;            // message 1, after a good one
    std::string definition;  // "" the authors'
    const char* index;       // the message named
    const char* want;
  };
  const Case cases[] = {
      {"two", GyroMsg{1, {1e-4, 2e-4}}, "", "1", "field 'delta' has 2 elements, not 3"},
      {"four", GyroMsg{1, {1e-4, 2e-4, 3e-4, 4e-4}}, "", "1", "field 'delta' has 4 elements, not 3"},
      {"empty_good", GyroMsg{1, {}}, "", "1",
       "field 'delta' has 0 elements, not 3 (dx, dy, dz in rad; empty only with status false)"},
      {"one_invalid", GyroMsg{0, {1e-4}}, "", "1", "field 'delta' has 1 elements, not 3"},
      {"nan", GyroMsg{1, {1e-4, kGyroNaN, 3e-4}}, "", "1", "field 'delta[1]' is nan, not a finite number"},
      {"inf_invalid", GyroMsg{0, {std::numeric_limits<double>::infinity(), 0, 0}}, "", "1",
       "field 'delta[0]' is inf, not a finite number"},
      // Definitions of the file's own: a float64 status, a scalar delta, no status at all.
      {"status_nan", GyroMsg{kGyroNaN, {0, 0, 0}}, "Header header\nfloat64 status\nfloat64[] delta" + header_def, "1",
       "field 'status' is nan, not a finite number"},
      {"delta_scalar", GyroMsg{}, "Header header\nbool status\nfloat64 delta" + header_def, "0",
       "field 'delta' is not an array"},
      {"no_status", GyroMsg{}, "Header header\nbool ok\nfloat64[] delta" + header_def, "0", "no field 'status'"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    const std::string dir = gyro_dir(std::string("bad_") + c.name);
    const std::string bag = bag_with_gyro(dir, {GyroMsg{}, c.bad}, "/gyro", "kvh_gyro/gyro", c.definition);
    auto r = import_recording(bag, dir + "/x.mcap", ImportOptions{});
    REQUIRE_FALSE(r.ok());
    INFO(r.error().message);
    CHECK_THAT(r.error().message, Catch::Contains("gyro.bag: /gyro message " + std::string(c.index) + " (chunk at byte ") &&
                                      Catch::Contains(c.want));
    CHECK_FALSE(fs::exists(dir + "/x.mcap"));
    CHECK_FALSE(fs::exists(dir + "/x.mcap.partial"));
  }
}

TEST_CASE("a default /gyro of another type is left out with a warning, a mapped one is an error", "[ros][import][gyro]") {
  const std::string dir = gyro_dir("other_type");
  const std::string def = "Header header\ngeometry_msgs/Vector3 angular_velocity" + kGyroSep +
                          "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id" + kGyroSep +
                          "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n";
  const std::string bag = bag_with_gyro(dir, {}, "/gyro", "geometry_msgs/Vector3Stamped", def);
  auto r = import_recording(bag, dir + "/x.mcap", ImportOptions{});
  INFO((r.ok() ? "" : r.error().message));
  REQUIRE(r.ok());
  REQUIRE(r->warnings.size() == 1);
  CHECK_THAT(r->warnings[0], Catch::Contains("gyro.bag: topic /gyro not imported as the gyro (a default topic): "
                                             "type geometry_msgs/Vector3Stamped cannot be the gyro"));
  CHECK(r->messages.count(Role::kGyro) == 0);
  auto listed = list_input(bag, default_topic_map());
  REQUIRE(listed.ok());
  bool noted = false;
  for (const auto& t : listed->topics) noted = noted || (t.topic == "/gyro" && !t.note.empty());
  CHECK(noted);
  auto map = parse_topic_map("topics: {/gyro: gyro}\n", "mine.yaml");
  REQUIRE(map.ok());
  ImportOptions o;
  o.map = *map;
  auto strict = import_recording(bag, dir + "/y.mcap", o);
  REQUIRE_FALSE(strict.ok());
  CHECK_THAT(strict.error().message,
             Catch::Contains("topic /gyro (gyro): type geometry_msgs/Vector3Stamped cannot be the gyro (readable types: kvh_gyro/gyro)"));
}

}  // namespace orthosonar::replay::ros
