#include "replay/synthetic.hpp"

#include <cmath>

#include "core/random.hpp"
#include "hal/fake_source.hpp"

namespace orthosonar::replay {
namespace {

SonarPing make_ping(Rng& rng, const SyntheticOptions& o, SonarMount mount, Time t, uint32_t id) {
  SonarPing p;
  const bool h = mount == SonarMount::kHorizontal;
  p.device_id = h ? 101u : 102u;
  p.part_number = h ? kPartM750d : kPartM1200d;
  p.mount = mount;
  p.stamp = t;
  p.ping_id = id;
  p.range_resolution_m = h ? 0.0202 : 0.0101;
  p.frequency_hz = h ? 1.2e6 : 2.1e6;
  p.gain_percent = rng.uniform(40.0, 60.0);
  p.rows = o.ping_rows;
  p.cols = o.ping_cols;
  p.bytes_per_pixel = o.bytes_per_pixel;
  const double half = (h ? 130.0 : 20.0) * M_PI / 360.0;
  for (int c = 0; c < p.cols; ++c) {
    const double s = p.cols > 1 ? static_cast<double>(c) / (p.cols - 1) : 0.5;
    p.bearings_rad.push_back(std::asin(std::sin(-half) + s * (std::sin(half) - std::sin(-half))));
  }
  const size_t n = size_t{p.rows} * p.cols;
  p.image.resize(n * p.bytes_per_pixel);
  const int bright_row = static_cast<int>(rng.below(p.rows));
  for (size_t i = 0; i < n; ++i) {
    const uint64_t r = rng.next_u64();
    // Speckle floor: mostly small values; a bright band near one range.
    uint32_t v = static_cast<uint32_t>(r & 0x0f) * static_cast<uint32_t>((r >> 4) & 0x03);
    const int row = static_cast<int>(i / p.cols);
    if (std::abs(row - bright_row) < 3) v = 120u + static_cast<uint32_t>((r >> 8) & 0x7f);
    if (p.bytes_per_pixel == 1) {
      p.image[i] = static_cast<uint8_t>(v);
    } else {
      const uint32_t w = v * 200u + static_cast<uint32_t>((r >> 16) & 0xff);
      p.image[2 * i] = static_cast<uint8_t>(w & 0xff);
      p.image[2 * i + 1] = static_cast<uint8_t>(w >> 8);
    }
  }
  return p;
}

SonarLabels make_labels(Rng& rng, const SonarPing& p) {
  SonarLabels l;
  l.stamp = p.stamp;
  l.mount = p.mount;
  l.ping_id = p.ping_id;
  l.rows = p.rows;
  l.cols = p.cols;
  const size_t n = size_t{p.rows} * p.cols;
  l.semantic.assign(n, 0);
  l.object_id.assign(n, 0);
  const auto obj = static_cast<uint32_t>(1 + rng.below(20));
  for (size_t i = 0; i < n; ++i) {
    if (p.image[i * p.bytes_per_pixel] >= 120) {
      l.semantic[i] = static_cast<uint8_t>(1 + obj % 4);
      l.object_id[i] = obj;
    }
  }
  return l;
}

Quat yaw_quat(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }

}  // namespace

std::vector<Event> synthetic_events(uint64_t seed, const SyntheticOptions& o) {
  Rng rng(derive_seed(seed, 0x5e7));
  std::vector<Payload> out;
  auto every = [&](double hz, int64_t offset_ns, auto&& make) {
    if (hz <= 0) return;
    const auto period = static_cast<int64_t>(std::llround(1e9 / hz));
    uint32_t k = 0;
    for (int64_t t = offset_ns; t < o.duration_ns; t += period) make(Time::from_ns(t), k++);
  };
  every(o.ping_rate_hz, 1'000'000, [&](Time t, uint32_t k) {
    for (SonarMount m : {SonarMount::kHorizontal, SonarMount::kVertical}) {
      const Time tm = m == SonarMount::kHorizontal ? t : t + Time::from_ms(3);
      SonarPing p = make_ping(rng, o, m, tm, k);
      if (o.labels) out.emplace_back(make_labels(rng, p));
      out.emplace_back(std::move(p));
    }
  });
  every(o.imu_rate_hz, 0, [&](Time t, uint32_t) {
    ImuReading m;
    m.stamp = t;
    m.q_W_V = yaw_quat(0.1 * t.seconds() + rng.normal(0, 0.003)).normalized();
    m.angular_velocity_V = Vec3(rng.normal(0, 0.01), rng.normal(0, 0.01), 0.1);
    m.linear_acceleration_V = Vec3(rng.normal(0, 0.05), rng.normal(0, 0.05), 9.81);
    out.emplace_back(m);
  });
  every(o.dvl_rate_hz, 2'000'000, [&](Time t, uint32_t k) {
    DvlReading m;
    m.stamp = t;
    m.velocity_V_mps = Vec3(0.4 + rng.normal(0, 0.01), rng.normal(0, 0.01), rng.normal(0, 0.01));
    m.valid = k % 17 != 16;
    m.altitude_m = m.valid ? 5.0 + rng.normal(0, 0.05) : -1.0;
    out.emplace_back(m);
  });
  every(o.depth_rate_hz, 4'000'000, [&](Time t, uint32_t) {
    out.emplace_back(DepthReading{t, 3.0 + rng.normal(0, 0.02)});
  });
  every(o.truth_rate_hz, 0, [&](Time t, uint32_t) {
    TruthPose m;
    m.stamp = t;
    m.p_W = Vec3(0.4 * t.seconds(), 0.0, -3.0);
    m.q_W_V = yaw_quat(0.1 * t.seconds());
    out.emplace_back(m);
  });
  return hal::make_events(out);
}

uint64_t payload_bytes(const std::vector<Event>& events) {
  uint64_t n = 0;
  for (const auto& e : events) {
    if (const auto* p = std::get_if<SonarPing>(&e.payload)) n += p->image.size();
    if (const auto* l = std::get_if<SonarLabels>(&e.payload)) n += l->semantic.size() + 4 * l->object_id.size();
  }
  return n;
}

}  // namespace orthosonar::replay
