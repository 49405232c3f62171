#include "core/inference/classifier.hpp"

#include <catch2/catch.hpp>
#include <cstring>

#include "core/inference/crops.hpp"
#include "core/inference/synthetic_crops.hpp"

using namespace orthosonar;
using namespace orthosonar::inference;

namespace {
const std::vector<SemanticClass> kClasses = {SemanticClass::kPiling, SemanticClass::kDock, SemanticClass::kSeawall};

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}
}  // namespace

TEST_CASE("classifier output has one probability per class and crop", "[unit]") {
  InferenceRuntime::configure(1, 7);
  Classifier net({}, kClasses, 1);
  const auto crops = synthetic_crop_set(2, 40, 3);
  std::vector<cv::Mat> imgs;
  for (const auto& c : crops) imgs.push_back(c.crop);
  const auto preds = net.classify(imgs, 11);
  REQUIRE(preds.size() == imgs.size());
  for (const auto& p : preds) {
    REQUIRE(p.mean_probabilities.size() == 3);
    double sum = 0;
    for (float v : p.mean_probabilities) sum += v;
    CHECK(sum == Approx(1.0).epsilon(1e-5));
  }
  const auto mc = net.mc_probabilities(imgs[0], 11);
  CHECK(mc.size() == 20);
}

TEST_CASE("same seed gives the same bits and MC passes vary around a reproducible mean", "[unit]") {
  InferenceRuntime::configure(1, 7);
  Classifier a({}, kClasses, 42), b({}, kClasses, 42);
  Rng rng(5);
  const cv::Mat crop = synthetic_crop(0, 40, rng);
  const auto pa = a.classify({crop}, 99);
  const auto pb = b.classify({crop}, 99);
  CHECK(same_bits(pa[0].mean_probabilities, pb[0].mean_probabilities));
  // A crop's result does not depend on the other crops of the batch.
  const auto batch = a.classify({synthetic_crop(1, 40, rng), crop}, 99);
  (void)batch;
  const auto mc = a.mc_probabilities(crop, 99);
  bool varies = false;
  for (const auto& row : mc) varies = varies || !same_bits(row, mc[0]);
  CHECK(varies);
  std::vector<float> mean(3, 0.0f);
  for (const auto& row : mc)
    for (size_t c = 0; c < 3; ++c) mean[c] += row[c] / static_cast<float>(mc.size());
  for (size_t c = 0; c < 3; ++c) CHECK(mean[c] == Approx(pa[0].mean_probabilities[c]).epsilon(1e-5));
  // Another seed gives other masks.
  const auto pc = a.classify({crop}, 100);
  CHECK_FALSE(same_bits(pa[0].mean_probabilities, pc[0].mean_probabilities));
}

TEST_CASE("serialize and deserialize keep the model bit for bit", "[unit]") {
  InferenceRuntime::configure(1, 7);
  Classifier a({}, kClasses, 3);
  auto loaded = Classifier::deserialize(a.serialize());
  REQUIRE(loaded.ok());
  CHECK(loaded->classes() == kClasses);
  Rng rng(1);
  const cv::Mat crop = synthetic_crop(2, 40, rng);
  CHECK(same_bits(a.classify({crop}, 5)[0].mean_probabilities, loaded->classify({crop}, 5)[0].mean_probabilities));
  CHECK_FALSE(Classifier::deserialize("not a model").ok());
}

TEST_CASE("training on a tiny synthetic set reaches high held-out accuracy", "[unit]") {
  InferenceRuntime::configure(1, 7);
  const auto train = synthetic_crop_set(100, 40, 100);
  const auto test = synthetic_crop_set(30, 40, 200);
  Classifier net({}, kClasses, 8);
  TrainConfig tc;
  tc.epochs = 15;
  net.train(train, tc, 9);
  size_t correct = 0, total = 0, accepted = 0;
  for (const auto& a : net.evaluate(test, 10)) {
    correct += a.correct;
    total += a.samples;
    accepted += a.accepted;
    CHECK(a.accuracy() >= 0.8);
  }
  CHECK(static_cast<double>(correct) / static_cast<double>(total) >= 0.9);
  CHECK(accepted > 0);
  // Training is reproducible bit for bit.
  Classifier again({}, kClasses, 8);
  again.train(train, tc, 9);
  CHECK(again.serialize() == net.serialize());
}

TEST_CASE("augmentation keeps size and range and is reproducible", "[unit]") {
  Rng r1(4), r2(4);
  const cv::Mat crop = synthetic_crop(1, 40, r1);
  Rng s1(8), s2(8);
  const cv::Mat a = augment_crop(crop, s1), b = augment_crop(crop, s2);
  REQUIRE(a.rows == 40);
  REQUIRE(a.cols == 40);
  double lo, hi;
  cv::minMaxLoc(a, &lo, &hi);
  CHECK(lo >= 0.0);
  CHECK(hi <= 1.0);
  CHECK(cv::norm(a, b, cv::NORM_INF) == 0.0);
  (void)r2;
}
