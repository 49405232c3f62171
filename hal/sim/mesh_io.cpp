// The mesh reader dispatch by extension. Each format has one reader and one writer:
// mesh_ply.cpp, mesh_obj.cpp, mesh_stl.cpp.
#include "hal/sim/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace orthosonar::sim {

Result<TriangleMesh> read_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".ply") return read_mesh_ply(path);
  if (ext == ".obj") return read_mesh_obj(path);
  if (ext == ".stl") return read_mesh_stl(path);
  return Error{path + ": unknown mesh extension (expected .ply, .obj or .stl)"};
}

}  // namespace orthosonar::sim
