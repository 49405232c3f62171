// Mapping properties: submaps move rigidly with their keyframe, and the voxel metrics do
// not depend on the order of the points.
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>

#include "core/geometry.hpp"
#include "core/mapping/metrics.hpp"
#include "core/mapping/submap.hpp"

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {
double draw(double lo, double hi) {
  const int k = *rc::gen::inRange(0, 1000001);
  return lo + (hi - lo) * (static_cast<double>(k) / 1000000.0);
}
SE3 any_pose() {
  return se3_from_xyz_rpy(draw(-50, 50), draw(-50, 50), draw(-10, 0), draw(-0.2, 0.2), draw(-0.2, 0.2),
                          draw(-3.1, 3.1));
}
std::vector<Eigen::Vector3f> any_cloud(int n) {
  std::vector<Eigen::Vector3f> c;
  for (int i = 0; i < n; ++i)
    c.emplace_back(static_cast<float>(draw(-20, 20)), static_cast<float>(draw(-20, 20)),
                   static_cast<float>(draw(-5, 5)));
  return c;
}
}  // namespace

TEST_CASE("moving a keyframe moves its submap rigidly", "[property]") {
  rc::prop("distances within a submap are preserved and other submaps do not move", [] {
    SubmapStore s;
    const int n_kf = *rc::gen::inRange(2, 5);
    std::vector<SE3> dr;
    for (int k = 0; k < n_kf; ++k) {
      dr.push_back(any_pose());
      s.begin(k, dr.back());
      const int clouds = *rc::gen::inRange(1, 4);
      for (int c = 0; c < clouds; ++c) RC_ASSERT(s.add(any_pose(), any_cloud(*rc::gen::inRange(1, 20))));
    }
    const int moved = *rc::gen::inRange(0, n_kf);
    const SE3 delta = any_pose();
    std::vector<SE3> poses = dr;
    poses[static_cast<size_t>(moved)] = delta * dr[static_cast<size_t>(moved)];
    const auto before = s.assemble(dr);
    const auto after = s.assemble(poses);
    RC_ASSERT(before.size() == after.size());
    size_t i = 0;
    for (int k = 0; k < n_kf; ++k) {
      for (size_t j = 0; j < s.points_K(k).size(); ++j, ++i) {
        const Eigen::Vector3d b = before[i].cast<double>(), a = after[i].cast<double>();
        if (k == moved) {
          RC_ASSERT((delta * b - a).norm() < 1e-3);
        } else {
          RC_ASSERT(b == a);
        }
      }
    }
  });
}

TEST_CASE("voxel coverage and centroids are invariant to point order", "[property]") {
  rc::prop("a permutation of the points gives the same voxels bit for bit", [] {
    auto pts = any_cloud(*rc::gen::inRange(0, 300));
    // Duplicate some points into shared voxels.
    const size_t n = pts.size();
    for (size_t i = 0; i < n; i += 3) pts.push_back(pts[i] + Eigen::Vector3f(0.01f, 0.0f, 0.0f));
    auto shuffled = pts;
    const auto order = *rc::gen::container<std::vector<int>>(shuffled.size(), rc::gen::arbitrary<int>());
    std::vector<size_t> idx(shuffled.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
      return order[a] != order[b] ? order[a] < order[b] : a < b;
    });
    for (size_t i = 0; i < idx.size(); ++i) shuffled[i] = pts[idx[i]];
    RC_ASSERT(coverage_voxels(pts) == coverage_voxels(shuffled));
    RC_ASSERT(voxel_centroids(pts) == voxel_centroids(shuffled));
    RC_ASSERT(static_cast<int64_t>(voxel_centroids(pts).size()) == coverage_voxels(pts));
  });
}
