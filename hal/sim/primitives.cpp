#include "hal/sim/primitives.hpp"

#include <cmath>
#include <numbers>

namespace orthosonar::sim {

int MeshBuilder::vertex(const Vec3& p) {
  m_.vertices.push_back(p.cast<float>());
  return static_cast<int>(m_.vertices.size()) - 1;
}

void MeshBuilder::triangle(int a, int b, int c, Label l) {
  m_.triangles.emplace_back(a, b, c);
  m_.object_id.push_back(l.object_id);
  m_.semantic.push_back(l.semantic);
}

void MeshBuilder::quad(int a, int b, int c, int d, Label l) {
  triangle(a, b, c, l);
  triangle(a, c, d, l);
}

void MeshBuilder::box(const Vec3& center, const Vec3& size, double yaw, Label l) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  int v[8];
  for (int i = 0; i < 8; ++i) {
    const Vec3 c((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    v[i] = vertex(center + R * c.cwiseProduct(size));
  }
  quad(v[0], v[1], v[3], v[2], l);  // bottom
  quad(v[4], v[6], v[7], v[5], l);  // top
  quad(v[0], v[4], v[5], v[1], l);
  quad(v[2], v[3], v[7], v[6], l);
  quad(v[0], v[2], v[6], v[4], l);
  quad(v[1], v[5], v[7], v[3], l);
}

void MeshBuilder::cylinder(const Vec3& a, const Vec3& b, double radius, int segments, Label l) {
  const Vec3 axis = (b - a).normalized();
  const Vec3 helper = std::abs(axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  const Vec3 u = axis.cross(helper).normalized();
  const Vec3 w = axis.cross(u);
  std::vector<std::vector<Vec3>> rings(2);
  for (int i = 0; i < segments; ++i) {
    const double t = 2.0 * std::numbers::pi * i / segments;
    const Vec3 off = radius * (std::cos(t) * u + std::sin(t) * w);
    rings[0].push_back(a + off);
    rings[1].push_back(b + off);
  }
  loft(rings, true, true, l);
}

void MeshBuilder::loft(const std::vector<std::vector<Vec3>>& rings, bool closed, bool caps, Label l) {
  if (rings.empty()) return;
  const size_t n = rings[0].size();
  std::vector<std::vector<int>> idx(rings.size());
  for (size_t r = 0; r < rings.size(); ++r) {
    for (const auto& p : rings[r]) idx[r].push_back(vertex(p));
  }
  const size_t segs = closed ? n : n - 1;
  for (size_t r = 0; r + 1 < rings.size(); ++r) {
    for (size_t i = 0; i < segs; ++i) {
      const size_t j = (i + 1) % n;
      quad(idx[r][i], idx[r][j], idx[r + 1][j], idx[r + 1][i], l);
    }
  }
  if (!caps) return;
  for (size_t r : {size_t{0}, rings.size() - 1}) {
    Vec3 c = Vec3::Zero();
    for (const auto& p : rings[r]) c += p;
    const int ci = vertex(c / static_cast<double>(n));
    for (size_t i = 0; i < segs; ++i) triangle(ci, idx[r][i], idx[r][(i + 1) % n], l);
  }
}

void MeshBuilder::heightfield(double x0, double y0, int nx, int ny, double cell,
                              const std::function<double(double, double)>& z, Label l) {
  const int first = static_cast<int>(m_.vertices.size());
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + i * cell, y = y0 + j * cell;
      vertex({x, y, z(x, y)});
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = first + j * (nx + 1) + i;
      quad(a, a + 1, a + nx + 2, a + nx + 1, l);
    }
  }
}

void MeshBuilder::corrugated_wall(const Vec2& a, const Vec2& b, double z0, double z1,
                                  double period_m, double depth_m, Label l) {
  const Vec2 d = b - a;
  const double len = d.norm();
  const Vec2 t = d / len;
  const Vec2 n(-t.y(), t.x());
  // Trapezoid profile per period: flat out, slope, flat in, slope.
  const double frac[4] = {0.0, 0.3, 0.5, 0.8};
  const double off[4] = {0.0, 0.0, depth_m, depth_m};
  std::vector<Vec2> plan;
  const int periods = std::max(1, static_cast<int>(std::lround(len / period_m)));
  const double p = len / periods;
  for (int k = 0; k < periods; ++k) {
    for (int q = 0; q < 4; ++q) plan.push_back(a + t * (p * (k + frac[q])) + n * off[q]);
  }
  plan.push_back(b);
  std::vector<std::vector<Vec3>> rings(2);
  for (const auto& q : plan) {
    rings[0].emplace_back(q.x(), q.y(), z0);
    rings[1].emplace_back(q.x(), q.y(), z1);
  }
  loft(rings, false, false, l);
}

void MeshBuilder::sphere(const Vec3& center, double radius, int segments, Label l) {
  std::vector<std::vector<Vec3>> rings;
  for (int i = 1; i < segments; ++i) {
    const double lat = -0.5 * std::numbers::pi + std::numbers::pi * i / segments;
    std::vector<Vec3> ring;
    for (int k = 0; k < 2 * segments; ++k) {
      const double lon = std::numbers::pi * k / segments;
      ring.push_back(center + radius * Vec3(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)));
    }
    rings.push_back(std::move(ring));
  }
  loft(rings, true, true, l);
}

void MeshBuilder::rock(const Vec3& at, double radius, Rng& rng, Label l) {
  // A perturbed octahedron subdivided once (18 vertices worth of facets), flattened a little.
  const Vec3 dirs[6] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  int v[6];
  for (int i = 0; i < 6; ++i) {
    const double s = radius * rng.uniform(0.7, 1.3) * (i >= 4 ? 0.7 : 1.0);
    v[i] = vertex(at + dirs[i] * s);
  }
  const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& f : faces) triangle(v[f[0]], v[f[1]], v[f[2]], l);
}

void transform_tail(TriangleMesh& mesh, size_t first_vertex, const SE3& T) {
  for (size_t i = first_vertex; i < mesh.vertices.size(); ++i) {
    mesh.vertices[i] = (T * mesh.vertices[i].cast<double>()).cast<float>();
  }
}

void hull(MeshBuilder& b, const HullShape& s, const SE3& T, Label l) {
  std::vector<std::vector<Vec3>> rings;
  const double hb_mid = 0.5 * s.beam_m;
  for (int i = 0; i <= s.stations; ++i) {
    const double u = static_cast<double>(i) / s.stations;  // 0 stern .. 1 bow
    double width = 1.0;
    if (u > s.bow_start_fraction) {
      const double q = (u - s.bow_start_fraction) / (1.0 - s.bow_start_fraction);
      width = 1.0 - q * q;
    } else if (u < 0.25) {
      const double q = (0.25 - u) / 0.25;
      width = 1.0 - (1.0 - s.stern_width_fraction) * q * q;
    }
    const double hb = std::max(0.04, hb_mid * width);
    // The keel rises a little at the stern (run) and the bow keeps its depth (or rams forward).
    const double draft = s.draft_m * (u < 0.15 ? 0.6 + 0.4 * u / 0.15 : 1.0);
    std::vector<Vec3> ring;
    for (int k = 0; k <= s.section_points; ++k) {
      const double a = -0.5 * std::numbers::pi + std::numbers::pi * k / s.section_points;
      const double sa = std::sin(a), ca = std::cos(a);
      const double e = 2.0 / s.fullness;
      const double y = hb * (sa < 0 ? -1.0 : 1.0) * std::pow(std::abs(sa), e);
      const double z = -draft * std::pow(std::abs(ca), e);
      // Ram/raked bow: the lower stem reaches forward of the waterline stem.
      const double x = -0.5 * s.length_m + u * s.length_m + (u > 0.98 ? s.bow_rake_m * std::abs(ca) : 0.0);
      ring.emplace_back(x, y, z);
    }
    // Topsides up to the deck edge, then across the deck (closing the ring).
    ring.insert(ring.begin(), Vec3(ring.front().x(), -hb, s.freeboard_m));
    ring.emplace_back(ring.back().x(), hb, s.freeboard_m);
    rings.push_back(std::move(ring));
  }
  TriangleMesh local;
  MeshBuilder lb(local);
  lb.loft(rings, true, true, l);
  transform_tail(local, 0, T);
  std::vector<int> map(local.vertices.size());
  for (size_t i = 0; i < local.vertices.size(); ++i) map[i] = b.vertex(local.vertices[i].cast<double>());
  for (size_t t = 0; t < local.triangles.size(); ++t) {
    const auto& tri = local.triangles[t];
    b.triangle(map[static_cast<size_t>(tri[0])], map[static_cast<size_t>(tri[1])], map[static_cast<size_t>(tri[2])], l);
  }
}

std::function<double(double, double)> seafloor_relief(double depth_m, double relief_m, uint64_t seed) {
  Rng rng(derive_seed(seed, 0x5EAF100Dull));
  struct Wave { double kx, ky, phase, amp; };
  std::vector<Wave> waves;
  for (int i = 0; i < 6; ++i) {
    const double wavelength = rng.uniform(12.0, 60.0);
    const double dir = rng.uniform(0.0, 2.0 * std::numbers::pi);
    const double k = 2.0 * std::numbers::pi / wavelength;
    waves.push_back({k * std::cos(dir), k * std::sin(dir), rng.uniform(0.0, 2.0 * std::numbers::pi),
                     relief_m * rng.uniform(0.3, 1.0) / 3.0});
  }
  return [depth_m, waves](double x, double y) {
    double z = -depth_m;
    for (const auto& w : waves) z += w.amp * std::sin(w.kx * x + w.ky * y + w.phase);
    return z;
  };
}

}  // namespace orthosonar::sim
