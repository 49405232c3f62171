#pragma once
// Generators shared by the property tests. Doubles are made from rapidcheck's integer
// draws with our own mapping, so the distribution is exactly what the name says and is
// reproduced from the printed seed (RC_PARAMS="seed=...").
#include <rapidcheck.h>

namespace orthosonar::property {

// Uniform on [lo, hi] with a 1e-6 grid.
inline double uniform(double lo, double hi) {
  const int k = *rc::gen::inRange(0, 1000001);
  return lo + (hi - lo) * (static_cast<double>(k) / 1000000.0);
}

}  // namespace orthosonar::property
