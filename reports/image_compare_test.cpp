#include "reports/image_compare.hpp"

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "core/random.hpp"
#include "reports/nearest.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

namespace {
cv::Mat pattern(int shift_px) {
  cv::Mat m(480, 640, CV_8UC3, cv::Scalar(30, 30, 30));
  for (int i = 0; i < 8; ++i) cv::circle(m, {60 + 70 * i + shift_px, 240}, 25, cv::Scalar(200, 220, 90), cv::FILLED);
  return m;
}
}  // namespace

TEST_CASE("image difference is 0 for identical images and 1 for black against white", "[report]") {
  const cv::Mat black(120, 160, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Mat white(120, 160, CV_8UC3, cv::Scalar(255, 255, 255));
  CHECK(image_difference(black, black) == 0.0);
  CHECK(image_difference(black, white) == Approx(1.0));
  CHECK(image_difference(pattern(0), pattern(0)) == 0.0);
  CHECK(image_difference(cv::Mat(), black) == 1.0);
}

TEST_CASE("image difference grows with displacement and tolerates one pixel", "[report]") {
  const double one = image_difference(pattern(0), pattern(1));
  const double ten = image_difference(pattern(0), pattern(10));
  const double forty = image_difference(pattern(0), pattern(40));
  CHECK(one < 0.01);
  CHECK(one < ten);
  CHECK(ten < forty);
  CHECK(forty > 0.03);
  // Symmetric, and sizes may differ (both are brought to the same grid).
  CHECK(image_difference(pattern(0), pattern(10)) == image_difference(pattern(10), pattern(0)));
  cv::Mat big;
  cv::resize(pattern(0), big, cv::Size(1280, 960), 0, 0, cv::INTER_NEAREST);
  CHECK(image_difference(pattern(0), big) < 0.01);
}

TEST_CASE("pixel variance separates blank images from drawings", "[report]") {
  CHECK(pixel_variance(cv::Mat(100, 100, CV_8UC3, cv::Scalar(80, 90, 100))) == 0.0);
  CHECK(pixel_variance(pattern(0)) > 100.0);
}

TEST_CASE("side by side puts both images on one canvas with captions", "[report]") {
  const cv::Mat out = side_by_side(pattern(0), "golden", pattern(5), "current");
  CHECK(out.cols == 640 * 2 + 8);
  CHECK(out.rows > 480);
  CHECK(out.type() == CV_8UC3);
}

TEST_CASE("grid nearest distances equal brute force below the cap", "[report]") {
  Rng rng(derive_seed(7, 1));
  std::vector<Eigen::Vector3f> ref, query;
  for (int i = 0; i < 400; ++i)
    ref.emplace_back(static_cast<float>(rng.uniform(-3, 3)), static_cast<float>(rng.uniform(-3, 3)),
                     static_cast<float>(rng.uniform(-1, 1)));
  for (int i = 0; i < 300; ++i)
    query.emplace_back(static_cast<float>(rng.uniform(-4, 4)), static_cast<float>(rng.uniform(-4, 4)),
                       static_cast<float>(rng.uniform(-2, 2)));
  const double cap = 0.4;
  const auto d = nearest_distances(query, ref, cap);
  REQUIRE(d.size() == query.size());
  int below = 0;
  for (size_t q = 0; q < query.size(); ++q) {
    float best = 1e30f;
    for (const auto& r : ref) best = std::min(best, (r - query[q]).norm());
    CHECK(d[q] == Approx(std::min(best, static_cast<float>(cap))).margin(1e-6));
    below += best < cap ? 1 : 0;
  }
  CHECK(below > 20);  // the comparison exercised the exact branch, not only the cap
  CHECK(nearest_distances(query, {}, cap)[0] == static_cast<float>(cap));
}
