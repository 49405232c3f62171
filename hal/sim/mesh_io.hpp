#pragma once
// Triangle mesh files: PLY (ascii and binary little/big endian), OBJ, STL (ascii and
// binary). PLY faces may carry "object_id" and "semantic" properties (written by
// write_mesh_ply) so a labelled mesh survives a round trip; other formats load with
// object id 1 and SemanticClass::kOther unless the caller relabels them.
#include <string>

#include "core/mesh.hpp"
#include "core/result.hpp"

namespace orthosonar::sim {

// Picks the reader by extension (.ply, .obj, .stl; case-insensitive). Polygons are fanned
// into triangles. Errors name the file and the line or byte offset at fault.
Result<TriangleMesh> read_mesh(const std::string& path);
Result<TriangleMesh> read_mesh_ply(const std::string& path);
Result<TriangleMesh> read_mesh_obj(const std::string& path);
Result<TriangleMesh> read_mesh_stl(const std::string& path);

// Binary little-endian PLY with float vertices and per-face object_id (uint) and
// semantic (uchar). Deterministic bytes for a given mesh.
Status write_mesh_ply(const TriangleMesh& mesh, const std::string& path);
// Wavefront OBJ and binary STL writers (no labels), for interchange and tests.
Status write_mesh_obj(const TriangleMesh& mesh, const std::string& path);
Status write_mesh_stl(const TriangleMesh& mesh, const std::string& path, bool binary = true);

}  // namespace orthosonar::sim
