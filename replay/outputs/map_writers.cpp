#include "replay/outputs/map_writers.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

#include <octomap/OcTree.h>

namespace orthosonar::outputs {
namespace {

static_assert(std::endian::native == std::endian::little, "writers assume a little-endian host");

Status write_bytes(const std::string& path, const std::string& header,
                   const std::vector<Eigen::Vector3f>& points) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  f << header;
  for (const auto& p : points) {
    float xyz[3] = {p.x(), p.y(), p.z()};
    f.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
  f.flush();
  if (!f) return Error{"write failed for '" + path + "'"};
  return {};
}

}  // namespace

Status write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  std::ostringstream h;
  h << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
    << "TYPE F F F\nCOUNT 1 1 1\nWIDTH " << points.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
    << "POINTS " << points.size() << "\nDATA binary\n";
  return write_bytes(path, h.str(), points);
}

Status write_ply(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment orthosonar map\nelement vertex " << points.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  return write_bytes(path, h.str(), points);
}

Status write_octomap(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                     double resolution_m) {
  octomap::OcTree tree(resolution_m);
  for (const auto& p : points) tree.updateNode(octomap::point3d(p.x(), p.y(), p.z()), true);
  tree.updateInnerOccupancy();
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  if (!tree.writeBinary(f)) return Error{"octomap write failed for '" + path + "'"};
  f.flush();
  if (!f) return Error{"write failed for '" + path + "'"};
  return {};
}

Result<std::vector<Eigen::Vector3f>> read_cloud(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{"cannot open '" + path + "'"};
  std::string line;
  size_t n = 0;
  bool data = false;
  while (std::getline(f, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "POINTS") ls >> n;
    if (key == "element") {
      std::string what;
      ls >> what >> n;
    }
    if (key == "DATA" || key == "end_header") {
      data = true;
      break;
    }
  }
  if (!data) return Error{"'" + path + "': no header end found"};
  std::vector<Eigen::Vector3f> out(n);
  for (size_t i = 0; i < n; ++i) {
    float xyz[3];
    if (!f.read(reinterpret_cast<char*>(xyz), sizeof xyz))
      return Error{"'" + path + "': truncated at point " + std::to_string(i)};
    out[i] = {xyz[0], xyz[1], xyz[2]};
  }
  return out;
}

}  // namespace orthosonar::outputs
