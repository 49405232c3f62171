#pragma once
// Map files for <out>/<system>/: the cloud as PCD (binary, fields x y z float; written and
// read through pcl::io) and PLY (binary little-endian; the one PLY reader and writer in
// hal/sim/mesh_io.hpp), and OctoMap occupancy (.bt) with every point inserted as an
// occupied cell. Byte-for-byte deterministic for a given cloud. Errors name the path and
// the field at fault; no header count is trusted beyond what the file's bytes can hold
// (replay/outputs/pcd_header.hpp, hal/sim/ply_header.hpp). No PCL types here: only
// pcd_io.cpp includes PCL.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/result.hpp"

namespace orthosonar::outputs {

Status write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points);
Status write_ply(const std::string& path, const std::vector<Eigen::Vector3f>& points);
// OctoMap's keys are 16 bits: it holds coordinates within +-32768 x resolution_m (+-3277 m at
// 0.1 m). Points outside (or not finite) cannot be inserted; their number is returned in
// `outside_key_range` (when given) so the caller can report them instead of losing them
// silently (run outputs: summary.json "octomap_points_outside_key_range").
Status write_octomap(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                     double resolution_m = 0.1, size_t* outside_key_range = nullptr);

// A PCD with any number of float fields per point (`values` row-major, names.size() per
// point), ASCII (PCL's formatting, 8 significant digits) or binary. For clouds that carry
// more than x y z (the fused points of `orthosonar fuse`).
enum class PcdEncoding { kAscii, kBinary };
Status write_pcd_fields(const std::string& path, const std::vector<std::string>& names,
                        const std::vector<float>& values, PcdEncoding encoding);

// Reads the x y z of a .pcd (pcl::io, any DATA encoding, float x y z required) or a .ply
// (sim::read_ply_points), picked by extension.
Result<std::vector<Eigen::Vector3f>> read_cloud(const std::string& path);
Result<std::vector<Eigen::Vector3f>> read_pcd(const std::string& path);

}  // namespace orthosonar::outputs
