#pragma once
// Triangle mesh and point files: the one reader and the one writer per format, shared
// by every caller (the simulator's scene files, --mesh, scene_mesh.ply, map.ply, the
// report). PLY (ascii and binary little/big endian), OBJ, STL (ascii and binary). PLY
// faces may carry "object_id" and "semantic" properties (written by write_mesh_ply) so
// a labelled mesh survives a round trip; other formats load with object id 1 and
// SemanticClass::kOther unless the caller relabels them.
//
// Hand-written, not PCL or VTK (whose loaders allocate whatever a header claims and drop
// per-face labels), and bounded: no count read from a file is trusted beyond what the
// file's bytes can hold (hal/sim/ply_header.hpp for PLY; STL's triangle count against
// the file size; OBJ indices against the vertices read so far). A broken file is an
// Error naming the file and the line, element or field at fault, never a hang, a crash
// or a giant allocation.
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/mesh.hpp"
#include "core/result.hpp"

namespace orthosonar::sim {

// Picks the reader by extension (.ply, .obj, .stl; case-insensitive). Polygons are fanned
// into triangles.
Result<TriangleMesh> read_mesh(const std::string& path);
Result<TriangleMesh> read_mesh_ply(const std::string& path);
Result<TriangleMesh> read_mesh_obj(const std::string& path);
Result<TriangleMesh> read_mesh_stl(const std::string& path);

// Binary little-endian PLY with float vertices and per-face object_id (uint) and
// semantic (uchar). Deterministic bytes for a given mesh.
Status write_mesh_ply(const TriangleMesh& mesh, const std::string& path);
// The same PLY writer and reader on bytes in memory (a scene mesh attached to a fixture);
// `name` stands for the file in errors. encode_mesh_ply gives write_mesh_ply's bytes.
std::string encode_mesh_ply(const TriangleMesh& mesh);
Result<TriangleMesh> decode_mesh_ply(std::string_view bytes, const std::string& name);
// Wavefront OBJ and binary STL writers (no labels), for interchange and tests.
Status write_mesh_obj(const TriangleMesh& mesh, const std::string& path);
Status write_mesh_stl(const TriangleMesh& mesh, const std::string& path, bool binary = true);

// A point cloud as PLY (map.ply): binary little-endian, one vertex element with float
// x y z and nothing else. Deterministic bytes for a given cloud.
Status write_ply_points(const std::vector<Eigen::Vector3f>& points, const std::string& path);
// The same with per-point float properties after x y z (e.g. a distance to a mesh), one
// value per point each, and a header comment. An Error if a property's count or name is bad.
struct PlyScalar {
  std::string name;           // [A-Za-z0-9_]+, not x, y or z
  std::vector<float> values;  // one per point
};
Status write_ply_points(const std::vector<Eigen::Vector3f>& points, const std::vector<PlyScalar>& scalars,
                        const std::string& comment, const std::string& path);
// The vertex positions of any PLY file (extra vertex properties and other elements are
// read and skipped) through the same parser as read_mesh_ply.
Result<std::vector<Eigen::Vector3f>> read_ply_points(const std::string& path);

}  // namespace orthosonar::sim
