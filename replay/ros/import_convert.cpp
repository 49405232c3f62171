// `orthosonar import`'s conversions: the readable ROS types and each decoded message turned into the fixture's payload.
#include "replay/ros/import_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"

namespace orthosonar::replay::ros::detail {

static constexpr TypeEntry kTypes[] = {
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
    {"kvh_gyro/gyro", Kind::kKvhGyro, {Role::kGyro, Role::kGyro}},
};

const TypeEntry* type_entry(const std::string& type) {
  for (const auto& e : kTypes)
    if (e.type == type) return &e;
  return nullptr;
}

static std::string types_for(Role role) {
  std::string s;
  for (const auto& e : kTypes)
    if (e.roles[0] == role || e.roles[1] == role) s += (s.empty() ? "" : ", ") + std::string(e.type);
  return s;
}

std::string check_type(Role role, const std::string& type) {
  const TypeEntry* e = type_entry(type);
  if (e == nullptr || (e->roles[0] != role && e->roles[1] != role))
    return "type " + type + " cannot be the " + std::string(role_name(role)) + " (readable types: " + types_for(role) +
           ")";
  return "";
}

namespace {

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

// kvh_gyro/gyro, as the authors' gyro_node publishes the DSP-1760's packets: `status`
// true and `delta` = dx, dy, dz (rad, the gyro's frame, one sample period each); on a
// packet it could not parse, status false and `delta` empty. Anything else is an error.
Result<GyroReading> convert_kvh_gyro(const MessageFields& f) {
  GyroReading g;
  auto status = f.finite("status");  // a bool: any byte but 0 is true, as genpy reads it
  if (!status) return status.error();
  g.valid = *status != 0.0;
  auto delta = f.get("delta");
  if (!delta) return delta.error();
  if ((*delta)->kind() != Value::Kind::kArray && (*delta)->kind() != Value::Kind::kBytes)
    return Error{f.at + ": field 'delta' is not an array (dx, dy, dz in rad)"};
  const std::vector<double> d = (*delta)->as_doubles();
  if (d.empty() && !g.valid) return g;  // the node's message for a mangled packet
  if (d.size() != 3)
    return Error{f.at + ": field 'delta' has " + std::to_string(d.size()) +
                 " elements, not 3 (dx, dy, dz in rad; empty only with status false)"};
  for (size_t i = 0; i < 3; ++i)
    if (!std::isfinite(d[i]))
      return Error{f.at + ": field 'delta[" + std::to_string(i) + "]' is " + import_number_text(d[i]) +
                   ", not a finite number"};
  g.value_G = Vec3(d[0], d[1], d[2]);
  return g;
}

}  // namespace

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
    case Kind::kKvhGyro: {
      // The gyro's own frame: its mounting is T_V_gyro (topics.yaml mounts.gyro), not `convention`.
      auto g = convert_kvh_gyro(f);
      if (!g) return g.error();
      g->stamp = t;
      return Payload(*g);
    }
  }
  return Error{at + ": unknown type"};
}

}  // namespace orthosonar::replay::ros::detail
