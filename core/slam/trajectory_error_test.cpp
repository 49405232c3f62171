#include "core/slam/trajectory_error.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace orthosonar;
using namespace orthosonar::slam;

TEST_CASE("ate_rmse of a known offset, with and without first-position alignment", "[unit]") {
  const std::vector<Vec3> truth = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  // Shifted by (5, 0, 0) and the last position 0.3 m off in y.
  const std::vector<Vec3> est = {{5, 0, 0}, {6, 0, 0}, {7, 0.3, 0}};
  const auto aligned = ate_rmse(est, truth);
  REQUIRE(aligned.ok());
  CHECK(*aligned == Approx(std::sqrt(0.09 / 3.0)));
  const auto raw = ate_rmse(est, truth, AteAlignment::kNone);
  REQUIRE(raw.ok());
  CHECK(*raw == Approx(std::sqrt((25.0 + 25.0 + 25.0 + 0.09) / 3.0)));
}

// Before: a size mismatch or an empty estimate returned 0.0, a perfect score.
TEST_CASE("ate_rmse of trajectories of different sizes or none is an error, never a score", "[unit]") {
  const std::vector<Vec3> truth = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<Vec3> shorter = {{0, 0, 0}, {1, 0, 0}};
  const auto mismatch = ate_rmse(shorter, truth);
  REQUIRE_FALSE(mismatch.ok());
  CHECK(mismatch.error().message.find("2 positions, truth 3") != std::string::npos);
  CHECK_FALSE(ate_rmse(truth, shorter).ok());
  CHECK_FALSE(ate_rmse({}, {}).ok());
  CHECK_FALSE(ate_rmse({}, truth).ok());
}
