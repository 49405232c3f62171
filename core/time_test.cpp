#include "core/time.hpp"

#include <catch2/catch.hpp>

using orthosonar::Time;

TEST_CASE("Time constructors agree on units", "[unit]") {
  CHECK(Time::from_s(2).ns() == 2'000'000'000);
  CHECK(Time::from_ms(3).ns() == 3'000'000);
  CHECK(Time::from_us(4).ns() == 4'000);
  CHECK(Time::from_seconds(0.1).ns() == 100'000'000);
  CHECK(Time::from_seconds(-0.1).ns() == -100'000'000);
  CHECK(Time::from_seconds(1e-9).ns() == 1);
}

TEST_CASE("Time arithmetic is exact integer arithmetic", "[unit]") {
  const Time a = Time::from_ms(1500), b = Time::from_ms(200);
  CHECK((a + b).ns() == 1'700'000'000);
  CHECK((a - b).ns() == 1'300'000'000);
  CHECK((b - a).ns() == -1'300'000'000);
  CHECK((a * 3).ns() == 4'500'000'000);
  CHECK((a / 3).ns() == 500'000'000);
  CHECK(a / b == 7);
  CHECK((a % b).ns() == 100'000'000);
  CHECK(abs(b - a) == Time::from_ms(1300));
  Time c = a;
  c += b;
  c -= Time::from_ms(700);
  CHECK(c == Time::from_s(1));
  CHECK(a.seconds() == Approx(1.5));
}

TEST_CASE("Time is totally ordered", "[unit]") {
  CHECK(Time::from_ns(1) < Time::from_ns(2));
  CHECK(Time::from_ns(2) >= Time::from_ns(2));
  CHECK(Time::min() < Time() );
  CHECK(Time() < Time::max());
}
