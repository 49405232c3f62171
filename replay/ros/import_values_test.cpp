// Values a recording's own message definitions allow but no sensor sends (issue 35): import
// decodes every message with the definition its file carries, so a float64 where the
// device has a uint16, a NaN, an infinity, a number beyond an integer field's range or an
// image whose header states another size can reach the converters. Each is an error naming
// the file, the topic, the message and the field, and no fixture is written; none is a
// double -> integer cast of NaN (undefined behaviour) or a value imported silently.
// The recordings are ROS 1 bags written here with small definitions of our own under the
// real type names (the converters read fields by name, so these are what a file may hold).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>

#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/ros/import.hpp"
#include "replay/ros/msg_encode.hpp"
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/rosbag.hpp"
#include "replay/ros/topic_map.hpp"
#include "replay/fixture/testing.hpp"

namespace orthosonar::replay::ros {
namespace {

namespace fs = std::filesystem;
using rosmsg::Value;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
const std::string kSep = "\n" + std::string(80, '=') + "\n";
const std::string kValuesHorizontalTopic = "/sonar_oculus_node/M750d/ping";

enum class SonarKind { kRaw, kCompressed, kProjected };

// One message per role; every field a float64 the test can set to anything.
struct Params {
  SonarKind sonar = SonarKind::kRaw;
  double ping_id = 3, range_resolution = 0.05, num_ranges = 16, num_beams = 8, mode = 1, gain = 40;
  std::vector<double> bearings = {-3000, -2000, -1000, 0, 500, 1500, 2500, 3500};  // 1/100 degree
  double height = 16, width = 8, step = 8;
  std::vector<uint8_t> compressed;  // OculusPing ping.data (default: a PNG of the image)
  double frequency = 750e3, beam_count = 8, dtype = 0;
  std::vector<std::array<double, 3>> beam_directions;  // default: from `bearings`
  std::vector<double> ranges;                           // default: num_ranges bins of range_resolution
  double qw = 1, qx = 0, qy = 0, qz = 0, wz = 0.1, az = 9.8;
  double tx = 1, ty = 2, tz = -3, tqw = 1;
  // The IMU with a std_msgs/Header of this definition ("" none) and stamp source header.
  std::string imu_header;
  std::vector<int64_t> imu_header_ns = {1'000'000'000};
};

Value values_number(double d) { return Value::number(d, 0, false); }
Value values_integer(int64_t i) { return Value::number(static_cast<double>(i), i, true); }
Value values_vec(std::initializer_list<std::pair<const char*, double>> xs) {
  std::vector<std::pair<std::string, Value>> f;
  for (const auto& [k, v] : xs) f.emplace_back(k, values_number(v));
  return Value::message(std::move(f));
}
Value values_numbers(const std::vector<double>& xs) {
  std::vector<Value> v;
  for (double x : xs) v.push_back(values_number(x));
  return Value::array(std::move(v));
}

std::vector<uint8_t> image_bytes() {
  std::vector<uint8_t> img(static_cast<size_t>(16 * 8));
  for (size_t i = 0; i < img.size(); ++i) img[i] = static_cast<uint8_t>(i * 7 % 251);
  return img;
}

struct Message {
  std::string topic, type, definition;
  Value value;
  uint64_t receive_ns;
};

std::vector<Message> messages_for(const Params& p, std::vector<uint8_t>& keep) {
  std::vector<Message> out;
  const uint64_t t = 1'000'000'000;
  keep = image_bytes();
  for (const char* topic : {"/sonar_oculus_node/M750d/ping", "/sonar_oculus_node/M1200d/ping"}) {
    if (p.sonar == SonarKind::kProjected) {
      std::vector<Value> dirs;
      if (p.beam_directions.empty()) {
        for (double c : p.bearings) {
          const double b = c * 0.01 * std::numbers::pi / 180.0;
          dirs.push_back(values_vec({{"x", 0.0}, {"y", -std::sin(b)}, {"z", std::cos(b)}}));
        }
      } else {
        for (const auto& d : p.beam_directions) dirs.push_back(values_vec({{"x", d[0]}, {"y", d[1]}, {"z", d[2]}}));
      }
      std::vector<double> ranges = p.ranges;
      if (ranges.empty())
        for (int i = 0; i < 16; ++i) ranges.push_back(0.5 + p.range_resolution * i);
      out.push_back({topic, "marine_acoustic_msgs/ProjectedSonarImage",
                     "Info ping_info\nV3[] beam_directions\nfloat64[] ranges\nImg image" + kSep +
                         "MSG: marine_acoustic_msgs/Info\nfloat64 frequency" + kSep +
                         "MSG: marine_acoustic_msgs/V3\nfloat64 x\nfloat64 y\nfloat64 z" + kSep +
                         "MSG: marine_acoustic_msgs/Img\nfloat64 beam_count\nfloat64 dtype\nuint8 is_bigendian\nuint8[] data\n",
                     Value::message({{"ping_info", values_vec({{"frequency", p.frequency}})},
                                     {"beam_directions", Value::array(std::move(dirs))},
                                     {"ranges", values_numbers(ranges)},
                                     {"image", Value::message({{"beam_count", values_number(p.beam_count)},
                                                               {"dtype", values_number(p.dtype)},
                                                               {"is_bigendian", values_integer(0)},
                                                               {"data", Value::bytes(keep)}})}}),
                     t});
      continue;
    }
    const bool compressed = p.sonar == SonarKind::kCompressed;
    const std::string image_def =
        compressed ? "MSG: sonar_oculus/Img\nstring format\nuint8[] data\n"
                   : "MSG: sonar_oculus/Img\nfloat64 height\nfloat64 width\nfloat64 step\nuint8 is_bigendian\n"
                     "string encoding\nuint8[] data\n";
    Value image = compressed ? Value::message({{"format", Value::string("mono8; png compressed")},
                                               {"data", Value::bytes(p.compressed)}})
                             : Value::message({{"height", values_number(p.height)},
                                               {"width", values_number(p.width)},
                                               {"step", values_number(p.step)},
                                               {"is_bigendian", values_integer(0)},
                                               {"encoding", Value::string("mono8")},
                                               {"data", Value::bytes(keep)}});
    out.push_back({topic, compressed ? "sonar_oculus/OculusPing" : "sonar_oculus/OculusPingUncompressed",
                   "float64 ping_id\nfloat64 range_resolution\nfloat64 num_ranges\nfloat64 num_beams\n"
                   "float64[] bearings\nFire fire_msg\nImg ping" +
                       kSep + "MSG: sonar_oculus/Fire\nfloat64 mode\nfloat64 gain" + kSep + image_def,
                   Value::message({{"ping_id", values_number(p.ping_id)},
                                   {"range_resolution", values_number(p.range_resolution)},
                                   {"num_ranges", values_number(p.num_ranges)},
                                   {"num_beams", values_number(p.num_beams)},
                                   {"bearings", values_numbers(p.bearings)},
                                   {"fire_msg", values_vec({{"mode", p.mode}, {"gain", p.gain}})},
                                   {"ping", std::move(image)}}),
                   t});
  }
  const std::string imu_def = "Q orientation\nV angular_velocity\nV linear_acceleration" + kSep +
                              "MSG: sensor_msgs/Q\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w" + kSep +
                              "MSG: sensor_msgs/V\nfloat64 x\nfloat64 y\nfloat64 z\n";
  for (int64_t ns : p.imu_header_ns) {
    std::vector<std::pair<std::string, Value>> f;
    if (!p.imu_header.empty()) {
      Value stamp = p.imu_header.find("float64 stamp") != std::string::npos ? values_number(static_cast<double>(ns))
                                                                            : Value::time(ns);
      f.emplace_back("header", Value::message({{"seq", values_integer(0)}, {"stamp", std::move(stamp)},
                                               {"frame_id", Value::string("imu")}}));
    }
    f.emplace_back("orientation", values_vec({{"x", p.qx}, {"y", p.qy}, {"z", p.qz}, {"w", p.qw}}));
    f.emplace_back("angular_velocity", values_vec({{"x", 0.0}, {"y", 0.0}, {"z", p.wz}}));
    f.emplace_back("linear_acceleration", values_vec({{"x", 0.0}, {"y", 0.0}, {"z", p.az}}));
    out.push_back({"/vn100/imu/raw", "sensor_msgs/Imu",
                   p.imu_header.empty() ? imu_def : "Header header\n" + imu_def + kSep + p.imu_header,
                   Value::message(std::move(f)), t});
  }
  out.push_back({"/rti/body_velocity/raw", "rti_dvl/DVL",
                 "V velocity\nfloat64 altitude" + kSep + "MSG: rti_dvl/V\nfloat64 x\nfloat64 y\nfloat64 z\n",
                 Value::message({{"velocity", values_vec({{"x", 0.5}, {"y", 0.0}, {"z", 0.0}})}, {"altitude", values_number(4)}}), t});
  out.push_back({"/bar30/depth/raw", "bar30_depth/Depth", "float64 depth\n", Value::message({{"depth", values_number(2.5)}}), t});
  out.push_back({"/orthosonar/truth", "geometry_msgs/PoseStamped",
                 "P pose" + kSep + "MSG: geometry_msgs/P\nV position\nQ orientation" + kSep +
                     "MSG: geometry_msgs/V\nfloat64 x\nfloat64 y\nfloat64 z" + kSep +
                     "MSG: geometry_msgs/Q\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
                 Value::message({{"pose", Value::message({{"position", values_vec({{"x", p.tx}, {"y", p.ty}, {"z", p.tz}})},
                                                          {"orientation", values_vec({{"x", 0.0}, {"y", 0.0}, {"z", 0.0},
                                                                               {"w", p.tqw}})}})}}),
                 t});
  return out;
}

std::string write_values_bag(const std::string& path, const Params& p) {
  std::vector<uint8_t> keep;
  const auto msgs = messages_for(p, keep);
  auto w = rosbag::BagWriter::open(path);
  REQUIRE(w.ok());
  std::map<std::string, uint32_t> conns;
  uint64_t k = 0;
  for (const Message& m : msgs) {
    if (!conns.count(m.topic)) {
      auto id = (*w)->add_connection(m.topic, m.type, std::string(32, '0'), m.definition);
      REQUIRE(id.ok());
      conns[m.topic] = *id;
    }
    auto schema = rosmsg::Schema::parse(m.type, m.definition, rosmsg::Dialect::kRos1);
    INFO(m.type << ": " << (schema.ok() ? "" : schema.error().message));
    REQUIRE(schema.ok());
    rosmsg::Writer wr(rosmsg::Encoding::kRos1);
    auto st = rosmsg::encode(*schema, m.value, wr);
    INFO((st.ok() ? "" : st.error().message));
    REQUIRE(st.ok());
    REQUIRE((*w)->write(conns[m.topic], m.receive_ns + k++, wr.bytes().data(), wr.bytes().size()).ok());
  }
  REQUIRE((*w)->close().ok());
  return path;
}

ImportOptions values_options(const std::string& extra_yaml = "") {
  auto map = parse_topic_map("stamp: receive\n" + extra_yaml, "values.yaml");
  INFO((map.ok() ? "" : map.error().message));
  REQUIRE(map.ok());
  ImportOptions o;
  o.map = *map;
  return o;
}

// Imports a bag of `p`; the result and where the fixture would be.
Result<ImportReport> import_values(const std::string& name, const Params& p, const std::string& extra_yaml = "") {
  const std::string dir = testing::case_dir("ros_import_values", name, true).string();
  const std::string bag = write_values_bag(dir + "/values.bag", p);
  auto r = import_recording(bag, dir + "/values.mcap", values_options(extra_yaml));
  if (!r) {
    CHECK_FALSE(fs::exists(dir + "/values.mcap"));
    CHECK_FALSE(fs::exists(dir + "/values.mcap.partial"));
  }
  return r;
}

void check_rejected(const std::string& name, const Params& p, const std::string& field, const std::string& topic = kValuesHorizontalTopic) {
  INFO(name);
  auto r = import_values(name, p);
  CHECK_FALSE(r.ok());
  if (r.ok()) return;
  INFO(r.error().message);
  CHECK_THAT(r.error().message, Catch::Contains("values.bag: " + topic + " message 0") && Catch::Contains(field));
}

std::vector<Event> values_events(const std::string& path) {
  auto src = FixtureSource::open(path);
  REQUIRE(src.ok());
  std::vector<Event> out;
  for (;;) {
    auto pulled = (*src)->next();
    REQUIRE_FALSE(pulled.error.has_value());
    if (!pulled.event) break;
    out.push_back(std::move(*pulled.event));
  }
  return out;
}

// A JPEG that is only a header: start of image, then a baseline frame header stating the size.
std::vector<uint8_t> jpeg_header_only(uint16_t rows, uint16_t cols) {
  return {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x04, 0x00, 0x00,  // SOI, an APP0 segment
          0xFF, 0xC0, 0x00, 0x0B, 0x08, static_cast<uint8_t>(rows >> 8), static_cast<uint8_t>(rows),
          static_cast<uint8_t>(cols >> 8), static_cast<uint8_t>(cols), 0x01, 0x01, 0x11, 0x00,
          0xFF, 0xD9};
}

}  // namespace

TEST_CASE("the test's own recording imports (so each rejection below is its one changed field)", "[ros][import]") {
  for (SonarKind kind : {SonarKind::kRaw, SonarKind::kCompressed, SonarKind::kProjected}) {
    Params p;
    p.sonar = kind;
    std::vector<uint8_t> img = image_bytes();
    p.compressed = *codec::encode_png(cv::Mat(16, 8, CV_8U, img.data()));
    auto r = import_values("valid" + std::to_string(static_cast<int>(kind)), p);
    INFO((r.ok() ? "" : r.error().message));
    REQUIRE(r.ok());
    CHECK(r->events == 6);
    const auto events = values_events(testing::case_dir("ros_import_values", "valid" + std::to_string(static_cast<int>(kind))).string() +
                                  "/values.mcap");
    bool ping = false;
    for (const Event& e : events) {
      if (const auto* s = std::get_if<SonarPing>(&e.payload); s && e.channel == Channel::kSonarHorizontal) {
        ping = true;
        CHECK(s->rows == 16);
        CHECK(s->cols == 8);
        CHECK(s->image == img);  // a PNG decodes exactly
        REQUIRE(s->bearings_rad.size() == 8);
        CHECK(s->bearings_rad[0] == Approx(-30.0 * std::numbers::pi / 180.0));
      }
    }
    CHECK(ping);
  }
}

TEST_CASE("import rejects non-finite and out-of-range OculusPing fields before converting them", "[ros][import]") {
  // Each of these reached a double -> integer cast (num_ranges, ping_id, fire_msg.mode,
  // ping.step; undefined for NaN and out-of-range values) or was imported as is (gain,
  // bearings) before the checks.
  Params p;
  p.num_ranges = kNaN;
  check_rejected("num_ranges_nan", p, "num_ranges nan x num_beams 8 is not an image");
  p = {};
  p.num_beams = kInf;
  check_rejected("num_beams_inf", p, "num_beams inf is not an image");
  p = {};
  p.ping_id = kNaN;
  check_rejected("ping_id_nan", p, "field 'ping_id' is nan, outside 0..4294967295");
  p = {};
  p.ping_id = 1e12;
  check_rejected("ping_id_huge", p, "field 'ping_id' is 1000000000000, outside 0..4294967295");
  p = {};
  p.ping_id = -1;
  check_rejected("ping_id_negative", p, "field 'ping_id' is -1, outside");
  p = {};
  p.mode = kNaN;
  check_rejected("mode_nan", p, "field 'fire_msg.mode' is nan, outside 0..255");
  p = {};
  p.mode = 1e300;
  check_rejected("mode_huge", p, "field 'fire_msg.mode' is 1.0000000000000001e+300, outside 0..255");
  p = {};
  p.gain = kInf;
  check_rejected("gain_inf", p, "field 'fire_msg.gain' is inf, not a finite number");
  p = {};
  p.bearings[2] = kNaN;
  check_rejected("bearing_nan", p, "field 'bearings[2]' is nan (1/100 degree), outside -36000..36000");
  p = {};
  p.bearings[7] = 1e200;
  check_rejected("bearing_huge", p, "field 'bearings[7]' is 9.9999999999999997e+199");
}

TEST_CASE("import rejects raw image sizes and steps that are not numbers of bytes", "[ros][import]") {
  Params p;
  p.height = kNaN;  // was cast to int64 for the message
  check_rejected("height_nan", p, "the image is nan x 8 but num_ranges x num_beams is 16 x 8");
  p = {};
  p.width = 1e300;
  check_rejected("width_huge", p, "the image is 16 x 1.0000000000000001e+300 but");
  p = {};
  p.step = kInf;
  check_rejected("step_inf", p, "rows of step inf");
  p = {};
  p.step = 1e30;
  check_rejected("step_huge", p, "rows of step 1e+30");
  p = {};
  p.step = kNaN;  // was cast to size_t: rows copied from anywhere (SIGSEGV)
  check_rejected("step_nan", p, "ping.data has 128 bytes, too few for 16 rows of step nan");
}

TEST_CASE("import checks a compressed ping's stated size before decoding it", "[ros][import]") {
  Params p;
  p.sonar = SonarKind::kCompressed;
  // 60000 x 60000 stated by 23 bytes: refused from the header, never handed to the decoder
  // (which said only "does not decode as an image" after trying).
  p.compressed = jpeg_header_only(60000, 60000);
  check_rejected("jpeg_huge", p, "the image is 60000 x 60000 but num_ranges x num_beams is 16 x 8");
  // A size that matches num_ranges x num_beams but exceeds what a ping can hold.
  p.num_ranges = 8192;
  p.num_beams = 4096;
  p.bearings.assign(4096, 0.0);
  p.compressed = jpeg_header_only(8192, 4096);
  check_rejected("jpeg_too_many_pixels", p, "the image is 8192 x 4096, more than 16777216 pixels");
  // A PNG stating another size than its pixels would decode to.
  p = {};
  p.sonar = SonarKind::kCompressed;
  std::vector<uint8_t> img = image_bytes();
  p.compressed = *codec::encode_png(cv::Mat(16, 8, CV_8U, img.data()));
  p.compressed[19] = 200;  // IHDR width 8 -> 200
  check_rejected("png_width", p, "the image is 16 x 200 but num_ranges x num_beams is 16 x 8");
  p.compressed = {'B', 'M', 0, 0, 0, 0};
  check_rejected("not_jpeg_or_png", p, "is neither a JPEG nor a PNG image");
}

TEST_CASE("import rejects non-finite ProjectedSonarImage fields", "[ros][import]") {
  Params p;
  p.sonar = SonarKind::kProjected;
  p.dtype = kNaN;  // was cast to int
  check_rejected("dtype_nan", p, "image.dtype nan is not one of 0..9");
  p.dtype = 1e10;
  check_rejected("dtype_huge", p, "image.dtype 10000000000 is not one of 0..9");
  p.dtype = 0;
  p.beam_count = kNaN;  // was cast to int64 for the message
  check_rejected("beam_count_nan", p, "image.beam_count nan but 8 beam_directions");
  p.beam_count = 8;
  p.frequency = kNaN;
  check_rejected("frequency_nan", p, "field 'ping_info.frequency' is nan, not a finite number");
  p.frequency = 750e3;
  p.beam_directions.assign(8, {0.0, 0.1, 1.0});
  p.beam_directions[5][1] = kInf;
  check_rejected("beam_direction_inf", p, "field 'beam_directions[5]' is not three finite numbers");
  p.beam_directions.clear();
  for (int i = 0; i < 16; ++i) p.ranges.push_back(0.5 + 0.05 * i);
  p.ranges[7] = kNaN;  // between two good ends: the spacing check let it through
  check_rejected("range_nan", p, "field 'ranges[7]' is nan, not a finite number");
}

TEST_CASE("import rejects non-finite IMU and truth values", "[ros][import]") {
  Params p;
  p.qw = kNaN;
  check_rejected("imu_q_nan", p, "field 'orientation.w' is nan, not a finite number", "/vn100/imu/raw");
  p = {};
  p.qx = kInf;
  check_rejected("imu_q_inf", p, "field 'orientation.x' is inf", "/vn100/imu/raw");
  p = {};
  p.qw = 1e6;
  check_rejected("imu_q_huge", p, "field 'orientation' has norm 1000000, not a rotation", "/vn100/imu/raw");
  p = {};
  p.wz = kNaN;
  check_rejected("imu_w_nan", p, "field 'angular_velocity.z' is nan", "/vn100/imu/raw");
  p = {};
  p.az = -kInf;
  check_rejected("imu_a_inf", p, "field 'linear_acceleration.z' is -inf", "/vn100/imu/raw");
  p = {};
  p.ty = kNaN;
  check_rejected("truth_p_nan", p, "field 'pose.position.y' is nan", "/orthosonar/truth");
  p = {};
  p.tqw = 0;
  check_rejected("truth_q_zero", p, "field 'pose.orientation' has norm 0, not a rotation", "/orthosonar/truth");
  p = {};
  p.tqw = kNaN;
  check_rejected("truth_q_nan", p, "field 'pose.orientation.w' is nan", "/orthosonar/truth");
}

TEST_CASE("header stamps come from the file's own Header, whatever its layout", "[ros][import]") {
  const std::string imu_header_stamp = "topics: {/vn100/imu/raw: {role: imu, stamp: header}}\n";
  SECTION("a stamp that is not a time") {
    Params p;
    p.imu_header = "MSG: std_msgs/Header\nuint32 seq\nfloat64 stamp\nstring frame_id\n";
    auto r = import_values("stamp_float", p, imu_header_stamp);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message,
               Catch::Contains("values.bag: /vn100/imu/raw message 0") && Catch::Contains("'header.stamp' is not a time"));
  }
  SECTION("a ROS 2 Header (no seq) in a ROS 1 bag: stamps decoded, sequences in stamp order") {
    // Read as if it had a seq, the first message's stamp would be 2.000000003 s (nsec, then
    // frame_id's length) and the second's 1.000000003 s: sequences numbered the other way round.
    Params p;
    p.imu_header = "MSG: std_msgs/Header\ntime stamp\nstring frame_id\n";
    p.imu_header_ns = {5'000'000'002, 6'000'000'001};
    auto r = import_values("header_ros2_layout", p, imu_header_stamp);
    INFO((r.ok() ? "" : r.error().message));
    REQUIRE(r.ok());
    std::vector<std::pair<int64_t, uint64_t>> imu;
    for (const Event& e : values_events(testing::case_dir("ros_import_values", "header_ros2_layout").string() + "/values.mcap"))
      if (e.channel == Channel::kImu) imu.emplace_back(e.stamp.ns(), e.sequence);
    REQUIRE(imu.size() == 2);
    CHECK(imu[0] == std::pair<int64_t, uint64_t>{5'000'000'002, 0});
    CHECK(imu[1] == std::pair<int64_t, uint64_t>{6'000'000'001, 1});
  }
}

}  // namespace orthosonar::replay::ros
