#pragma once
// Sonar image formation by ray casting (SPEC §10, docs/SCENES.md "Image formation"). For
// each beam of the mount's head, rays stratified across the aperture (elevation_samples)
// and across the beam width (beam_samples) are cast with Embree; the first hit at range r
// with incidence angle i adds
//   reflectivity(class) * cos(i)^k * aperture_pattern(elevation)
// to its range bin (shadows follow from first hits). The field profile adds: seafloor hits
// scatter mu cos^2(i) on a relief-perturbed normal times a grain texture (Lambert); each hit
// leaves one-bounce ghosts through the sea surface (and optionally the seabed plane); the
// azimuth beam pattern (main lobe + side lobes) spreads each echo across beams. Then
// spreading r^-p, two-way absorption, per-pixel speckle (seeded per frame by
// derive_seed(seed, stream, ping_id), so any frame regenerates alone), an additive noise
// floor (before the TVG in the field profile), the TVG, gain, gamma and 8-bit quantisation.
//
// Sonar frame S: x forward, y left, z up; beams measure the angle towards +y ("bearing"),
// the aperture spans the angle towards +z. The vertical sonar is the same device rolled
// +90 deg about x, so pass T_W_S = T_W_V * T_V_v and its beams measure elevation (up +).
//
// Thread safety: render() and cast() are const and may run concurrently.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/events.hpp"
#include "core/mesh.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::sim {

struct SonarRender {
  SonarPing ping;
  SonarLabels labels;  // filled when labels are requested, else empty
};

// The echo image before speckle, noise and quantisation, for known-answer tests and
// tools: echo[row * cols + col] is the intensity the scene returns (after the beam
// pattern and multipath, before range gains); row_signal[row] the range gain it gets
// (spreading, absorption, TVG), row_noise[row] the gain of the noise floor.
struct EchoImage {
  int rows = 0, cols = 0;
  double range_resolution_m = 0.0;
  std::vector<double> bearings_rad;
  std::vector<float> echo, row_signal, row_noise;
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

  EchoImage echo(const SE3& T_W_S, SonarMount mount) const;

  // Distance along a unit direction to the first surface within max_m, if any.
  std::optional<double> cast(const Vec3& origin_W, const Vec3& direction_W, double max_m) const;

  // The bearing table of a mount's pings (radians, quantised to 1/100 degree like the device).
  const std::vector<double>& bearings_rad(SonarMount mount) const;
  const SonarGeometry& geometry(SonarMount mount) const;
  uint64_t rays_per_ping(SonarMount mount) const;
  // The one-way absorption the mount's head applies (dB/m; 0 in the clean profile).
  double absorption_db_per_m(SonarMount mount) const;

 private:
  std::vector<float> accumulate(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                                     bool with_labels, SonarRender& out) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Speckle stream ids for derive_seed (documented so a frame can be regenerated alone).
inline constexpr uint64_t kSpeckleStreamHorizontal = 0x5350454b48ull;  // "SPEKH"
inline constexpr uint64_t kSpeckleStreamVertical = 0x5350454b56ull;    // "SPEKV"

}  // namespace orthosonar::sim
