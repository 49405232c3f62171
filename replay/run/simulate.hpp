#pragma once
// `orthosonar simulate`'s mission run: every event of a Simulator into a fixture that embeds
// its scene (written as <out>.partial and renamed when complete), with fan PNGs of the
// pings at chosen mission times.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/sim/simulator.hpp"

namespace orthosonar::run {

struct SimulateOptions {
  std::string out;                  // fixture to write (.mcap); empty: none
  int zstd_level = 1;               // the fixture's chunk compression
  std::string snapshot_dir;         // fan PNGs of the pings at snapshot_at_s; empty: none
  std::vector<double> snapshot_at_s;
};

struct SimulateCounts {
  std::array<uint64_t, kChannelCount> per_channel{};
  uint64_t events = 0;
};

// Pulls every event of `simulator`. Errors: the simulator's, the writer's, a snapshot's.
Result<SimulateCounts> simulate_to_fixture(sim::Simulator& simulator, const SimulateOptions& options);

}  // namespace orthosonar::run
