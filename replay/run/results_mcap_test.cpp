// results.mcap (replay/run/results_mcap.hpp) read back with the generic MCAP reader: the
// topics, schema names and encodings, message counts and times; every message parses as
// JSON with its schema's required fields; the map bytes are the map's floats; the bytes
// are the same on every write; and a whole run's output directory holds it without it
// entering the digest.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mapping/pipeline.hpp"
#include "replay/mcap/mcap_generic.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/results_mcap.hpp"
#include "replay/run/truth_spill.hpp"
#include "replay/run/run.hpp"
#include "replay/fixture/testing.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using nlohmann::json;

namespace {

fs::path test_dir() {
  return replay::testing::case_dir("results_mcap", Catch::getResultCapture().getCurrentTestName(), true);
}

std::vector<uint8_t> base64_decode(const std::string& s) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  REQUIRE(s.size() % 4 == 0);
  std::vector<uint8_t> out;
  for (size_t i = 0; i < s.size(); i += 4) {
    uint32_t v = 0;
    int pad = 0;
    for (size_t k = 0; k < 4; ++k) {
      const int d = s[i + k] == '=' ? (++pad, 0) : value(s[i + k]);
      REQUIRE(d >= 0);
      v = (v << 6) | static_cast<uint32_t>(d);
    }
    for (int b = 0; b < 3 - pad; ++b) out.push_back(static_cast<uint8_t>(v >> (16 - 8 * b)));
  }
  return out;
}

struct Read {
  std::map<std::string, std::string> schema_of;    // topic -> schema name
  std::map<std::string, json> schema_json;          // schema name -> schema
  std::map<std::string, std::vector<json>> messages;  // topic -> messages in file order
  std::map<std::string, std::vector<uint64_t>> log_times;
};

Read read_back(const std::string& path) {
  Read r;
  std::map<uint16_t, std::string> topics;
  const Status st = replay::mcap::visit_messages(
      path,
      [&](const replay::mcap::RawChannel& c, const replay::mcap::RawSchema* s) -> Status {
        REQUIRE(s != nullptr);
        CHECK(c.message_encoding == "json");
        CHECK(s->encoding == "jsonschema");
        topics[c.id] = c.topic;
        r.schema_of[c.topic] = s->name;
        r.schema_json[s->name] = json::parse(s->data);
        return {};
      },
      [&](const replay::mcap::RawMessage& m) -> Status {
        const std::string& topic = topics.at(m.channel_id);
        CHECK(m.sequence == r.messages[topic].size());
        CHECK(m.publish_time_ns == m.log_time_ns);
        r.messages[topic].push_back(json::parse(reinterpret_cast<const char*>(m.data),
                                                reinterpret_cast<const char*>(m.data) + m.size));
        r.log_times[topic].push_back(m.log_time_ns);
        return {};
      });
  REQUIRE(st.ok());
  return r;
}

// Every key the schema lists as required is present, recursively through objects and arrays.
void check_required(const json& value, const json& schema, const std::string& where) {
  if (schema.contains("required"))
    for (const auto& key : schema["required"]) {
      INFO(where << " needs " << key);
      CHECK(value.contains(key.get<std::string>()));
    }
  if (schema.contains("properties") && value.is_object())
    for (const auto& [key, sub] : schema["properties"].items())
      if (value.contains(key)) check_required(value[key], sub, where + "." + key);
  if (schema.contains("items") && value.is_array())
    for (size_t i = 0; i < value.size(); ++i)
      check_required(value[i], schema["items"], where + "[" + std::to_string(i) + "]");
}

uint64_t stamp_ns(const json& t) { return t["sec"].get<uint64_t>() * 1'000'000'000u + t["nsec"].get<uint64_t>(); }

run::RunOutput synthetic_run() {
  run::RunOutput r;
  r.metadata = {{"scene", "unit"}, {"duration_s", "1"}};
  r.digest.overall_hex = std::string(64, 'a');
  r.digest.outputs = {{"fusion/map", std::string(64, 'b')}};
  run::SystemOutput fusion;
  fusion.name = "fusion";
  fusion.map_W = {{0.1f, -2.5f, 3.0f}, {1e-3f, 7.25f, -0.3f}, {100.5f, 0.0f, -12.125f}, {-0.7f, 0.2f, 9.9f}};
  run::SystemOutput submap;
  submap.name = "submap";  // an empty map is still a (zero-point) cloud
  r.systems = {fusion, submap};
  for (int i = 0; i < 25; ++i) {  // 40 ms apart from t = 1 s
    TruthPose p;
    p.stamp = Time::from_ms(1000 + 40 * i);
    p.p_W = Vec3(0.1 * i, -0.05 * i, -2.0);
    p.q_W_V = Quat(Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitZ()));
    r.truth.push_back(p);
  }
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, -5}, {10, 0, -5}, {10, 10, -5.5f}, {0, 10, -5}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.object_id = {1, 1};
  mesh.semantic = {SemanticClass::kSeafloor, SemanticClass::kSeafloor};
  r.mesh = mesh;
  r.mesh_note = "embedded:unit";
  r.stream_span = Time::from_ms(960);
  return r;
}

}  // namespace

TEST_CASE("results.mcap holds maps, trajectories, transforms and the truth mesh as Foxglove JSON", "[results_mcap]") {
  const fs::path dir = test_dir();
  const run::RunOutput run = synthetic_run();
  const std::string path = (dir / "results.mcap").string();
  REQUIRE(run::write_results_mcap(run, path).ok());
  const Read r = read_back(path);

  const std::map<std::string, std::string> expected = {
      {"/orthosonar/scene", "foxglove.SceneUpdate"},
      {"/orthosonar/tf", "foxglove.FrameTransform"},
      {"/orthosonar/fusion/map", "foxglove.PointCloud"},
      {"/orthosonar/submap/map", "foxglove.PointCloud"},
      {"/orthosonar/trajectory/truth", "foxglove.PosesInFrame"}};
  CHECK(r.schema_of == expected);  // no DR or SLAM trajectory without a pipeline
  for (const auto& [name, schema] : r.schema_json) {
    CHECK(schema["title"] == name);
    CHECK(schema["type"] == "object");
    CHECK(schema.contains("required"));
  }
  for (const auto& [topic, msgs] : r.messages)
    for (const auto& m : msgs) check_required(m, r.schema_json.at(r.schema_of.at(topic)), topic);

  const uint64_t start = 1'000'000'000u, end = 1'960'000'000u;
  // Scene: one entity, one indexed triangle list, at the start.
  REQUIRE(r.messages.at("/orthosonar/scene").size() == 1);
  const json& scene = r.messages.at("/orthosonar/scene")[0];
  CHECK(r.log_times.at("/orthosonar/scene")[0] == start);
  REQUIRE(scene["entities"].size() == 1);
  const json& entity = scene["entities"][0];
  CHECK(entity["frame_id"] == "world");
  CHECK(stamp_ns(entity["timestamp"]) == start);
  REQUIRE(entity["triangles"].size() == 1);
  const json& tri = entity["triangles"][0];
  CHECK(tri["indices"] == json({0, 1, 2, 0, 2, 3}));
  REQUIRE(tri["points"].size() == 4);
  CHECK(tri["points"][2]["z"].get<float>() == -5.5f);
  CHECK(tri["color"]["a"].get<double>() > 0.0);

  // The map: x y z float32 at stride 12, its bytes exactly the map's floats.
  REQUIRE(r.messages.at("/orthosonar/fusion/map").size() == 1);
  const json& cloud = r.messages.at("/orthosonar/fusion/map")[0];
  CHECK(r.log_times.at("/orthosonar/fusion/map")[0] == end);
  CHECK(stamp_ns(cloud["timestamp"]) == end);
  CHECK(cloud["frame_id"] == "world");
  CHECK(cloud["point_stride"] == 12);
  CHECK(cloud["fields"] == json::parse(R"([{"name":"x","offset":0,"type":7},{"name":"y","offset":4,"type":7},
                                            {"name":"z","offset":8,"type":7}])"));
  CHECK(cloud["pose"]["orientation"]["w"] == 1);
  const auto bytes = base64_decode(cloud["data"].get<std::string>());
  REQUIRE(bytes.size() == run.systems[0].map_W.size() * 12);
  for (size_t i = 0; i < run.systems[0].map_W.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const size_t at = i * 12 + static_cast<size_t>(k) * 4;
      uint32_t u = 0;
      for (size_t b = 0; b < 4; ++b) u |= uint32_t{bytes[at + b]} << (8 * b);
      float f;
      std::memcpy(&f, &u, sizeof f);
      CHECK(f == run.systems[0].map_W[i][k]);
    }
  CHECK(r.messages.at("/orthosonar/submap/map")[0]["data"] == "");

  // Transforms: truth at most every 100 ms (1.00, 1.12, 1.24, ... 1.96 s), in time order.
  const auto& tf = r.messages.at("/orthosonar/tf");
  REQUIRE(tf.size() == 9);
  for (size_t i = 0; i < tf.size(); ++i) {
    CHECK(tf[i]["parent_frame_id"] == "world");
    CHECK(tf[i]["child_frame_id"] == "vehicle_truth");
    CHECK(stamp_ns(tf[i]["timestamp"]) == start + 120'000'000u * i);
    CHECK(r.log_times.at("/orthosonar/tf")[i] == start + 120'000'000u * i);
  }

  // The truth trajectory: the same poses as the tf stream (every third of these 40 ms
  // apart), unit quaternions with w >= 0, equal to the transforms' own.
  const json& truth = r.messages.at("/orthosonar/trajectory/truth").at(0);
  REQUIRE(truth["poses"].size() == tf.size());
  for (size_t j = 0; j < tf.size(); ++j) {
    const size_t i = 3 * j;
    const json& p = truth["poses"][j];
    CHECK(p["position"]["x"].get<double>() == Approx(run.truth[i].p_W.x()));
    CHECK(p["position"] == tf[j]["translation"]);
    CHECK(p["orientation"] == tf[j]["rotation"]);
    const json& q = p["orientation"];
    const double n = std::sqrt(std::pow(q["x"].get<double>(), 2) + std::pow(q["y"].get<double>(), 2) +
                               std::pow(q["z"].get<double>(), 2) + std::pow(q["w"].get<double>(), 2));
    CHECK(n == Approx(1.0));
    CHECK(q["w"].get<double>() >= 0.0);
    CHECK(q["z"].get<double>() == Approx(std::sin(0.01 * static_cast<double>(i))));
  }

  // Same bytes on every write; the Metadata record says what the file is.
  const std::string again = (dir / "again.mcap").string();
  REQUIRE(run::write_results_mcap(run, again).ok());
  const auto a = replay::testing::read_bytes(path);
  CHECK(a == replay::testing::read_bytes(again));
  const std::string text(a.begin(), a.end());
  CHECK(text.find("orthosonar") != std::string::npos);
  CHECK(text.find(std::string(64, 'a')) != std::string::npos);  // the overall digest
  CHECK(text.find("map_points.fusion") != std::string::npos);
}

TEST_CASE("results.mcap refuses a truth mesh with an index out of range, naming the file", "[results_mcap]") {
  run::RunOutput run = synthetic_run();
  run.mesh->triangles[1] = Eigen::Vector3i(0, 2, 7);
  const std::string path = (test_dir() / "bad.mcap").string();
  const Status st = run::write_results_mcap(run, path);
  REQUIRE_FALSE(st.ok());
  CHECK(st.error().message.find(path) != std::string::npos);
}

TEST_CASE("a simulated run's output directory has results.mcap, outside the digest", "[results_mcap]") {
  const fs::path dir = test_dir();
  run::MissionSpec spec;
  spec.scene = "aircraft";  // the harbor's first seconds see nothing to map
  spec.duration_s = 12.0;
  spec.resolution = sim::Resolution::kReduced;
  spec.seed = 3;
  spec.render_threads = 1;
  const std::string fixture = (dir / "aircraft_12s.mcap").string();
  REQUIRE(run::ensure_mission_fixture(spec, fixture).ok());
  run::RunOptions options;
  auto out = run::run_fixture(fixture, options);
  REQUIRE(out.ok());
  REQUIRE(out->counts.keyframes > 0);
  REQUIRE(out->mesh.has_value());
  REQUIRE(run::write_run_outputs(*out, options, (dir / "out").string()).ok());

  const std::string path = (dir / "out" / run::kResultsMcapFile).string();
  const Read r = read_back(path);
  std::set<std::string> topics;
  for (const auto& [topic, schema] : r.schema_of) topics.insert(topic);
  CHECK(topics == std::set<std::string>{"/orthosonar/scene", "/orthosonar/tf", "/orthosonar/fusion/map",
                                         "/orthosonar/submap/map", "/orthosonar/trajectory/truth",
                                         "/orthosonar/trajectory/dr", "/orthosonar/trajectory/slam"});
  for (const auto& [topic, msgs] : r.messages)
    for (const auto& m : msgs) check_required(m, r.schema_json.at(r.schema_of.at(topic)), topic);
  const auto kf = static_cast<size_t>(out->counts.keyframes);
  CHECK(r.messages.at("/orthosonar/trajectory/slam")[0]["poses"].size() == kf);
  CHECK(r.messages.at("/orthosonar/trajectory/dr")[0]["poses"].size() == kf);
  // The truth trajectory at the tf stream's spacing: as many poses as truth transforms.
  const size_t truth_poses = r.messages.at("/orthosonar/trajectory/truth")[0]["poses"].size();
  CHECK(truth_poses > 0);
  REQUIRE(out->truth_all);  // the run kept its truth on disk (replay/run/truth_spill.hpp)
  CHECK(truth_poses == out->truth_all->shown_count());
  CHECK(truth_poses < out->truth_all->size());
  for (const auto& s : out->systems) {
    CHECK_FALSE(s.map_W.empty());
    CHECK(base64_decode(r.messages.at("/orthosonar/" + s.name + "/map")[0]["data"]).size() == s.map_W.size() * 12);
  }
  std::map<std::string, size_t> children;
  for (const auto& t : r.messages.at("/orthosonar/tf")) ++children[t["child_frame_id"].get<std::string>()];
  CHECK(children["vehicle_slam"] == kf);
  CHECK(children["vehicle_dr"] == kf);
  CHECK(children["vehicle_truth"] == truth_poses);
  const auto& tf_times = r.log_times.at("/orthosonar/tf");
  CHECK(std::is_sorted(tf_times.begin(), tf_times.end()));
  CHECK(tf_times.back() <= r.log_times.at("/orthosonar/fusion/map")[0]);
  const json& scene = r.messages.at("/orthosonar/scene")[0];
  CHECK(scene["entities"][0]["triangles"][0]["indices"].size() == out->mesh->triangle_count() * 3);

  // A rendering, not a digest input: no digest entry for it, and the same bytes again.
  for (const auto& [name, hex] : out->digest.outputs) CHECK(name.find("results") == std::string::npos);
  const std::string again = (dir / "again.mcap").string();
  REQUIRE(run::write_results_mcap(*out, again).ok());
  CHECK(replay::testing::read_bytes(path) == replay::testing::read_bytes(again));
}
