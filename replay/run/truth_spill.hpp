#pragma once
// A run's ground truth kept on disk, not in memory (issue 41). A simulated mission has a
// truth pose at every sensor stamp (about 110 a second: 36 MB an hour as TruthPose), which
// only traj_truth.tum needs whole; the metrics ask for the truth at keyframe stamps, and
// results.mcap shows it at 10 Hz. TruthSpill appends every pose to an unlinked temporary
// file (64 bytes a pose, host byte order: it never leaves the process) and keeps in memory
// only a write buffer; the poses at most every 100 ms (results.mcap's view) are read back
// from the file as they are shown (an 8-hour mission's 288,000 would be 32 MB).
//
// subset(stamps) gives the first and last poses and, for each stamp, the poses either side
// of it in the whole stream (the stream's lower bound and the pose before it): interpolating
// the truth at those stamps in the subset gives exactly what it gives in the whole stream
// (mapping::truth_pose_at), so metrics and digests are unchanged.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::run {

class TruthSpill {
 public:
  // At most one pose per this interval is kept in memory (the first, then the first at
  // least this long after the last kept).
  static constexpr int64_t kShownSpacingNs = 100'000'000;

  // Opens the temporary file (std::tmpfile: $TMPDIR is not consulted, P_tmpdir is). Errors
  // say why it could not.
  static Result<std::unique_ptr<TruthSpill>> open();
  ~TruthSpill();
  TruthSpill(const TruthSpill&) = delete;
  TruthSpill& operator=(const TruthSpill&) = delete;

  // Appends a pose (stream order; stamps non-decreasing, as a fixture source yields them).
  // A write error is kept and returned by finish() and every later call.
  void append(const TruthPose& p);
  // Writes the buffer out; after it, only reads. Errors name the temporary file's failure.
  Status finish();

  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  // The poses at most every kShownSpacingNs, in order, read back from the file (after
  // finish()), and how many there are.
  Status for_each_shown(const std::function<void(const TruthPose&)>& f) const;
  size_t shown_count() const { return shown_count_; }
  // The same poses of a whole stream held in memory (a run without a spill).
  static std::vector<TruthPose> thin(const std::vector<TruthPose>& truth);
  // See the header comment. `stamps` in any order.
  Result<std::vector<TruthPose>> subset(const std::vector<Time>& stamps) const;
  // Every pose in order, read back in blocks.
  Status for_each(const std::function<void(const TruthPose&)>& f) const;
  // Heap bytes held (core/memory.hpp's sense): the write buffer.
  int64_t memory_bytes() const;

 private:
  explicit TruthSpill(std::FILE* f) : file_(f) {}
  Status read(size_t first, size_t n, std::vector<TruthPose>& out) const;
  Status flush_buffer();
  // The thinning rule: whether a pose at `stamp` is shown, given the last shown stamp (none
  // yet: `first`); updates both when it is.
  static bool show(Time stamp, Time& last, bool& first);

  std::FILE* file_ = nullptr;
  std::vector<TruthPose> buffer_;  // not yet written
  Time last_shown_;
  bool none_shown_ = true;
  size_t shown_count_ = 0;
  size_t count_ = 0;
  size_t written_ = 0;
  std::string error_;
};

}  // namespace orthosonar::run
