// `orthosonar selfcheck`: proves the build links and its numerics behave as the
// reference build expects (SE(3) round trip, exact time arithmetic), and that every numeric
// pin (docs/ARCHITECTURE.md, "Cross-machine determinism: pinned numerics") took: each is
// printed with the value asked for and the value the library reports.
#include <cmath>
#include <iostream>

#include "core/geometry.hpp"
#include "core/inference/numeric_pins.hpp"
#include "core/time.hpp"
#include "hal/sim/embree_device.hpp"
#include "orthosonar/version.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {

int run_selfcheck() {
  int failures = 0;
  auto check = [&](bool ok, const std::string& what) {
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

  // The pins, applied at startup by main() (inference::apply_numeric_pins).
  std::cout << "numeric pins (pinned -> effective):\n";
  const sim::EmbreeIsaReport e = sim::embree_isa_report();
  check(e.ok, "pin embree.isa: " + std::string(sim::kEmbreePinnedIsa) + " -> " + (e.isa.empty() ? "?" : e.isa) +
                  "  [device \"" + e.config + "\"; " + (e.ok ? e.intersector : e.error) +
                  "; this CPU: " + e.cpu_targets + "]");
  for (const inference::NumericPin& p : inference::numeric_pins_report()) {
    check(p.ok, "pin " + p.name + ": " + p.pinned + " -> " + p.effective + "  [" + p.note + "]");
  }
  std::cout << "selfcheck: " << (failures == 0 ? "ok" : "FAILED") << "\n";
  return failures == 0 ? 0 : 1;
}

namespace {

const bool registered_selfcheck = register_command(
    {"selfcheck", "Check that the build links, its numerics are the reference ones and every numeric pin took",
     [](CLI::App&) -> std::function<int()> { return run_selfcheck; }});

}  // namespace
}  // namespace orthosonar::cli
