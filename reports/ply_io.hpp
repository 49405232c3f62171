#pragma once
// A small PLY reader and writer for the report: point clouds (x y z plus any extra
// vertex properties, which are skipped) and triangle meshes (a vertex_indices list per
// face, optional per-face "semantic" and "object_id"). ascii and binary_little_endian.
// No PCL: the report reads what replay/outputs writes and nothing more.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh.hpp"
#include "core/result.hpp"

namespace orthosonar::reports {

// Vertices and faces of a PLY file. Faces with more than three corners are fanned into
// triangles; `semantic` and `object_id` are filled per triangle (kNone / 0 when absent).
Result<TriangleMesh> read_ply(const std::string& path);

// Only the vertex positions (a map cloud).
Result<std::vector<Eigen::Vector3f>> read_ply_points(const std::string& path);

// Binary little-endian writers (used by tests to synthesise run directories).
Status write_ply_points(const std::string& path, const std::vector<Eigen::Vector3f>& points);
Status write_ply_mesh(const std::string& path, const TriangleMesh& mesh);

}  // namespace orthosonar::reports
