#pragma once
// Mesh building blocks for the built-in scenes. Every function appends labelled triangles
// (object id, semantic class) to a TriangleMesh; winding is not significant (the renderer
// uses |cos| of the incidence angle). All lengths in metres, angles in radians, W frame.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/geometry.hpp"
#include "core/mesh.hpp"
#include "core/random.hpp"

namespace orthosonar::sim {

struct Label {
  uint32_t object_id = 0;
  SemanticClass semantic = SemanticClass::kOther;
};

class MeshBuilder {
 public:
  explicit MeshBuilder(TriangleMesh& mesh) : m_(mesh) {}
  int vertex(const Vec3& p);
  void triangle(int a, int b, int c, Label l);
  void quad(int a, int b, int c, int d, Label l);
  // An oriented box: centre, size (x, y, z), yaw about z.
  void box(const Vec3& center, const Vec3& size, double yaw, Label l);
  // A cylinder between two points (capped).
  void cylinder(const Vec3& a, const Vec3& b, double radius, int segments, Label l);
  // A surface through rings of equal size: ring i joins ring i+1; closed rings join their
  // last point to the first; caps fan the first and last rings from their centroids.
  void loft(const std::vector<std::vector<Vec3>>& rings, bool closed, bool caps, Label l);
  // A height field z(x, y) on a grid of nx x ny cells of size cell starting at (x0, y0).
  void heightfield(double x0, double y0, int nx, int ny, double cell,
                   const std::function<double(double, double)>& z, Label l);
  // A sheet-pile (trapezoidal corrugated) wall from a to b (plan), z from z0 to z1.
  void corrugated_wall(const Vec2& a, const Vec2& b, double z0, double z1, double period_m,
                       double depth_m, Label l);
  // A UV sphere (rings of latitude, closed at the poles by caps).
  void sphere(const Vec3& center, double radius, int segments, Label l);
  // An irregular rock of about the given radius resting at (x, y, z).
  void rock(const Vec3& at, double radius, Rng& rng, Label l);

 private:
  TriangleMesh& m_;
};

// Applies a rigid transform to the vertices appended since `first_vertex`.
void transform_tail(TriangleMesh& mesh, size_t first_vertex, const SE3& T);

// A ship-like hull along +x centred at the origin, waterline at z = 0: half-beam and keel
// depth vary along the length; sections are superellipses (fullness 2 = round, larger =
// boxier). Deck at z = freeboard. bow_rake_m moves the stem forward at the keel (a ram
// bow when positive).
struct HullShape {
  double length_m = 40.0;
  double beam_m = 9.0;
  double draft_m = 4.0;
  double freeboard_m = 3.0;
  double fullness = 3.0;
  double stern_width_fraction = 0.55;  // half-beam at the transom relative to midship
  double bow_start_fraction = 0.6;     // where the bow taper begins
  double bow_rake_m = 0.0;
  int stations = 40;
  int section_points = 16;
};
void hull(MeshBuilder& b, const HullShape& shape, const SE3& T_W_hull, Label l);

// A smooth seafloor at depth (z = -depth) with gentle relief from the seed.
std::function<double(double, double)> seafloor_relief(double depth_m, double relief_m, uint64_t seed);

}  // namespace orthosonar::sim
