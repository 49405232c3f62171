#pragma once
// Minimum-cost assignment for rectangular cost matrices (SPEC §4.6): the Hungarian
// method (Jonker-Volgenant style shortest augmenting paths with potentials), exact.
#include <Eigen/Core>
#include <vector>

namespace orthosonar::perception {

// For a rows x cols matrix of finite costs, assigns min(rows, cols) pairs, each row and
// column used at most once, with minimum total cost. Returns, per row, its column or -1
// when unassigned (only possible when rows > cols). Deterministic: ties resolve to the
// same answer on every run. An empty matrix gives an empty (or all -1) result.
std::vector<int> solve_assignment(const Eigen::MatrixXd& cost);

// Total cost of an assignment as returned above.
double assignment_cost(const Eigen::MatrixXd& cost, const std::vector<int>& row_to_col);

}  // namespace orthosonar::perception
