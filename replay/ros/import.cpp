// `orthosonar import` (import.hpp). Two passes over the recording, both in file order:
// the first reads each mapped message's stamp (the header's, without decoding the rest)
// and numbers the messages of each channel in stamp order; the second decodes, converts
// and writes them. Memory holds one chunk and 12 bytes per message, never the recording.
#include "replay/ros/import.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>

#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"
#include "orthosonar/version.hpp"
#include "replay/mcap_generic.hpp"
#include "replay/ros/msg_types.hpp"
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/rosbag.hpp"

namespace orthosonar::replay::ros {
namespace {

using rosmsg::Value;

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr int64_t kNsPerS = 1'000'000'000;

// ---- The recording: a bag or an MCAP file, visited in file order ----------------------

struct SrcChannel {
  std::string topic, type, definition;
  rosmsg::Dialect dialect = rosmsg::Dialect::kRos1;
  rosmsg::Encoding encoding = rosmsg::Encoding::kRos1;
  std::string encoding_name;  // as the file says
  std::string unusable;       // why its messages cannot be decoded ("" when they can)
};

struct SrcMessage {
  uint32_t channel = 0;
  uint64_t receive_ns = 0;
  const uint8_t* data = nullptr;
  size_t size = 0;
  uint64_t chunk_offset = 0, offset = 0;
};

using OnChannel = std::function<Status(uint32_t, const SrcChannel&)>;
using OnMessage = std::function<Status(const SrcMessage&)>;

bool starts_with(const uint8_t* p, size_t n, std::string_view s) {
  return n >= s.size() && std::memcmp(p, s.data(), s.size()) == 0;
}

struct Recording {
  std::string path, format;
  uint64_t bytes = 0;
  bool complete = true;
  std::string recovery;

  // Visits the whole file (again from the start on every call).
  Status visit(const OnChannel& on_channel, const OnMessage& on_message) {
    if (format == "ros1 bag") {
      auto bag = rosbag::BagReader::open(path);
      if (!bag) return bag.error();
      const auto& info = (*bag)->info();
      complete = info.complete;
      if (!info.complete)
        recovery = "kept " + std::to_string(info.bytes_recovered) + " of " + std::to_string(info.file_bytes) +
                   " bytes: " + info.detail;
      for (const auto& c : (*bag)->connections()) {
        SrcChannel s;
        s.topic = c.topic;
        s.type = normalise_type(c.type);
        s.definition = c.message_definition;
        s.encoding_name = "ros1";
        if (s.definition.empty()) s.definition = std::string(rosmsg::definition(s.type, rosmsg::Dialect::kRos1));
        if (auto st = on_channel(c.id, s); !st) return st;
      }
      return (*bag)->for_each([&](const rosbag::Connection& c, const rosbag::MessageView& m) {
        return on_message(SrcMessage{c.id, m.time_ns, m.data, m.size, m.chunk_offset, m.offset});
      });
    }
    RecoveryReport rec;
    Status s = mcap::visit_messages(
        path,
        [&](const mcap::RawChannel& c, const mcap::RawSchema* schema) {
          SrcChannel s;
          s.topic = c.topic;
          s.encoding_name = c.message_encoding;
          if (schema != nullptr) {
            s.type = normalise_type(schema->name);
            s.definition = schema->data;
            if (schema->encoding == "ros2msg") s.dialect = rosmsg::Dialect::kRos2;
            else if (schema->encoding == "ros1msg") s.dialect = rosmsg::Dialect::kRos1;
            else s.unusable = "schema encoding '" + schema->encoding + "' (ros1msg or ros2msg expected)";
          } else {
            s.unusable = "no schema";
          }
          if (c.message_encoding == "cdr") s.encoding = rosmsg::Encoding::kCdr;
          else if (c.message_encoding == "ros1") s.encoding = rosmsg::Encoding::kRos1;
          else if (s.unusable.empty()) s.unusable = "message encoding '" + c.message_encoding + "' (ros1 or cdr expected)";
          if (s.unusable.empty() && s.definition.empty())
            s.definition = std::string(rosmsg::definition(s.type, s.dialect));
          return on_channel(c.id, s);
        },
        [&](const mcap::RawMessage& m) {
          return on_message(SrcMessage{m.channel_id, m.log_time_ns, m.data, m.size, m.chunk_offset, m.offset});
        },
        &rec);
    complete = rec.complete;
    if (!rec.complete)
      recovery = "kept " + std::to_string(rec.bytes_recovered) + " of " + std::to_string(rec.bytes_total) +
                 " bytes: " + rec.detail;
    return s;
  }
};

Result<Recording> open_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  uint8_t head[13] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto n = static_cast<size_t>(in.gcount());
  Recording r;
  r.path = path;
  std::error_code ec;
  r.bytes = std::filesystem::file_size(path, ec);
  if (starts_with(head, n, "#ROSBAG V2.0\n")) {
    r.format = "ros1 bag";
  } else if (starts_with(head, n, "\x89MCAP0\r\n")) {
    r.format = "mcap";
  } else if (starts_with(head, n, "#ROSBAG V")) {
    return Error{path + ": a ROS bag of another format version (only 2.0, the format of ROS 1 since 2010, is read)"};
  } else {
    return Error{path + ": neither a ROS 1 bag (\"#ROSBAG V2.0\") nor an MCAP file (magic \\x89MCAP0) at byte 0"};
  }
  return r;
}

std::string where(const Recording& rec, const SrcChannel& c, uint64_t index, const SrcMessage& m) {
  std::string s = rec.path + ": " + c.topic + " message " + std::to_string(index);
  if (m.chunk_offset != 0)
    s += " (chunk at byte " + std::to_string(m.chunk_offset) + ", offset " + std::to_string(m.offset) + ")";
  else
    s += " (byte " + std::to_string(m.offset) + ")";
  return s;
}

// ---- Converters -------------------------------------------------------------------------

enum class Kind { kOculusPing, kOculusPingRaw, kProjected, kImu, kRtiDvl, kTwistCov, kTwist, kBar30, kPressure,
                  kPose, kOdometry };

struct TypeEntry {
  std::string_view type;
  Kind kind;
  Role roles[2];  // the roles it can feed (second = first when only one)
};
constexpr TypeEntry kTypes[] = {
    {"sonar_oculus/OculusPing", Kind::kOculusPing, {Role::kHorizontalSonar, Role::kVerticalSonar}},
    {"sonar_oculus/OculusPingUncompressed", Kind::kOculusPingRaw, {Role::kHorizontalSonar, Role::kVerticalSonar}},
    {"marine_acoustic_msgs/ProjectedSonarImage", Kind::kProjected, {Role::kHorizontalSonar, Role::kVerticalSonar}},
    {"acoustic_msgs/ProjectedSonarImage", Kind::kProjected, {Role::kHorizontalSonar, Role::kVerticalSonar}},
    {"sensor_msgs/Imu", Kind::kImu, {Role::kImu, Role::kImu}},
    {"rti_dvl/DVL", Kind::kRtiDvl, {Role::kDvl, Role::kDvl}},
    {"geometry_msgs/TwistWithCovarianceStamped", Kind::kTwistCov, {Role::kDvl, Role::kDvl}},
    {"geometry_msgs/TwistStamped", Kind::kTwist, {Role::kDvl, Role::kDvl}},
    {"bar30_depth/Depth", Kind::kBar30, {Role::kDepth, Role::kDepth}},
    {"sensor_msgs/FluidPressure", Kind::kPressure, {Role::kDepth, Role::kDepth}},
    {"geometry_msgs/PoseStamped", Kind::kPose, {Role::kTruth, Role::kTruth}},
    {"nav_msgs/Odometry", Kind::kOdometry, {Role::kTruth, Role::kTruth}},
};

const TypeEntry* type_entry(const std::string& type) {
  for (const auto& e : kTypes)
    if (e.type == type) return &e;
  return nullptr;
}

std::string types_for(Role role) {
  std::string s;
  for (const auto& e : kTypes)
    if (e.roles[0] == role || e.roles[1] == role) s += (s.empty() ? "" : ", ") + std::string(e.type);
  return s;
}

// Why `type` cannot feed `role` ("" when it can).
std::string check_type(Role role, const std::string& type) {
  const TypeEntry* e = type_entry(type);
  if (e == nullptr || (e->roles[0] != role && e->roles[1] != role))
    return "type " + type + " cannot be the " + std::string(role_name(role)) + " (readable types: " + types_for(role) +
           ")";
  return "";
}

// A decoded number for an error message: any double, never cast to an integer.
std::string import_number_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Field access with errors naming the field.
struct MessageFields {
  const Value& root;
  const std::string& at;
  Result<const Value*> get(std::string_view path) const {
    const Value* v = root.find(path);
    if (v == nullptr) return Error{at + ": no field '" + std::string(path) + "'"};
    return v;
  }
  Result<double> num(std::string_view path) const {
    auto v = get(path);
    if (!v) return v.error();
    if ((*v)->kind() != Value::Kind::kNumber) return Error{at + ": field '" + std::string(path) + "' is not a number"};
    return (*v)->as_double();
  }
  bool has_number(std::string_view path) const {
    const Value* v = root.find(path);
    return v != nullptr && v->kind() == Value::Kind::kNumber;
  }
  // A number that must be finite (a file's own definition may make any field a float).
  Result<double> finite(std::string_view path) const {
    auto v = num(path);
    if (!v) return v.error();
    if (!std::isfinite(*v))
      return Error{at + ": field '" + std::string(path) + "' is " + import_number_text(*v) + ", not a finite number"};
    return *v;
  }
  // An integer field checked against [lo, hi] before any cast (NaN and out-of-range values
  // make a double -> integer conversion undefined).
  Result<int64_t> integer(std::string_view path, int64_t lo, int64_t hi) const {
    auto v = num(path);
    if (!v) return v.error();
    if (!(*v >= static_cast<double>(lo) && *v <= static_cast<double>(hi)))
      return Error{at + ": field '" + std::string(path) + "' is " + import_number_text(*v) + ", outside " +
                   std::to_string(lo) + ".." + std::to_string(hi)};
    return static_cast<int64_t>(*v);
  }
  // Finite components unless `any_value` (a DVL marks a bad velocity with NaN).
  Result<Vec3> vec3(std::string_view path, bool any_value = false) const {
    const std::string p(path);
    auto get_one = [&](const std::string& q) { return any_value ? num(q) : finite(q); };
    auto x = get_one(p + ".x"), y = get_one(p + ".y"), z = get_one(p + ".z");
    if (!x) return x.error();
    if (!y) return y.error();
    if (!z) return z.error();
    return Vec3(*x, *y, *z);
  }
  Result<Quat> quat(std::string_view path) const {
    const std::string p(path);
    auto w = finite(p + ".w");
    if (!w) return w.error();
    auto v = vec3(path);
    if (!v) return v.error();
    return Quat(*w, v->x(), v->y(), v->z());
  }
};

// NED world / FRD body to ENU world / FLU body (REP-103).
Vec3 frd_to_flu(const Vec3& v) { return Vec3(v.x(), -v.y(), -v.z()); }
Vec3 ned_to_enu(const Vec3& v) { return Vec3(v.y(), v.x(), -v.z()); }
Quat ned_frd_to_enu_flu(const Quat& q_ned_frd) {
  Eigen::Matrix3d R_enu_ned;
  R_enu_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Matrix3d R_frd_flu = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return Quat(R_enu_ned * q_ned_frd.toRotationMatrix() * R_frd_flu);
}

// Oculus operating frequency from the part and the fire message's mode (1 low, 2 high).
double oculus_frequency(uint16_t part, int mode) {
  const bool high = mode == 2;
  if (part == kPartM1200d) return high ? 2.1e6 : 1.2e6;
  return high ? 1.2e6 : 750e3;  // M750d and unknown parts
}

// A compressed ping holds at most this many pixels (an M1200d's 512 beams x 2000 ranges is
// a sixteenth of it); the decoder allocates what the image's header states.
constexpr uint64_t kImportMaxImagePixels = uint64_t{1} << 24;

// Rows and columns stated by a PNG's IHDR or a JPEG's first frame header (SOFn), the header
// the decoder sizes its image by; nullopt when the bytes are neither or the header is cut.
std::optional<std::pair<uint32_t, uint32_t>> import_image_size(const uint8_t* d, size_t n) {
  auto be16 = [&](size_t at) { return static_cast<uint32_t>(d[at]) << 8 | d[at + 1]; };
  auto be32 = [&](size_t at) { return be16(at) << 16 | be16(at + 2); };
  static constexpr uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 24 && std::memcmp(d, kPng, 8) == 0) {
    if (std::memcmp(d + 12, "IHDR", 4) != 0) return std::nullopt;
    return std::pair{be32(20), be32(16)};  // height, width
  }
  if (n < 4 || d[0] != 0xFF || d[1] != 0xD8) return std::nullopt;
  // Marker segments up to the first SOFn (C0..CF except DHT C4, JPG C8, DAC CC).
  for (size_t at = 2; at + 1 < n;) {
    if (d[at] != 0xFF) return std::nullopt;
    const uint8_t marker = d[at + 1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {  // no length
      at += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA || at + 4 > n) return std::nullopt;  // EOI or scan data before a frame
    const size_t len = be16(at + 2);
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (len < 7 || at + 9 > n) return std::nullopt;
      return std::pair{be16(at + 5), be16(at + 7)};  // height, width
    }
    if (len < 2) return std::nullopt;
    at += 2 + len;
  }
  return std::nullopt;
}

void copy_image(SonarPing& p, const uint8_t* data, size_t step, uint32_t height, uint32_t width, int bpp,
                  bool big_endian) {
  p.bytes_per_pixel = static_cast<uint8_t>(bpp);
  const size_t row = static_cast<size_t>(width) * static_cast<size_t>(bpp);
  p.image.resize(row * height);
  for (uint32_t r = 0; r < height; ++r) std::memcpy(p.image.data() + r * row, data + r * step, row);
  if (bpp == 2 && big_endian)
    for (size_t i = 0; i + 1 < p.image.size(); i += 2) std::swap(p.image[i], p.image[i + 1]);
}

Result<SonarPing> convert_oculus(const MessageFields& f, const TopicRule& rule, bool compressed) {
  SonarPing p;
  p.mount = rule.role == Role::kVerticalSonar ? SonarMount::kVertical : SonarMount::kHorizontal;
  p.device_id = rule.device_id;
  auto part = f.num("part_number");
  const uint16_t default_part = p.mount == SonarMount::kVertical ? kPartM1200d : kPartM750d;
  p.part_number = rule.part_number != 0 ? rule.part_number
                  : (part && *part > 0 && *part <= 65535) ? static_cast<uint16_t>(*part) : default_part;
  auto ping_id = f.integer("ping_id", 0, UINT32_MAX);
  if (!ping_id) return ping_id.error();
  p.ping_id = static_cast<uint32_t>(*ping_id);
  auto res = f.num("range_resolution");
  if (!res) return res.error();
  if (!(*res > 0) || !std::isfinite(*res)) return Error{f.at + ": range_resolution " + std::to_string(*res) + " m is not positive"};
  p.range_resolution_m = *res;
  // Optional fields: absent is a default, present must be a finite (mode: 0..255) number.
  p.gain_percent = 0.0;
  if (f.has_number("fire_msg.gain")) {
    auto gain = f.finite("fire_msg.gain");
    if (!gain) return gain.error();
    p.gain_percent = *gain;
  }
  int mode = 1;
  if (f.has_number("fire_msg.mode")) {
    auto m = f.integer("fire_msg.mode", 0, 255);
    if (!m) return m.error();
    mode = static_cast<int>(*m);
  }
  p.frequency_hz = oculus_frequency(p.part_number, mode);
  auto nr = f.num("num_ranges"), nb = f.num("num_beams");
  if (!nr) return nr.error();
  if (!nb) return nb.error();
  // Written so that NaN fails it too.
  if (!(*nr >= 1 && *nr <= 65535 && *nb >= 2 && *nb <= 65535))
    return Error{f.at + ": num_ranges " + import_number_text(*nr) + " x num_beams " + import_number_text(*nb) +
                 " is not an image (1..65535 x 2..65535)"};
  p.rows = static_cast<uint16_t>(*nr);
  p.cols = static_cast<uint16_t>(*nb);
  auto bearings = f.get("bearings");
  if (!bearings) return bearings.error();
  const std::vector<double> centi = (*bearings)->as_doubles();
  if (centi.size() != p.cols)
    return Error{f.at + ": " + std::to_string(centi.size()) + " bearings for num_beams " + std::to_string(p.cols)};
  p.bearings_rad.reserve(centi.size());
  for (size_t i = 0; i < centi.size(); ++i) {
    const double c = centi[i];
    // int16 as the device sends them; a file's own definition may make them anything.
    if (!(std::abs(c) <= 36000.0))
      return Error{f.at + ": field 'bearings[" + std::to_string(i) + "]' is " + import_number_text(c) +
                   " (1/100 degree), outside -36000..36000"};
    // The device's table: int16, 1/100 degree (the same arithmetic as every other reader).
    const double rad = c * 0.01 * kDegree;
    p.bearings_rad.push_back(rule.flip_bearings ? -rad : rad);
  }
  auto img = f.get("ping");
  if (!img) return img.error();
  const MessageFields fi{**img, f.at};
  if (compressed) {
    auto data = fi.get("data");
    if (!data) return data.error();
    const auto bytes = (*data)->bytes();
    if (bytes.empty()) return Error{f.at + ": ping.data is empty"};
    auto format = fi.get("format");
    const std::string fmt = format ? (*format)->as_string() : "";
    // The size the image's header states, checked before decoding: a few hundred bytes of
    // JPEG can state 65535 x 65535 pixels, and the decoder allocates what the header says.
    const auto stated = import_image_size(bytes.data(), bytes.size());
    if (!stated)
      return Error{f.at + ": ping.data (format '" + fmt + "') is neither a JPEG nor a PNG image (no size in its header)"};
    if (stated->first != p.rows || stated->second != p.cols)
      return Error{f.at + ": the image is " + std::to_string(stated->first) + " x " + std::to_string(stated->second) +
                   " but num_ranges x num_beams is " + std::to_string(p.rows) + " x " + std::to_string(p.cols)};
    if (static_cast<uint64_t>(p.rows) * p.cols > kImportMaxImagePixels)
      return Error{f.at + ": the image is " + std::to_string(p.rows) + " x " + std::to_string(p.cols) + ", more than " +
                   std::to_string(kImportMaxImagePixels) + " pixels"};
    auto decoded = codec::decode_image(bytes, codec::DecodeAs::kGray, f.at + ": ping.data (format '" + fmt + "')",
                                       kImportMaxImagePixels);
    if (!decoded) return decoded.error();
    const cv::Mat& m = *decoded;
    if (m.rows != p.rows || m.cols != p.cols)
      return Error{f.at + ": the image is " + std::to_string(m.rows) + " x " + std::to_string(m.cols) +
                   " but num_ranges x num_beams is " + std::to_string(p.rows) + " x " + std::to_string(p.cols)};
    const int bpp = m.depth() == CV_16U ? 2 : 1;
    if (m.depth() != CV_8U && m.depth() != CV_16U) return Error{f.at + ": ping.data decodes to neither 8- nor 16-bit pixels"};
    copy_image(p, m.data, m.step[0], p.rows, p.cols, bpp, false);
    return p;
  }
  auto height = fi.num("height"), width = fi.num("width"), step = fi.num("step"), be = fi.num("is_bigendian");
  auto enc = fi.get("encoding");
  auto data = fi.get("data");
  if (!height) return height.error();
  if (!width) return width.error();
  if (!step) return step.error();
  if (!enc) return enc.error();
  if (!data) return data.error();
  const std::string e = (*enc)->as_string();
  const int bpp = (e == "mono8" || e == "8UC1") ? 1 : (e == "mono16" || e == "16UC1") ? 2 : 0;
  if (bpp == 0) return Error{f.at + ": ping.encoding '" + e + "' (mono8, 8UC1, mono16 or 16UC1 expected)"};
  if (*height != p.rows || *width != p.cols)  // NaN too
    return Error{f.at + ": the image is " + import_number_text(*height) + " x " + import_number_text(*width) +
                 " but num_ranges x num_beams is " + std::to_string(p.rows) + " x " + std::to_string(p.cols)};
  const auto bytes = (*data)->bytes();
  const auto row = static_cast<double>(p.cols) * bpp;
  // Written so that a NaN or infinite step fails it: the cast below needs step <= bytes.
  if (!(*step >= row && static_cast<double>(bytes.size()) >= *step * (p.rows - 1) + row))
    return Error{f.at + ": ping.data has " + std::to_string(bytes.size()) + " bytes, too few for " +
                 std::to_string(p.rows) + " rows of step " + import_number_text(*step)};
  copy_image(p, bytes.data(), static_cast<size_t>(*step), p.rows, p.cols, bpp, be && *be != 0);
  return p;
}

Result<SonarPing> convert_projected(const MessageFields& f, const TopicRule& rule) {
  SonarPing p;
  p.mount = rule.role == Role::kVerticalSonar ? SonarMount::kVertical : SonarMount::kHorizontal;
  p.device_id = rule.device_id;
  p.part_number = rule.part_number != 0 ? rule.part_number
                                        : (p.mount == SonarMount::kVertical ? kPartM1200d : kPartM750d);
  p.frequency_hz = 0.0;
  if (f.has_number("ping_info.frequency")) {
    auto freq = f.finite("ping_info.frequency");
    if (!freq) return freq.error();
    p.frequency_hz = *freq;
  }
  auto dirs = f.get("beam_directions");
  if (!dirs) return dirs.error();
  for (size_t i = 0; i < (*dirs)->elements().size(); ++i) {
    const Value& d = (*dirs)->elements()[i];
    const Value* x = d.find("x");
    const Value* y = d.find("y");
    const Value* z = d.find("z");
    if (x == nullptr || y == nullptr || z == nullptr) return Error{f.at + ": beam_directions element without x, y, z"};
    for (const Value* c : {x, y, z})
      if (c->kind() != Value::Kind::kNumber || !std::isfinite(c->as_double()))
        return Error{f.at + ": field 'beam_directions[" + std::to_string(i) + "]' is not three finite numbers"};
    // Fan in the sensor's Y-Z plane, Z forward, X up: azimuth about X, positive to the left.
    const double b = std::atan2(-y->as_double(), z->as_double());
    p.bearings_rad.push_back(rule.flip_bearings ? -b : b);
  }
  auto ranges_v = f.get("ranges");
  if (!ranges_v) return ranges_v.error();
  const std::vector<double> ranges = (*ranges_v)->as_doubles();
  for (size_t i = 0; i < ranges.size(); ++i)
    if (!std::isfinite(ranges[i]))
      return Error{f.at + ": field 'ranges[" + std::to_string(i) + "]' is " + import_number_text(ranges[i]) +
                   ", not a finite number"};
  if (ranges.size() < 2 || ranges.size() > 65535 || p.bearings_rad.size() < 2 || p.bearings_rad.size() > 65535)
    return Error{f.at + ": " + std::to_string(ranges.size()) + " ranges x " + std::to_string(p.bearings_rad.size()) +
                 " beam_directions is not an image (2..65535 each)"};
  const double res = (ranges.back() - ranges.front()) / static_cast<double>(ranges.size() - 1);
  if (!(res > 0) || !std::isfinite(res)) return Error{f.at + ": ranges do not increase"};
  for (size_t i = 0; i < ranges.size(); ++i)
    if (std::abs(ranges[i] - (ranges.front() + res * static_cast<double>(i))) > 0.05 * res)
      return Error{f.at + ": ranges[" + std::to_string(i) + "] = " + std::to_string(ranges[i]) +
                   " m: range bins are not evenly spaced (orthosonar's images are)"};
  p.range_resolution_m = res;
  p.rows = static_cast<uint16_t>(ranges.size());
  p.cols = static_cast<uint16_t>(p.bearings_rad.size());
  auto dtype = f.num("image.dtype"), be = f.num("image.is_bigendian"), count = f.num("image.beam_count");
  auto data = f.get("image.data");
  if (!dtype) return dtype.error();
  if (!data) return data.error();
  if (count && *count != p.cols)  // NaN too
    return Error{f.at + ": image.beam_count " + import_number_text(*count) + " but " + std::to_string(p.cols) +
                 " beam_directions"};
  const auto bytes = (*data)->bytes();
  const size_t n = static_cast<size_t>(p.rows) * p.cols;
  // Checked before the cast (NaN or a huge dtype would make it undefined).
  if (!(*dtype >= 0 && *dtype <= 9))
    return Error{f.at + ": image.dtype " + import_number_text(*dtype) + " is not one of 0..9"};
  const int dt = static_cast<int>(*dtype);
  const size_t size = dt == 0 || dt == 1 ? 1 : dt == 2 || dt == 3 ? 2 : dt == 4 || dt == 5 || dt == 8 ? 4 : 8;
  if (bytes.size() != n * size)
    return Error{f.at + ": image.data has " + std::to_string(bytes.size()) + " bytes; " + std::to_string(p.rows) +
                 " ranges x " + std::to_string(p.cols) + " beams of dtype " + std::to_string(dt) + " need " +
                 std::to_string(n * size)};
  const bool big = be && *be != 0;
  if (dt == 0 || dt == 2) {
    copy_image(p, bytes.data(), size * p.cols, p.rows, p.cols, static_cast<int>(size), big);
    return p;
  }
  if (dt == 8 || dt == 9) {
    // Float intensities: [0, 1] scaled to 8 bits, anything larger taken as 0..255.
    std::vector<double> v(n);
    double mx = 0.0;
    for (size_t i = 0; i < n; ++i) {
      uint8_t b[8];
      std::memcpy(b, bytes.data() + i * size, size);
      if (big) std::reverse(b, b + size);
      if (dt == 8) {
        float x;
        std::memcpy(&x, b, 4);
        v[i] = x;
      } else {
        std::memcpy(&v[i], b, 8);
      }
      if (!std::isfinite(v[i])) v[i] = 0.0;
      mx = std::max(mx, v[i]);
    }
    const double scale = mx <= 1.0 ? 255.0 : 1.0;
    p.bytes_per_pixel = 1;
    p.image.resize(n);
    // Clamped before rounding: lround of a value beyond long's range is unspecified.
    for (size_t i = 0; i < n; ++i) p.image[i] = static_cast<uint8_t>(std::lround(std::clamp(v[i] * scale, 0.0, 255.0)));
    return p;
  }
  return Error{f.at + ": image.dtype " + std::to_string(dt) + " (uint8 0, uint16 2, float32 8 and float64 9 are read)"};
}

Result<Payload> convert(Kind kind, const Value& msg, const TopicRule& rule, int64_t stamp_ns, const std::string& at) {
  const MessageFields f{msg, at};
  const Time t = Time::from_ns(stamp_ns);
  const bool ned = rule.convention == Convention::kNedFrd;
  switch (kind) {
    case Kind::kOculusPing:
    case Kind::kOculusPingRaw:
    case Kind::kProjected: {
      auto p = kind == Kind::kProjected ? convert_projected(f, rule) : convert_oculus(f, rule, kind == Kind::kOculusPing);
      if (!p) return p.error();
      p->stamp = t;
      return Payload(std::move(*p));
    }
    case Kind::kImu: {
      ImuReading r;
      r.stamp = t;
      auto q = f.quat("orientation");
      auto w = f.vec3("angular_velocity");
      auto a = f.vec3("linear_acceleration");
      if (!q) return q.error();
      if (!w) return w.error();
      if (!a) return a.error();
      auto cov = f.get("orientation_covariance");
      const auto c = cov ? (*cov)->as_doubles() : std::vector<double>{};
      if (q->coeffs().squaredNorm() < 0.25 || (!c.empty() && c[0] == -1.0))
        return Error{at + ": orientation unknown (a zero quaternion or orientation_covariance[0] = -1); "
                          "the pipeline needs the IMU's orientation"};
      if (q->coeffs().squaredNorm() > 4.0)
        return Error{at + ": field 'orientation' has norm " + import_number_text(q->coeffs().norm()) +
                     ", not a rotation (a unit quaternion)"};
      r.q_W_V = ned ? ned_frd_to_enu_flu(*q) : *q;
      r.angular_velocity_V = ned ? frd_to_flu(*w) : *w;
      r.linear_acceleration_V = ned ? frd_to_flu(*a) : *a;
      return Payload(r);
    }
    case Kind::kRtiDvl:
    case Kind::kTwistCov:
    case Kind::kTwist: {
      DvlReading r;
      r.stamp = t;
      const char* path = kind == Kind::kRtiDvl ? "velocity" : kind == Kind::kTwistCov ? "twist.twist.linear" : "twist.linear";
      auto v = f.vec3(path, true);
      if (!v) return v.error();
      // Invalid: not finite, or the DVL's "bad velocity" marker (RTI: 88.888).
      r.valid = v->allFinite() && v->cwiseAbs().maxCoeff() < 50.0;
      if (kind == Kind::kTwistCov) {
        auto cov = f.get("twist.covariance");
        if (cov) {
          const auto c = (*cov)->as_doubles();
          if (!c.empty() && c[0] < 0) r.valid = false;
        }
      }
      r.velocity_V_mps = r.valid ? (ned ? frd_to_flu(*v) : *v) : Vec3::Zero();
      if (kind == Kind::kRtiDvl) {
        auto alt = f.num("altitude");
        r.altitude_m = alt && std::isfinite(*alt) && *alt > 0 ? *alt : 0.0;
      }
      return Payload(r);
    }
    case Kind::kBar30:
    case Kind::kPressure: {
      DepthReading r;
      r.stamp = t;
      if (kind == Kind::kBar30) {
        auto d = f.num("depth");
        if (!d) return d.error();
        r.depth_m = *d;
      } else {
        auto pa = f.num("fluid_pressure");
        if (!pa) return pa.error();
        r.depth_m = (*pa - rule.atmospheric_pressure_pa) / (rule.fluid_density_kg_m3 * rule.gravity_m_s2);
      }
      if (!std::isfinite(r.depth_m)) return Error{at + ": depth is not a finite number"};
      return Payload(r);
    }
    case Kind::kPose:
    case Kind::kOdometry: {
      TruthPose r;
      r.stamp = t;
      const std::string base = kind == Kind::kPose ? "pose" : "pose.pose";
      auto p = f.vec3(base + ".position");
      auto q = f.quat(base + ".orientation");
      if (!p) return p.error();
      if (!q) return q.error();
      if (!(q->coeffs().squaredNorm() >= 0.25 && q->coeffs().squaredNorm() <= 4.0))
        return Error{at + ": field '" + base + ".orientation' has norm " + import_number_text(q->coeffs().norm()) +
                     ", not a rotation (a unit quaternion)"};
      r.p_W = ned ? ned_to_enu(*p) : *p;
      r.q_W_V = ned ? ned_frd_to_enu_flu(*q) : *q;
      return Payload(r);
    }
  }
  return Error{at + ": unknown type"};
}

// ---- Channel state shared by both passes ------------------------------------------------

struct ChannelState {
  SrcChannel src;
  const TopicRule* rule = nullptr;  // nullptr: not imported
  const TypeEntry* entry = nullptr;
  std::optional<rosmsg::Schema> schema;
  bool header_first = false;        // the root's first field is a std_msgs/Header
  uint64_t index = 0;               // messages seen on this channel (this pass)
};

// Whether the file's own std_msgs/Header is laid out as fast_header_stamp reads it: ros1
// `uint32 seq` then `time stamp`; CDR `builtin_interfaces/Time stamp` first. Another
// layout (a ROS 2 Header in a ros1-encoded file, a definition of its own) is decoded.
bool import_standard_header(const rosmsg::Schema& schema, rosmsg::Encoding encoding) {
  const rosmsg::MsgSpec* h = schema.find("std_msgs/Header");
  if (h == nullptr) return false;
  const auto& f = h->fields;
  auto is_stamp = [](const rosmsg::Field& x) { return x.prim == rosmsg::Prim::kTime && x.array < 0; };
  if (encoding == rosmsg::Encoding::kRos1)
    return f.size() >= 2 && f[0].array < 0 && (f[0].prim == rosmsg::Prim::kUint32 || f[0].prim == rosmsg::Prim::kInt32) &&
           is_stamp(f[1]) && f[1].name == "stamp";
  return !f.empty() && is_stamp(f[0]) && f[0].name == "stamp";
}

// The header stamp read straight from the bytes when the root starts with a Header.
std::optional<int64_t> fast_header_stamp(const ChannelState& c, const SrcMessage& m) {
  if (!c.header_first) return std::nullopt;
  auto u32 = [&](size_t at, bool big) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<uint32_t>(m.data[at + static_cast<size_t>(i)]) << (big ? 8 * (3 - i) : 8 * i);
    return v;
  };
  if (c.src.encoding == rosmsg::Encoding::kRos1) {
    if (m.size < 12) return std::nullopt;
    return static_cast<int64_t>(u32(4, false)) * kNsPerS + u32(8, false);
  }
  if (m.size < 12 || m.data[0] != 0 || (m.data[1] != 0 && m.data[1] != 1)) return std::nullopt;
  const bool big = m.data[1] == 0;
  const auto sec = static_cast<int32_t>(u32(4, big));
  return static_cast<int64_t>(sec) * kNsPerS + u32(8, big);
}

}  // namespace

double TopicInfo::rate_hz() const {
  if (count < 2 || last_ns <= first_ns) return 0.0;
  return static_cast<double>(count - 1) / (static_cast<double>(last_ns - first_ns) * 1e-9);
}

std::string normalise_type(const std::string& type) {
  const auto a = type.find("/msg/");
  if (a != std::string::npos) return type.substr(0, a) + "/" + type.substr(a + 5);
  return type;
}

namespace {

// Resolves channels against the map (both commands).
struct Resolver {
  const TopicMap& map;
  std::map<uint32_t, ChannelState> channels;
  std::map<Role, std::string> role_topic;
  Status add(uint32_t id, const SrcChannel& s, const std::string& path, bool strict) {
    ChannelState c;
    c.src = s;
    c.rule = map.find(s.topic);
    if (c.rule != nullptr) {
      std::string why = s.unusable;
      if (why.empty()) why = check_type(c.rule->role, s.type);
      if (why.empty()) {
        c.entry = type_entry(s.type);
        auto schema = rosmsg::Schema::parse(s.type, s.definition, s.dialect);
        if (!schema) why = "its definition does not parse: " + schema.error().message;
        else c.schema = std::move(*schema);
      }
      if (!why.empty()) {
        if (strict) return Error{path + ": topic " + s.topic + " (" + std::string(role_name(c.rule->role)) + "): " + why};
        c.src.unusable = why;
      } else {
        const auto [it, fresh] = role_topic.emplace(c.rule->role, s.topic);
        if (!fresh && it->second != s.topic) {
          if (strict)
            return Error{path + ": two topics for the " + std::string(role_name(c.rule->role)) + ": " + it->second +
                         " and " + s.topic + " (map one of them to another role, or drop it from topics.yaml)"};
          c.src.unusable = "another topic (" + it->second + ") already feeds this role";
        }
        const auto& fields = c.schema->find(c.schema->root())->fields;
        c.header_first = !fields.empty() && fields.front().prim == rosmsg::Prim::kMessage &&
                         fields.front().array < 0 && fields.front().type == "std_msgs/Header" &&
                         import_standard_header(*c.schema, s.encoding);
      }
    }
    channels[id] = std::move(c);
    return {};
  }
};

}  // namespace

namespace {

void count(std::map<std::string, TopicInfo>& topics, const std::string& topic, const SrcMessage& m) {
  TopicInfo& t = topics[topic];
  if (t.count == 0) t.first_ns = t.last_ns = m.receive_ns;
  ++t.count;
  t.first_ns = std::min(t.first_ns, m.receive_ns);
  t.last_ns = std::max(t.last_ns, m.receive_ns);
}

InputSummary summarise(const std::string& path, const Recording* rec, const Resolver& res,
                       std::map<std::string, TopicInfo> topics) {
  InputSummary out;
  out.path = path;
  out.format = rec->format;
  out.bytes = rec->bytes;
  out.complete = rec->complete;
  out.recovery = rec->recovery;
  for (const auto& [id, c] : res.channels) {
    TopicInfo& t = topics[c.src.topic];
    t.topic = c.src.topic;
    if (t.type.empty()) t.type = c.src.type;
    t.encoding = c.src.encoding_name;
    if (c.rule != nullptr) t.role = c.rule->role;
    if (!c.src.unusable.empty()) t.note = c.src.unusable;
  }
  for (auto& [name, t] : topics) out.topics.push_back(t);
  return out;
}

}  // namespace

Result<InputSummary> list_input(const std::string& path, const TopicMap& map) {
  auto rec = open_recording(path);
  if (!rec) return rec.error();
  Resolver res{map, {}, {}};
  std::map<std::string, TopicInfo> topics;
  Status s = rec->visit([&](uint32_t id, const SrcChannel& c) { return res.add(id, c, path, false); },
                        [&](const SrcMessage& m) -> Status {
                          const auto it = res.channels.find(m.channel);
                          if (it == res.channels.end())
                            return Error{path + ": message on undefined connection " + std::to_string(m.channel)};
                          count(topics, it->second.src.topic, m);
                          return {};
                        });
  if (!s) return s.error();
  return summarise(path, &*rec, res, std::move(topics));
}

Result<ImportReport> import_recording(const std::string& in, const std::string& out, const ImportOptions& options) {
  auto rec = open_recording(in);
  if (!rec) return rec.error();
  ImportReport report;

  // Pass 1: channels, stamps, per-channel order.
  Resolver res{options.map, {}, {}};
  struct Stamp {
    int64_t ns;
    uint32_t k;  // the message's index among imported messages, file order
  };
  std::map<Channel, std::vector<Stamp>> stamps;
  uint32_t k = 0;
  std::map<std::string, TopicInfo> topics;
  Status s = rec->visit([&](uint32_t id, const SrcChannel& c) { return res.add(id, c, in, true); },
                        [&](const SrcMessage& m) -> Status {
                          const auto it = res.channels.find(m.channel);
                          if (it == res.channels.end())
                            return Error{in + ": message on undefined connection " + std::to_string(m.channel)};
                          ChannelState& c = it->second;
                          count(topics, c.src.topic, m);
                          const uint64_t index = c.index++;
                          if (c.rule == nullptr) return {};
                          int64_t ns = static_cast<int64_t>(m.receive_ns);
                          if (c.rule->stamp == StampSource::kHeader) {
                            auto fast = fast_header_stamp(c, m);
                            if (!fast) {
                              auto v = rosmsg::decode(*c.schema, c.src.encoding, m.data, m.size);
                              if (!v) return Error{where(*rec, c.src, index, m) + ": " + v.error().message};
                              const Value* h = v->find("header.stamp");
                              if (h == nullptr)
                                return Error{where(*rec, c.src, index, m) +
                                             ": no header.stamp (set `stamp: receive` for this topic in topics.yaml)"};
                              if (h->kind() != Value::Kind::kTime)
                                return Error{where(*rec, c.src, index, m) + ": field 'header.stamp' is not a time"};
                              fast = h->as_ns();
                            }
                            ns = *fast;
                          }
                          if (ns < 0 || ns >= (int64_t{1} << 32) * kNsPerS)
                            return Error{where(*rec, c.src, index, m) + ": stamp " + std::to_string(ns) +
                                         " ns is outside the ROS time range"};
                          if (k == UINT32_MAX) return Error{in + ": more than 4294967295 messages"};
                          stamps[channel_for(c.rule->role)].push_back({ns, k++});
                          return {};
                        });
  if (!s) return s.error();
  std::string missing;
  for (Role r : kRequiredRoles)
    if (!stamps.count(channel_for(r))) missing += (missing.empty() ? "" : ", ") + std::string(role_name(r));
  if (!missing.empty()) {
    std::string mapped;
    for (const auto& [role, topic] : res.role_topic) mapped += "\n  " + topic + " -> " + std::string(role_name(role));
    return Error{in + ": no messages for " + missing + " (mapped topics:" + (mapped.empty() ? " none" : mapped) +
                 "); map a topic to each role in topics.yaml (--map), see `orthosonar import --list " + in + "`" +
                 (rec->complete ? "" : "; " + in + " is truncated: " + rec->recovery)};
  }
  std::vector<uint64_t> sequence(k);
  for (auto& [ch, v] : stamps) {
    std::stable_sort(v.begin(), v.end(), [](const Stamp& a, const Stamp& b) { return a.ns < b.ns; });
    for (size_t i = 0; i < v.size(); ++i) sequence[v[i].k] = i;
  }
  int64_t first = INT64_MAX, last = INT64_MIN;
  for (const auto& [ch, v] : stamps) {
    first = std::min(first, v.front().ns);
    last = std::max(last, v.back().ns);
  }

  // Pass 2: decode, convert, write (to a temporary name, renamed when complete).
  FixtureMetadata md;
  md["imported_from"] = std::filesystem::path(in).filename().string();
  md["import_format"] = rec->format;
  md["software_version"] = kVersion;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(last - first) * 1e-9);
  md["duration_s"] = buf;
  if (!options.map.T_V_h.empty()) md["T_V_h"] = options.map.T_V_h;
  if (!options.map.T_V_v.empty()) md["T_V_v"] = options.map.T_V_v;
  for (const auto& [role, topic] : res.role_topic) md["topic." + std::string(role_name(role))] = topic;
  const std::string tmp = out + ".partial";
  auto writer = FixtureWriter::open(tmp, md, options.writer);
  if (!writer) return writer.error();
  for (auto& [id, c] : res.channels) c.index = 0;
  k = 0;
  s = rec->visit([&](uint32_t, const SrcChannel&) { return Status{}; },
                 [&](const SrcMessage& m) -> Status {
                   ChannelState& c = res.channels.at(m.channel);
                   const uint64_t index = c.index++;
                   if (c.rule == nullptr) return {};
                   const uint32_t kk = k++;
                   auto v = rosmsg::decode(*c.schema, c.src.encoding, m.data, m.size);
                   if (!v) return Error{where(*rec, c.src, index, m) + ": " + v.error().message};
                   int64_t ns = static_cast<int64_t>(m.receive_ns);
                   if (c.rule->stamp == StampSource::kHeader) {
                     const Value* h = v->find("header.stamp");
                     if (h == nullptr) return Error{where(*rec, c.src, index, m) + ": no header.stamp"};
                     if (h->kind() != Value::Kind::kTime)
                       return Error{where(*rec, c.src, index, m) + ": field 'header.stamp' is not a time"};
                     ns = h->as_ns();
                   }
                   // Pass 1 checked the stamp it read; the decoded one is the same (see
                   // header_first), checked again so that no path writes one out of range.
                   if (ns < 0 || ns >= (int64_t{1} << 32) * kNsPerS)
                     return Error{where(*rec, c.src, index, m) + ": stamp " + std::to_string(ns) +
                                  " ns is outside the ROS time range"};
                   auto payload = convert(c.entry->kind, *v, *c.rule, ns, where(*rec, c.src, index, m));
                   if (!payload) return payload.error();
                   Event e;
                   e.stamp = Time::from_ns(ns);
                   e.channel = channel_for(c.rule->role);
                   e.sequence = sequence[kk];
                   if (auto* ping = std::get_if<SonarPing>(&*payload); ping && c.entry->kind == Kind::kProjected)
                     ping->ping_id = static_cast<uint32_t>(e.sequence);
                   e.payload = std::move(*payload);
                   ++report.messages[c.rule->role];
                   ++report.events;
                   return (*writer)->write(e);
                 });
  if (s) s = (*writer)->close();
  writer->reset();
  if (!s) {
    std::remove(tmp.c_str());
    return s.error();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) {
    std::remove(tmp.c_str());
    return Error{out + ": cannot write (" + ec.message() + ")"};
  }
  report.input = summarise(in, &*rec, res, std::move(topics));
  report.first_ns = first;
  report.last_ns = last;
  if (!rec->complete) report.warnings.push_back(in + " is truncated: " + rec->recovery);
  return report;
}

}  // namespace orthosonar::replay::ros
