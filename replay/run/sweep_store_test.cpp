#include "replay/run/sweep_store.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "hal/fake_source.hpp"

using namespace orthosonar;
using namespace orthosonar::run;

namespace {

// Events of every payload type, several at equal stamps, pushed in an order that is not
// event_before's (the store must order them as hal::FakeSource does); pings of each mount
// share one of two beam tables.
std::vector<Event> store_test_events(uint32_t seed, size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::uniform_int_distribution<int> kind(0, 6), dt(0, 3);
  const std::vector<double> tables[2] = {{-0.5, -0.1, 0.2, 0.6}, {-0.3, 0.0, 0.3}};
  std::vector<Event> out;
  std::array<uint64_t, kChannelCount> seq{};
  Time t = Time::from_ms(1000);
  for (size_t i = 0; i < n; ++i) {
    t = t + Time::from_ms(dt(rng));  // equal stamps about a quarter of the time
    Payload p;
    switch (kind(rng)) {
      case 0: {
        SonarPing s;
        s.mount = rng() % 2 ? SonarMount::kHorizontal : SonarMount::kVertical;
        s.stamp = t;
        s.ping_id = static_cast<uint32_t>(i);
        s.bearings_rad = tables[rng() % 2];
        if (rng() % 8 == 0) s.bearings_rad = {u(rng), u(rng)};  // a table of its own
        s.rows = 3;
        s.cols = static_cast<uint16_t>(s.bearings_rad.size());
        if (rng() % 2) s.image.assign(static_cast<size_t>(s.rows) * s.cols, static_cast<uint8_t>(rng()));
        p = s;
        break;
      }
      case 1: p = DvlReading{t, Vec3(u(rng), u(rng), u(rng)), rng() % 5 != 0, u(rng)}; break;
      case 2: p = ImuReading{t, Quat(u(rng), u(rng), u(rng), u(rng)).normalized(), Vec3(u(rng), 0, 1), Vec3::Zero()}; break;
      case 3: p = DepthReading{t, u(rng)}; break;
      case 4: p = TruthPose{t, Vec3(u(rng), u(rng), u(rng)), Quat::Identity()}; break;
      case 5: {
        SonarLabels l;
        l.stamp = t;
        l.rows = 1;
        l.cols = 2;
        l.semantic = {1, 2};
        l.object_id = {7, 9};
        p = l;
        break;
      }
      default: {
        GyroReading g;
        g.stamp = t;
        g.value_G = Vec3(u(rng), u(rng), u(rng));
        g.sequence = static_cast<uint8_t>(i % 128);
        p = g;
      }
    }
    const Channel ch = channel_of(p);
    out.push_back(Event{t, ch, seq[static_cast<size_t>(ch)]++, p});
  }
  // Swap neighbours at equal stamps so the pushed order is not event_before's.
  for (size_t i = 1; i < out.size(); ++i)
    if (out[i].stamp == out[i - 1].stamp && rng() % 2) std::swap(out[i], out[i - 1]);
  return out;
}

perception::FusionResult store_test_fusion(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-30.0f, 30.0f);
  perception::FusionResult r;
  r.candidates_h = rng() % 1000;
  r.candidates_v = rng() % 1000;
  r.subproblems = rng() % 100;
  r.matches = rng() % 100;
  r.culled_low_confidence = rng() % 10;
  r.sloped_face = rng() % 10;
  for (size_t i = rng() % 50; i > 0; --i) {
    perception::FusedPoint p;
    p.p_V = Eigen::Vector3f(u(rng), u(rng), u(rng));
    p.range_m = u(rng);
    p.bearing_rad = u(rng);
    p.elevation_rad = u(rng);
    p.intensity_h = u(rng);
    p.intensity_v = std::numeric_limits<float>::denorm_min();
    p.confidence = -0.0f;
    p.run_near_m = u(rng);
    p.run_far_m = u(rng);
    p.elevation_sigma_rad = u(rng);
    p.elevation_from = rng() % 2 ? perception::FusedPoint::Elevation::sloped_face : perception::FusedPoint::Elevation::v_return;
    r.points.push_back(p);
  }
  int row = 0;
  for (size_t i = rng() % 3000; i > 0; --i) {
    row += static_cast<int>(rng() % 3);
    r.detections_h.push_back({row, static_cast<int>(rng() % 512), static_cast<float>(rng() % 256)});
  }
  for (size_t i = rng() % 40; i > 0; --i)
    r.detections_v.push_back({static_cast<int>(rng() % 600), static_cast<int>(rng() % 256), u(rng)});
  return r;
}

bool store_same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void check_same_fusion(const perception::FusionResult& a, const perception::FusionResult& b) {
  CHECK(a.candidates_h == b.candidates_h);
  CHECK(a.candidates_v == b.candidates_v);
  CHECK(a.subproblems == b.subproblems);
  CHECK(a.matches == b.matches);
  CHECK(a.culled_low_confidence == b.culled_low_confidence);
  CHECK(a.sloped_face == b.sloped_face);
  REQUIRE(a.points.size() == b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    const auto &p = a.points[i], &q = b.points[i];
    for (int k = 0; k < 3; ++k) CHECK(store_same_bits(p.p_V[k], q.p_V[k]));
    CHECK(store_same_bits(p.range_m, q.range_m));
    CHECK(store_same_bits(p.bearing_rad, q.bearing_rad));
    CHECK(store_same_bits(p.elevation_rad, q.elevation_rad));
    CHECK(store_same_bits(p.elevation_sigma_rad, q.elevation_sigma_rad));
    CHECK(store_same_bits(p.intensity_h, q.intensity_h));
    CHECK(store_same_bits(p.intensity_v, q.intensity_v));
    CHECK(store_same_bits(p.run_near_m, q.run_near_m));
    CHECK(store_same_bits(p.run_far_m, q.run_far_m));
    CHECK(p.elevation_from == q.elevation_from);
    CHECK(store_same_bits(p.confidence, q.confidence));
  }
  for (const auto& [da, db] : {std::pair{&a.detections_h, &b.detections_h}, std::pair{&a.detections_v, &b.detections_v}}) {
    REQUIRE(da->size() == db->size());
    for (size_t i = 0; i < da->size(); ++i) {
      CHECK((*da)[i].row == (*db)[i].row);
      CHECK((*da)[i].col == (*db)[i].col);
      CHECK(store_same_bits((*da)[i].intensity, (*db)[i].intensity));
    }
  }
}

}  // namespace

TEST_CASE("sweep events: the same events in hal::FakeSource's order, beam tables shared", "[unit]") {
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    const auto events = store_test_events(seed, 2000);
    SweepEvents store;
    for (const auto& e : events) store.push_back(e);
    store.finish();
    hal::FakeSource fake(events);
    SweepEventSource source(store);
    REQUIRE(store.size() == events.size());
    size_t n = 0;
    for (;;) {
      const auto a = fake.next();
      const auto b = source.next();
      REQUIRE(a.end_of_stream == b.end_of_stream);
      if (a.end_of_stream) break;
      REQUIRE(a.event.has_value());
      REQUIRE(b.event.has_value());
      CHECK(*a.event == *b.event);
      ++n;
    }
    CHECK(n == events.size());
    // Two shared tables and the pings with a table of their own (about one in eight).
    size_t pings = 0;
    for (const auto& e : events) pings += std::holds_alternative<SonarPing>(e.payload) ? 1 : 0;
    CHECK(store.beam_tables() >= 2);
    CHECK(store.beam_tables() < 2 + pings / 4);
    CHECK(store.memory_bytes() < static_cast<int64_t>(events.size() * sizeof(Event)));
  }
}

TEST_CASE("sweep fusion cache: every result back bit for bit, compressed, and none for unknown pairs", "[unit]") {
  FusionCache cache;
  std::vector<perception::FusionResult> put;
  int64_t raw = 0;
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    put.push_back(store_test_fusion(seed));
    cache.put(Time::from_ms(seed), Time::from_ms(seed + 3), put.back());
    raw += static_cast<int64_t>(serialise_fusion(put.back()).size());
    check_same_fusion(deserialise_fusion(serialise_fusion(put.back())), put.back());
  }
  CHECK(cache.size() == put.size());
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    const auto got = cache.get(Time::from_ms(seed), Time::from_ms(seed + 3));
    REQUIRE(got.has_value());
    check_same_fusion(*got, put[seed - 1]);
  }
  CHECK_FALSE(cache.get(Time::from_ms(1), Time::from_ms(5)).has_value());
  CHECK_FALSE(cache.get(Time::from_ms(99), Time::from_ms(102)).has_value());
  // Row deltas and byte-valued intensities compress: well under the serialised size.
  CHECK(cache.memory_bytes() < raw / 2);
  // An empty result round-trips too.
  check_same_fusion(deserialise_fusion(serialise_fusion({})), {});
  // A cut-short blob is an error, not a silently shorter result.
  auto bytes = serialise_fusion(put[0]);
  bytes.pop_back();
  CHECK_THROWS_WITH(deserialise_fusion(bytes), Catch::Contains("cut short"));
}
