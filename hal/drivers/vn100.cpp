#include "hal/drivers/vn100.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string_view>
#include <tuple>
#include <type_traits>

namespace orthosonar::hal::drivers::vn100 {
namespace {

// Field sizes in bytes by bit (VN-100 ICD, Binary Output group tables; 0 = no size given:
// reserved, undocumented, or the bit-15 extension). The VectorNav SDK's
// getStaticBinaryTypeSize() agrees. Attitude bits 9-11 have sizes in the SDK but no name or
// meaning in any ICD, so we do not accept them.
constexpr std::array<uint8_t, 16> kCommonSizes = {8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8, 0};
constexpr std::array<uint8_t, 16> kTimeSizes = {8, 8, 8, 2, 8, 8, 8, 4, 4, 1, 0, 0, 0, 0, 0, 0};
constexpr std::array<uint8_t, 16> kImuSizes = {2, 12, 12, 12, 4, 4, 16, 12, 12, 12, 12, 2, 0, 0, 0, 0};
constexpr std::array<uint8_t, 16> kAttitudeSizes = {2, 12, 16, 36, 12, 12, 12, 12, 12, 0, 0, 0, 12, 4, 0, 0};

// The supported groups in wire (group-bit) order.
constexpr std::array<uint8_t, 4> kGroups = {kGroupCommon, kGroupTime, kGroupImu, kGroupAttitude};

constexpr const std::array<uint8_t, 16>* sizes_of(uint8_t group) {
  switch (group) {
    case kGroupCommon: return &kCommonSizes;
    case kGroupTime: return &kTimeSizes;
    case kGroupImu: return &kImuSizes;
    case kGroupAttitude: return &kAttitudeSizes;
    default: return nullptr;
  }
}

const char* group_name(unsigned bit) {
  static constexpr std::array<const char*, 8> kNames = {"Common", "Time", "IMU", "GNSS (VN-200/300)",
                                                        "Attitude", "INS (VN-200/300)", "GNSS2 (VN-300)",
                                                        "extension"};
  return kNames[bit & 7u];
}

Error err(const std::string& what) { return Error{"vn100: " + what}; }

std::string hex(unsigned v, int digits) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%0*X", digits, v);
  return b;
}

// ---- Field layout: one list per group, fields in bit order, members in wire order. Every
// codec below (read, write, size, describe) walks these lists, so the layout lives here once.

template <class S>
  requires std::is_same_v<std::remove_const_t<S>, UncompImu>
constexpr auto members(S& s) { return std::tie(s.accel, s.gyro); }
template <class S>
  requires std::is_same_v<std::remove_const_t<S>, MagPres>
constexpr auto members(S& s) { return std::tie(s.mag, s.temp_c, s.pres_kpa); }
template <class S>
  requires std::is_same_v<std::remove_const_t<S>, Deltas>
constexpr auto members(S& s) { return std::tie(s.dtime_s, s.dtheta_deg, s.dvel_mps); }
template <class S>
  requires std::is_same_v<std::remove_const_t<S>, DeltaTheta>
constexpr auto members(S& s) { return std::tie(s.dtime_s, s.dtheta_deg); }
template <class S>
  requires std::is_same_v<std::remove_const_t<S>, TimeUtc>
constexpr auto members(S& s) { return std::tie(s.year, s.month, s.day, s.hour, s.minute, s.second, s.ms); }
template <class S>
  requires std::is_same_v<std::remove_const_t<S>, Heave>
constexpr auto members(S& s) { return std::tie(s.heave_m, s.heave_rate_mps, s.delayed_heave_m); }

template <class T>
concept Compound = requires(T& t) { members(t); };
template <class T>
struct IsArray : std::false_type {};
template <class T, size_t N>
struct IsArray<std::array<T, N>> : std::true_type {};

// Walks a value down to its scalars (arithmetic types) in wire order.
template <class T, class F>
constexpr void scalars(T& v, F& f) {
  using U = std::remove_const_t<T>;
  if constexpr (std::is_arithmetic_v<U>) {
    f(v);
  } else if constexpr (IsArray<U>::value) {
    for (auto& x : v) scalars(x, f);
  } else {
    static_assert(Compound<U>);
    std::apply([&f](auto&... m) { (scalars(m, f), ...); }, members(v));
  }
}

// The fields of each group as (bit, optional, names); names are space-separated, one per scalar.
// M is Message or const Message (and likewise for the group structs).
template <class M, class V>
constexpr void common_fields(M& m, V&& v) {
  v(0, m.time_startup_ns, "TimeStartup");
  v(1, m.time_gps_ns, "TimeGps");
  v(2, m.time_syncin_ns, "TimeSyncIn");
  v(3, m.ypr_deg, "Yaw Pitch Roll");
  v(4, m.quat_xyzw, "QuatX QuatY QuatZ QuatW");
  v(5, m.angular_rate, "AngularRateX AngularRateY AngularRateZ");
  v(6, m.position_lla, "Latitude Longitude Altitude");
  v(7, m.velocity_ned, "VelN VelE VelD");
  v(8, m.accel, "CompAccX CompAccY CompAccZ");
  v(9, m.uncomp_imu, "AccX AccY AccZ GyroX GyroY GyroZ");
  v(10, m.mag_pres, "CompMagX CompMagY CompMagZ Temp Pres");
  v(11, m.deltas, "DeltaTime DeltaThetaX DeltaThetaY DeltaThetaZ DeltaVelX DeltaVelY DeltaVelZ");
  v(12, m.ins_status, "InsStatus");
  v(13, m.sync_in_cnt, "SyncInCnt");
  v(14, m.time_gps_pps_ns, "TimeGpsPps");
}
template <class T, class V>
constexpr void time_fields(T& t, V&& v) {
  v(0, t.time_startup_ns, "TimeStartup");
  v(1, t.time_gps_ns, "TimeGps");
  v(2, t.gps_tow_ns, "GpsTow");
  v(3, t.gps_week, "GpsWeek");
  v(4, t.time_syncin_ns, "TimeSyncIn");
  v(5, t.time_gps_pps_ns, "TimeGpsPps");
  v(6, t.time_utc, "UtcYear UtcMonth UtcDay UtcHour UtcMinute UtcSecond UtcMs");
  v(7, t.sync_in_cnt, "SyncInCnt");
  v(8, t.sync_out_cnt, "SyncOutCnt");
  v(9, t.time_status, "TimeStatus");
}
template <class I, class V>
constexpr void imu_fields(I& i, V&& v) {
  v(0, i.imu_status, "ImuStatus");
  v(1, i.uncomp_mag, "MagX MagY MagZ");
  v(2, i.uncomp_accel, "AccX AccY AccZ");
  v(3, i.uncomp_gyro, "GyroX GyroY GyroZ");
  v(4, i.temp_c, "Temp");
  v(5, i.pres_kpa, "Pres");
  v(6, i.delta_theta, "DeltaTime DeltaThetaX DeltaThetaY DeltaThetaZ");
  v(7, i.delta_vel_mps, "DeltaVelX DeltaVelY DeltaVelZ");
  v(8, i.mag, "CompMagX CompMagY CompMagZ");
  v(9, i.accel, "CompAccX CompAccY CompAccZ");
  v(10, i.angular_rate, "AngularRateX AngularRateY AngularRateZ");
  v(11, i.sens_sat, "SensSat");
}
template <class A, class V>
constexpr void attitude_fields(A& a, V&& v) {
  v(0, a.vpe_status, "VpeStatus");
  v(1, a.ypr_deg, "Yaw Pitch Roll");
  v(2, a.quat_xyzw, "QuatX QuatY QuatZ QuatW");
  v(3, a.dcm, "DCM1 DCM2 DCM3 DCM4 DCM5 DCM6 DCM7 DCM8 DCM9");
  v(4, a.mag_ned, "MagNED1 MagNED2 MagNED3");
  v(5, a.accel_ned, "AccNED1 AccNED2 AccNED3");
  v(6, a.linear_accel_body, "LinAccBodyX LinAccBodyY LinAccBodyZ");
  v(7, a.linear_accel_ned, "LinAccNED1 LinAccNED2 LinAccNED3");
  v(8, a.ypr_u_deg, "YawU PitchU RollU");
  v(12, a.heave, "Heave HeaveRate DelayedHeave");
  v(13, a.att_u_deg, "AttU");
}
template <class M, class V>
constexpr void group_fields(M& m, uint8_t group, V&& v) {
  switch (group) {
    case kGroupCommon: common_fields(m, v); break;
    case kGroupTime: time_fields(m.time, v); break;
    case kGroupImu: imu_fields(m.imu, v); break;
    case kGroupAttitude: attitude_fields(m.attitude, v); break;
    default: break;
  }
}

template <class T>
constexpr size_t wire_size() {
  T t{};
  size_t n = 0;
  auto add = [&n](auto& s) { n += sizeof(s); };
  scalars(t, add);
  return n;
}
template <class T>
constexpr size_t scalar_count() {
  T t{};
  size_t n = 0;
  auto add = [&n](auto&) { ++n; };
  scalars(t, add);
  return n;
}
constexpr size_t word_count(std::string_view s) {
  size_t n = 0;
  bool in = false;
  for (char c : s) {
    if (c != ' ' && !in) ++n;
    in = c != ' ';
  }
  return n;
}

// The layout lists agree with the ICD size tables: every sized bit has a field of that wire
// size, bits ascend, and each field has one name per scalar.
constexpr bool layout_matches_icd() {
  Message m{};
  for (uint8_t g : kGroups) {
    const auto& sizes = *sizes_of(g);
    int last = -1;
    size_t visited = 0, sized = 0;
    bool ok = true;
    group_fields(m, g, [&](unsigned bit, auto& opt, std::string_view names) {
      using T = typename std::remove_cvref_t<decltype(opt)>::value_type;
      ok = ok && static_cast<int>(bit) > last && bit < 16 && wire_size<T>() == sizes[bit] &&
           word_count(names) == scalar_count<T>();
      last = static_cast<int>(bit);
      ++visited;
    });
    for (uint8_t s : sizes) sized += s != 0;
    if (!ok || visited != sized) return false;
  }
  return true;
}
static_assert(layout_matches_icd(), "field layout disagrees with the ICD size tables");

constexpr size_t max_packet_bytes() {
  size_t n = 1 + 1 + 2 + 2 * kGroups.size();  // sync, groups, masks, CRC
  for (uint8_t g : kGroups)
    for (uint8_t s : *sizes_of(g)) n += s;
  return n;
}
static_assert(max_packet_bytes() == kMaxPacketBytes);

// ---- Scalar codecs.
struct ScalarReader {
  ByteReader& r;
  void operator()(uint8_t& v) { v = r.u8(); }
  void operator()(int8_t& v) { v = static_cast<int8_t>(r.u8()); }
  void operator()(uint16_t& v) { v = r.u16(); }
  void operator()(uint32_t& v) { v = r.u32(); }
  void operator()(uint64_t& v) { v = r.u64(); }
  void operator()(float& v) { v = r.f32(); }
  void operator()(double& v) { v = r.f64(); }
};
struct ScalarWriter {
  ByteWriter& w;
  void operator()(uint8_t v) { w.u8(v); }
  void operator()(int8_t v) { w.u8(static_cast<uint8_t>(v)); }
  void operator()(uint16_t v) { w.u16(v); }
  void operator()(uint32_t v) { w.u32(v); }
  void operator()(uint64_t v) { w.u64(v); }
  void operator()(float v) { w.f32(v); }
  void operator()(double v) { w.f64(v); }
};
// Floats with 9 significant digits and doubles with 17: each reads back to the same value.
struct ScalarText {
  std::string operator()(float v) const {
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", static_cast<double>(v));
    return b;
  }
  std::string operator()(double v) const {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
  }
  std::string operator()(int8_t v) const { return std::to_string(static_cast<int>(v)); }
  std::string operator()(uint8_t v) const { return std::to_string(static_cast<unsigned>(v)); }
  template <class I>
  std::string operator()(I v) const { return std::to_string(v); }
};

// Decodes a packet whose length packet_length() has established and whose CRC is good.
Message decode(std::span<const uint8_t> packet) {
  const uint8_t groups = packet[1];
  ByteReader masks(packet, 2);
  size_t n_groups = 0;
  for (uint8_t g : kGroups) n_groups += (groups & g) != 0;
  ByteReader r(packet, 2 + 2 * n_groups);
  Message m;
  for (uint8_t g : kGroups) {
    if (!(groups & g)) continue;
    const uint16_t mask = masks.u16();
    group_fields(m, g, [&](unsigned bit, auto& opt, std::string_view) {
      if (!(mask & (1u << bit))) return;
      ScalarReader read{r};
      scalars(opt.emplace(), read);
    });
  }
  return m;
}

// Orientation of the body (FRD) in NED from whichever field the packet carries.
Result<Quat> orientation_ned_frd(const Message& m) {
  const auto& quat = m.quat_xyzw ? m.quat_xyzw : m.attitude.quat_xyzw;
  const auto& ypr = m.ypr_deg ? m.ypr_deg : m.attitude.ypr_deg;
  Quat q;
  if (quat) {
    const auto& v = *quat;
    q = Quat(v[3], v[0], v[1], v[2]);
  } else if (m.attitude.dcm) {
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = (*m.attitude.dcm)[static_cast<size_t>(3 * i + j)];
    if (!R.allFinite() || (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-2 || R.determinant() < 0.5)
      return err("DCM is not a rotation matrix");
    q = Quat(R);
  } else if (ypr) {
    const double d = std::numbers::pi / 180.0;
    const auto& a = *ypr;
    q = Quat(Eigen::AngleAxisd(a[0] * d, Vec3::UnitZ()) * Eigen::AngleAxisd(a[1] * d, Vec3::UnitY()) *
             Eigen::AngleAxisd(a[2] * d, Vec3::UnitX()));
  } else {
    return err("VN-100 packet has no orientation field (need Quaternion, DCM or YawPitchRoll)");
  }
  const double n = q.norm();
  if (!std::isfinite(n) || n < 0.5 || n > 1.5) return err("orientation quaternion is not unit");
  return q.normalized();
}

// q_ENU_NED (maps NED vectors to ENU) and q_FRD_FLU (180 degrees about x).
Quat q_enu_ned() { return Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3(1, 1, 0).normalized())); }
Quat q_frd_flu() { return Quat(0.0, 1.0, 0.0, 0.0); }
Vec3 frd_to_flu(const Float3& v) { return {v[0], -static_cast<double>(v[1]), -static_cast<double>(v[2])}; }

}  // namespace

uint16_t crc16_xmodem(std::span<const uint8_t> data) {
  uint16_t crc = 0;
  for (uint8_t b : data) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(b) << 8));
    for (int i = 0; i < 8; ++i)
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021) : static_cast<uint16_t>(crc << 1);
  }
  return crc;
}

std::optional<size_t> field_size(uint8_t group, unsigned bit) {
  const auto* sizes = sizes_of(group);
  if (sizes == nullptr || bit >= 16 || (*sizes)[bit] == 0) return std::nullopt;
  return (*sizes)[bit];
}

uint8_t groups_of(const Message& m) {
  uint8_t groups = 0;
  for (uint8_t g : kGroups)
    if (fields_of(m, g) != 0) groups = static_cast<uint8_t>(groups | g);
  return groups;
}

uint16_t fields_of(const Message& m, uint8_t group) {
  uint16_t mask = 0;
  group_fields(m, group, [&](unsigned bit, auto& opt, std::string_view) {
    if (opt) mask = static_cast<uint16_t>(mask | (1u << bit));
  });
  return mask;
}

PacketLength packet_length(std::span<const uint8_t> data) {
  using S = PacketLength::Status;
  PacketLength out;  // kNeedMoreBytes
  if (data.empty()) return out;
  if (data[0] != kSync) return {S::kUnsupported, 0, "missing sync byte 0xFA"};
  if (data.size() < 2) return out;
  const uint8_t groups = data[1];
  if (groups == 0) return {S::kUnsupported, 0, "groups byte 0x00 (no group)"};
  for (unsigned bit = 0; bit < 8; ++bit)
    if ((groups & (1u << bit)) && !(kSupportedGroups & (1u << bit)))
      return {S::kUnsupported, 0,
              "groups byte " + hex(groups, 2) + ": group bit " + std::to_string(bit) + " (" + group_name(bit) +
                  ") is not supported (VN-100 groups: Common, Time, IMU, Attitude)"};
  size_t n_groups = 0;
  for (uint8_t g : kGroups) n_groups += (groups & g) != 0;
  if (data.size() < 2 + 2 * n_groups) return out;
  ByteReader r(data, 2);
  size_t payload = 0;
  for (uint8_t g : kGroups) {
    if (!(groups & g)) continue;
    const uint16_t mask = r.u16();
    const unsigned gbit = static_cast<unsigned>(std::countr_zero(g));
    if (mask == 0) return {S::kUnsupported, 0, std::string(group_name(gbit)) + " group present with an empty field mask"};
    for (unsigned bit = 0; bit < 16; ++bit) {
      if (!(mask & (1u << bit))) continue;
      const auto size = field_size(g, bit);
      if (!size)
        return {S::kUnsupported, 0,
                std::string(group_name(gbit)) + " field mask " + hex(mask, 4) + ": bit " + std::to_string(bit) +
                    " has no size in the VN-100 ICD (reserved or undocumented)"};
      payload += *size;
    }
  }
  return {S::kKnown, 2 + 2 * n_groups + payload + 2, {}};
}

Result<Message> parse_packet(std::span<const uint8_t> data, size_t* used) {
  const PacketLength len = packet_length(data);
  if (len.status == PacketLength::Status::kUnsupported) return err(len.reason);
  if (len.status == PacketLength::Status::kNeedMoreBytes)
    return err("truncated header: " + std::to_string(data.size()) + " bytes");
  if (data.size() < len.bytes)
    return err("truncated: " + std::to_string(data.size()) + " of " + std::to_string(len.bytes) + " bytes");
  const auto packet = data.first(len.bytes);
  if (crc16_xmodem(packet.subspan(1)) != 0) return err("CRC mismatch");
  if (used) *used = len.bytes;
  return decode(packet);
}

Bytes encode_packet(const Message& m) {
  Bytes out;
  out.reserve(kMaxPacketBytes);
  ByteWriter w(out);
  const uint8_t groups = groups_of(m);
  w.u8(kSync);
  w.u8(groups);
  for (uint8_t g : kGroups)
    if (groups & g) w.u16(fields_of(m, g));
  for (uint8_t g : kGroups) {
    group_fields(m, g, [&](unsigned, auto& opt, std::string_view) {
      if (!opt) return;
      ScalarWriter write{w};
      scalars(*opt, write);
    });
  }
  const uint16_t crc = crc16_xmodem(std::span<const uint8_t>(out).subspan(1));
  w.u8(static_cast<uint8_t>(crc >> 8));
  w.u8(static_cast<uint8_t>(crc & 0xFF));
  return out;
}

void StreamParser::push(std::span<const uint8_t> bytes) {
  if (start_ > 0) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
  if (bytes.size() >= kMaxBuffered) {
    stats_.dropped_bytes += buf_.size() + (bytes.size() - kMaxBuffered);
    buf_.assign(bytes.end() - static_cast<std::ptrdiff_t>(kMaxBuffered), bytes.end());
    return;
  }
  if (buf_.size() + bytes.size() > kMaxBuffered) {
    const size_t drop = buf_.size() + bytes.size() - kMaxBuffered;
    stats_.dropped_bytes += drop;
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(drop));
  }
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void StreamParser::reject(std::string why) {
  last_error_ = std::move(why);
  start_ += 1;  // only the sync byte: a real packet may start inside the rejected one
  stats_.skipped_bytes += 1;
}

std::optional<Message> StreamParser::pop() {
  for (;;) {
    size_t i = start_;
    while (i < buf_.size() && buf_[i] != kSync) ++i;
    stats_.skipped_bytes += i - start_;
    start_ = i;
    const std::span<const uint8_t> avail(buf_.data() + start_, buf_.size() - start_);
    const PacketLength len = packet_length(avail);
    if (len.status == PacketLength::Status::kNeedMoreBytes) return std::nullopt;
    if (len.status == PacketLength::Status::kUnsupported) {
      ++stats_.unsupported;
      reject("vn100: " + len.reason);
      continue;
    }
    if (avail.size() < len.bytes) return std::nullopt;
    const auto packet = avail.first(len.bytes);
    if (crc16_xmodem(packet.subspan(1)) != 0) {
      ++stats_.bad_crc;
      reject("vn100: CRC mismatch on a " + std::to_string(len.bytes) + "-byte packet (groups " +
             hex(packet[1], 2) + ")");
      continue;
    }
    Message m = decode(packet);
    start_ += len.bytes;
    last_packet_bytes_ = len.bytes;
    ++stats_.accepted;
    return m;
  }
}

Result<ImuReading> to_imu_reading(const Message& m, const Quat& q_V_S, Time stamp) {
  auto q_ned_frd = orientation_ned_frd(m);
  if (!q_ned_frd) return q_ned_frd.error();
  ImuReading r;
  r.stamp = stamp;
  const Quat q_W_S = q_enu_ned() * *q_ned_frd * q_frd_flu();
  r.q_W_V = (q_W_S * q_V_S.conjugate()).normalized();
  const Float3* rate = m.angular_rate       ? &*m.angular_rate
                       : m.imu.angular_rate ? &*m.imu.angular_rate
                       : m.imu.uncomp_gyro  ? &*m.imu.uncomp_gyro
                       : m.uncomp_imu       ? &m.uncomp_imu->gyro
                                            : nullptr;
  const Float3* accel = m.accel              ? &*m.accel
                        : m.imu.accel        ? &*m.imu.accel
                        : m.imu.uncomp_accel ? &*m.imu.uncomp_accel
                        : m.uncomp_imu       ? &m.uncomp_imu->accel
                                             : nullptr;
  if (rate) r.angular_velocity_V = q_V_S * frd_to_flu(*rate);
  if (accel) r.linear_acceleration_V = q_V_S * frd_to_flu(*accel);
  if (!r.angular_velocity_V.allFinite() || !r.linear_acceleration_V.allFinite()) return err("non-finite rates");
  return r;
}

Message message_from(const ImuReading& r, const Quat& q_V_S) {
  const Quat q_W_S = r.q_W_V * q_V_S;
  const Quat q_ned_frd = (q_enu_ned().conjugate() * q_W_S * q_frd_flu().conjugate()).normalized();
  Message m;
  m.time_startup_ns = static_cast<uint64_t>(r.stamp.ns() < 0 ? 0 : r.stamp.ns());
  m.quat_xyzw = std::array<float, 4>{static_cast<float>(q_ned_frd.x()), static_cast<float>(q_ned_frd.y()),
                                     static_cast<float>(q_ned_frd.z()), static_cast<float>(q_ned_frd.w())};
  const Vec3 w = q_V_S.conjugate() * r.angular_velocity_V;
  const Vec3 a = q_V_S.conjugate() * r.linear_acceleration_V;
  m.angular_rate = Float3{static_cast<float>(w.x()), static_cast<float>(-w.y()), static_cast<float>(-w.z())};
  m.accel = Float3{static_cast<float>(a.x()), static_cast<float>(-a.y()), static_cast<float>(-a.z())};
  return m;
}

std::vector<std::pair<std::string, std::string>> describe(const Message& m) {
  std::vector<std::pair<std::string, std::string>> out;
  for (uint8_t g : kGroups) {
    const std::string prefix = g == kGroupCommon ? "Common." : "";
    group_fields(m, g, [&](unsigned, auto& opt, std::string_view names) {
      if (!opt) return;
      size_t at = 0;
      auto emit = [&](auto v) {
        const size_t end = std::min(names.find(' ', at), names.size());
        out.emplace_back(prefix + std::string(names.substr(at, end - at)), ScalarText{}(v));
        at = end + 1;
      };
      scalars(*opt, emit);
    });
  }
  return out;
}

}  // namespace orthosonar::hal::drivers::vn100
