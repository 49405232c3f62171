// Perception benchmarks (SPEC §3, §4): CFAR on one full-resolution 512 x 600 image and
// fusion of one full pair (both CFARs + association). Target: <= 2 ms per pair, one core.
// Images are synthetic but sonar-like: exponential speckle, a bright curved wall across
// the fan, a seafloor band in the far half, all seeded.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/perception/fusion.hpp"
#include "core/random.hpp"

namespace {

using namespace orthosonar;
using namespace orthosonar::perception;

SonarPing sonar_like(SonarMount mount, uint64_t seed) {
  SonarPing p;
  p.mount = mount;
  p.rows = 600;
  p.cols = 512;
  p.range_resolution_m = 0.05;
  const double half = 65.0 * std::numbers::pi / 180.0;
  for (int c = 0; c < p.cols; ++c) {
    const double u = -1.0 + 2.0 * (c + 0.5) / p.cols;
    p.bearings_rad.push_back(half * (0.92 * u + 0.08 * u * u * u));
  }
  Rng rng(seed);
  p.image.resize(static_cast<size_t>(p.rows) * p.cols);
  for (int r = 0; r < p.rows; ++r) {
    for (int c = 0; c < p.cols; ++c) {
      const double b = p.bearings_rad[static_cast<size_t>(c)];
      const double wall_row = 8.0 / std::max(0.2, std::cos(b)) / p.range_resolution_m;
      double mean = r > 380 ? 45.0 : 12.0;                  // seafloor band beyond 19 m
      if (std::abs(r - wall_row) < 2.0) mean = 180.0;       // the wall
      const double x = rng.exponential(mean);
      p.image[static_cast<size_t>(r * p.cols + c)] = static_cast<uint8_t>(std::min(255.0, x));
    }
  }
  return p;
}

const SonarPing& image_h() {
  static const SonarPing p = sonar_like(SonarMount::kHorizontal, 1);
  return p;
}
const SonarPing& image_v() {
  static const SonarPing p = sonar_like(SonarMount::kVertical, 2);
  return p;
}

// CFAR on one image per iteration; the detection count as a counter.
void run_cfar(benchmark::State& state, const CfarConfig& cfg, const SonarPing& image) {
  size_t n = 0;
  for (auto _ : state) {
    auto d = cfar_detect(image, cfg);
    n = d.size();
    benchmark::DoNotOptimize(d.data());
  }
  state.counters["detections"] = static_cast<double>(n);
}

void BM_CfarSocaCross512x600(benchmark::State& state) {
  const CfarConfig cfg;
  run_cfar(state, cfg, image_h());
}
BENCHMARK(BM_CfarSocaCross512x600)->Unit(benchmark::kMicrosecond);

// Worst case: no gate, so every cell runs the full test.
void BM_CfarSocaCross512x600NoGate(benchmark::State& state) {
  CfarConfig cfg;
  cfg.gate = 0.0;
  run_cfar(state, cfg, image_h());
}
BENCHMARK(BM_CfarSocaCross512x600NoGate)->Unit(benchmark::kMicrosecond);

void BM_CfarSocaRange512x600NoGate(benchmark::State& state) {
  CfarConfig cfg;
  cfg.window = CfarWindow::kRange;
  cfg.gate = 0.0;
  run_cfar(state, cfg, image_h());
}
BENCHMARK(BM_CfarSocaRange512x600NoGate)->Unit(benchmark::kMicrosecond);

// CA and GOCA with the gate off (every cell tested).
void BM_CfarCaCross512x600NoGate(benchmark::State& state) {
  CfarConfig cfg;
  cfg.method = CfarMethod::kCa;
  cfg.gate = 0.0;
  run_cfar(state, cfg, image_h());
}
BENCHMARK(BM_CfarCaCross512x600NoGate)->Unit(benchmark::kMicrosecond);

void BM_CfarGocaCross512x600NoGate(benchmark::State& state) {
  CfarConfig cfg;
  cfg.method = CfarMethod::kGoca;
  cfg.gate = 0.0;
  run_cfar(state, cfg, image_h());
}
BENCHMARK(BM_CfarGocaCross512x600NoGate)->Unit(benchmark::kMicrosecond);

// A field-like noise floor: speckle with mean 95 everywhere, so about half of the cells
// are above the default gate of 65 (the gate no longer skips most of the work).
const SonarPing& image_field() {
  static const SonarPing p = [] {
    SonarPing f = image_h();
    Rng rng(3);
    for (uint8_t& x : f.image) x = static_cast<uint8_t>(std::min(255.0, rng.exponential(95.0)));
    return f;
  }();
  return p;
}

void BM_CfarSocaCross512x600Field(benchmark::State& state) {
  const CfarConfig cfg;
  run_cfar(state, cfg, image_field());
}
BENCHMARK(BM_CfarSocaCross512x600Field)->Unit(benchmark::kMicrosecond);

void BM_FusePair512x600(benchmark::State& state) {
  const FusionConfig cfg;
  FusionResult r;
  for (auto _ : state) {
    r = fuse_pair(image_h(), image_v(), cfg);
    benchmark::DoNotOptimize(r.points.data());
  }
  state.counters["det_h"] = static_cast<double>(r.detections_h.size());
  state.counters["det_v"] = static_cast<double>(r.detections_v.size());
  state.counters["subproblems"] = static_cast<double>(r.subproblems);
  state.counters["points"] = static_cast<double>(r.points.size());
}
BENCHMARK(BM_FusePair512x600)->Unit(benchmark::kMicrosecond);

}  // namespace
