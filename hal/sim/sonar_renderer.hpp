#pragma once
// Sonar image formation by ray casting (SPEC §10). For each beam, rays stratified across
// the aperture (elevation_samples) and across the beam width (beam_samples) are cast with
// Embree; the first hit at range r with incidence angle i adds
//   reflectivity(class) * cos(i)^k * aperture_pattern(elevation) * r^-p
// to its range bin (shadows follow from first hits). Then per-pixel speckle (seeded per
// frame by derive_seed(seed, stream, ping_id), so any frame regenerates alone), an additive
// noise floor, time-varied gain, gain, gamma and 8-bit quantisation.
//
// Sonar frame S: x forward, y left, z up; beams measure the angle towards +y ("bearing"),
// the aperture spans the angle towards +z. The vertical sonar is the same device rolled
// +90 deg about x, so pass T_W_S = T_W_V * T_V_v and its beams measure elevation (up +).
//
// Thread safety: render() and cast() are const and may run concurrently.
#include <cstdint>
#include <memory>
#include <optional>

#include "core/events.hpp"
#include "core/mesh.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::sim {

struct SonarRender {
  SonarPing ping;
  SonarLabels labels;  // filled when labels are requested, else empty
};

class SonarRenderer {
 public:
  // Builds the Embree scene (one build thread: deterministic BVH). The mesh is copied.
  SonarRenderer(const TriangleMesh& mesh, const SonarModelConfig& config, Resolution resolution,
                uint64_t seed);
  ~SonarRenderer();
  SonarRenderer(const SonarRenderer&) = delete;
  SonarRenderer& operator=(const SonarRenderer&) = delete;

  SonarRender render(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                     bool with_labels = false) const;

  // Distance along a unit direction to the first surface within max_m, if any.
  std::optional<double> cast(const Vec3& origin_W, const Vec3& direction_W, double max_m) const;

  // The bearing table of the pings (radians, quantised to 1/100 degree like the device).
  const std::vector<double>& bearings_rad() const;
  const SonarGeometry& geometry() const;
  uint64_t rays_per_ping() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Speckle stream ids for derive_seed (documented so a frame can be regenerated alone).
inline constexpr uint64_t kSpeckleStreamHorizontal = 0x5350454b48ull;  // "SPEKH"
inline constexpr uint64_t kSpeckleStreamVertical = 0x5350454b56ull;    // "SPEKV"

}  // namespace orthosonar::sim
