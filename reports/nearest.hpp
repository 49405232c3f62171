#pragma once
// Cloud-to-cloud distances for the difference view: for every query point, the distance
// to its nearest neighbour in a reference cloud, found through a uniform hash grid.
#include <vector>

#include <Eigen/Core>

namespace orthosonar::reports {

// Distance (m) from each query point to the nearest reference point, exact below
// `max_distance_m` and clamped to it above (the colour scale saturates there anyway).
// An empty reference gives max_distance_m everywhere. Deterministic (lookups only).
std::vector<float> nearest_distances(const std::vector<Eigen::Vector3f>& query,
                                     const std::vector<Eigen::Vector3f>& reference, double max_distance_m);

}  // namespace orthosonar::reports
