#pragma once
// Synthetic event streams for fixture tests, the interop check and benchmarks: every
// payload type on every channel at plausible rates, images with sonar-like statistics
// (a speckled noise floor and a few bright returns). Deterministic in the seed.
#include <cstdint>
#include <vector>

#include "core/events.hpp"

namespace orthosonar::replay {

struct SyntheticOptions {
  int64_t duration_ns = 2'000'000'000;
  double ping_rate_hz = 10.0;     // per sonar; the vertical fires 3 ms after the horizontal
  uint16_t ping_rows = 64;        // range bins
  uint16_t ping_cols = 32;        // beams
  uint8_t bytes_per_pixel = 1;
  double imu_rate_hz = 50.0;
  double dvl_rate_hz = 5.0;
  double depth_rate_hz = 10.0;
  double truth_rate_hz = 20.0;
  bool labels = true;             // a labels message per ping
};

// Events sorted by event_before, sequences 0, 1, ... per channel.
std::vector<Event> synthetic_events(uint64_t seed, const SyntheticOptions& options = {});

// Total bytes of sonar image and label payload in `events` (for throughput figures).
uint64_t payload_bytes(const std::vector<Event>& events);

}  // namespace orthosonar::replay
