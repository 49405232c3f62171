#pragma once
// What the keyframe sweep keeps between its preparation pass and its cells (issue 41),
// held compactly: a sweep of the 3,600 s full-resolution fixture held 1.7 million events as
// 160-byte variants (274 MB), each of 36,000 pings with its own copy of the beam table
// (147 MB), every pair's fusion result whole (276 MB, 1,200 horizontal detections a pair),
// and a copy of the whole stream per running cell: 1.88 GB peak.
//
// SweepEvents: one 24-byte slot per event (stamp, channel, sequence, where its payload is)
// and the payloads in one store per type, a ping's beam table shared with every other
// ping that has the same table. at(i) gives back the event exactly as it was pushed.
// SweepEventSource serves them to a cell by reference, in the order hal::FakeSource would
// (a stable sort by event_before), so cells run on the same stream as before.
//
// FusionCache: each pair's FusionResult serialised column-wise (row deltas, columns,
// intensities, points) and zstd-compressed; get() gives back the same result bit for bit.
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "core/events.hpp"
#include "core/perception/fusion.hpp"
#include "hal/event_source.hpp"

namespace orthosonar::run {

class SweepEvents {
 public:
  void push_back(Event e);
  // Orders the events as hal::FakeSource does (stable, by event_before) and releases the
  // slack. Call once, after the last push_back.
  void finish();
  size_t size() const { return slots_.size(); }
  Event at(size_t i) const;
  size_t beam_tables() const { return tables_.size(); }
  int64_t memory_bytes() const;

 private:
  enum class Kind : uint8_t { kPing, kDvl, kImu, kDepth, kTruth, kLabels, kGyro };
  struct Slot {
    Time stamp;
    uint64_t sequence = 0;
    Channel channel = Channel::kImu;
    Kind kind = Kind::kImu;
    uint32_t index = 0;  // into the payload store of `kind`
  };
  uint32_t table_of(std::vector<double> bearings);

  std::vector<Slot> slots_;
  std::deque<SonarPing> pings_;          // bearings_rad moved out to tables_
  std::deque<uint32_t> ping_table_;      // per ping: its beam table
  std::vector<std::vector<double>> tables_;
  std::vector<uint32_t> recent_tables_;  // the tables the last pings used, newest last
  std::deque<DvlReading> dvl_;
  std::deque<ImuReading> imu_;
  std::deque<DepthReading> depth_;
  std::deque<TruthPose> truth_;
  std::deque<SonarLabels> labels_;
  std::deque<GyroReading> gyro_;
};

class SweepEventSource final : public hal::EventSource {
 public:
  explicit SweepEventSource(const SweepEvents& events) : events_(events) {}
  hal::Pulled next() override;
  std::string describe() const override { return "sweep stream"; }

 private:
  const SweepEvents& events_;
  size_t index_ = 0;
};

class FusionCache {
 public:
  // Thread-safe: the preparation pass fuses pairs on several threads.
  void put(Time h_stamp, Time v_stamp, const perception::FusionResult& r);
  // The result put for this pair, bit for bit; nullopt when none was. Thread-safe.
  std::optional<perception::FusionResult> get(Time h_stamp, Time v_stamp) const;
  size_t size() const;
  int64_t memory_bytes() const;  // the compressed results and the map's nodes

 private:
  mutable std::mutex mu_;
  std::map<std::pair<int64_t, int64_t>, std::vector<uint8_t>> blobs_;
  int64_t bytes_ = 0;
};

// The serialised form FusionCache compresses, exposed for tests.
std::vector<uint8_t> serialise_fusion(const perception::FusionResult& r);
perception::FusionResult deserialise_fusion(const std::vector<uint8_t>& bytes);

}  // namespace orthosonar::run
