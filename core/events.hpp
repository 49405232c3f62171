#pragma once
// Sensor events: what a source (live driver, simulator, fixture) hands the core.
// Every event carries its own stamp; the core never reads a clock (SPEC §9).
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "core/geometry.hpp"
#include "core/time.hpp"

namespace orthosonar {

enum class SonarMount : uint8_t { kHorizontal = 0, kVertical = 1 };

// Oculus part numbers (SPEC §1).
inline constexpr uint16_t kPartM750d = 1032;
inline constexpr uint16_t kPartM1200d = 1042;

// One sonar ping. Image rows are range bins (row i is at range res * (i + 1)), columns
// are beams; bearings come from the ping's own table, never assumed uniform.
struct SonarPing {
  uint32_t device_id = 0;
  uint16_t part_number = 0;
  SonarMount mount = SonarMount::kHorizontal;
  Time stamp;
  uint32_t ping_id = 0;
  double range_resolution_m = 0.05;
  double frequency_hz = 0.0;
  double gain_percent = 0.0;
  std::vector<double> bearings_rad;   // one per beam, positive to the left (h) / up (v)
  uint16_t rows = 0;                  // range bins
  uint16_t cols = 0;                  // beams
  uint8_t bytes_per_pixel = 1;        // 1 (8-bit) or 2 (16-bit, little-endian)
  std::vector<uint8_t> image;         // rows * cols * bytes_per_pixel, row-major

  double range_of_row(int row) const { return range_resolution_m * (row + 1); }
  double max_range_m() const { return range_of_row(rows - 1); }
  // Intensity at (row, col) as a number (8- or 16-bit).
  uint16_t at(int row, int col) const {
    const size_t i = static_cast<size_t>(row) * cols + static_cast<size_t>(col);
    if (bytes_per_pixel == 1) return image[i];
    return static_cast<uint16_t>(image[2 * i] | (image[2 * i + 1] << 8));
  }
  friend bool operator==(const SonarPing&, const SonarPing&) = default;
};

// DVL body-frame (vehicle frame V) velocity.
struct DvlReading {
  Time stamp;
  Vec3 velocity_V_mps = Vec3::Zero();
  bool valid = true;
  double altitude_m = 0.0;  // distance to the bottom; <= 0 when unknown
  friend bool operator==(const DvlReading&, const DvlReading&) = default;
};

// IMU orientation of V in the world frame W, with rates and accelerations when known.
struct ImuReading {
  Time stamp;
  Quat q_W_V = Quat::Identity();
  Vec3 angular_velocity_V = Vec3::Zero();     // rad/s
  Vec3 linear_acceleration_V = Vec3::Zero();  // m/s^2
  friend bool operator==(const ImuReading& a, const ImuReading& b) {
    return a.stamp == b.stamp && a.q_W_V.coeffs() == b.q_W_V.coeffs() &&
           a.angular_velocity_V == b.angular_velocity_V &&
           a.linear_acceleration_V == b.linear_acceleration_V;
  }
};

// Pressure depth, metres below the surface (positive down). World z = -depth.
struct DepthReading {
  Time stamp;
  double depth_m = 0.0;
  friend bool operator==(const DepthReading&, const DepthReading&) = default;
};

// One sample of a fibre-optic gyro (the paper's KVH DSP-1760) in its own frame G: the
// angle it turned through since its previous sample (delta angles, rad) or its rate
// (rad/s), per the device's configuration. Earth's rotation is in it; dead reckoning
// removes it and rotates G into V by the configured mounting.
struct GyroReading {
  Time stamp;
  Vec3 value_G = Vec3::Zero();  // rad (delta angles) or rad/s (rates)
  bool is_rate = false;         // false: delta angles; true: rates
  bool valid = true;            // the device's status: every axis good
  uint8_t sequence = 0;         // the device's packet counter (DSP-1760: 0-127), 0 when unknown
  double temperature_c = 0.0;   // the device's temperature, 0 when unknown
  friend bool operator==(const GyroReading& a, const GyroReading& b) {
    return a.stamp == b.stamp && a.value_G == b.value_G && a.is_rate == b.is_rate && a.valid == b.valid &&
           a.sequence == b.sequence && a.temperature_c == b.temperature_c;
  }
};

// Ground-truth pose of V in W (simulation only; the pipeline never reads it).
struct TruthPose {
  Time stamp;
  Vec3 p_W = Vec3::Zero();
  Quat q_W_V = Quat::Identity();
  friend bool operator==(const TruthPose& a, const TruthPose& b) {
    return a.stamp == b.stamp && a.p_W == b.p_W && a.q_W_V.coeffs() == b.q_W_V.coeffs();
  }
};

// Per-pixel ground-truth labels for one simulated ping (for training the classifier;
// the pipeline never reads them). Same geometry as the ping with the same ping_id.
struct SonarLabels {
  Time stamp;
  SonarMount mount = SonarMount::kHorizontal;
  uint32_t ping_id = 0;
  uint16_t rows = 0;
  uint16_t cols = 0;
  std::vector<uint8_t> semantic;    // SemanticClass per pixel (core/mesh.hpp), 0 = none
  std::vector<uint32_t> object_id;  // object per pixel, 0 = none
  friend bool operator==(const SonarLabels&, const SonarLabels&) = default;
};

// Channels, in the tie-break order of SPEC §9 (stamp, channel, sequence).
enum class Channel : uint8_t {
  kSonarHorizontal = 0,
  kSonarVertical = 1,
  kImu = 2,
  kDvl = 3,
  kDepth = 4,
  kTruthPose = 5,
  kLabelsHorizontal = 6,
  kLabelsVertical = 7,
  kGyro = 8,  // last, so that recordings without a gyro keep their order and ids
};
inline constexpr int kChannelCount = 9;
// Topic names as the field vehicle publishes them (SPEC §11).
const char* channel_topic(Channel c);

using Payload =
    std::variant<SonarPing, DvlReading, ImuReading, DepthReading, TruthPose, SonarLabels, GyroReading>;

struct Event {
  Time stamp;
  Channel channel = Channel::kImu;
  uint64_t sequence = 0;  // per channel, strictly increasing from 0
  Payload payload;
  friend bool operator==(const Event&, const Event&) = default;
};

// Channel implied by a payload (a sonar ping's mount picks h or v).
Channel channel_of(const Payload& p);
Time stamp_of(const Payload& p);

// The explicit total order of SPEC §9: (stamp, channel, sequence).
inline bool event_before(const Event& a, const Event& b) {
  if (a.stamp != b.stamp) return a.stamp < b.stamp;
  if (a.channel != b.channel) return a.channel < b.channel;
  return a.sequence < b.sequence;
}

}  // namespace orthosonar
