// CFAR side by side (issue 37): cfar_detect against a naive per-cell loop of the same
// method (reference::naive_detect: every training side summed cell by cell, O(train
// cells) per cell, as sonar-SLAM's `soca` loop does), on the issue's image: 600 rows x
// 512 beams, 8-bit exponential speckle of mean 20 with 300 bright blobs (seeded), SOCA,
// 20 training and 5 guard cells per side, Pfa 0.1. Gate off (-1: every cell is tested;
// 0 would skip the zero cells) for the range and the cross window, and the gate at 65.
// Before timing, both must give the same detections (else the benchmark reports an error).
// The ratio naive / ours is tracked at every commit: run with
//   orthosonar_bench --benchmark_filter='BM_Cfar37'
#include <benchmark/benchmark.h>

#include <vector>

#include "core/perception/cfar.hpp"
#include "core/perception/cfar_reference.hpp"

namespace {

using namespace orthosonar;
using namespace orthosonar::perception;

const SonarPing& issue_image() {
  static const SonarPing p = reference::speckle_with_targets(600, 512, 20.0, 300, 37);
  return p;
}

// One image per iteration, ours or naive; the detection count and the fraction of cells
// detected as counters.
void BM_Cfar37(benchmark::State& state, CfarWindow window, double gate, bool naive) {
  const SonarPing& img = issue_image();
  const CfarConfig cfg = reference::speckle_with_targets_config(window, gate);
  const auto ours = cfar_detect(img, cfg);
  if (!reference::same_detections(ours, reference::naive_cfar(img, cfg))) {
    state.SkipWithError("cfar_detect and the naive reference disagree on this image");
    return;
  }
  size_t n = 0;
  for (auto _ : state) {
    auto d = naive ? reference::naive_cfar(img, cfg) : cfar_detect(img, cfg);
    n = d.size();
    benchmark::DoNotOptimize(d.data());
    benchmark::ClobberMemory();
  }
  state.counters["detections"] = static_cast<double>(n);
  state.counters["det_fraction"] = static_cast<double>(n) / (static_cast<double>(img.rows) * img.cols);
}

BENCHMARK_CAPTURE(BM_Cfar37, range_gate_off_ours, CfarWindow::kRange, -1.0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, range_gate_off_naive, CfarWindow::kRange, -1.0, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, cross_gate_off_ours, CfarWindow::kCross, -1.0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, cross_gate_off_naive, CfarWindow::kCross, -1.0, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, range_gate65_ours, CfarWindow::kRange, 65.0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, range_gate65_naive, CfarWindow::kRange, 65.0, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, cross_gate65_ours, CfarWindow::kCross, 65.0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cfar37, cross_gate65_naive, CfarWindow::kCross, 65.0, true)->Unit(benchmark::kMillisecond);

}  // namespace
