#include "replay/ros/codec/ros1_codec.hpp"

#include <cmath>
#include <string>

#include "replay/mcap/mcap_format.hpp"

namespace orthosonar::replay::ros1 {
namespace {

#define OS_SEP "================================================================================\n"
#define OS_HEADER_DEF "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n"
#define OS_QUAT_DEF "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"
#define OS_VEC3_DEF "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n"
#define OS_POINT_DEF "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n"

constexpr SchemaDef kPing{1, "orthosonar_msgs/OculusPing",
    "# One Oculus multibeam ping (sonar_oculus/OculusPing-like), image uncompressed.\n"
    "# Rows are range bins (row i at range_resolution * (i + 1)), columns are beams.\n"
    "std_msgs/Header header\n"
    "uint32 device_id\n"
    "uint16 part_number\n"
    "uint8 MOUNT_HORIZONTAL=0\n"
    "uint8 MOUNT_VERTICAL=1\n"
    "uint8 mount\n"
    "uint32 ping_id\n"
    "float64 range_resolution\n"
    "float64 frequency\n"
    "float64 gain\n"
    "int16[] bearings\n"
    "float64[] bearings_rad\n"
    "uint16 rows\n"
    "uint16 cols\n"
    "uint8 bytes_per_pixel\n"
    "uint8[] image\n" OS_SEP OS_HEADER_DEF};

constexpr SchemaDef kImu{2, "sensor_msgs/Imu",
    "std_msgs/Header header\n"
    "geometry_msgs/Quaternion orientation\n"
    "float64[9] orientation_covariance\n"
    "geometry_msgs/Vector3 angular_velocity\n"
    "float64[9] angular_velocity_covariance\n"
    "geometry_msgs/Vector3 linear_acceleration\n"
    "float64[9] linear_acceleration_covariance\n" OS_SEP OS_HEADER_DEF OS_SEP OS_QUAT_DEF OS_SEP
    OS_VEC3_DEF};

constexpr SchemaDef kDvl{3, "orthosonar_msgs/DvlVelocity",
    "# Bottom-track velocity in the vehicle frame V, validity and altitude (<= 0: unknown).\n"
    "std_msgs/Header header\n"
    "geometry_msgs/Vector3 velocity\n"
    "bool valid\n"
    "float64 altitude\n" OS_SEP OS_HEADER_DEF OS_SEP OS_VEC3_DEF};

constexpr SchemaDef kDepth{4, "orthosonar_msgs/Depth",
    "# Pressure depth in metres below the surface (positive down).\n"
    "std_msgs/Header header\n"
    "float64 depth\n" OS_SEP OS_HEADER_DEF};

constexpr SchemaDef kPose{5, "geometry_msgs/PoseStamped",
    "std_msgs/Header header\n"
    "geometry_msgs/Pose pose\n" OS_SEP OS_HEADER_DEF OS_SEP
    "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"
    OS_SEP OS_POINT_DEF OS_SEP OS_QUAT_DEF};

constexpr SchemaDef kLabels{6, "orthosonar_msgs/SonarLabels",
    "# Per-pixel ground truth for the ping with the same ping_id (simulation only).\n"
    "std_msgs/Header header\n"
    "uint8 mount\n"
    "uint32 ping_id\n"
    "uint16 rows\n"
    "uint16 cols\n"
    "uint8[] semantic\n"
    "uint32[] object_id\n" OS_SEP OS_HEADER_DEF};

constexpr SchemaDef kGyro{7, "orthosonar_msgs/Gyro",
    "# One fibre-optic gyro sample (KVH DSP-1760) in the gyro's own frame: delta angles\n"
    "# (rad) since the previous sample, or rates (rad/s) when is_rate. Earth's rotation is in it.\n"
    "std_msgs/Header header\n"
    "bool status\n"
    "bool is_rate\n"
    "geometry_msgs/Vector3 value\n"
    "uint8 sequence\n"
    "float64 temperature\n" OS_SEP OS_HEADER_DEF OS_SEP OS_VEC3_DEF};

constexpr int64_t kNsPerS = 1'000'000'000;
constexpr int64_t kMaxRosStampNs = (int64_t{1} << 32) * kNsPerS;  // exclusive

Status put_header(const Event& e, Time stamp, CanonicalWriter& out) {
  if (e.sequence > UINT32_MAX) return Error{"sequence " + std::to_string(e.sequence) + " exceeds uint32"};
  if (stamp.ns() < 0 || stamp.ns() >= kMaxRosStampNs)
    return Error{"payload stamp " + std::to_string(stamp.ns()) + " ns outside the ros1 time range"};
  out.put_u32(static_cast<uint32_t>(e.sequence));
  out.put_u32(static_cast<uint32_t>(stamp.ns() / kNsPerS));
  out.put_u32(static_cast<uint32_t>(stamp.ns() % kNsPerS));
  out.put_string(frame_id_for(e.channel));
  return {};
}

void put_vec3(const Vec3& v, CanonicalWriter& out) {
  out.put_f64(v.x());
  out.put_f64(v.y());
  out.put_f64(v.z());
}
void put_quat(const Quat& q, CanonicalWriter& out) {
  out.put_f64(q.x());
  out.put_f64(q.y());
  out.put_f64(q.z());
  out.put_f64(q.w());
}
void put_zeros9(CanonicalWriter& out) {
  for (int i = 0; i < 9; ++i) out.put_f64(0.0);
}

Time get_header(mcap::ByteReader& r, uint32_t* seq) {
  const uint32_t s = r.u32();
  if (seq != nullptr) *seq = s;
  const int64_t secs = r.u32();
  const int64_t nsecs = r.u32();
  r.str();  // frame_id
  return Time::from_ns(secs * kNsPerS + nsecs);
}
Vec3 get_vec3(mcap::ByteReader& r) {
  const double x = r.f64(), y = r.f64(), z = r.f64();
  return Vec3(x, y, z);
}
Quat get_quat(mcap::ByteReader& r) {
  const double x = r.f64(), y = r.f64(), z = r.f64(), w = r.f64();
  return Quat(w, x, y, z);
}

bool is_sonar(Channel c) { return c == Channel::kSonarHorizontal || c == Channel::kSonarVertical; }
bool is_labels(Channel c) { return c == Channel::kLabelsHorizontal || c == Channel::kLabelsVertical; }

}  // namespace

const SchemaDef& schema_for(Channel c) {
  switch (c) {
    case Channel::kSonarHorizontal:
    case Channel::kSonarVertical: return kPing;
    case Channel::kImu: return kImu;
    case Channel::kDvl: return kDvl;
    case Channel::kDepth: return kDepth;
    case Channel::kTruthPose: return kPose;
    case Channel::kLabelsHorizontal:
    case Channel::kLabelsVertical: return kLabels;
    case Channel::kGyro: return kGyro;
  }
  return kDepth;
}

std::string_view frame_id_for(Channel c) {
  switch (c) {
    case Channel::kSonarHorizontal:
    case Channel::kLabelsHorizontal: return "sonar_horizontal";
    case Channel::kSonarVertical:
    case Channel::kLabelsVertical: return "sonar_vertical";
    case Channel::kImu: return "vehicle";
    case Channel::kDvl: return "vehicle";
    case Channel::kDepth: return "vehicle";
    case Channel::kTruthPose: return "world";
    case Channel::kGyro: return "gyro";
  }
  return "";
}

int16_t bearing_centideg(double rad) {
  const double cd = std::round(rad * (18000.0 / M_PI));
  if (!(cd > -32768.0)) return INT16_MIN;
  if (cd > 32767.0) return INT16_MAX;
  return static_cast<int16_t>(cd);
}

Status encode(const Event& e, CanonicalWriter& out) {
  if (channel_of(e.payload) != e.channel)
    return Error{std::string("payload does not belong to channel ") + channel_topic(e.channel)};
  if (auto s = put_header(e, stamp_of(e.payload), out); !s) return s;
  if (const auto* p = std::get_if<SonarPing>(&e.payload)) {
    const size_t n = size_t{p->rows} * p->cols * p->bytes_per_pixel;
    if (p->bytes_per_pixel != 1 && p->bytes_per_pixel != 2) return Error{"bytes_per_pixel must be 1 or 2"};
    if (p->image.size() != n || p->bearings_rad.size() != p->cols)
      return Error{"ping image/bearing sizes disagree with rows, cols and bytes_per_pixel"};
    out.put_u32(p->device_id);
    out.put_u16(p->part_number);
    out.put_u8(static_cast<uint8_t>(p->mount));
    out.put_u32(p->ping_id);
    out.put_f64(p->range_resolution_m);
    out.put_f64(p->frequency_hz);
    out.put_f64(p->gain_percent);
    out.put_u32(static_cast<uint32_t>(p->bearings_rad.size()));
    for (double b : p->bearings_rad) out.put_i16(bearing_centideg(b));
    out.put_u32(static_cast<uint32_t>(p->bearings_rad.size()));
    for (double b : p->bearings_rad) out.put_f64(b);
    out.put_u16(p->rows);
    out.put_u16(p->cols);
    out.put_u8(p->bytes_per_pixel);
    out.put_u32(static_cast<uint32_t>(p->image.size()));
    out.put_bytes(p->image);
  } else if (const auto* imu = std::get_if<ImuReading>(&e.payload)) {
    put_quat(imu->q_W_V, out);
    put_zeros9(out);
    put_vec3(imu->angular_velocity_V, out);
    put_zeros9(out);
    put_vec3(imu->linear_acceleration_V, out);
    put_zeros9(out);
  } else if (const auto* d = std::get_if<DvlReading>(&e.payload)) {
    put_vec3(d->velocity_V_mps, out);
    out.put_bool(d->valid);
    out.put_f64(d->altitude_m);
  } else if (const auto* z = std::get_if<DepthReading>(&e.payload)) {
    out.put_f64(z->depth_m);
  } else if (const auto* t = std::get_if<TruthPose>(&e.payload)) {
    put_vec3(t->p_W, out);
    put_quat(t->q_W_V, out);
  } else if (const auto* l = std::get_if<SonarLabels>(&e.payload)) {
    const size_t n = size_t{l->rows} * l->cols;
    if (l->semantic.size() != n || l->object_id.size() != n)
      return Error{"label sizes disagree with rows and cols"};
    out.put_u8(static_cast<uint8_t>(l->mount));
    out.put_u32(l->ping_id);
    out.put_u16(l->rows);
    out.put_u16(l->cols);
    out.put_u32(static_cast<uint32_t>(n));
    out.put_bytes(l->semantic);
    out.put_u32(static_cast<uint32_t>(n));
    for (uint32_t id : l->object_id) out.put_u32(id);
  } else if (const auto* g = std::get_if<GyroReading>(&e.payload)) {
    out.put_bool(g->valid);
    out.put_bool(g->is_rate);
    put_vec3(g->value_G, out);
    out.put_u8(g->sequence);
    out.put_f64(g->temperature_c);
  }
  return {};
}

Result<Payload> decode(Channel c, const uint8_t* data, size_t size, uint32_t* header_seq) {
  mcap::ByteReader r(data, size);
  const Time stamp = get_header(r, header_seq);
  Payload out;
  if (is_sonar(c)) {
    SonarPing p;
    p.stamp = stamp;
    p.device_id = r.u32();
    p.part_number = r.u16();
    const uint8_t mount = r.u8();
    p.mount = c == Channel::kSonarHorizontal ? SonarMount::kHorizontal : SonarMount::kVertical;
    if (mount != static_cast<uint8_t>(p.mount)) return Error{"ping mount disagrees with its topic"};
    p.ping_id = r.u32();
    p.range_resolution_m = r.f64();
    p.frequency_hz = r.f64();
    p.gain_percent = r.f64();
    const uint32_t nb16 = r.u32();
    if (!r.skip(size_t{nb16} * 2)) return Error{"ping truncated in bearings"};
    const uint32_t nb = r.u32();
    if (nb > r.remaining() / 8) return Error{"ping truncated in bearings_rad"};
    p.bearings_rad.resize(nb);
    for (auto& b : p.bearings_rad) b = r.f64();
    p.rows = r.u16();
    p.cols = r.u16();
    p.bytes_per_pixel = r.u8();
    const uint32_t ni = r.u32();
    const uint8_t* img = r.take(ni);
    if (!r.ok()) return Error{"ping truncated"};
    if ((p.bytes_per_pixel != 1 && p.bytes_per_pixel != 2) || nb != p.cols || nb16 != nb ||
        ni != size_t{p.rows} * p.cols * p.bytes_per_pixel)
      return Error{"ping sizes inconsistent (rows, cols, bytes_per_pixel, bearings, image)"};
    p.image.assign(img, img + ni);
    out = std::move(p);
  } else if (c == Channel::kImu) {
    ImuReading m;
    m.stamp = stamp;
    m.q_W_V = get_quat(r);
    // A NaN orientation would reach dead reckoning's poses and int64(floor(NaN)) voxel keys.
    if (r.ok() && !m.q_W_V.coeffs().allFinite()) return Error{"imu field 'orientation' is not finite"};
    r.skip(72);
    m.angular_velocity_V = get_vec3(r);
    r.skip(72);
    m.linear_acceleration_V = get_vec3(r);
    r.skip(72);
    out = m;
  } else if (c == Channel::kDvl) {
    DvlReading m;
    m.stamp = stamp;
    m.velocity_V_mps = get_vec3(r);
    const uint8_t valid = r.u8();
    if (valid > 1) return Error{"dvl valid flag is not a bool"};
    m.valid = valid == 1;
    m.altitude_m = r.f64();
    out = m;
  } else if (c == Channel::kDepth) {
    DepthReading m;
    m.stamp = stamp;
    m.depth_m = r.f64();
    out = m;
  } else if (c == Channel::kTruthPose) {
    TruthPose m;
    m.stamp = stamp;
    m.p_W = get_vec3(r);
    m.q_W_V = get_quat(r);
    // Truth places the true-pose map's points: NaN would reach its voxel keys.
    if (r.ok() && !m.p_W.allFinite()) return Error{"truth field 'position' is not finite"};
    if (r.ok() && !m.q_W_V.coeffs().allFinite()) return Error{"truth field 'orientation' is not finite"};
    out = m;
  } else if (is_labels(c)) {
    SonarLabels l;
    l.stamp = stamp;
    const uint8_t mount = r.u8();
    l.mount = c == Channel::kLabelsHorizontal ? SonarMount::kHorizontal : SonarMount::kVertical;
    if (mount != static_cast<uint8_t>(l.mount)) return Error{"labels mount disagrees with its topic"};
    l.ping_id = r.u32();
    l.rows = r.u16();
    l.cols = r.u16();
    const size_t n = size_t{l.rows} * l.cols;
    const uint32_t ns = r.u32();
    const uint8_t* sem = r.take(ns);
    if (!r.ok() || ns != n) return Error{"labels semantic size inconsistent"};
    l.semantic.assign(sem, sem + ns);
    const uint32_t no = r.u32();
    if (!r.ok() || no != n || no > r.remaining() / 4) return Error{"labels object_id size inconsistent"};
    l.object_id.resize(no);
    for (auto& id : l.object_id) id = r.u32();
    out = std::move(l);
  } else if (c == Channel::kGyro) {
    GyroReading g;
    g.stamp = stamp;
    const uint8_t status = r.u8(), is_rate = r.u8();
    if (r.ok() && (status > 1 || is_rate > 1)) return Error{"gyro field 'status' or 'is_rate' is not a bool"};
    g.valid = status == 1;
    g.is_rate = is_rate == 1;
    g.value_G = get_vec3(r);
    // Dead reckoning integrates the value into every later heading: NaN would reach them all.
    if (r.ok() && !g.value_G.allFinite()) return Error{"gyro field 'value' is not finite"};
    g.sequence = r.u8();
    g.temperature_c = r.f64();
    out = g;
  }
  if (!r.ok()) return Error{"message truncated"};
  if (r.remaining() != 0) return Error{"message has " + std::to_string(r.remaining()) + " trailing bytes"};
  return out;
}

}  // namespace orthosonar::replay::ros1
