// The 8-bit CFAR threshold table: smax[N][x] from the exact rule, its linear estimate, and
// the per-thread cache of tables by (pfa, gate).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception::detail {

void ThresholdTable::build(int n) {
  built_[static_cast<size_t>(n)] = 1;
  int32_t* row = table_.data() + static_cast<size_t>(n) * 256;
  const double a = alpha_[static_cast<size_t>(n)];
  const int64_t cap = 255 * static_cast<int64_t>(n);
  for (int64_t x = 1; x < 256; ++x) {  // x = 0 is never a detection for α >= 0
    if (x <= gate_) continue;
    const double lhs = static_cast<double>(x * n);
    auto hit = [&](int64_t s) { return s == 0 || ratio_test(lhs, a, static_cast<double>(s)); };  // S = 0: x > 0
    int64_t s = cap;
    if (a > 0.0) s = static_cast<int64_t>(std::floor(std::min(lhs / a, static_cast<double>(cap))));
    if (hit(s)) {
      while (s < cap && hit(s + 1)) ++s;
    } else {
      while (!hit(s)) --s;  // hit(0)
    }
    row[x] = static_cast<int32_t>(s);
  }
  // T(x) = trunc(fl(x k)), k = fl(N / α), evaluated exactly as the vector code does;
  // smax[N][x] - T(x) over the cells above the gate spans [lo, hi].
  Linear& lin = linear_[static_cast<size_t>(n)];
  lin = Linear{};
  const int64_t x_first = std::max<int64_t>(gate_ + 1, 1);
  if (a > 0.0 && x_first <= 255 && static_cast<double>(n) / a * 255.0 < 8388608.0) {
    lin.k = static_cast<float>(static_cast<double>(n) / a);
    int64_t lo = cap + 1, hi = -cap - 1, t_max = 0;
    for (int64_t x = 0; x < 256; ++x) {
      const auto t = static_cast<int64_t>(static_cast<int32_t>(static_cast<float>(x) * lin.k));
      t_max = std::max(t_max, t);
      if (x < x_first) continue;
      lo = std::min(lo, row[x] - t);
      hi = std::max(hi, row[x] - t);
    }
    lin.fits16 = t_max + std::max<int64_t>(hi + 1, 0) <= 32767 && lo + 1 >= -32768 && t_max <= 32767;
    lin.lo1 = static_cast<int32_t>(lo + 1);
    lin.hi1 = static_cast<int32_t>(hi + 1);
    lin.x_gate = static_cast<int32_t>(x_first - 1);
    lin.ok = true;
  }
}

ThresholdTable& threshold_table(double pfa, int64_t gate) {
  thread_local ThresholdTable tables[4];
  thread_local uint64_t clock = 0;
  ThresholdTable* pick = &tables[0];
  for (ThresholdTable& t : tables) {
    if (t.matches(pfa, gate)) {
      pick = &t;
      break;
    }
    if (t.last_use < pick->last_use) pick = &t;
  }
  if (!pick->matches(pfa, gate)) pick->reset(pfa, gate);
  pick->last_use = ++clock;
  return *pick;
}

}  // namespace orthosonar::perception::detail
