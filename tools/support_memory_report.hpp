#pragma once
// `replay --memory-report FILE` (issue 41): where a run's memory goes. Samples the process's
// resident memory (VmRSS, and its peak VmHWM, from /proc/self/status) together with what
// each part of the pipeline holds (Pipeline::memory(), the source's buffered events) at the
// first event, every minute of sensor time, the end of the stream, after the metrics and
// after the outputs are written; writes the samples as CSV and prints the budget: each
// part at the end of the stream, its largest sample, and its growth per hour of mission.
#include <cstdint>
#include <string>
#include <vector>

#include "core/memory.hpp"
#include "replay/run/run.hpp"

namespace orthosonar::cli {

// The process's resident bytes now and at most so far (VmRSS, VmHWM); {-1, -1} where
// /proc/self/status cannot be read.
struct ResidentBytes {
  int64_t now = -1, peak = -1;
};
ResidentBytes resident_bytes();

class MemoryReport {
 public:
  // One sample (run::RunControl::memory calls it on the feeding thread).
  void sample(const run::RunControl::MemoryView& view);
  // After the outputs are written: the pipeline still alive in the run output, and what its
  // truth spill holds (RunOutput::truth_all).
  void sample_outputs(const mapping::Pipeline& pipeline, int64_t truth_spill_bytes);
  // sensor_s, phase, rss_mb, peak_rss_mb, then one column per part (MB), parts_mb.
  Status write_csv(const std::string& path) const;
  // The budget as a Markdown table (part | end of stream | largest | growth per hour).
  std::string budget() const;
  bool empty() const { return rows_.empty(); }

 private:
  struct Row {
    double sensor_s = 0.0;
    std::string phase;
    ResidentBytes rss;
    MemoryParts parts;  // "decoder_buffers" first, then Pipeline::memory()'s
  };
  std::vector<Row> rows_;
  Time first_;
  bool have_first_ = false;
};

}  // namespace orthosonar::cli
