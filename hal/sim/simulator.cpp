#include "hal/sim/simulator.hpp"
#include "core/geometry.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "core/random.hpp"
#include "hal/sim/ping_prefetch.hpp"
#include "orthosonar/version.hpp"

namespace orthosonar::sim {
namespace {

constexpr uint64_t kImuStream = 0x494d55ull, kBiasStream = 0x42494153ull, kDvlStream = 0x44564cull,
                   kDepthStream = 0x44455054ull, kGyroBiasStream = 0x47594230ull, kFogStream = 0x464f47ull,
                   kFogBiasStream = 0x464f4742ull;
// The Earth's rotation rate, 15.04107 deg per hour (one turn per sidereal day).
constexpr double kEarthRateRps = 15.04107 / 3600.0 * std::numbers::pi / 180.0;

// A regular stream of stamps: offset + period * i for i < count.
struct Stream {
  Time offset, period;
  uint64_t count = 0;
  Time stamp(uint64_t i) const { return offset + period * static_cast<int64_t>(i); }
};

Stream make_stream(double offset_s, double rate_hz, Time duration, bool enabled = true) {
  Stream s{Time::from_seconds(offset_s), Time::from_seconds(1.0 / rate_hz), 0};
  if (enabled && s.offset < duration) s.count = static_cast<uint64_t>((duration - s.offset - Time::from_ns(1)) / s.period) + 1;
  return s;
}

Quat quat_rpy(double roll, double pitch, double yaw) {
  return Quat(se3_from_xyz_rpy(0, 0, 0, roll, pitch, yaw).rotation());
}

}  // namespace

struct Simulator::Impl {
  Scene scene;
  SimConfig cfg;
  Time duration;
  std::unique_ptr<SonarRenderer> renderer;
  std::unique_ptr<Trajectory> trajectory;
  std::array<Stream, kChannelCount> streams{};  // the truth entry is unused
  std::array<uint64_t, kChannelCount> next{};   // next index per channel (truth: sequence)
  std::array<uint64_t, kChannelCount> truth_next{};  // per sensor stream: first stamp without truth
  std::vector<double> yaw_bias_rad;                  // per IMU sample
  Vec3 gyro_bias_rps = Vec3::Zero();                 // constant per mission
  Vec3 fog_bias_rps = Vec3::Zero();                  // the fibre-optic gyro's, constant per mission
  std::array<std::optional<SonarLabels>, 2> pending_labels;
  std::unique_ptr<PingPrefetch> prefetch;

  static constexpr std::array<Channel, 5> kSensors = {Channel::kSonarHorizontal, Channel::kSonarVertical,
                                                      Channel::kImu, Channel::kDvl, Channel::kDepth};

  SonarRender render_ping(SonarMount mount, uint64_t index) const {
    const Channel c = mount == SonarMount::kHorizontal ? Channel::kSonarHorizontal : Channel::kSonarVertical;
    const Time t = streams[static_cast<size_t>(c)].stamp(index);
    const SE3 T_W_S = trajectory->at(t).T_W_V() * (mount == SonarMount::kHorizontal ? cfg.T_V_h : cfg.T_V_v);
    SonarRender r = renderer->render(T_W_S, mount, t, static_cast<uint32_t>(index), cfg.labels);
    r.ping.device_id = mount == SonarMount::kHorizontal ? cfg.device_id_h : cfg.device_id_v;
    return r;
  }

  Payload make(Channel c, uint64_t i) {
    const Time t = streams[static_cast<size_t>(c)].stamp(i);
    switch (c) {
      case Channel::kSonarHorizontal:
      case Channel::kSonarVertical: {
        const SonarMount mount = c == Channel::kSonarHorizontal ? SonarMount::kHorizontal : SonarMount::kVertical;
        SonarRender r = prefetch ? prefetch->take(mount, i) : render_ping(mount, i);
        if (cfg.labels) pending_labels[static_cast<size_t>(mount)] = std::move(r.labels);
        return std::move(r.ping);
      }
      case Channel::kLabelsHorizontal:
      case Channel::kLabelsVertical: {
        auto& slot = pending_labels[c == Channel::kLabelsHorizontal ? 0 : 1];
        SonarLabels l = std::move(*slot);
        slot.reset();
        return l;
      }
      case Channel::kImu: {
        const VehicleState s = trajectory->at(t);
        Rng rng(derive_seed(cfg.seed, kImuStream, i));
        const auto& n = cfg.nav;
        ImuReading r;
        r.stamp = t;
        r.q_W_V = quat_rpy(s.roll_rad + rng.normal(0, n.imu_roll_pitch_sigma_deg * kRadPerDeg),
                           s.pitch_rad + rng.normal(0, n.imu_roll_pitch_sigma_deg * kRadPerDeg),
                           wrap_angle(s.yaw_rad + yaw_bias_rad[i] + rng.normal(0, n.imu_yaw_sigma_deg * kRadPerDeg)));
        const double g = n.imu_gyro_sigma_dps * kRadPerDeg;
        r.angular_velocity_V =
            s.omega_V_rps + gyro_bias_rps + Vec3(rng.normal(0, g), rng.normal(0, g), rng.normal(0, g));
        const Eigen::Matrix3d R = s.T_W_V().rotation();
        r.linear_acceleration_V = R.transpose() * Vec3(0, 0, 9.80665);
        return r;
      }
      case Channel::kDvl: {
        const VehicleState s = trajectory->at(t);
        Rng rng(derive_seed(cfg.seed, kDvlStream, i));
        const auto& n = cfg.nav;
        DvlReading r;
        r.stamp = t;
        const Eigen::Matrix3d R = s.T_W_V().rotation();
        const Vec3 v_V = R.transpose() * s.v_W_mps;
        r.velocity_V_mps = v_V + Vec3(rng.normal(0, n.dvl_sigma_mps), rng.normal(0, n.dvl_sigma_mps),
                                      rng.normal(0, n.dvl_sigma_mps));
        const auto alt = renderer->cast(s.p_W, -Vec3::UnitZ(), n.dvl_max_altitude_m);
        r.altitude_m = alt ? *alt : 0.0;
        r.valid = alt.has_value() && rng.uniform() >= n.dvl_invalid_probability;
        if (!r.valid) r.velocity_V_mps = Vec3::Zero();
        return r;
      }
      case Channel::kDepth: {
        Rng rng(derive_seed(cfg.seed, kDepthStream, i));
        // float32 metres, as the depth sensor's driver publishes them (bar30_depth/Depth), so
        // a mission exported in the authors' types imports back to the same readings.
        const double depth = -trajectory->at(t).p_W.z() + rng.normal(0, cfg.nav.depth_sigma_m);
        return DepthReading{t, static_cast<double>(static_cast<float>(depth))};
      }
      case Channel::kGyro: return fog_reading(t, i);
      case Channel::kTruthPose: break;
    }
    const VehicleState s = trajectory->at(t);
    return TruthPose{t, s.p_W, Quat(s.T_W_V().rotation())};
  }

  // The fibre-optic gyro's sample at t: the rotation of V since the previous sample (the
  // rotation vector of R(t - T)^T R(t)) plus the Earth's rotation seen in V (W is east,
  // north, up: Earth rate (0, cos lat, sin lat)), its bias and angle random walk, in the
  // gyro's frame G; as rates (divided by T) when the device is configured for rates.
  GyroReading fog_reading(Time t, uint64_t i) const {
    const auto& n = cfg.nav;
    const Time period = streams[static_cast<size_t>(Channel::kGyro)].period;
    const double T = period.seconds();
    const VehicleState a = trajectory->at(t - period), b = trajectory->at(t);
    const Eigen::Matrix3d Ra = a.T_W_V().rotation(), Rb = b.T_W_V().rotation();
    const Eigen::AngleAxisd turn(Ra.transpose() * Rb);
    Vec3 d_V = turn.angle() * turn.axis();
    const double lat = scene.latitude_deg * std::numbers::pi / 180.0;
    const Vec3 earth_W(0.0, std::cos(lat) * kEarthRateRps, std::sin(lat) * kEarthRateRps);
    d_V += Rb.transpose() * earth_W * T;
    Rng rng(derive_seed(cfg.seed, kFogStream, i));
    const double arw = n.gyro_arw_deg_per_sqrt_h * std::numbers::pi / 180.0 / 60.0;  // rad/sqrt(s)
    const double s = arw * std::sqrt(T);
    const Eigen::Matrix3d R_V_G = cfg.T_V_gyro.rotation();
    Vec3 d_G = R_V_G.transpose() * d_V + fog_bias_rps * T + Vec3(rng.normal(0, s), rng.normal(0, s), rng.normal(0, s));
    GyroReading g;
    g.stamp = t;
    g.is_rate = n.gyro_rates;
    g.value_G = n.gyro_rates ? Vec3(d_G / T) : d_G;
    g.valid = true;
    g.sequence = static_cast<uint8_t>(i % 128);
    g.temperature_c = 25.0;
    return g;
  }

  // The stamp of the next truth pose: the earliest sensor stamp not yet covered.
  std::optional<Time> next_truth_stamp() const {
    std::optional<Time> best;
    for (Channel c : kSensors) {
      const auto& st = streams[static_cast<size_t>(c)];
      const uint64_t k = truth_next[static_cast<size_t>(c)];
      if (k < st.count && (!best || st.stamp(k) < *best)) best = st.stamp(k);
    }
    return best;
  }
};

Simulator::Simulator(Scene scene, SimConfig config) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = std::move(scene);
  m.cfg = config;
  m.duration = Time::from_seconds(config.duration_s);
  SonarModelConfig sonar = config.sonar;
  sonar.seafloor_depth_m = m.scene.seafloor_depth_m;  // the seabed mirror (optional multipath)
  m.renderer = std::make_unique<SonarRenderer>(m.scene.mesh, sonar, config.resolution, config.seed);
  m.trajectory = std::make_unique<Trajectory>(m.scene.route, m.scene.vehicle_depth_m, config.vehicle, m.duration);
  const auto& n = config.nav;
  auto& s = m.streams;
  s[static_cast<size_t>(Channel::kSonarHorizontal)] = make_stream(n.ping_offset_s, n.ping_rate_hz, m.duration);
  s[static_cast<size_t>(Channel::kSonarVertical)] =
      make_stream(n.ping_offset_s + n.vertical_delay_s, n.ping_rate_hz, m.duration);
  s[static_cast<size_t>(Channel::kImu)] = make_stream(0.0, n.imu_rate_hz, m.duration);
  s[static_cast<size_t>(Channel::kDvl)] = make_stream(n.dvl_offset_s, n.dvl_rate_hz, m.duration);
  s[static_cast<size_t>(Channel::kDepth)] = make_stream(n.depth_offset_s, n.depth_rate_hz, m.duration);
  // The gyro's first sample closes its first interval, one period in.
  if (n.gyro_rate_hz > 0.0)
    s[static_cast<size_t>(Channel::kGyro)] = make_stream(1.0 / n.gyro_rate_hz, n.gyro_rate_hz, m.duration);
  s[static_cast<size_t>(Channel::kLabelsHorizontal)] =
      make_stream(n.ping_offset_s, n.ping_rate_hz, m.duration, config.labels);
  s[static_cast<size_t>(Channel::kLabelsVertical)] =
      make_stream(n.ping_offset_s + n.vertical_delay_s, n.ping_rate_hz, m.duration, config.labels);
  // Yaw bias: a steady drift plus a random walk, starting at zero.
  const auto& imu = s[static_cast<size_t>(Channel::kImu)];
  const double dt = imu.period.seconds();
  double b = 0.0;
  m.yaw_bias_rad.reserve(imu.count);
  for (uint64_t i = 0; i < imu.count; ++i) {
    m.yaw_bias_rad.push_back(b);
    Rng rng(derive_seed(config.seed, kBiasStream, i));
    b += n.imu_yaw_bias_rate_dps * kRadPerDeg * dt + n.imu_yaw_bias_walk_deg_per_sqrt_s * kRadPerDeg * std::sqrt(dt) * rng.normal();
  }
  {
    Rng rng(derive_seed(config.seed, kGyroBiasStream, 0));
    const double sb = n.imu_gyro_bias_dps * kRadPerDeg;
    m.gyro_bias_rps = Vec3(rng.normal(0, sb), rng.normal(0, sb), rng.normal(0, sb));
  }
  if (n.gyro_rate_hz > 0.0) {
    Rng rng(derive_seed(config.seed, kFogBiasStream, 0));
    const double sb = n.gyro_bias_dph / 3600.0 * std::numbers::pi / 180.0;
    m.fog_bias_rps = Vec3(rng.normal(0, sb), rng.normal(0, sb), rng.normal(0, sb));
  }
  if (config.render_threads > 1) {
    m.prefetch = std::make_unique<PingPrefetch>(
        config.render_threads, s[0].count, s[1].count,
        [&m](SonarMount mount, uint64_t i) { return m.render_ping(mount, i); });
  }
}

Simulator::~Simulator() = default;

Pulled Simulator::next() {
  Impl& m = *impl_;
  std::optional<Time> best;
  Channel best_c = Channel::kImu;
  for (int ci = 0; ci < kChannelCount; ++ci) {
    const auto c = static_cast<Channel>(ci);
    std::optional<Time> t;
    if (c == Channel::kTruthPose) {
      t = m.next_truth_stamp();
    } else if (m.next[static_cast<size_t>(ci)] < m.streams[static_cast<size_t>(ci)].count) {
      t = m.streams[static_cast<size_t>(ci)].stamp(m.next[static_cast<size_t>(ci)]);
    }
    if (t && (!best || *t < *best)) {  // channels visited in order: ties keep the lower channel
      best = t;
      best_c = c;
    }
  }
  if (!best) return Pulled::end();
  Event e;
  e.stamp = *best;
  e.channel = best_c;
  e.sequence = m.next[static_cast<size_t>(best_c)]++;
  if (best_c == Channel::kTruthPose) {
    for (Channel c : Impl::kSensors) {
      auto& k = m.truth_next[static_cast<size_t>(c)];
      const auto& st = m.streams[static_cast<size_t>(c)];
      while (k < st.count && st.stamp(k) <= *best) ++k;
    }
    const VehicleState s = m.trajectory->at(*best);
    e.payload = TruthPose{*best, s.p_W, Quat(s.T_W_V().rotation())};
  } else {
    e.payload = m.make(best_c, e.sequence);
  }
  return Pulled::of(std::move(e));
}

std::string Simulator::describe() const { return "sim:" + impl_->scene.name; }

std::map<std::string, std::string> Simulator::metadata() const {
  const Impl& m = *impl_;
  char buf[64];
  std::map<std::string, std::string> md;
  md["scene"] = portable_origin(m.scene);  // no folder: the fixture embeds the scene (embed_scene)
  md["seed"] = std::to_string(m.cfg.seed);
  md["scene_seed"] = std::to_string(m.scene.seed);
  md["resolution"] = resolution_name(m.cfg.resolution);
  std::snprintf(buf, sizeof buf, "%.17g", m.cfg.duration_s);
  md["duration_s"] = buf;
  md["T_V_h"] = format_pose6(m.cfg.T_V_h);
  md["T_V_v"] = format_pose6(m.cfg.T_V_v);
  std::snprintf(buf, sizeof buf, "%.17g", m.scene.vehicle_depth_m);
  md["vehicle_depth_m"] = buf;
  md["software_version"] = kVersion;
  md["labels"] = m.cfg.labels ? "true" : "false";
  md["profile"] = profile_name(m.cfg.profile);
  md["nav_profile"] = nav_profile_name(m.cfg.nav_profile);
  if (m.scene.route_name != "default") md["route"] = m.scene.route_name;  // missing: the scene's own
  if (m.cfg.nav.gyro_rate_hz > 0.0) {
    md["T_V_gyro"] = format_pose6(m.cfg.T_V_gyro);
    std::snprintf(buf, sizeof buf, "%.17g", m.scene.latitude_deg);
    md["latitude_deg"] = buf;
  }
  return md;
}

const Scene& Simulator::scene() const { return impl_->scene; }
const SimConfig& Simulator::config() const { return impl_->cfg; }
const SonarRenderer& Simulator::renderer() const { return *impl_->renderer; }
const Trajectory& Simulator::trajectory() const { return *impl_->trajectory; }
uint64_t Simulator::planned_count(Channel c) const {
  if (c != Channel::kTruthPose) return impl_->streams[static_cast<size_t>(c)].count;
  uint64_t n = 0;  // distinct sensor stamps
  std::array<uint64_t, 5> k{};
  while (true) {
    std::optional<Time> best;
    for (size_t s = 0; s < 5; ++s) {
      const auto& st = impl_->streams[static_cast<size_t>(Impl::kSensors[s])];
      if (k[s] < st.count && (!best || st.stamp(k[s]) < *best)) best = st.stamp(k[s]);
    }
    if (!best) return n;
    ++n;
    for (size_t s = 0; s < 5; ++s) {
      const auto& st = impl_->streams[static_cast<size_t>(Impl::kSensors[s])];
      while (k[s] < st.count && st.stamp(k[s]) <= *best) ++k[s];
    }
  }
}

}  // namespace orthosonar::sim
