#include "reports/nearest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace orthosonar::reports {
namespace {

struct Key {
  int64_t x, y, z;
  bool operator==(const Key&) const = default;
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    const auto h = static_cast<uint64_t>(k.x) * 73856093ull ^ static_cast<uint64_t>(k.y) * 19349663ull ^
                   static_cast<uint64_t>(k.z) * 83492791ull;
    return static_cast<size_t>(h);
  }
};

Key key_of(const Eigen::Vector3f& p, double cell) {
  return {static_cast<int64_t>(std::floor(p.x() / cell)), static_cast<int64_t>(std::floor(p.y() / cell)),
          static_cast<int64_t>(std::floor(p.z() / cell))};
}

}  // namespace

std::vector<float> nearest_distances(const std::vector<Eigen::Vector3f>& query,
                                     const std::vector<Eigen::Vector3f>& reference, double max_distance_m) {
  const float cap = static_cast<float>(max_distance_m);
  std::vector<float> out(query.size(), cap);
  if (reference.empty() || max_distance_m <= 0.0) return out;
  // With cells as wide as the cap, any neighbour closer than the cap lies in the 27
  // cells around the query's own.
  const double cell = max_distance_m;
  std::unordered_map<Key, std::vector<uint32_t>, KeyHash> grid;
  for (size_t i = 0; i < reference.size(); ++i) grid[key_of(reference[i], cell)].push_back(static_cast<uint32_t>(i));
  for (size_t q = 0; q < query.size(); ++q) {
    const Key k = key_of(query[q], cell);
    float best2 = cap * cap;
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (uint32_t r : it->second) best2 = std::min(best2, (reference[r] - query[q]).squaredNorm());
        }
    out[q] = std::min(cap, std::sqrt(best2));
  }
  return out;
}

}  // namespace orthosonar::reports
