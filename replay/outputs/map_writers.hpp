#pragma once
// Map writers for <out>/<system>/: the cloud as PCD (binary, fields x y z float) and PLY
// (binary little-endian), and OctoMap occupancy (.bt) with every point inserted as an
// occupied cell. Byte-for-byte deterministic for a given cloud. Errors name the path.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/result.hpp"

namespace orthosonar::outputs {

Status write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points);
Status write_ply(const std::string& path, const std::vector<Eigen::Vector3f>& points);
Status write_octomap(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                     double resolution_m = 0.1);

// Reads a cloud written by write_pcd or write_ply (for tests and tools).
Result<std::vector<Eigen::Vector3f>> read_cloud(const std::string& path);

}  // namespace orthosonar::outputs
