// Inference per frame (SPEC §7 runtime "inference per frame"; issue target <= 20 ms on one
// core): DBSCAN + crops + MC-dropout CNN (20 passes) + registration + Bayes + MAP on a
// full-resolution (600 x 512) horizontal frame with eight pilings, three of them inside
// the overlap. The model is untrained (timing does not depend on the weights) and has one
// class, so every cluster is accepted and takes the full path (the worst case).
#include <benchmark/benchmark.h>

#include <numbers>

#include "core/inference/dbscan.hpp"
#include "core/inference/object_inference.hpp"
#include "core/inference/synthetic_crops.hpp"

using namespace orthosonar;
using namespace orthosonar::inference;

namespace {

std::vector<SyntheticPiling> eight_pilings() {
  std::vector<SyntheticPiling> p;
  const double bearings_deg[] = {-50, -35, -20, -5, 3, 8, 25, 45};
  for (int i = 0; i < 8; ++i) {
    const double th = bearings_deg[i] * std::numbers::pi / 180.0, r = 6.0 + 1.5 * (i % 4);
    p.push_back({r * std::cos(th), r * std::sin(th), 0.4});
  }
  return p;
}

const std::vector<SemanticClass> kClasses = {SemanticClass::kSeafloor, SemanticClass::kPiling, SemanticClass::kDock,
                                             SemanticClass::kSeawall, SemanticClass::kBoat};

void BM_InferencePerFrame(benchmark::State& state) {
  InferenceRuntime::configure(1, 1);
  InferenceConfig cfg;
  // One class: every cluster is accepted and takes registration + Bayes + MAP.
  ObjectInference inf(cfg, Classifier({}, {SemanticClass::kPiling}, 1));
  const auto frame = synthetic_piling_frame(eight_pilings(), -1.0, 1);
  (void)inf.process(frame.h, frame.detections, frame.fused);  // warm: class models exist
  size_t inferred = 0;
  for (auto _ : state) {
    auto r = inf.process(frame.h, frame.detections, frame.fused);
    inferred = r.inferred_V.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["clusters"] = 8;
  state.counters["inferred_points"] = static_cast<double>(inferred);
}
BENCHMARK(BM_InferencePerFrame)->Unit(benchmark::kMillisecond);

void BM_ClassifyMcDropout(benchmark::State& state) {
  InferenceRuntime::configure(1, 1);
  const Classifier net({}, kClasses, 1);
  const auto set = synthetic_crop_set(static_cast<int>(state.range(0)), 40, 2);
  std::vector<cv::Mat> crops;
  for (const auto& c : set) crops.push_back(c.crop);
  for (auto _ : state) benchmark::DoNotOptimize(net.classify(crops, 3));
  state.counters["crops"] = static_cast<double>(crops.size());
}
BENCHMARK(BM_ClassifyMcDropout)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_Dbscan(benchmark::State& state) {
  const auto frame = synthetic_piling_frame(eight_pilings(), -1.0, 1);
  for (auto _ : state) benchmark::DoNotOptimize(dbscan_clusters(frame.detections, {}));
  state.counters["pixels"] = static_cast<double>(frame.detections.size());
}
BENCHMARK(BM_Dbscan)->Unit(benchmark::kMicrosecond);

}  // namespace
