#include <catch2/catch.hpp>

#include "core/perception/pairing.hpp"

using namespace orthosonar;
using namespace orthosonar::perception;

namespace {
SonarPing ping(SonarMount m, int64_t ms, uint32_t id) {
  SonarPing p;
  p.mount = m;
  p.stamp = Time::from_ms(ms);
  p.ping_id = id;
  return p;
}
}  // namespace

TEST_CASE("PingPairer pairs closest pings and counts the unpaired", "[unit]") {
  PingPairer pairer(Time::from_ms(100));
  std::vector<std::pair<uint32_t, uint32_t>> got;
  auto drain = [&] {
    while (auto pr = pairer.pop()) got.emplace_back(pr->first.ping_id, pr->second.ping_id);
  };
  // 5 Hz h; v fires 5 ms later, except v ping for h #2 is lost and an extra v at 1.5 s.
  for (int k = 0; k < 6; ++k) {
    pairer.push(ping(SonarMount::kHorizontal, 200 * k, static_cast<uint32_t>(k)));
    drain();
    if (k != 2) pairer.push(ping(SonarMount::kVertical, 200 * k + 5, static_cast<uint32_t>(100 + k)));
    drain();
  }
  pairer.push(ping(SonarMount::kVertical, 1500, 999));
  pairer.flush();
  drain();
  const std::vector<std::pair<uint32_t, uint32_t>> want = {{0, 100}, {1, 101}, {3, 103}, {4, 104}, {5, 105}};
  CHECK(got == want);
  CHECK(pairer.pairs() == 5);
  CHECK(pairer.unpaired_h() == 1);
  CHECK(pairer.unpaired_v() == 1);
}

TEST_CASE("PingPairer chooses the nearer of two v pings and respects max_dt", "[unit]") {
  PingPairer pairer(Time::from_ms(50));
  pairer.push(ping(SonarMount::kVertical, 960, 1));
  pairer.push(ping(SonarMount::kHorizontal, 1000, 2));
  pairer.push(ping(SonarMount::kVertical, 1010, 3));
  pairer.push(ping(SonarMount::kHorizontal, 2000, 4));  // nothing within 50 ms
  pairer.flush();
  auto a = pairer.pop();
  REQUIRE(a);
  CHECK(a->first.ping_id == 2);
  CHECK(a->second.ping_id == 3);
  CHECK_FALSE(pairer.pop());
  CHECK(pairer.unpaired_h() == 1);
  CHECK(pairer.unpaired_v() == 1);
}

TEST_CASE("PingPairer waits until a later v ping could no longer be closer", "[unit]") {
  PingPairer pairer(Time::from_ms(100));
  pairer.push(ping(SonarMount::kHorizontal, 1000, 1));
  pairer.push(ping(SonarMount::kVertical, 1050, 2));
  CHECK_FALSE(pairer.pop());  // a v ping at 1001..1049 could still come
  pairer.push(ping(SonarMount::kVertical, 1101, 3));
  auto a = pairer.pop();
  REQUIRE(a);
  CHECK(a->second.ping_id == 2);
}
