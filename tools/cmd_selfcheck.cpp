// `orthosonar selfcheck`: proves the build links and its numerics behave as the
// reference build expects (SE(3) round trip, exact time arithmetic).
#include <cmath>
#include <iostream>

#include "core/geometry.hpp"
#include "core/time.hpp"
#include "orthosonar/version.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {

int run_selfcheck() {
  int failures = 0;
  auto check = [&](bool ok, const char* what) {
    std::cout << "  " << (ok ? "ok   " : "FAIL ") << what << "\n";
    if (!ok) ++failures;
  };
  std::cout << "orthosonar " << kVersion << " selfcheck\n";
  const SE3 T = se3_from_xyz_rpy(1.0, -2.0, -3.0, 0.1, -0.05, 1.2);
  check(((T * T.inverse()).matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-12, "SE(3) compose with inverse");
  const SE2 a{1.0, 2.0, 3.0};
  check(std::abs((a * a.inverse()).theta) < 1e-15, "SE(2) compose with inverse");
  check((Time::from_ms(1500) - Time::from_ms(500)) == Time::from_s(1), "Time arithmetic");
  // With -ffp-contract=off, a*b+c is rounded twice; the reference build promises that.
  volatile double x = 1.0 + 1e-8, y = 1.0 - 1e-8, z = -1.0;
  check(x * y + z == (1.0 + 1e-8) * (1.0 - 1e-8) - 1.0, "no FMA contraction");
  std::cout << "selfcheck: " << (failures == 0 ? "ok" : "FAILED") << "\n";
  return failures == 0 ? 0 : 1;
}

namespace {

const bool registered = register_command(
    {"selfcheck", "Check that the build links and its numerics are the reference ones",
     [](CLI::App&) -> std::function<int()> { return run_selfcheck; }});

}  // namespace
}  // namespace orthosonar::cli
