#pragma once
// A triangle mesh with an object id and a semantic class per triangle: the scene
// representation shared by the simulator (ray casting), metrics (ground-truth distance)
// and reports (overlays). Coordinates in the world frame W, metres.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace orthosonar {

// Semantic classes (SPEC §10). Order is part of the fixture/label format: append only.
enum class SemanticClass : uint8_t {
  kNone = 0,      // no hit / water
  kSeafloor = 1,
  kPiling = 2,
  kDock = 3,
  kSeawall = 4,
  kHull = 5,
  kBoat = 6,
  kAircraft = 7,
  kOther = 8,
};
inline constexpr int kSemanticClassCount = 9;
const char* semantic_class_name(SemanticClass c);

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;      // indices into vertices
  std::vector<uint32_t> object_id;             // per triangle
  std::vector<SemanticClass> semantic;         // per triangle

  size_t triangle_count() const { return triangles.size(); }
  // Appends another mesh (its vertex indices shifted).
  void append(const TriangleMesh& other);
  // True when every index is in range and the per-triangle arrays match in size.
  bool valid() const;
};

}  // namespace orthosonar
