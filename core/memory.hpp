#pragma once
// What a part of the pipeline holds in memory (issue 41): heap bytes counted from container
// capacities, so a run can say where its memory goes (replay --memory-report). Estimates of
// the payload, not of allocator overhead; no I/O, nothing read from the process.
#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "core/events.hpp"

namespace orthosonar {

// (part name, bytes), in a fixed order.
using MemoryParts = std::vector<std::pair<std::string, int64_t>>;

template <typename T, typename A>
int64_t heap_bytes(const std::vector<T, A>& v) {
  return static_cast<int64_t>(v.capacity() * sizeof(T));
}
// A deque holds its elements in blocks of about 512 bytes; the unused part of the end blocks
// is not counted.
template <typename T, typename A>
int64_t heap_bytes(const std::deque<T, A>& d) {
  return static_cast<int64_t>(d.size() * sizeof(T));
}
inline int64_t heap_bytes(const std::string& s) {
  return s.capacity() > 15 ? static_cast<int64_t>(s.capacity() + 1) : 0;  // beyond the small-string buffer
}
inline int64_t heap_bytes(const SonarPing& p) { return heap_bytes(p.image) + heap_bytes(p.bearings_rad); }

}  // namespace orthosonar
