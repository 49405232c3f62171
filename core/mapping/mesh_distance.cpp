#include "core/mapping/mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace orthosonar::mapping {

using Eigen::Vector3d;

Vector3d closest_point_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                                   const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double denom = d1 - d3;
    return denom > 0.0 ? Vector3d(a + (d1 / denom) * ab) : a;
  }
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double denom = d2 - d6;
    return denom > 0.0 ? Vector3d(a + (d2 / denom) * ac) : a;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double denom = (d4 - d3) + (d5 - d6);
    return denom > 0.0 ? Vector3d(b + ((d4 - d3) / denom) * (c - b)) : b;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // Degenerate (zero-area) triangle: the nearest of its three edges' closest points.
    auto seg = [&](const Vector3d& s, const Vector3d& e) {
      const Vector3d d = e - s;
      const double len2 = d.squaredNorm();
      const double u = len2 > 0.0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
      return Vector3d(s + u * d);
    };
    const std::array<Vector3d, 3> q = {seg(a, b), seg(b, c), seg(c, a)};
    int best = 0;
    for (int i = 1; i < 3; ++i)
      if ((q[static_cast<size_t>(i)] - p).squaredNorm() < (q[static_cast<size_t>(best)] - p).squaredNorm()) best = i;
    return q[static_cast<size_t>(best)];
  }
  const double v = vb / sum, w = vc / sum;
  return a + ab * v + ac * w;
}

MeshDistance::MeshDistance(const TriangleMesh& mesh) {
  tris_.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    tris_.push_back({mesh.vertices[static_cast<size_t>(t[0])].cast<double>(),
                     mesh.vertices[static_cast<size_t>(t[1])].cast<double>(),
                     mesh.vertices[static_cast<size_t>(t[2])].cast<double>()});
  }
  if (!tris_.empty()) {
    nodes_.reserve(2 * tris_.size() / 4 + 8);
    build(0, static_cast<int32_t>(tris_.size()));
  }
}

int32_t MeshDistance::build(int32_t first, int32_t count) {
  const auto idx = static_cast<int32_t>(nodes_.size());
  nodes_.push_back({});
  Node n;
  n.lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  n.hi = -n.lo;
  for (int32_t i = first; i < first + count; ++i) {
    const Tri& t = tris_[static_cast<size_t>(i)];
    n.lo = n.lo.cwiseMin(t.a).cwiseMin(t.b).cwiseMin(t.c);
    n.hi = n.hi.cwiseMax(t.a).cwiseMax(t.b).cwiseMax(t.c);
  }
  constexpr int32_t kLeafSize = 4;
  if (count <= kLeafSize) {
    n.first = first;
    n.count = count;
    nodes_[static_cast<size_t>(idx)] = n;
    return idx;
  }
  Eigen::Index axis = 0;
  (n.hi - n.lo).maxCoeff(&axis);
  // Stable sort by centroid along the axis: equal keys keep their (deterministic) order.
  const auto begin = tris_.begin() + first;
  std::stable_sort(begin, begin + count, [axis](const Tri& x, const Tri& y) {
    return (x.a[axis] + x.b[axis] + x.c[axis]) < (y.a[axis] + y.b[axis] + y.c[axis]);
  });
  const int32_t half = count / 2;
  n.left = build(first, half);
  n.right = build(first + half, count - half);
  nodes_[static_cast<size_t>(idx)] = n;
  return idx;
}

double MeshDistance::box_distance_sq(const Node& n, const Vector3d& p) {
  const Vector3d d = (n.lo - p).cwiseMax(p - n.hi).cwiseMax(Vector3d::Zero());
  return d.squaredNorm();
}

double MeshDistance::distance(const Vector3d& p) const { return nearest(p).distance; }

MeshDistance::Nearest MeshDistance::nearest(const Vector3d& p) const {
  if (tris_.empty()) return {std::numeric_limits<double>::infinity(), Vector3d::Zero()};
  double best = std::numeric_limits<double>::infinity();
  const Tri* best_tri = nullptr;
  std::vector<int32_t> stack;
  stack.reserve(64);
  stack.push_back(0);
  while (!stack.empty()) {
    const Node& n = nodes_[static_cast<size_t>(stack.back())];
    stack.pop_back();
    if (box_distance_sq(n, p) >= best) continue;
    if (n.left < 0) {
      for (int32_t i = n.first; i < n.first + n.count; ++i) {
        const Tri& t = tris_[static_cast<size_t>(i)];
        const double d = (closest_point_on_triangle(p, t.a, t.b, t.c) - p).squaredNorm();
        if (d < best) {
          best = d;
          best_tri = &t;
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last).
    const Node& l = nodes_[static_cast<size_t>(n.left)];
    const Node& r = nodes_[static_cast<size_t>(n.right)];
    if (box_distance_sq(l, p) <= box_distance_sq(r, p)) {
      stack.push_back(n.right);
      stack.push_back(n.left);
    } else {
      stack.push_back(n.left);
      stack.push_back(n.right);
    }
  }
  Vector3d normal = Vector3d::Zero();
  if (best_tri) {
    const Vector3d c = (best_tri->b - best_tri->a).cross(best_tri->c - best_tri->a);
    if (c.norm() > 0.0) normal = c.normalized();
  }
  return {std::sqrt(best), normal};
}

double MeshDistance::distance_brute_force(const Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : tris_) best = std::min(best, (closest_point_on_triangle(p, t.a, t.b, t.c) - p).squaredNorm());
  return std::sqrt(best);
}

}  // namespace orthosonar::mapping
