#include "core/perception/assignment.hpp"

#include <limits>

namespace orthosonar::perception {
namespace {

// Shortest augmenting path Hungarian method with row/column potentials for n <= m:
// adds rows one at a time, each time growing a Dijkstra-like tree over columns on
// reduced costs until a free column is reached, then flips the path. O(n^2 m), exact.
// Ties go to the lowest column index (strict comparisons in index order).
std::vector<int> hungarian_wide(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(static_cast<size_t>(n) + 1, 0.0), v(static_cast<size_t>(m) + 1, 0.0);
  std::vector<int> p(static_cast<size_t>(m) + 1, 0), way(static_cast<size_t>(m) + 1, 0);
  std::vector<double> minv(static_cast<size_t>(m) + 1);
  std::vector<char> used(static_cast<size_t>(m) + 1);
  auto at = [](auto& vec, int i) -> auto& { return vec[static_cast<size_t>(i)]; };
  for (int i = 1; i <= n; ++i) {
    at(p, 0) = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      at(used, j0) = 1;
      const int i0 = at(p, j0);
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (at(used, j)) continue;
        const double cur = a(i0 - 1, j - 1) - at(u, i0) - at(v, j);
        if (cur < at(minv, j)) {
          at(minv, j) = cur;
          at(way, j) = j0;
        }
        if (at(minv, j) < delta) {
          delta = at(minv, j);
          j1 = j;
        }
      }
      if (j1 == 0) break;  // only with non-finite costs; leaves the row unassigned
      for (int j = 0; j <= m; ++j) {
        if (at(used, j)) {
          at(u, at(p, j)) += delta;
          at(v, j) -= delta;
        } else {
          at(minv, j) -= delta;
        }
      }
      j0 = j1;
    } while (at(p, j0) != 0);
    if (at(p, j0) != 0) continue;
    do {
      const int j1 = at(way, j0);
      at(p, j0) = at(p, j1);
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(static_cast<size_t>(n), -1);
  for (int j = 1; j <= m; ++j)
    if (at(p, j) != 0) row_to_col[static_cast<size_t>(at(p, j) - 1)] = j - 1;
  return row_to_col;
}

}  // namespace

std::vector<int> solve_assignment(const Eigen::MatrixXd& cost) {
  const auto rows = cost.rows(), cols = cost.cols();
  if (rows == 0 || cols == 0) return std::vector<int>(static_cast<size_t>(rows), -1);
  if (rows <= cols) return hungarian_wide(cost);
  const Eigen::MatrixXd t = cost.transpose();
  const std::vector<int> col_to_row = hungarian_wide(t);
  std::vector<int> row_to_col(static_cast<size_t>(rows), -1);
  for (size_t j = 0; j < col_to_row.size(); ++j)
    if (col_to_row[j] >= 0) row_to_col[static_cast<size_t>(col_to_row[j])] = static_cast<int>(j);
  return row_to_col;
}

double assignment_cost(const Eigen::MatrixXd& cost, const std::vector<int>& row_to_col) {
  double total = 0.0;
  for (size_t i = 0; i < row_to_col.size(); ++i)
    if (row_to_col[i] >= 0) total += cost(static_cast<Eigen::Index>(i), row_to_col[i]);
  return total;
}

}  // namespace orthosonar::perception
