#pragma once
// `--rate R`: live-like replay. Wraps an EventSource and holds each event back until
// wall time has advanced (stamp - first stamp) / R since the first event. It only delays:
// events, their order and therefore every output are unchanged (SPEC §9). Lives in
// tools/ because it reads a clock, which the core and the replay library never do.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "hal/event_source.hpp"

namespace orthosonar::cli {

class PacedSource final : public hal::EventSource {
 public:
  // rate: stream seconds per wall second (1 = real time, 2 = twice as fast); must be > 0.
  PacedSource(std::unique_ptr<hal::EventSource> inner, double rate);
  hal::Pulled next() override;
  std::string describe() const override;

 private:
  std::unique_ptr<hal::EventSource> inner_;
  double rate_;
  std::optional<Time> first_stamp_;
  std::chrono::steady_clock::time_point wall_start_;
};

// `source` unchanged when rate is 0 (as fast as possible), else wrapped in a PacedSource.
std::unique_ptr<hal::EventSource> paced(std::unique_ptr<hal::EventSource> source, double rate);

}  // namespace orthosonar::cli
