#pragma once
// Exact statistics of integer image intensities (8- or 16-bit) through a histogram:
// quantiles, mean, the count above a gate, and Otsu's dark/bright split. Used to measure
// perception against truth (perception_metrics.hpp) and to describe real pings.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/events.hpp"

namespace orthosonar::mapping {

// a / b, or 0 when b is 0.
double ratio(double a, double b);

struct IntensityHistogram {
  std::vector<uint64_t> count;  // count[x]: pixels of intensity x
  uint64_t n = 0;
  double sum = 0.0;

  void add(uint32_t x);
  void add(const IntensityHistogram& o);
  // Every pixel of a ping.
  void add(const SonarPing& ping);
  // Quantile q of the values in [lo, hi]: the sorted sample at floor(q (m - 1)), m the
  // count in [lo, hi]; NaN when there is none.
  double quantile(double q, size_t lo = 0, size_t hi = std::numeric_limits<size_t>::max()) const;
  double mean() const;  // NaN when empty
  uint64_t above(double gate) const;  // values > gate
  // above(gate) / n, or 0 when empty.
  double fraction_above(double gate) const;
};

// Otsu's threshold t of a histogram: dark = values <= t, bright = values > t. NaN fields
// for an empty histogram; a histogram of one value is all dark.
struct OtsuSplit {
  double threshold = std::numeric_limits<double>::quiet_NaN();
  double dark_fraction = std::numeric_limits<double>::quiet_NaN();
  double dark_p50 = std::numeric_limits<double>::quiet_NaN();
  double bright_fraction = std::numeric_limits<double>::quiet_NaN();
  double bright_p50 = std::numeric_limits<double>::quiet_NaN();
};
OtsuSplit otsu(const IntensityHistogram& h);

}  // namespace orthosonar::mapping
