#pragma once
// What a reader recovered of an MCAP file: whole, or cut short at a byte offset with the
// messages and sensor time before the cut (issue 16, issue 40).
#include <cstdint>
#include <string>

namespace orthosonar::replay {

// A reader's account of one file. A cut file is read up to its last complete record.
struct RecoveryReport {
  bool complete = true;          // footer and summary present and valid
  uint64_t bytes_total = 0;
  uint64_t bytes_recovered = 0;  // up to the end of the last complete record/chunk
  uint64_t messages_recovered = 0;
  std::string detail;            // why reading stopped early, naming the byte offset
  // Log times spanned by the recovered messages (chunk and message-run headers; 0 when
  // none): the sensor time a cut recording still holds.
  uint64_t first_ns = 0, last_ns = 0;
  double sensor_seconds() const { return last_ns > first_ns ? static_cast<double>(last_ns - first_ns) * 1e-9 : 0.0; }
};

}  // namespace orthosonar::replay
