#include <catch2/catch.hpp>

#include "core/perception/assignment.hpp"

using namespace orthosonar::perception;

TEST_CASE("Hungarian solves a square matrix where greedy fails", "[unit]") {
  Eigen::MatrixXd c(3, 3);
  c << 1, 2, 3,
       2, 4, 6,
       3, 6, 9;
  // Greedy row 0 -> col 0 gives 1 + 4 + 9 = 14; the optimum is 3 + 4 + 3 = 10.
  const auto m = solve_assignment(c);
  CHECK(assignment_cost(c, m) == Approx(10.0));
}

TEST_CASE("Hungarian handles tall and wide rectangular matrices", "[unit]") {
  Eigen::MatrixXd wide(2, 4);
  wide << 5, 1, 9, 9,
          5, 2, 9, 0;
  const auto mw = solve_assignment(wide);
  REQUIRE(mw.size() == 2);
  CHECK(mw[0] == 1);
  CHECK(mw[1] == 3);
  const Eigen::MatrixXd tall = wide.transpose();
  const auto mt = solve_assignment(tall);
  REQUIRE(mt.size() == 4);
  CHECK(mt[0] == -1);
  CHECK(mt[1] == 0);
  CHECK(mt[2] == -1);
  CHECK(mt[3] == 1);
}

TEST_CASE("Hungarian on empty and single-cell matrices", "[unit]") {
  CHECK(solve_assignment(Eigen::MatrixXd(0, 3)).empty());
  CHECK(solve_assignment(Eigen::MatrixXd(2, 0)) == std::vector<int>{-1, -1});
  Eigen::MatrixXd one(1, 1);
  one << 3.5;
  CHECK(solve_assignment(one) == std::vector<int>{0});
}
