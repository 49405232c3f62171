#include "core/inference/object_inference.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/inference/synthetic_crops.hpp"

using namespace orthosonar;
using namespace orthosonar::inference;

namespace {
// A one-class model accepts every cluster (its softmax is 1), which isolates the
// geometry of the pipeline from the classifier's training.
ObjectInference one_class_pipeline() {
  InferenceRuntime::configure(1, 1);
  InferenceConfig cfg;
  cfg.T_V_h = SE3::Identity();
  return ObjectInference(cfg, Classifier({}, {SemanticClass::kPiling}, 1));
}
}  // namespace

TEST_CASE("a piling seen in 3D lends its height to a piling seen only in 2D", "[unit]") {
  ObjectInference inf = one_class_pipeline();
  const double z = -1.2;
  // Frame 1: one piling ahead, inside the overlap: fused heights update the class model.
  const auto f1 = synthetic_piling_frame({{10.0, 0.0, 0.4}}, z, 1);
  REQUIRE(f1.fused.size() > 10);
  const auto r1 = inf.process(f1.h, f1.detections, f1.fused);
  REQUIRE(r1.stats.clusters == 1);
  CHECK(r1.stats.known == 1);
  CHECK(r1.stats.bayes_updates == f1.fused.size());
  REQUIRE(inf.height_model(SemanticClass::kPiling) != nullptr);
  // Frame 2: another piling at 35° bearing, no fused points at all.
  const double th = 35.0 * std::numbers::pi / 180.0;
  const auto f2 = synthetic_piling_frame({{9.0 * std::cos(th), 9.0 * std::sin(th), 0.4}}, z, 2);
  REQUIRE(f2.fused.empty());
  const auto r2 = inf.process(f2.h, f2.detections, {});
  REQUIRE(r2.stats.clusters == 1);
  CHECK(r2.stats.registration_failures == 0);
  REQUIRE(r2.inferred_V.size() > 20);
  for (const auto& p : r2.inferred_V) {
    CHECK(std::abs(p.z() - z) <= 0.03);                                   // the learned height
    CHECK(std::abs(std::atan2(p.y(), p.x()) - th) < 0.1);                  // where the object is
  }
}

TEST_CASE("frames without 3D for an unseen class infer nothing", "[unit]") {
  ObjectInference inf = one_class_pipeline();
  const auto f = synthetic_piling_frame({{8.0, 4.0, 0.4}}, -1.0, 3);
  const auto r = inf.process(f.h, f.detections, {});
  CHECK(r.stats.clusters == 1);
  CHECK(r.inferred_V.empty());
  CHECK(inf.height_model(SemanticClass::kPiling) == nullptr);
}

TEST_CASE("processing is deterministic", "[unit]") {
  const auto f = synthetic_piling_frame({{10.0, 0.5, 0.4}, {7.0, -5.0, 0.4}, {6.0, 6.0, 0.3}}, 0.8, 4);
  ObjectInference a = one_class_pipeline(), b = one_class_pipeline();
  const auto ra = a.process(f.h, f.detections, f.fused);
  const auto rb = b.process(f.h, f.detections, f.fused);
  CHECK(ra.inferred_V == rb.inferred_V);
  CHECK(ra.stats.clusters == 3);
}
