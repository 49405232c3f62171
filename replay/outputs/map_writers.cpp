#include "replay/outputs/map_writers.hpp"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <filesystem>
#include <fstream>

#include <octomap/OcTree.h>

#include "hal/sim/mesh_io.hpp"

namespace orthosonar::outputs {

Status write_ply(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  return sim::write_ply_points(points, path);
}

Status write_octomap(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                     double resolution_m, size_t* outside_key_range) {
  octomap::OcTree tree(resolution_m);
  size_t outside = 0;
  // coordToKeyChecked casts coordinate / resolution to int before it checks the range:
  // undefined for NaN or beyond int's range (clang's UBSan). Anything beyond twice the key
  // range (+-32768 cells) is outside it anyway; the rest is OctoMap's to decide.
  const double limit = 65536.0 * resolution_m;
  for (const auto& p : points) {
    const bool castable = p.allFinite() && std::abs(p.x()) < limit && std::abs(p.y()) < limit && std::abs(p.z()) < limit;
    const octomap::point3d q(p.x(), p.y(), p.z());
    octomap::OcTreeKey key;
    if (!castable || !tree.coordToKeyChecked(q, key)) {  // updateNode would drop it without a word
      ++outside;
      continue;
    }
    tree.updateNode(key, true);
  }
  if (outside_key_range != nullptr) *outside_key_range = outside;
  tree.updateInnerOccupancy();
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  if (!tree.writeBinary(f)) return Error{"octomap write failed for '" + path + "'"};
  f.flush();
  if (!f) return Error{"write failed for '" + path + "'"};
  return {};
}

Result<std::vector<Eigen::Vector3f>> read_cloud(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".pcd") return read_pcd(path);
  if (ext == ".ply") return sim::read_ply_points(path);
  return Error{path + ": unknown cloud extension (expected .pcd or .ply)"};
}

}  // namespace orthosonar::outputs
