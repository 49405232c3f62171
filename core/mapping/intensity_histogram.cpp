#include "core/mapping/intensity_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace orthosonar::mapping {

double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

void IntensityHistogram::add(uint32_t x) {
  if (x >= count.size()) count.resize(x + 1, 0);
  ++count[x];
  ++n;
  sum += x;
}

void IntensityHistogram::add(const IntensityHistogram& o) {
  if (o.count.size() > count.size()) count.resize(o.count.size(), 0);
  for (size_t i = 0; i < o.count.size(); ++i) count[i] += o.count[i];
  n += o.n;
  sum += o.sum;
}

void IntensityHistogram::add(const SonarPing& ping) {
  for (int row = 0; row < ping.rows; ++row)
    for (int col = 0; col < ping.cols; ++col) add(ping.at(row, col));
}

double IntensityHistogram::quantile(double q, size_t lo, size_t hi) const {
  hi = std::min(hi, count.empty() ? 0 : count.size() - 1);
  uint64_t m = 0;
  for (size_t i = lo; i <= hi && i < count.size(); ++i) m += count[i];
  if (m == 0) return std::nan("");
  const auto k = static_cast<uint64_t>(std::floor(q * static_cast<double>(m - 1)));
  uint64_t c = 0;
  for (size_t i = lo; i <= hi; ++i) {
    c += count[i];
    if (c > k) return static_cast<double>(i);
  }
  return static_cast<double>(hi);
}

double IntensityHistogram::mean() const { return n ? sum / static_cast<double>(n) : std::nan(""); }

uint64_t IntensityHistogram::above(double gate) const {
  uint64_t a = 0;
  for (size_t i = 0; i < count.size(); ++i)
    if (static_cast<double>(i) > gate) a += count[i];
  return a;
}

double IntensityHistogram::fraction_above(double gate) const {
  return ratio(static_cast<double>(above(gate)), static_cast<double>(n));
}

OtsuSplit otsu(const IntensityHistogram& h) {
  OtsuSplit s;
  if (h.n == 0) return s;
  const double total = static_cast<double>(h.n);
  double w0 = 0.0, sum0 = 0.0, best = -1.0;
  size_t t_best = 0;
  for (size_t t = 0; t + 1 < h.count.size(); ++t) {
    w0 += static_cast<double>(h.count[t]);
    sum0 += static_cast<double>(t) * static_cast<double>(h.count[t]);
    const double w1 = total - w0;
    if (w0 == 0.0 || w1 == 0.0) continue;
    const double m0 = sum0 / w0, m1 = (h.sum - sum0) / w1;
    const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      t_best = t;
    }
  }
  if (best < 0.0) t_best = h.count.size() - 1;  // a single value: everything is "dark"
  s.threshold = static_cast<double>(t_best);
  uint64_t dark = 0;
  for (size_t i = 0; i <= t_best && i < h.count.size(); ++i) dark += h.count[i];
  s.dark_fraction = static_cast<double>(dark) / total;
  s.bright_fraction = 1.0 - s.dark_fraction;
  s.dark_p50 = h.quantile(0.5, 0, t_best);
  s.bright_p50 = h.quantile(0.5, t_best + 1);
  return s;
}

}  // namespace orthosonar::mapping
