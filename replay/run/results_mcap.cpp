// results.mcap (results_mcap.hpp): Foxglove JSON messages through the generic MCAP writer.
#include "replay/run/results_mcap.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "orthosonar/version.hpp"
#include "replay/mcap/mcap_generic.hpp"
#include "replay/run/run.hpp"
#include "replay/run/truth_spill.hpp"

namespace orthosonar::run {
namespace {

// The official Foxglove JSON schemas (foxglove/schemas, published as @foxglove/schemas
// 2.1.0 jsonschema), compacted: the "description" and "$comment" texts are dropped;
// everything that constrains a message (titles, types, properties, required lists, enum
// consts, bounds, contentEncoding) is kept as published. Foxglove turns a PointCloud's
// `data` into bytes because its schema says contentEncoding base64.
// clang-format off
constexpr const char* kPointCloudSchema =
    R"({"title":"foxglove.PointCloud","type":"object","properties":{"timestamp":{"type":"object",)"
    R"("title":"time","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer",)"
    R"("minimum":0,"maximum":999999999}}},"frame_id":{"type":"string"},"pose":{"title":"foxglove.Pose",)"
    R"("type":"object","properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("point_stride":{"type":"integer","minimum":0},"fields":{"type":"array",)"
    R"("items":{"title":"foxglove.PackedElementField","type":"object",)"
    R"("properties":{"name":{"type":"string"},"offset":{"type":"integer","minimum":0},)"
    R"("type":{"title":"foxglove.NumericType","oneOf":[{"title":"UNKNOWN","const":0},{"title":"UINT8",)"
    R"("const":1},{"title":"INT8","const":2},{"title":"UINT16","const":3},{"title":"INT16","const":4},)"
    R"({"title":"UINT32","const":5},{"title":"INT32","const":6},{"title":"FLOAT32","const":7},)"
    R"({"title":"FLOAT64","const":8}]}},"required":["name","offset","type"]}},"data":{"type":"string",)"
    R"("contentEncoding":"base64"}},"required":["timestamp","frame_id","pose","point_stride","fields",)"
    R"("data"]})";
constexpr const char* kPosesInFrameSchema =
    R"({"title":"foxglove.PosesInFrame","type":"object","properties":{"timestamp":{"type":"object",)"
    R"("title":"time","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer",)"
    R"("minimum":0,"maximum":999999999}}},"frame_id":{"type":"string"},"poses":{"type":"array",)"
    R"("items":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]}}},)"
    R"("required":["timestamp","frame_id","poses"]})";
constexpr const char* kFrameTransformSchema =
    R"({"title":"foxglove.FrameTransform","type":"object","properties":{"timestamp":{"type":"object",)"
    R"("title":"time","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer",)"
    R"("minimum":0,"maximum":999999999}}},"parent_frame_id":{"type":"string"},)"
    R"("child_frame_id":{"type":"string"},"translation":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"rotation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["timestamp","parent_frame_id",)"
    R"("child_frame_id","translation","rotation"]})";
constexpr const char* kSceneUpdateSchema =
    R"({"title":"foxglove.SceneUpdate","type":"object","properties":{"deletions":{"type":"array",)"
    R"("items":{"title":"foxglove.SceneEntityDeletion","type":"object",)"
    R"("properties":{"timestamp":{"type":"object","title":"time","properties":{"sec":{"type":"integer",)"
    R"("minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}}},)"
    R"("type":{"title":"foxglove.SceneEntityDeletionType","oneOf":[{"title":"MATCHING_ID","const":0},)"
    R"({"title":"ALL","const":1}]},"id":{"type":"string"}},"required":["timestamp","type","id"]}},)"
    R"("entities":{"type":"array","items":{"title":"foxglove.SceneEntity","type":"object",)"
    R"("properties":{"timestamp":{"type":"object","title":"time","properties":{"sec":{"type":"integer",)"
    R"("minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}}},)"
    R"("frame_id":{"type":"string"},"id":{"type":"string"},"lifetime":{"type":"object","title":"duration",)"
    R"("properties":{"sec":{"type":"integer"},"nsec":{"type":"integer","minimum":0,"maximum":999999999}}},)"
    R"("frame_locked":{"type":"boolean"},"metadata":{"type":"array",)"
    R"("items":{"title":"foxglove.KeyValuePair","type":"object","properties":{"key":{"type":"string"},)"
    R"("value":{"type":"string"}},"required":["key","value"]}},"arrows":{"type":"array",)"
    R"("items":{"title":"foxglove.ArrowPrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("shaft_length":{"type":"number"},"shaft_diameter":{"type":"number"},"head_length":{"type":"number"},)"
    R"("head_diameter":{"type":"number"},"color":{"title":"foxglove.Color","type":"object",)"
    R"("properties":{"r":{"type":"number"},"g":{"type":"number"},"b":{"type":"number"},)"
    R"("a":{"type":"number"}},"required":["r","g","b","a"]}},"required":["pose","shaft_length",)"
    R"("shaft_diameter","head_length","head_diameter","color"]}},"cubes":{"type":"array",)"
    R"("items":{"title":"foxglove.CubePrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("size":{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},)"
    R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},)"
    R"("color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]}},)"
    R"("required":["pose","size","color"]}},"spheres":{"type":"array",)"
    R"("items":{"title":"foxglove.SpherePrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("size":{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},)"
    R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},)"
    R"("color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]}},)"
    R"("required":["pose","size","color"]}},"cylinders":{"type":"array",)"
    R"("items":{"title":"foxglove.CylinderPrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("size":{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},)"
    R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},)"
    R"("bottom_scale":{"type":"number"},"top_scale":{"type":"number"},"color":{"title":"foxglove.Color",)"
    R"("type":"object","properties":{"r":{"type":"number"},"g":{"type":"number"},"b":{"type":"number"},)"
    R"("a":{"type":"number"}},"required":["r","g","b","a"]}},"required":["pose","size","bottom_scale",)"
    R"("top_scale","color"]}},"lines":{"type":"array","items":{"title":"foxglove.LinePrimitive",)"
    R"("type":"object","properties":{"type":{"title":"foxglove.LineType","oneOf":[{"title":"LINE_STRIP",)"
    R"("const":0},{"title":"LINE_LOOP","const":1},{"title":"LINE_LIST","const":2}]},)"
    R"("pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("thickness":{"type":"number"},"scale_invariant":{"type":"boolean"},"points":{"type":"array",)"
    R"("items":{"title":"foxglove.Point3","type":"object","properties":{"x":{"type":"number"},)"
    R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]}},)"
    R"("color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]},)"
    R"("colors":{"type":"array","items":{"title":"foxglove.Color","type":"object",)"
    R"("properties":{"r":{"type":"number"},"g":{"type":"number"},"b":{"type":"number"},)"
    R"("a":{"type":"number"}},"required":["r","g","b","a"]}},"indices":{"type":"array",)"
    R"("items":{"type":"integer","minimum":0}}},"required":["type","pose","thickness","scale_invariant",)"
    R"("points","color","colors","indices"]}},"triangles":{"type":"array",)"
    R"("items":{"title":"foxglove.TriangleListPrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("points":{"type":"array","items":{"title":"foxglove.Point3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]}},"color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]},)"
    R"("colors":{"type":"array","items":{"title":"foxglove.Color","type":"object",)"
    R"("properties":{"r":{"type":"number"},"g":{"type":"number"},"b":{"type":"number"},)"
    R"("a":{"type":"number"}},"required":["r","g","b","a"]}},"indices":{"type":"array",)"
    R"("items":{"type":"integer","minimum":0}}},"required":["pose","points","color","colors","indices"]}},)"
    R"("texts":{"type":"array","items":{"title":"foxglove.TextPrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("billboard":{"type":"boolean"},"font_size":{"type":"number"},"scale_invariant":{"type":"boolean"},)"
    R"("color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]},)"
    R"("text":{"type":"string"}},"required":["pose","billboard","font_size","scale_invariant","color",)"
    R"("text"]}},"models":{"type":"array","items":{"title":"foxglove.ModelPrimitive","type":"object",)"
    R"("properties":{"pose":{"title":"foxglove.Pose","type":"object",)"
    R"("properties":{"position":{"title":"foxglove.Vector3","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x",)"
    R"("y","z"]},"orientation":{"title":"foxglove.Quaternion","type":"object",)"
    R"("properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)"
    R"("w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},)"
    R"("scale":{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},)"
    R"("y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},)"
    R"("color":{"title":"foxglove.Color","type":"object","properties":{"r":{"type":"number"},)"
    R"("g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]},)"
    R"("override_color":{"type":"boolean"},"url":{"type":"string"},"media_type":{"type":"string"},)"
    R"("data":{"type":"string","contentEncoding":"base64"}},"required":["pose","scale","color",)"
    R"("override_color","url","media_type","data"]}}},"required":["timestamp","frame_id","id","lifetime",)"
    R"("frame_locked","metadata","arrows","cubes","spheres","cylinders","lines","triangles","texts",)"
    R"("models"]}}},"required":["deletions","entities"]})";
// clang-format on

using Json = nlohmann::json;
// Mesh vertices are float: written in float's shortest round-trip form ("0.1", not
// "0.10000000149011612"), which keeps a large mesh's message short.
using JsonF = nlohmann::basic_json<std::map, std::vector, std::string, bool, std::int64_t, std::uint64_t, float>;

constexpr const char* kWorld = "world";
constexpr size_t kTruthTrajectoryPoses = 40'000;  // 66 min at 10 Hz

// MCAP log times and Foxglove times are unsigned: a negative stamp is shown at 0.
uint64_t log_ns(Time t) { return t.ns() < 0 ? 0 : static_cast<uint64_t>(t.ns()); }

template <typename J>
J time_json(Time t) {
  const uint64_t ns = log_ns(t);
  return J{{"sec", ns / 1'000'000'000u}, {"nsec", ns % 1'000'000'000u}};
}

// Poses are written as JSON text directly: a run has one truth pose per sensor stamp (63,000
// in 600 s), and as nlohmann objects (a map node per key, copied into the trajectory
// message) they took 0.9 s and about 190 MB at the end of a full-resolution replay. The
// text is what nlohmann's dump gives for the same objects (keys in std::map order, numbers
// through its own serializer), byte for byte (results_mcap_test compares them).
std::string json_number(double v) { return Json(v).dump(); }

struct PoseText {
  std::string position, orientation;  // {"x":..,"y":..,"z":..} and {"w":..,"x":..,"y":..,"z":..}
};

// Unit quaternion with w >= 0 (one representation per rotation, as the TUM files write).
PoseText pose_text(const Eigen::Vector3d& p, Eigen::Quaterniond q) {
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  PoseText t;
  t.position = "{\"x\":" + json_number(p.x()) + ",\"y\":" + json_number(p.y()) + ",\"z\":" + json_number(p.z()) + "}";
  t.orientation =
      "{\"w\":" + json_number(q.w()) + ",\"x\":" + json_number(q.x()) + ",\"y\":" + json_number(q.y()) + ",\"z\":" + json_number(q.z()) + "}";
  return t;
}
PoseText pose_text(const SE3& T) { return pose_text(T.translation(), Eigen::Quaterniond(T.rotation())); }

std::string time_text(Time t) {
  const uint64_t ns = log_ns(t);
  return "{\"nsec\":" + std::to_string(ns % 1'000'000'000u) + ",\"sec\":" + std::to_string(ns / 1'000'000'000u) + "}";
}

template <typename J>
J identity_pose() {
  return J{{"position", {{"x", 0}, {"y", 0}, {"z", 0}}}, {"orientation", {{"x", 0}, {"y", 0}, {"z", 0}, {"w", 1}}}};
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t v = (uint32_t{bytes[i]} << 16) | (uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (int s : {18, 12, 6, 0}) out += kAlphabet[(v >> s) & 63u];
  }
  if (const size_t rest = bytes.size() - i; rest > 0) {
    const uint32_t v = (uint32_t{bytes[i]} << 16) | (rest == 2 ? uint32_t{bytes[i + 1]} << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63u];
    out += kAlphabet[(v >> 12) & 63u];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63u] : '=';
    out += '=';
  }
  return out;
}

// x y z float32 little-endian (NumericType FLOAT32 = 7), 12 bytes a point, on any host.
Json point_cloud_json(const std::vector<Eigen::Vector3f>& points_W, Time stamp) {
  std::vector<uint8_t> bytes;
  bytes.reserve(points_W.size() * 12);
  for (const auto& p : points_W)
    for (int k = 0; k < 3; ++k) {
      uint32_t u = 0;
      const float f = p[k];
      std::memcpy(&u, &f, sizeof u);
      for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<uint8_t>(u >> (8 * b)));
    }
  Json fields = Json::array();
  for (int k = 0; k < 3; ++k) fields.push_back({{"name", std::string(1, "xyz"[k])}, {"offset", 4 * k}, {"type", 7}});
  return {{"timestamp", time_json<Json>(stamp)}, {"frame_id", kWorld},     {"pose", identity_pose<Json>()},
          {"point_stride", 12},                  {"fields", std::move(fields)}, {"data", base64(bytes)}};
}

// foxglove.PosesInFrame: the poses pose(0) ... pose(n-1), each made when it is written (a
// run's pose texts are never all held at once).
template <typename PoseAt>
std::string poses_text(size_t n, const PoseAt& pose, Time stamp) {
  std::string out = "{\"frame_id\":\"" + std::string(kWorld) + "\",\"poses\":[";
  out.reserve(out.size() + n * 160 + 64);  // a pose is 120-150 characters
  for (size_t i = 0; i < n; ++i) {
    const PoseText p = pose(i);
    if (i > 0) out += ',';
    out += "{\"orientation\":";
    out += p.orientation;
    out += ",\"position\":";
    out += p.position;
    out += '}';
  }
  return out + "],\"timestamp\":" + time_text(stamp) + "}";
}

// foxglove.FrameTransform.
std::string transform_text(Time stamp, const std::string& child, const PoseText& pose) {
  return "{\"child_frame_id\":\"" + child + "\",\"parent_frame_id\":\"" + std::string(kWorld) +
         "\",\"rotation\":" + pose.orientation + ",\"timestamp\":" + time_text(stamp) +
         ",\"translation\":" + pose.position + "}";
}

// One entity, one indexed triangle list (vertices shared, not repeated per triangle).
JsonF scene_json(const TriangleMesh& mesh, const std::string& note, Time stamp) {
  JsonF points = JsonF::array();
  for (const auto& v : mesh.vertices) points.push_back({{"x", v.x()}, {"y", v.y()}, {"z", v.z()}});
  JsonF indices = JsonF::array();
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) indices.push_back(t[k]);
  JsonF triangles = JsonF::array();
  triangles.push_back({{"pose", identity_pose<JsonF>()},
                       {"points", std::move(points)},
                       {"color", {{"r", 0.55f}, {"g", 0.6f}, {"b", 0.65f}, {"a", 0.4f}}},
                       {"colors", JsonF::array()},
                       {"indices", std::move(indices)}});
  JsonF entity = {{"timestamp", time_json<JsonF>(stamp)},
                  {"frame_id", kWorld},
                  {"id", "truth_mesh"},
                  {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                  {"frame_locked", false},
                  {"metadata", JsonF::array({{{"key", "source"}, {"value", note}}})},
                  {"arrows", JsonF::array()},
                  {"cubes", JsonF::array()},
                  {"spheres", JsonF::array()},
                  {"cylinders", JsonF::array()},
                  {"lines", JsonF::array()},
                  {"triangles", std::move(triangles)},
                  {"texts", JsonF::array()},
                  {"models", JsonF::array()}};
  return {{"deletions", JsonF::array()}, {"entities", JsonF::array({std::move(entity)})}};
}

// What the file says it is: versions, digests, fixture metadata, configuration, counts and
// accuracy. Nothing timed (stage runtimes, wall time) so the bytes stay reproducible.
std::map<std::string, std::string> metadata_values(const RunOutput& run) {
  std::map<std::string, std::string> m;
  m["content"] = "orthosonar run results (maps, trajectories, truth mesh); a rendering, not a digest input";
  m["software_version"] = kVersion;
  m["digest"] = run.digest.overall_hex;
  for (const auto& [name, hex] : run.digest.outputs) m["digest." + name] = hex;
  for (const auto& [k, v] : run.metadata) m["fixture." + k] = v;
  m["config"] = config_to_json(run.config).dump();
  Json sources = Json::object();
  for (const auto& [k, v] : run.config_sources) sources[k] = v;
  m["config_sources"] = sources.dump();
  m["ground_truth_mesh"] = run.mesh_note;
  m["stream_s"] = Json(run.stream_span.seconds()).dump();
  m["ate_dr_m"] = run.ate_dr_m ? Json(*run.ate_dr_m).dump() : "null";
  m["ate_slam_m"] = run.ate_slam_m ? Json(*run.ate_slam_m).dump() : "null";
  if (run.pipeline) {
    Json counts = Json::object();
    for (const auto& [k, v] : count_fields(run.counts, run.pipeline->dead_reckoning().counts())) counts[k] = v;
    m["counts"] = counts.dump();
  }
  std::string systems;
  for (const auto& s : run.systems) {
    systems += (systems.empty() ? "" : ",") + s.name;
    m["map_points." + s.name] = std::to_string(s.map_W.size());
    m["coverage_voxels." + s.name] = std::to_string(s.coverage_voxels);
    if (s.accuracy) {
      m["mae_m." + s.name] = Json(s.accuracy->mae_m).dump();
      m["rmse_m." + s.name] = Json(s.accuracy->rmse_m).dump();
    }
  }
  m["systems"] = systems;
  return m;
}

// The stamps the file spans: the run keeps no absolute first/last event stamp, so these
// come from the truth, the keyframes and dead reckoning (falling back to [0, stream span]).
std::pair<Time, Time> time_bounds(const RunOutput& run) {
  std::vector<Time> stamps;
  if (!run.truth.empty()) stamps.insert(stamps.end(), {run.truth.front().stamp, run.truth.back().stamp});
  if (run.pipeline) {
    const auto& kfs = run.pipeline->slam().keyframes();
    if (!kfs.empty()) stamps.insert(stamps.end(), {kfs.front().stamp, kfs.back().stamp});
    const auto& dr = run.pipeline->dead_reckoning();
    if (!dr.empty()) stamps.insert(stamps.end(), {dr.first_time(), dr.last_time()});
  }
  if (stamps.empty()) return {Time(), run.stream_span};
  return {*std::min_element(stamps.begin(), stamps.end()), *std::max_element(stamps.begin(), stamps.end())};
}

}  // namespace

Status write_results_mcap(const RunOutput& run, const std::string& path) {
  if (run.mesh && !run.mesh->valid()) return Error{path + ": the truth mesh has a triangle index out of range"};
  replay::mcap::GenericWriterOptions options;
  options.library = std::string("orthosonar ") + kVersion;
  auto opened = replay::mcap::GenericWriter::open(path, options);
  if (!opened.ok()) return opened.error();
  replay::mcap::GenericWriter& w = **opened;
  const auto [start, end] = time_bounds(run);

  std::map<std::string, uint16_t> schemas;
  auto channel = [&](const std::string& topic, const std::string& schema_name, const char* schema_text) {
    auto it = schemas.find(schema_name);
    if (it == schemas.end())
      it = schemas.emplace(schema_name, w.add_schema(schema_name, "jsonschema", schema_text)).first;
    return w.add_channel(it->second, topic, "json");
  };
  std::map<uint16_t, uint32_t> sequence;
  auto emit = [&](uint16_t ch, Time stamp, const std::string& bytes) {
    const uint64_t t = log_ns(stamp);
    return w.write(ch, sequence[ch]++, t, t, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  };

  // In log-time order: the scene at the start, the tf stream, then the end-of-run results.
  if (run.mesh)
    if (Status st = emit(channel("/orthosonar/scene", "foxglove.SceneUpdate", kSceneUpdateSchema), start,
                         scene_json(*run.mesh, run.mesh_note, start).dump());
        !st.ok())
      return st;

  // The truth at most every 100 ms (TruthSpill::kShownSpacingNs): the tf stream's and the
  // truth trajectory's poses. A full-rate truth is 110 poses a second, 60 MB of text in an
  // hour, and traj_truth.tum already holds it whole. A run that kept its truth on disk has
  // these poses read back from its file as they are written (an 8-hour mission's 288,000
  // are 32 MB: issue 41); one that kept it in memory thins it here by the same rule.
  std::vector<TruthPose> thinned;
  if (!run.truth_all) {
    thinned = TruthSpill::thin(run.truth);
    std::stable_sort(thinned.begin(), thinned.end(), [](const TruthPose& a, const TruthPose& b) { return a.stamp < b.stamp; });
  }
  const size_t truth_count = run.truth_all ? run.truth_all->shown_count() : thinned.size();
  const auto for_each_truth = [&](const std::function<void(const TruthPose&)>& f) -> Status {
    if (run.truth_all) return run.truth_all->for_each_shown(f);
    for (const TruthPose& p : thinned) f(p);
    return {};
  };
  static const std::vector<slam::Keyframe> kNoKeyframes;
  const std::vector<slam::Keyframe>& kfs = run.pipeline ? run.pipeline->slam().keyframes() : kNoKeyframes;
  const auto dr_pose = [&](size_t k) { return pose_text(kfs[k].T_W_V_dr); };
  const auto slam_pose = [&](size_t k) { return pose_text(kfs[k].T_W_V_slam); };
  // The tf stream in stamp order, at equal stamps truth, dr, slam: the keyframes' transforms
  // sorted here, merged with the truth as it is read (its stamps never decrease).
  struct Tf {
    Time stamp;
    int order;  // dr 1, slam 2
    size_t index;
  };
  std::vector<Tf> tf;
  tf.reserve(2 * kfs.size());
  for (size_t k = 0; k < kfs.size(); ++k) {
    tf.push_back({kfs[k].stamp, 1, k});
    tf.push_back({kfs[k].stamp, 2, k});
  }
  std::stable_sort(tf.begin(), tf.end(), [](const Tf& a, const Tf& b) {
    return std::tie(a.stamp, a.order) < std::tie(b.stamp, b.order);
  });
  // The truth trajectory is one message: at most kTruthTrajectoryPoses poses of the tf
  // stream's, every stride-th (an 8-hour mission's 288,000 would be 45 MB of JSON), kept as
  // they pass.
  const size_t stride = (truth_count + kTruthTrajectoryPoses - 1) / kTruthTrajectoryPoses;  // 0 when empty
  std::vector<TruthPose> truth_trajectory;
  truth_trajectory.reserve(stride > 0 ? (truth_count + stride - 1) / stride : 0);
  std::optional<uint16_t> tf_channel;
  Status tf_status;
  static constexpr const char* kChild[] = {"vehicle_truth", "vehicle_dr", "vehicle_slam"};
  const auto emit_tf = [&](Time stamp, int order, const PoseText& pose) {
    if (!tf_status.ok()) return;
    if (!tf_channel) tf_channel = channel("/orthosonar/tf", "foxglove.FrameTransform", kFrameTransformSchema);
    tf_status = emit(*tf_channel, stamp, transform_text(stamp, kChild[order], pose));
  };
  size_t next_kf = 0, truth_index = 0;
  const auto emit_keyframes_before = [&](const Time* stamp) {  // all when stamp is null
    for (; next_kf < tf.size() && (stamp == nullptr || tf[next_kf].stamp < *stamp); ++next_kf) {
      const Tf& f = tf[next_kf];
      emit_tf(f.stamp, f.order, f.order == 1 ? dr_pose(f.index) : slam_pose(f.index));
    }
  };
  if (Status st = for_each_truth([&](const TruthPose& p) {
        emit_keyframes_before(&p.stamp);
        const PoseText pose = pose_text(p.p_W, p.q_W_V);
        emit_tf(p.stamp, 0, pose);
        if (stride > 0 && truth_index++ % stride == 0) truth_trajectory.push_back(p);
      });
      !st.ok())
    return st;
  emit_keyframes_before(nullptr);
  if (!tf_status.ok()) return tf_status;

  for (const auto& s : run.systems)
    if (Status st = emit(channel("/orthosonar/" + s.name + "/map", "foxglove.PointCloud", kPointCloudSchema), end,
                         point_cloud_json(s.map_W, end).dump());
        !st.ok())
      return st;
  const Time stamp_end = end;  // a structured binding cannot be captured (clang 14)
  const auto trajectory = [&](const char* name, size_t n, const auto& pose) -> Status {
    if (n == 0) return {};
    return emit(channel(std::string("/orthosonar/trajectory/") + name, "foxglove.PosesInFrame", kPosesInFrameSchema),
                stamp_end, poses_text(n, pose, stamp_end));
  };
  if (Status st = trajectory("truth", truth_trajectory.size(),
                             [&](size_t j) { return pose_text(truth_trajectory[j].p_W, truth_trajectory[j].q_W_V); });
      !st.ok())
    return st;
  if (Status st = trajectory("dr", kfs.size(), dr_pose); !st.ok()) return st;
  if (Status st = trajectory("slam", kfs.size(), slam_pose); !st.ok()) return st;
  if (Status st = w.metadata("orthosonar", metadata_values(run)); !st.ok()) return st;
  return w.close();
}

}  // namespace orthosonar::run
