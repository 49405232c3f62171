// Properties of perception: CFAR scale invariance (SPEC §3) and the exact Hungarian
// assignment against brute force (SPEC §4.6).
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <numeric>

#include "core/perception/assignment.hpp"
#include "core/perception/cfar.hpp"

using namespace orthosonar;
using namespace orthosonar::perception;

namespace {

// Minimum total cost over every injective map of the smaller side into the larger.
double brute_force_min(const Eigen::MatrixXd& c) {
  const bool wide = c.rows() <= c.cols();
  const Eigen::MatrixXd m = wide ? c : Eigen::MatrixXd(c.transpose());
  const int n = static_cast<int>(m.rows()), k = static_cast<int>(m.cols());
  std::vector<int> cols(static_cast<size_t>(k));
  std::iota(cols.begin(), cols.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  // Every permutation of the columns; its first n entries are an injective map.
  do {
    double s = 0;
    for (int i = 0; i < n; ++i) s += m(i, cols[static_cast<size_t>(i)]);
    best = std::min(best, s);
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}

}  // namespace

TEST_CASE("Hungarian equals brute force on random rectangular matrices", "[property]") {
  rc::prop("min total cost and a valid assignment", [] {
    const int rows = *rc::gen::inRange(1, 7);
    const int cols = *rc::gen::inRange(1, 7);
    // Small integer costs make ties common, which is where wrong solvers slip.
    const auto vals = *rc::gen::container<std::vector<int>>(static_cast<size_t>(rows * cols),
                                                           rc::gen::inRange(0, 10));
    Eigen::MatrixXd c(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) c(i, j) = vals[static_cast<size_t>(i * cols + j)] * 0.5;
    const std::vector<int> m = solve_assignment(c);
    RC_ASSERT(m.size() == static_cast<size_t>(rows));
    std::vector<int> used;
    for (int j : m) {
      RC_ASSERT(j >= -1);
      RC_ASSERT(j < cols);
      if (j >= 0) used.push_back(j);
    }
    RC_ASSERT(used.size() == static_cast<size_t>(std::min(rows, cols)));
    std::sort(used.begin(), used.end());
    RC_ASSERT(std::adjacent_find(used.begin(), used.end()) == used.end());
    RC_ASSERT(std::abs(assignment_cost(c, m) - brute_force_min(c)) < 1e-9);
  });
}

TEST_CASE("CFAR is scale-invariant apart from the gate", "[property]") {
  rc::prop("k * image with k * gate gives the same detections", [] {
    const int rows = *rc::gen::inRange(1, 48);
    const int cols = *rc::gen::inRange(1, 48);
    const int k = *rc::gen::inRange(1, 257);
    const auto vals = *rc::gen::container<std::vector<int>>(static_cast<size_t>(rows * cols),
                                                           rc::gen::inRange(0, 256));
    CfarConfig cfg;
    cfg.method = *rc::gen::element(CfarMethod::kSoca, CfarMethod::kCa, CfarMethod::kGoca);
    cfg.window = *rc::gen::element(CfarWindow::kCross, CfarWindow::kRange);
    cfg.train_cells = *rc::gen::inRange(1, 21);
    cfg.guard_cells = *rc::gen::inRange(0, 6);
    cfg.pfa = *rc::gen::element(0.1, 0.01, 0.3);
    cfg.gate = *rc::gen::inRange(0, 100);
    // 16-bit pings so that k * 255 still fits.
    SonarPing a, b;
    a.rows = b.rows = static_cast<uint16_t>(rows);
    a.cols = b.cols = static_cast<uint16_t>(cols);
    a.bytes_per_pixel = b.bytes_per_pixel = 2;
    for (int x : vals) {
      const int y = x * k;
      a.image.push_back(static_cast<uint8_t>(x & 0xff));
      a.image.push_back(static_cast<uint8_t>(x >> 8));
      b.image.push_back(static_cast<uint8_t>(y & 0xff));
      b.image.push_back(static_cast<uint8_t>(y >> 8));
    }
    CfarConfig scaled = cfg;
    scaled.gate = cfg.gate * k;
    const auto da = cfar_detect(a, cfg);
    const auto db = cfar_detect(b, scaled);
    RC_ASSERT(da.size() == db.size());
    for (size_t i = 0; i < da.size(); ++i) {
      RC_ASSERT(da[i].row == db[i].row);
      RC_ASSERT(da[i].col == db[i].col);
    }
  });
}
