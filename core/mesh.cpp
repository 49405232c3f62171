#include "core/mesh.hpp"

namespace orthosonar {

const char* semantic_class_name(SemanticClass c) {
  switch (c) {
    case SemanticClass::kNone: return "none";
    case SemanticClass::kSeafloor: return "seafloor";
    case SemanticClass::kPiling: return "piling";
    case SemanticClass::kDock: return "dock";
    case SemanticClass::kSeawall: return "seawall";
    case SemanticClass::kHull: return "hull";
    case SemanticClass::kBoat: return "boat";
    case SemanticClass::kAircraft: return "aircraft";
    case SemanticClass::kOther: return "other";
  }
  return "?";
}

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles) triangles.push_back(t.array() + offset);
  object_id.insert(object_id.end(), other.object_id.begin(), other.object_id.end());
  semantic.insert(semantic.end(), other.semantic.begin(), other.semantic.end());
}

bool TriangleMesh::valid() const {
  if (object_id.size() != triangles.size() || semantic.size() != triangles.size()) return false;
  const int n = static_cast<int>(vertices.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || t[k] >= n) return false;
  return true;
}

}  // namespace orthosonar
