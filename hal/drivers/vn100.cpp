#include "hal/drivers/vn100.hpp"

#include <cmath>
#include <numbers>

namespace orthosonar::hal::drivers::vn100 {
namespace {

// Sizes of Common-group fields by bit (VN-100/VN-300 user manual, binary output group 1).
constexpr std::array<size_t, 16> kCommonSizes = {8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8, 0};
constexpr size_t kMaxPacket = 512;

Error err(const std::string& what) { return Error{"vn100: " + what}; }

// q_ENU_NED (maps NED vectors to ENU) and q_FRD_FLU (180 degrees about x).
Quat q_enu_ned() { return Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3(1, 1, 0).normalized())); }
Quat q_frd_flu() { return Quat(0.0, 1.0, 0.0, 0.0); }
Vec3 frd_to_flu(const std::array<float, 3>& v) { return {v[0], -static_cast<double>(v[1]), -static_cast<double>(v[2])}; }

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

Result<Message> parse_packet(std::span<const uint8_t> data, size_t* used) {
  if (data.size() < 4) return err("packet needs at least 4 bytes");
  if (data[0] != kSync) return err("missing sync byte 0xFA");
  const uint8_t groups = data[1];
  if (groups != kGroupCommon)
    return err("groups byte 0x" + std::to_string(groups) + ": only the Common group (0x01) is supported");
  ByteReader r(data, 2);
  Message m;
  m.common_fields = r.u16();
  if (m.common_fields == 0) return err("empty field mask");
  if (m.common_fields & 0x8000) return err("unknown Common field bit 15");
  size_t payload = 0;
  for (size_t bit = 0; bit < 16; ++bit)
    if (m.common_fields & (1u << bit)) payload += kCommonSizes[bit];
  const size_t total = 4 + payload + 2;
  if (total > kMaxPacket) return err("packet too large");
  if (data.size() < total) return err("truncated: " + std::to_string(data.size()) + " of " + std::to_string(total) + " bytes");
  if (crc16_xmodem(data.subspan(1, total - 1)) != 0) return err("CRC mismatch");
  auto f3 = [&] { return std::array<float, 3>{r.f32(), r.f32(), r.f32()}; };
  for (size_t bit = 0; bit < 15; ++bit) {
    if (!(m.common_fields & (1u << bit))) continue;
    const uint16_t b = static_cast<uint16_t>(1u << bit);
    if (b == kTimeStartup) {
      m.time_startup_ns = r.u64();
    } else if (b == kYawPitchRoll) {
      m.ypr_deg = f3();
    } else if (b == kQuaternion) {
      m.quat_xyzw = std::array<float, 4>{r.f32(), r.f32(), r.f32(), r.f32()};
    } else if (b == kAngularRate) {
      m.angular_rate = f3();
    } else if (b == kAccel) {
      m.accel = f3();
    } else {
      r.skip(kCommonSizes[bit]);
    }
  }
  if (r.failed() || r.position() != total - 2) return err("field layout misread");
  if (used) *used = total;
  return m;
}

Bytes encode_packet(const Message& m) {
  Bytes out;
  ByteWriter w(out);
  uint16_t fields = 0;
  if (m.time_startup_ns) fields |= kTimeStartup;
  if (m.ypr_deg) fields |= kYawPitchRoll;
  if (m.quat_xyzw) fields |= kQuaternion;
  if (m.angular_rate) fields |= kAngularRate;
  if (m.accel) fields |= kAccel;
  w.u8(kSync);
  w.u8(kGroupCommon);
  w.u16(fields);
  if (m.time_startup_ns) w.u64(*m.time_startup_ns);
  if (m.ypr_deg) for (float v : *m.ypr_deg) w.f32(v);
  if (m.quat_xyzw) for (float v : *m.quat_xyzw) w.f32(v);
  if (m.angular_rate) for (float v : *m.angular_rate) w.f32(v);
  if (m.accel) for (float v : *m.accel) w.f32(v);
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
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

std::optional<Message> StreamParser::pop() {
  for (;;) {
    size_t i = start_;
    while (i < buf_.size() && buf_[i] != kSync) ++i;
    garbage_ += i - start_;
    start_ = i;
    if (buf_.size() - start_ < 4) return std::nullopt;
    const std::span<const uint8_t> avail(buf_.data() + start_, buf_.size() - start_);
    size_t used = 0;
    auto m = parse_packet(avail, &used);
    if (m) {
      start_ += used;
      ++messages_;
      return std::move(*m);
    }
    // Wait for more bytes when the packet is merely incomplete; otherwise skip the sync byte.
    if (avail[1] == kGroupCommon) {
      const uint16_t fields = static_cast<uint16_t>(avail[2] | (avail[3] << 8));
      size_t payload = 0;
      for (size_t bit = 0; bit < 16; ++bit)
        if (fields & (1u << bit)) payload += kCommonSizes[bit];
      if (fields != 0 && !(fields & 0x8000) && avail.size() < 6 + payload) return std::nullopt;
    }
    ++malformed_;
    last_error_ = m.error().message;
    start_ += 1;
  }
}

Result<ImuReading> to_imu_reading(const Message& m, const Quat& q_V_S, Time stamp) {
  Quat q_ned_frd;
  if (m.quat_xyzw) {
    const auto& q = *m.quat_xyzw;
    q_ned_frd = Quat(q[3], q[0], q[1], q[2]);
  } else if (m.ypr_deg) {
    const double d = std::numbers::pi / 180.0;
    const auto& a = *m.ypr_deg;
    q_ned_frd = Quat(Eigen::AngleAxisd(a[0] * d, Vec3::UnitZ()) * Eigen::AngleAxisd(a[1] * d, Vec3::UnitY()) *
                     Eigen::AngleAxisd(a[2] * d, Vec3::UnitX()));
  } else {
    return err("packet has no orientation (quaternion or yaw/pitch/roll)");
  }
  const double n = q_ned_frd.norm();
  if (!std::isfinite(n) || n < 0.5 || n > 1.5) return err("orientation quaternion is not unit");
  q_ned_frd.normalize();
  ImuReading r;
  r.stamp = stamp;
  const Quat q_W_S = q_enu_ned() * q_ned_frd * q_frd_flu();
  r.q_W_V = (q_W_S * q_V_S.conjugate()).normalized();
  if (m.angular_rate) r.angular_velocity_V = q_V_S * frd_to_flu(*m.angular_rate);
  if (m.accel) r.linear_acceleration_V = q_V_S * frd_to_flu(*m.accel);
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
  m.angular_rate = std::array<float, 3>{static_cast<float>(w.x()), static_cast<float>(-w.y()), static_cast<float>(-w.z())};
  m.accel = std::array<float, 3>{static_cast<float>(a.x()), static_cast<float>(-a.y()), static_cast<float>(-a.z())};
  return m;
}

}  // namespace orthosonar::hal::drivers::vn100
