#include "reports/synthetic_run.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "core/random.hpp"
#include "hal/sim/mesh_io.hpp"
#include "replay/outputs/map_writers.hpp"
#include "replay/outputs/ping_pair_io.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::reports {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kSeafloorZ = -8.0;
constexpr double kPilingRadius = 0.3;

Eigen::Vector2d piling_xy(int i) { return {-8.0 + 4.0 * (i % 5), i < 5 ? -3.0 : 3.0}; }

void add_box(TriangleMesh& m, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, SemanticClass cls, uint32_t id) {
  const int base = static_cast<int>(m.vertices.size());
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(base + q[0], base + q[1], base + q[2]);
    m.triangles.emplace_back(base + q[0], base + q[2], base + q[3]);
    for (int t = 0; t < 2; ++t) {
      m.semantic.push_back(cls);
      m.object_id.push_back(id);
    }
  }
}

TriangleMesh scene_mesh() {
  TriangleMesh m;
  // Seafloor: a 60 m square, 4x4 quads.
  const int n = 4;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.vertices.emplace_back(static_cast<float>(-30.0 + 15.0 * i), static_cast<float>(-30.0 + 15.0 * j),
                              static_cast<float>(kSeafloorZ));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      m.triangles.emplace_back(a, a + 1, a + n + 2);
      m.triangles.emplace_back(a, a + n + 2, a + n + 1);
      for (int t = 0; t < 2; ++t) {
        m.semantic.push_back(SemanticClass::kSeafloor);
        m.object_id.push_back(0);
      }
    }
  // Pilings: 16-sided cylinders from the seafloor to above the surface.
  for (int p = 0; p < 10; ++p) {
    const Eigen::Vector2d c = piling_xy(p);
    const int base = static_cast<int>(m.vertices.size());
    const int sides = 16;
    for (int s = 0; s < sides; ++s) {
      const double a = 2.0 * std::numbers::pi * s / sides;
      const auto x = static_cast<float>(c.x() + kPilingRadius * std::cos(a));
      const auto y = static_cast<float>(c.y() + kPilingRadius * std::sin(a));
      m.vertices.emplace_back(x, y, static_cast<float>(kSeafloorZ));
      m.vertices.emplace_back(x, y, 0.5f);
    }
    for (int s = 0; s < sides; ++s) {
      const int a = base + 2 * s, b = base + 2 * ((s + 1) % sides);
      m.triangles.emplace_back(a, b, b + 1);
      m.triangles.emplace_back(a, b + 1, a + 1);
      for (int t = 0; t < 2; ++t) {
        m.semantic.push_back(SemanticClass::kPiling);
        m.object_id.push_back(static_cast<uint32_t>(1 + p));
      }
    }
  }
  add_box(m, {-10.0f, 3.6f, -0.4f}, {10.0f, 5.6f, 0.3f}, SemanticClass::kDock, 20);
  return m;
}

// A loop around the piling rows at 2.5 m depth, 0.4 m/s, one pose per second.
Trajectory truth_loop() {
  Trajectory t;
  const double a = 13.0, b = 7.0;
  const int n = 160;
  for (int i = 0; i <= n; ++i) {
    const double s = 2.0 * std::numbers::pi * i / n;
    TumPose p;
    p.t_s = i;
    p.position = {a * std::cos(s), b * std::sin(s), -2.5};
    const double yaw = std::atan2(b * std::cos(s), -a * std::sin(s));
    p.q_xyzw = {0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)};
    t.push_back(p);
  }
  return t;
}

Status write_json(const fs::path& p, const json& j) {
  std::ofstream out(p);
  out << j.dump(2) << "\n";
  if (!out) return Error{"cannot write '" + p.string() + "'"};
  return Status::Ok();
}

}  // namespace

Status write_synthetic_run(const std::string& dir, const SyntheticRunConfig& config) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Error{"cannot create '" + dir + "': " + ec.message()};
  const fs::path root(dir);
  Rng rng(derive_seed(config.seed, 0x5e9u));

  if (config.with_mesh)
    if (auto s = sim::write_mesh_ply(scene_mesh(), (root / "scene_mesh.ply").string()); !s) return s;
  const Trajectory truth = truth_loop();
  Trajectory dr = truth, slam = truth;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double f = static_cast<double>(i) / static_cast<double>(truth.size());
    dr[i].position += Eigen::Vector3d(1.5 * f * f * 4.0, -2.0 * f, 0.0);
    slam[i].position += Eigen::Vector3d(0.15 * std::sin(6.0 * f), 0.1 * std::cos(5.0 * f) - 0.1, 0.0);
  }
  if (auto s = write_tum((root / "traj_truth.tum").string(), truth); !s) return s;
  if (auto s = write_tum((root / "traj_dr.tum").string(), dr); !s) return s;
  if (auto s = write_tum((root / "traj_slam.tum").string(), slam); !s) return s;

  json digest = {{"overall", "0"}, {"outputs", json::object()}};
  const std::vector<std::string> systems = {"fusion", "submap", "inference"};
  for (size_t si = 0; si < systems.size(); ++si) {
    // Denser maps for the later systems (the paper's ordering of coverage).
    const int per_piling = config.points_per_piling * static_cast<int>(si + 1);
    std::vector<Eigen::Vector3f> map;
    for (int p = 0; p < 10; ++p) {
      const Eigen::Vector2d c = piling_xy(p);
      const double facing = std::atan2(-c.y(), -c.x());  // the side seen from the loop's inside
      for (int k = 0; k < per_piling; ++k) {
        const double a = facing + rng.uniform(-1.8, 1.8);
        const double r = kPilingRadius + 0.03 * rng.normal();
        const double z = rng.uniform(kSeafloorZ + 0.5, 0.2);
        if (rng.uniform() < config.drop_fraction) continue;
        map.emplace_back(static_cast<float>(c.x() + r * std::cos(a) + config.map_shift_m),
                         static_cast<float>(c.y() + r * std::sin(a)), static_cast<float>(z));
      }
    }
    for (int k = 0; k < per_piling * 3; ++k) {  // seafloor returns and the dock's underside
      const bool dock = k % 3 == 0;
      const double x = rng.uniform(-10.0, 10.0), y = dock ? rng.uniform(3.6, 5.6) : rng.uniform(-6.0, 6.0);
      const double z = dock ? -0.4 + 0.03 * rng.normal() : kSeafloorZ + 0.05 * rng.normal();
      if (rng.uniform() < config.drop_fraction) continue;
      map.emplace_back(static_cast<float>(x + config.map_shift_m), static_cast<float>(y), static_cast<float>(z));
    }
    fs::create_directories(root / systems[si], ec);
    if (auto s = outputs::write_ply((root / systems[si] / "map.ply").string(), map); !s) return s;
    const json metrics = {{"system", systems[si]},
                          {"coverage_voxels", static_cast<double>(map.size()) * 0.8},
                          {"mae_m", 0.05 + 0.01 * static_cast<double>(si)},
                          {"rmse_m", 0.08 + 0.01 * static_cast<double>(si)},
                          {"ate_dr_m", 2.1},
                          {"ate_slam_m", 0.14},
                          {"runtime", {{"fusion_pair", {{"mean_ms", 1.5}, {"sd_ms", 0.2}, {"count", 160}}},
                                       {"slam_update", {{"mean_ms", 12.0}, {"sd_ms", 3.0}, {"count", 40}}}}},
                          {"counts", {{"points", map.size()}}}};
    if (auto s = write_json(root / systems[si] / "metrics.json", metrics); !s) return s;
    digest["outputs"][systems[si] + "/map"] = std::string(64, static_cast<char>('a' + si));
  }
  const json summary = {{"fixture", {{"scene", "synthetic_pilings"}, {"seed", config.seed}, {"duration_s", 160.0},
                                     {"counts", {{"sonar_h", 1600}, {"sonar_v", 1600}, {"dvl", 8000}}}}},
                        {"software_version", "synthetic"},
                        {"config", {{"fusion", {{"cfar_pfa", 0.1}, {"min_intensity", 65}}}}},
                        {"counts", {{"pairs", 1600}, {"unpaired", 3}}}};
  if (auto s = write_json(root / "summary.json", summary); !s) return s;
  digest["overall"] = std::string(64, 'f');
  if (auto s = write_json(root / "digest.json", digest); !s) return s;

  if (config.with_ping_pair) {
    // A wall 8 m ahead across both fans: an arc on each image, detections on it, and the
    // fused points where the two apertures share it.
    auto ping = [](SonarMount mount, uint32_t id) {
      SonarPing p;
      p.mount = mount;
      p.device_id = id;
      p.stamp = Time::from_seconds(12.5);
      p.range_resolution_m = 0.1;
      p.rows = 120;
      p.cols = 64;
      for (int c = 0; c < p.cols; ++c) p.bearings_rad.push_back((-65.0 + 130.0 * c / (p.cols - 1)) * std::numbers::pi / 180.0);
      p.image.assign(static_cast<size_t>(p.rows) * p.cols, 12);
      for (int c = 0; c < p.cols; ++c) p.image[static_cast<size_t>(79) * p.cols + static_cast<size_t>(c)] = 200;
      return p;
    };
    const SonarPing h = ping(SonarMount::kHorizontal, 101), v = ping(SonarMount::kVertical, 102);
    perception::FusionResult fused;
    for (int c = 0; c < h.cols; ++c) fused.detections_h.push_back({79, c, 200.0f});
    for (int c = 27; c <= 36; ++c) fused.detections_v.push_back({79, c, 200.0f});
    for (int c = 28; c <= 35; c += 7) {
      perception::FusedPoint f;
      f.range_m = 8.0f;
      f.bearing_rad = static_cast<float>(h.bearings_rad[static_cast<size_t>(c)]);
      f.elevation_rad = static_cast<float>(v.bearings_rad[static_cast<size_t>(c)]);
      f.confidence = 0.8f;
      fused.points.push_back(f);
    }
    if (auto s = outputs::write_ping_pair((root / "ping_pair").string(), h, v, fused, 10.0); !s) return s;
  }
  if (config.with_grid) {
    json cells = json::array();
    for (const auto& sys : systems)
      for (double rot : {30.0, 60.0, 90.0})
        for (double dist : {1.0, 2.0, 3.0, 4.0, 5.0}) {
          const double base = sys == "fusion" ? 4000 : sys == "inference" ? 9000 : 15000;
          cells.push_back({{"system", sys}, {"distance_m", dist}, {"rotation_deg", rot},
                           {"coverage_voxels", std::round(base / (0.6 + 0.2 * dist) * (1.0 + rot / 300.0))},
                           {"mae_m", 0.05 + 0.004 * dist}, {"rmse_m", 0.08 + 0.005 * dist}, {"ate_slam_m", 0.2}});
        }
    if (auto s = write_json(root / "grid.json", {{"scene", "synthetic_pilings"}, {"cells", cells}}); !s) return s;
  }
  return Status::Ok();
}

}  // namespace orthosonar::reports
