#pragma once
// rapidcheck generators of fixture events for the replay properties: every payload type,
// doubles drawn as arbitrary finite bit patterns (subnormals, huge, negative zero), small
// images of 8 or 16 bits, stamps anywhere in the ros1 time range.
#include <rapidcheck.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "core/events.hpp"

namespace orthosonar::replay_gen {

inline double any_double() {
  const auto bits = *rc::gen::arbitrary<uint64_t>();
  const double d = std::bit_cast<double>(bits);
  return std::isfinite(d) ? d : static_cast<double>(bits >> 11);
}
inline Vec3 any_vec3() { return Vec3(any_double(), any_double(), any_double()); }
inline Quat any_quat() { return Quat(any_double(), any_double(), any_double(), any_double()); }

inline SonarPing any_ping(SonarMount mount, Time stamp) {
  SonarPing p;
  p.device_id = *rc::gen::arbitrary<uint32_t>();
  p.part_number = *rc::gen::arbitrary<uint16_t>();
  p.mount = mount;
  p.stamp = stamp;
  p.ping_id = *rc::gen::arbitrary<uint32_t>();
  p.range_resolution_m = any_double();
  p.frequency_hz = any_double();
  p.gain_percent = any_double();
  p.rows = *rc::gen::inRange<uint16_t>(0, 9);
  p.cols = *rc::gen::inRange<uint16_t>(0, 9);
  p.bytes_per_pixel = *rc::gen::element<uint8_t>(1, 2);
  for (int i = 0; i < p.cols; ++i) p.bearings_rad.push_back(any_double());
  p.image = *rc::gen::container<std::vector<uint8_t>>(size_t{p.rows} * p.cols * p.bytes_per_pixel,
                                                      rc::gen::arbitrary<uint8_t>());
  return p;
}

inline SonarLabels any_labels(SonarMount mount, Time stamp) {
  SonarLabels l;
  l.stamp = stamp;
  l.mount = mount;
  l.ping_id = *rc::gen::arbitrary<uint32_t>();
  l.rows = *rc::gen::inRange<uint16_t>(0, 7);
  l.cols = *rc::gen::inRange<uint16_t>(0, 7);
  const size_t n = size_t{l.rows} * l.cols;
  l.semantic = *rc::gen::container<std::vector<uint8_t>>(n, rc::gen::arbitrary<uint8_t>());
  l.object_id = *rc::gen::container<std::vector<uint32_t>>(n, rc::gen::arbitrary<uint32_t>());
  return l;
}

inline Payload any_payload(Channel c, Time t) {
  switch (c) {
    case Channel::kSonarHorizontal: return any_ping(SonarMount::kHorizontal, t);
    case Channel::kSonarVertical: return any_ping(SonarMount::kVertical, t);
    case Channel::kImu: return ImuReading{t, any_quat(), any_vec3(), any_vec3()};
    case Channel::kDvl: return DvlReading{t, any_vec3(), *rc::gen::arbitrary<bool>(), any_double()};
    case Channel::kDepth: return DepthReading{t, any_double()};
    case Channel::kTruthPose: return TruthPose{t, any_vec3(), any_quat()};
    case Channel::kLabelsHorizontal: return any_labels(SonarMount::kHorizontal, t);
    case Channel::kLabelsVertical: return any_labels(SonarMount::kVertical, t);
    case Channel::kGyro: {
      GyroReading g;
      g.stamp = t;
      g.value_G = any_vec3();
      g.is_rate = *rc::gen::arbitrary<bool>();
      g.valid = *rc::gen::arbitrary<bool>();
      g.sequence = *rc::gen::arbitrary<uint8_t>();
      g.temperature_c = any_double();
      return g;
    }
  }
  return DepthReading{t, 0.0};
}

// Up to max_events events in the contract order (stamp, channel, sequence), sequences
// 0, 1, ... per channel; stamps may repeat, also within a channel.
// Stamps are multiples of quantum_ns below max_stamp_ns.
inline std::vector<Event> any_events(int max_events, int64_t max_stamp_ns, int64_t quantum_ns = 1) {
  const int n = *rc::gen::inRange(0, max_events + 1);
  std::vector<Event> ev;
  for (int i = 0; i < n; ++i) {
    const auto c = static_cast<Channel>(*rc::gen::inRange(0, kChannelCount));
    const Time t = Time::from_ns(*rc::gen::inRange<int64_t>(0, max_stamp_ns / quantum_ns) * quantum_ns);
    ev.push_back(Event{t, c, 0, any_payload(c, t)});
  }
  std::stable_sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) {
    return a.stamp != b.stamp ? a.stamp < b.stamp : a.channel < b.channel;
  });
  std::array<uint64_t, kChannelCount> seq{};
  for (auto& e : ev) e.sequence = seq[static_cast<size_t>(e.channel)]++;
  return ev;
}

}  // namespace orthosonar::replay_gen
