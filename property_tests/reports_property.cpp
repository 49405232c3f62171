// Properties of the report's comparison primitives: image_difference is a metric on the
// downscaled grayscale images (zero on identity, symmetric, triangle inequality, in
// [0, 1]); grid nearest-neighbour distances equal brute force below the cap.
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "core/random.hpp"
#include "reports/image_compare.hpp"
#include "reports/nearest.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

namespace {

// A random image of a few filled shapes, from a seed (our Rng, not rapidcheck's bytes, so
// images are varied at any size).
cv::Mat random_image(uint64_t seed) {
  Rng rng(derive_seed(seed, 0x1a6e));
  const int w = 80 + static_cast<int>(rng.below(240)), h = 60 + static_cast<int>(rng.below(180));
  cv::Mat m(h, w, CV_8UC3, cv::Scalar(static_cast<double>(rng.below(256)), 40, 40));
  const int shapes = 1 + static_cast<int>(rng.below(6));
  for (int i = 0; i < shapes; ++i)
    cv::circle(m, {static_cast<int>(rng.below(static_cast<uint64_t>(w))), static_cast<int>(rng.below(static_cast<uint64_t>(h)))},
               2 + static_cast<int>(rng.below(30)),
               cv::Scalar(static_cast<double>(rng.below(256)), static_cast<double>(rng.below(256)), 200), cv::FILLED);
  return m;
}

}  // namespace

TEST_CASE("image difference is a bounded metric", "[property]") {
  rc::prop("identity, symmetry, triangle inequality, range", [](uint64_t sa, uint64_t sb, uint64_t sc) {
    const cv::Mat a = random_image(sa), b = random_image(sb), c = random_image(sc);
    RC_ASSERT(image_difference(a, a) == 0.0);
    const double ab = image_difference(a, b), ba = image_difference(b, a);
    RC_ASSERT(std::abs(ab - ba) < 1e-12);
    RC_ASSERT(ab >= 0.0);
    RC_ASSERT(ab <= 1.0);
    RC_ASSERT(image_difference(a, c) <= ab + image_difference(b, c) + 1e-9);
  });
}

TEST_CASE("grid nearest distances match brute force", "[property]") {
  rc::prop("exact below the cap, the cap above", [](uint64_t seed) {
    Rng rng(derive_seed(seed, 0x2b));
    const double cap = rng.uniform(0.05, 1.0);
    std::vector<Eigen::Vector3f> ref, query;
    const auto n = 1 + rng.below(200), m = 1 + rng.below(100);
    for (uint64_t i = 0; i < n; ++i)
      ref.emplace_back(static_cast<float>(rng.uniform(-2, 2)), static_cast<float>(rng.uniform(-2, 2)),
                       static_cast<float>(rng.uniform(-2, 2)));
    for (uint64_t i = 0; i < m; ++i)
      query.emplace_back(static_cast<float>(rng.uniform(-3, 3)), static_cast<float>(rng.uniform(-3, 3)),
                         static_cast<float>(rng.uniform(-3, 3)));
    const auto d = nearest_distances(query, ref, cap);
    RC_ASSERT(d.size() == query.size());
    for (size_t q = 0; q < query.size(); ++q) {
      float best = 1e30f;
      for (const auto& r : ref) best = std::min(best, (r - query[q]).norm());
      RC_ASSERT(std::abs(d[q] - std::min(best, static_cast<float>(cap))) < 1e-5f);
    }
  });
}
