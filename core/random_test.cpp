#include "core/random.hpp"

#include <catch2/catch.hpp>
#include <numbers>

// random.hpp spells 2π out (it also compiles as C++17); it must be the double the C++20
// constant gives, or every simulated noise draw would change.
static_assert(2.0 * 3.141592653589793238462643383279502884 == 2.0 * std::numbers::pi);

using orthosonar::Rng;

TEST_CASE("Rng repeats for a seed and differs between seeds", "[unit]") {
  Rng a(42), b(42), c(43);
  for (int i = 0; i < 100; ++i) {
    const uint64_t x = a.next_u64();
    CHECK(x == b.next_u64());
    CHECK(x != c.next_u64());
  }
}

TEST_CASE("Rng sequence is pinned (platform independence)", "[unit]") {
  // Pinned values: a change here changes every simulated fixture and digest.
  Rng r(1);
  const uint64_t first = r.next_u64();
  Rng again(1);
  CHECK(again.next_u64() == first);
  CHECK(orthosonar::derive_seed(1, 2, 3) != orthosonar::derive_seed(1, 2, 4));
  CHECK(orthosonar::mix64(0) == 0xE220A8397B1DCDAFull);
}

TEST_CASE("Rng distributions have the stated moments", "[unit]") {
  Rng r(7);
  const int n = 200000;
  double su = 0, sn = 0, sn2 = 0, se = 0;
  for (int i = 0; i < n; ++i) {
    su += r.uniform();
    const double g = r.normal();
    sn += g;
    sn2 += g * g;
    se += r.exponential(2.0);
  }
  CHECK(su / n == Approx(0.5).margin(0.005));
  CHECK(sn / n == Approx(0.0).margin(0.01));
  CHECK(sn2 / n == Approx(1.0).margin(0.02));
  CHECK(se / n == Approx(2.0).margin(0.03));
  for (int i = 0; i < 1000; ++i) CHECK(r.below(7) < 7);
}
