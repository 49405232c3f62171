#pragma once
// Exact point-to-triangle-mesh distance through a bounding-volume hierarchy. The tree is
// built by sorting triangle centroids along the longest axis with an index tie-break, so
// the same mesh always gives the same tree and the same answers.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/mesh.hpp"

namespace orthosonar::mapping {

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection §5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);
  bool empty() const { return tris_.empty(); }
  // Distance (m) from p to the nearest triangle; +inf for an empty mesh.
  double distance(const Eigen::Vector3d& p) const;
  // The same with the nearest triangle's unit normal (zero for a degenerate triangle or an
  // empty mesh); of equally near triangles, the first the search meets (deterministic).
  struct Nearest {
    double distance = 0.0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  };
  Nearest nearest(const Eigen::Vector3d& p) const;
  // The same by testing every triangle (a test oracle).
  double distance_brute_force(const Eigen::Vector3d& p) const;

 private:
  struct Tri {
    Eigen::Vector3d a, b, c;
  };
  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    int32_t left = -1;   // child node index, or -1 for a leaf
    int32_t right = -1;
    int32_t first = 0;   // leaf: range [first, first + count) in tris_
    int32_t count = 0;
  };
  int32_t build(int32_t first, int32_t count);
  static double box_distance_sq(const Node& n, const Eigen::Vector3d& p);

  std::vector<Tri> tris_;
  std::vector<Node> nodes_;
};

}  // namespace orthosonar::mapping
