#include "core/mapping/systems.hpp"

#include <catch2/catch.hpp>

#include "core/mapping/metrics.hpp"
#include "core/perception/fusion.hpp"

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {

perception::FusionResult cloud(std::vector<Eigen::Vector3f> pts) {
  perception::FusionResult r;
  for (const auto& p : pts) {
    perception::FusedPoint f;
    f.p_V = p;
    r.points.push_back(f);
  }
  return r;
}

PairInput pair_at(Time t, const SE3& T, const perception::FusionResult& f) {
  PairInput p;
  p.stamp = t;
  p.fused = &f;
  p.T_W_V_dr = T;
  return p;
}

}  // namespace

TEST_CASE("submap stores clouds in the keyframe frame by DR", "[unit]") {
  SubmapStore s;
  CHECK_FALSE(s.add(SE3::Identity(), {{1, 0, 0}}));
  const SE3 T_W_K = se3_from_xyz_rpy(10, 0, -2, 0, 0, 0.5);
  s.begin(0, T_W_K);
  const SE3 T_W_V = se3_from_xyz_rpy(11, 1, -2, 0, 0, 0.9);
  REQUIRE(s.add(T_W_V, {{2, 0, 0}}));
  const Eigen::Vector3d expect_K = T_W_K.inverse() * T_W_V * Eigen::Vector3d(2, 0, 0);
  CHECK((s.points_K(0)[0].cast<double>() - expect_K).norm() < 1e-5);
  // With the DR pose as the keyframe pose the map point is where DR put it.
  const auto map = s.assemble({T_W_K});
  CHECK((map[0].cast<double>() - T_W_V * Eigen::Vector3d(2, 0, 0)).norm() < 1e-5);
}

TEST_CASE("fusion mapping keeps only each keyframe's own pair", "[unit]") {
  FusionMapping fm;
  Submapping sm;
  const auto a = cloud({{5, 0, 0}});
  const auto b = cloud({{6, 0, 0}, {6, 1, 0}});
  const auto c = cloud({{7, 0, 0}});
  for (MappingSystem* m : {static_cast<MappingSystem*>(&fm), static_cast<MappingSystem*>(&sm)}) {
    m->on_pair(pair_at(Time::from_ms(0), SE3::Identity(), a));  // before any keyframe
    m->on_keyframe({0, Time::from_ms(200), SE3::Identity()});
    m->on_pair(pair_at(Time::from_ms(200), SE3::Identity(), b));
    m->on_pair(pair_at(Time::from_ms(400), se3_from_xyz_rpy(1, 0, 0, 0, 0, 0), c));
    m->on_keyframe({1, Time::from_ms(600), se3_from_xyz_rpy(2, 0, 0, 0, 0, 0)});
    m->on_pair(pair_at(Time::from_ms(600), se3_from_xyz_rpy(2, 0, 0, 0, 0, 0), a));
  }
  CHECK(fm.map_points_W().size() == 3);
  CHECK(sm.map_points_W().size() == 4);
  CHECK(sm.dropped_pairs() == 1);
  // A loop closure moves keyframe 1 by +1 m in y: its points follow rigidly.
  const std::vector<SE3> moved = {SE3::Identity(), se3_from_xyz_rpy(2, 1, 0, 0, 0, 0)};
  fm.on_poses_updated(moved);
  sm.on_poses_updated(moved);
  const auto fmap = fm.map_points_W();
  CHECK((fmap.back() - Eigen::Vector3f(7, 1, 0)).norm() < 1e-5f);
  const auto smap = sm.map_points_W();
  CHECK((smap[2] - Eigen::Vector3f(8, 0, 0)).norm() < 1e-5f);  // keyframe 0 unmoved
  CHECK((smap[3] - Eigen::Vector3f(7, 1, 0)).norm() < 1e-5f);
  // Other poses (e.g. the true ones) place the same clouds without touching the SLAM map.
  const std::vector<SE3> other = {se3_from_xyz_rpy(0, 0, 0, 0, 0, 1.5707963267948966), se3_from_xyz_rpy(2, -1, 0, 0, 0, 0)};
  const auto fother = fm.map_points_W_with(other);
  const auto sother = sm.map_points_W_with(other);
  REQUIRE(fother.has_value());
  REQUIRE(sother.has_value());
  CHECK(((*fother)[0] - Eigen::Vector3f(0, 6, 0)).norm() < 1e-5f);  // keyframe 0 turned 90 degrees
  CHECK((fother->back() - Eigen::Vector3f(7, -1, 0)).norm() < 1e-5f);
  CHECK(((*sother)[3] - Eigen::Vector3f(7, -1, 0)).norm() < 1e-5f);
  CHECK(fm.map_points_W() == fmap);
  CHECK(sm.map_points_W() == smap);
  CHECK(make_geometric_system("fusion")->name() == "fusion");
  CHECK(make_geometric_system("nope") == nullptr);
}
