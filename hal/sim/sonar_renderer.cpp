#include "hal/sim/sonar_renderer.hpp"
#include "core/geometry.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/random.hpp"
#include "hal/sim/embree_device.hpp"

namespace orthosonar::sim {
namespace {

constexpr int kTable = 4096;     // speckle / noise inverse-CDF tables (12-bit index)
constexpr int kGammaLut = 16384;  // linear [0, 1] -> 8-bit
constexpr int kCosTable = 1024;
constexpr uint64_t kRayPatternStream = 0x52415950415454ull;  // fixed device ray pattern

// Inverse CDF of Gamma(L, 1/L) (mean 1) at the centres of kTable equal-probability cells.
std::vector<float> erlang_table(int looks) {
  std::vector<float> t(kTable);
  auto cdf = [looks](double x) {
    double term = 1.0, sum = 1.0;
    for (int n = 1; n < looks; ++n) {
      term *= looks * x / n;
      sum += term;
    }
    return 1.0 - std::exp(-looks * x) * sum;
  };
  for (int i = 0; i < kTable; ++i) {
    const double p = (i + 0.5) / kTable;
    double lo = 0.0, hi = 64.0;
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      (cdf(mid) < p ? lo : hi) = mid;
    }
    t[static_cast<size_t>(i)] = static_cast<float>(0.5 * (lo + hi));
  }
  return t;
}

// A smooth, seeded 2D value-noise field of unit-ish variance, a function of world (x, y)
// only (so the seabed looks the same from every ping): lattice values from a hash,
// smoothstep-interpolated. Only +, -, *, / (no libm): the same bits on every machine.
float lattice(int64_t ix, int64_t iy, uint64_t stream) {
  const uint64_t h = mix64(mix64(static_cast<uint64_t>(ix) ^ stream) ^ static_cast<uint64_t>(iy));
  return static_cast<float>(static_cast<double>(h >> 11) * 0x1.0p-53 * 2.0 - 1.0) * 1.7320508f;  // U(-sqrt3, sqrt3)
}
// value_noise with the four lattice values of the last cell kept: neighbouring hits often
// fall in the same cell; the same arithmetic on the same values, hence the same bits.
struct LatticeCell {
  int64_t ix = 0, iy = 0;
  float a = 0.0f, b = 0.0f, c = 0.0f, d = 0.0f;
  bool valid = false;
};
inline void fetch_cell(LatticeCell& m, int64_t ix, int64_t iy, uint64_t stream) {
  if (!m.valid || m.ix != ix || m.iy != iy) {
    m.a = lattice(ix, iy, stream);
    m.b = lattice(ix + 1, iy, stream);
    m.c = lattice(ix, iy + 1, stream);
    m.d = lattice(ix + 1, iy + 1, stream);
    m.ix = ix;
    m.iy = iy;
    m.valid = true;
  }
}
inline float value_noise_cached(double x, double y, uint64_t stream, LatticeCell& m) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
  const float sx = tx * tx * (3.0f - 2.0f * tx), sy = ty * ty * (3.0f - 2.0f * ty);
  fetch_cell(m, ix, iy, stream);
  const float ab = m.a + (m.b - m.a) * sx, cd = m.c + (m.d - m.c) * sx;
  return 1.5f * (ab + (cd - ab) * sy);
}
constexpr uint64_t kTextureStream = 0x5345414254455854ull, kReliefXStream = 0x52454c49454658ull,
                   kReliefYStream = 0x52454c49454659ull;

}  // namespace

// Per-mount tables: the device's bearing table, ray pattern and range-dependent gains.
struct HeadTables {  // internal to this file
  SonarHead spec;
  SonarGeometry geo;
  std::vector<double> bearings;
  std::vector<float> tan_mid;           // tan of the midpoints between beams (beam lookup)
  float tan_lo = 0.0f, tan_hi = 0.0f;   // tan of the fan's outer edges
  int rays_per_beam = 0;
  // Ray pattern in the sonar frame, beam-major, and each ray's weight (aperture pattern,
  // normalised per beam) and its unnormalised aperture gain G(phi).
  std::vector<float> dx, dy, dz, weight, gain_ap;
  std::vector<float> row_signal;        // spreading * absorption * TVG * bin-width normalisation
  std::vector<float> row_noise;         // TVG applied to the noise floor (1: range-independent)
  std::vector<float> side_min;          // per row: the weakest echo whose side lobes can show
  // Beam pattern as a scatter kernel: echo in beam j adds k_main[j][k] (k = -main_half..)
  // to beams j + k, and, when strong, k_side taps (offset, weight) further out.
  int main_half = 0;
  std::vector<float> k_main;            // beams x (2 main_half + 1)
  std::vector<std::vector<std::pair<int, float>>> k_side;
  float side_peak = 0.0f;               // the largest side-lobe tap (relative to the echo)
  double absorption_db_per_m = 0.0;
  // Per ray: sqrt(max G / G(ray)), the largest factor a multipath ghost can get (early out).
  std::vector<float> ghost_bound;
  // With a range-independent noise gain: the byte of an empty pixel per noise-table index.
  std::vector<uint8_t> zero_lut;
};

struct SonarRenderer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  SonarModelConfig cfg;
  uint64_t seed = 0;
  HeadTables heads[2];                        // indexed by SonarMount
  std::vector<Eigen::Vector3f> normal;  // unit normal per triangle
  std::vector<float> reflect;           // reflectivity per triangle
  std::vector<uint8_t> semantic;
  std::vector<uint32_t> object;
  std::vector<float> cos_pow;           // cos(incidence)^k on [0, 1]
  std::vector<float> gap_lut;           // aperture gain G(phi) against sin(phi) on [-1, 1]
  std::vector<float> texture_lut;       // exp(sigma t - sigma^2 / 2) for t on [-4, 4]
  std::vector<float> speckle, noise;
  std::vector<uint8_t> gamma_lut;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

constexpr int kApLut = 4096;
constexpr int kTexLut = 2048;

// Two-way azimuth pattern of a uniformly weighted aperture, sinc^4, scaled beyond the first
// null so that the first side lobe peaks at side_lobe_db; u = angle / (beam_width / 0.6391)
// puts the -3 dB points at +-beam_width / 2.
double beam_pattern(double u, double side_scale) {
  const double au = std::abs(u);
  if (au < 1e-9) return 1.0;
  const double s = std::sin(std::numbers::pi * au) / (std::numbers::pi * au);
  const double p = s * s * s * s;
  return au < 1.0 ? p : p * side_scale;
}

void build_head(HeadTables& h, const SonarHead& spec, const SonarModelConfig& cfg, Resolution resolution) {
  h.spec = spec;
  h.geo = sonar_geometry(spec, resolution);
  // Bearing table like the device's: int16 in 1/100 degree, denser near the centre.
  const int nb = h.geo.beams;
  const double half = 0.5 * spec.swath_deg;
  for (int j = 0; j < nb; ++j) {
    const double u = -1.0 + 2.0 * (j + 0.5) / nb;
    const double deg = half * ((1.0 - cfg.bearing_cubic) * u + cfg.bearing_cubic * u * u * u);
    const auto centi = static_cast<int16_t>(std::lround(deg * 100.0));
    h.bearings.push_back(centi * 0.01 * kRadPerDeg);
  }
  for (int j = 0; j + 1 < nb; ++j) {
    h.tan_mid.push_back(static_cast<float>(std::tan(0.5 * (h.bearings[static_cast<size_t>(j)] + h.bearings[static_cast<size_t>(j + 1)]))));
  }
  h.tan_lo = static_cast<float>(std::tan(1.5 * h.bearings.front() - 0.5 * h.bearings[1]));
  h.tan_hi = static_cast<float>(std::tan(1.5 * h.bearings.back() - 0.5 * h.bearings[static_cast<size_t>(nb - 2)]));
  // Ray pattern: beam_samples across the beam width, elevation_samples stratified (jittered
  // within strata) across the aperture. The pattern is fixed per beam (the device's
  // geometry) and differs between beams, so no stripes line up across the image.
  const int S = cfg.beam_samples, E = cfg.elevation_samples;
  h.rays_per_beam = ((S * E + 15) / 16) * 16;
  const double ap = spec.aperture_deg * kRadPerDeg, sigma = cfg.aperture_sigma_deg * kRadPerDeg * (spec.aperture_deg / 20.0);
  for (int j = 0; j < nb; ++j) {
    const double lo = j > 0 ? h.bearings[static_cast<size_t>(j - 1)] : 2 * h.bearings[0] - h.bearings[1];
    const double hi = j + 1 < nb ? h.bearings[static_cast<size_t>(j + 1)]
                                 : 2 * h.bearings[static_cast<size_t>(nb - 1)] - h.bearings[static_cast<size_t>(nb - 2)];
    const double width = 0.5 * (hi - lo) * cfg.beam_width_factor;
    Rng rng(derive_seed(kRayPatternStream, static_cast<uint64_t>(j)));
    std::vector<double> w;
    for (int s = 0; s < S; ++s) {
      for (int e = 0; e < E; ++e) {
        const double th = h.bearings[static_cast<size_t>(j)] + width * ((s + rng.uniform()) / S - 0.5);
        const double ph = -0.5 * ap + ap * (e + rng.uniform()) / E;
        h.dx.push_back(static_cast<float>(std::cos(ph) * std::cos(th)));
        h.dy.push_back(static_cast<float>(std::cos(ph) * std::sin(th)));
        h.dz.push_back(static_cast<float>(std::sin(ph)));
        w.push_back(std::exp(-0.5 * (ph / sigma) * (ph / sigma)));
      }
    }
    double sum = 0;
    for (double x : w) sum += x;
    for (double x : w) {
      h.weight.push_back(static_cast<float>(x / sum));
      h.gain_ap.push_back(static_cast<float>(x));
    }
    for (int pad = S * E; pad < h.rays_per_beam; ++pad) {  // padding rays (masked off)
      h.dx.push_back(1.0f);
      h.dy.push_back(0.0f);
      h.dz.push_back(0.0f);
      h.weight.push_back(0.0f);
      h.gain_ap.push_back(1.0f);
    }
  }
  // Range: spreading r^-p and two-way absorption against the TVG r^q times the share of the
  // absorption it gives back, all relative to tvg_reference_m; the noise floor enters before
  // the TVG in the field profile, so it rises with range as on the device.
  h.absorption_db_per_m = head_absorption_db_per_m(cfg, spec);
  const double res = h.geo.range_resolution_m, rref = cfg.tvg_reference_m, a2 = 2.0 * h.absorption_db_per_m;
  for (int i = 0; i < h.geo.range_bins; ++i) {
    const double r = res * (i + 1);
    const double loss_db = -a2 * (r - rref), tvg_abs_db = cfg.tvg_absorption_fraction * a2 * (r - rref);
    const double tvg = std::pow(r / rref, cfg.tvg_exponent) * std::pow(10.0, tvg_abs_db / 10.0);
    double signal = std::pow(r, -cfg.spreading_exponent) * std::pow(r / rref, cfg.tvg_exponent) *
                    std::pow(rref, cfg.spreading_exponent) * (0.05 / res);
    if (a2 > 0.0) signal *= std::pow(10.0, (loss_db + tvg_abs_db) / 10.0);
    h.row_signal.push_back(static_cast<float>(signal));
    h.row_noise.push_back(cfg.noise_before_tvg ? static_cast<float>(tvg) : 1.0f);
  }
  // Beam pattern kernels (field profile): normalised per source beam so an extended target
  // keeps its calibrated level; side-lobe taps kept down to side_lobe_floor_db.
  h.k_side.assign(static_cast<size_t>(nb), {});
  if (cfg.beam_pattern && spec.beam_width_deg > 0.0) {
    const double u_scale = 0.6391 / (spec.beam_width_deg * kRadPerDeg);
    const double natural_sll = 0.0022;  // sinc^4's first side lobe, -26.6 dB
    double first_peak = 0.0;
    for (double u = 1.0; u < 2.0; u += 1e-4) first_peak = std::max(first_peak, beam_pattern(u, 1.0));
    (void)natural_sll;
    const double side_scale = std::pow(10.0, cfg.side_lobe_db / 10.0) / first_peak;
    const double floor_lin = std::pow(10.0, cfg.side_lobe_floor_db / 10.0);
    // Main lobe taps: |u| < 1 (to the first null).
    double min_spacing = 1e9;
    for (int j = 0; j + 1 < nb; ++j) min_spacing = std::min(min_spacing, h.bearings[static_cast<size_t>(j + 1)] - h.bearings[static_cast<size_t>(j)]);
    h.main_half = std::max(1, static_cast<int>(std::ceil(1.0 / (u_scale * min_spacing))));
    const int W = 2 * h.main_half + 1;
    h.k_main.assign(static_cast<size_t>(nb) * static_cast<size_t>(W), 0.0f);
    for (int j = 0; j < nb; ++j) {
      double total = 0.0;
      std::vector<std::pair<int, double>> side;
      std::vector<double> main(static_cast<size_t>(W), 0.0);
      for (int k = -j; j + k < nb; ++k) {
        const double u = (h.bearings[static_cast<size_t>(j + k)] - h.bearings[static_cast<size_t>(j)]) * u_scale;
        const double p = beam_pattern(u, side_scale);
        if (std::abs(u) < 1.0) {
          if (std::abs(k) <= h.main_half) main[static_cast<size_t>(k + h.main_half)] = p;
          total += p;
        } else if (p >= floor_lin) {
          side.emplace_back(k, p);
          total += p;
        }
      }
      for (int k = 0; k < W; ++k) h.k_main[static_cast<size_t>(j) * static_cast<size_t>(W) + static_cast<size_t>(k)] = static_cast<float>(main[static_cast<size_t>(k)] / total);
      for (const auto& [k, p] : side) {
        const float t = static_cast<float>(p / total);
        h.k_side[static_cast<size_t>(j)].emplace_back(k, t);
        h.side_peak = std::max(h.side_peak, t);
      }
    }
    // Side lobes matter only where they can reach a tenth of the noise floor.
    for (int i = 0; i < h.geo.range_bins; ++i) {
      const double noise = std::max(cfg.noise_floor, 1e-12) * h.row_noise[static_cast<size_t>(i)];
      h.side_min.push_back(static_cast<float>(0.1 * noise / (std::max<double>(h.side_peak, 1e-30) * h.row_signal[static_cast<size_t>(i)])));
    }
  }
}

// The beam whose sector contains tan(bearing) = y / x, or -1 outside the fan.
int beam_of(const HeadTables& h, float y, float x) {
  if (!(x > 0.0f)) return -1;
  const float t = y / x;
  if (t < h.tan_lo || t > h.tan_hi) return -1;
  return static_cast<int>(std::upper_bound(h.tan_mid.begin(), h.tan_mid.end(), t) - h.tan_mid.begin());
}

}  // namespace

SonarRenderer::SonarRenderer(const TriangleMesh& mesh, const SonarModelConfig& cfg, Resolution resolution, uint64_t seed)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cfg = cfg;
  m.seed = seed;
  // Embree with one build thread (the BVH build is deterministic) and its ISA pinned to
  // SSE2 (embree_device.hpp): the same kernels, hence the same hits, on every x86-64 CPU.
  // The scene is static and robust against rays grazing shared edges.
  m.device = rtcNewDevice(kEmbreeDeviceConfig);
  if (m.device == nullptr || rtcGetDeviceError(m.device) != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("Embree: cannot create a device with \"") + kEmbreeDeviceConfig + "\"");
  }
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  if (!mesh.triangles.empty()) {
    RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) vb[3 * i + static_cast<size_t>(k)] = mesh.vertices[i][k];
    }
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      for (int k = 0; k < 3; ++k) ib[3 * i + static_cast<size_t>(k)] = static_cast<unsigned>(mesh.triangles[i][k]);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(m.scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(m.scene);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Eigen::Vector3f& a = mesh.vertices[static_cast<size_t>(t[0])];
    const Eigen::Vector3f n = (mesh.vertices[static_cast<size_t>(t[1])] - a).cross(mesh.vertices[static_cast<size_t>(t[2])] - a);
    const float len = n.norm();
    m.normal.push_back(len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f::UnitZ());
    const auto c = static_cast<size_t>(mesh.semantic[i]);
    m.semantic.push_back(static_cast<uint8_t>(c));
    m.object.push_back(mesh.object_id[i]);
    m.reflect.push_back(static_cast<float>(c < cfg.reflectivity.size() ? cfg.reflectivity[c] : 0.5));
  }
  for (int mount = 0; mount < 2; ++mount) {
    build_head(m.heads[mount], mount == 0 ? cfg.head_h : cfg.head_v, cfg, resolution);
  }
  for (int i = 0; i < kCosTable; ++i) {
    m.cos_pow.push_back(static_cast<float>(std::pow((i + 0.5) / kCosTable, cfg.incidence_exponent)));
  }
  // G(phi) against sin(phi) for the mirrored (multipath) arrivals: the same Gaussian as the
  // ray weights, per head aperture scaled in render (the LUT is for a 20 deg aperture's sigma).
  for (int i = 0; i < kApLut; ++i) {
    const double sphi = -1.0 + 2.0 * (i + 0.5) / kApLut;
    const double phi = std::asin(sphi), sigma = cfg.aperture_sigma_deg * kRadPerDeg;
    m.gap_lut.push_back(static_cast<float>(std::exp(-0.5 * (phi / sigma) * (phi / sigma))));
  }
  for (int i = 0; i < kTexLut; ++i) {
    const double t = -4.0 + 8.0 * (i + 0.5) / kTexLut, sg = cfg.seabed_texture;
    m.texture_lut.push_back(static_cast<float>(std::exp(sg * t - 0.5 * sg * sg)));
  }
  m.speckle = erlang_table(cfg.speckle_looks);
  m.noise = erlang_table(1);
  for (int i = 0; i < kGammaLut; ++i) {
    const double v = std::pow(static_cast<double>(i) / (kGammaLut - 1), cfg.gamma);
    m.gamma_lut.push_back(static_cast<uint8_t>(std::lround(255.0 * v)));
  }
  const float gap_max = *std::max_element(m.gap_lut.begin(), m.gap_lut.end());
  const float gain = static_cast<float>(cfg.gain) * (kGammaLut - 1);
  const float noise_floor = static_cast<float>(cfg.noise_floor);
  for (HeadTables& h : m.heads) {
    for (float g : h.gain_ap) h.ghost_bound.push_back(std::sqrt(gap_max / g));
    if (!h.row_noise.empty() && std::all_of(h.row_noise.begin(), h.row_noise.end(), [&h](float x) { return x == h.row_noise.front(); })) {
      // As render computes a pixel with accum == 0: (0 * row_signal * speckle + nf * noise) * gain.
      const float nf = noise_floor * h.row_noise.front();
      for (int i = 0; i < kTable; ++i) {
        const float signal = 0.0f;
        const float lin = (signal + nf * m.noise[static_cast<size_t>(i)]) * gain;
        const int q = !(lin < static_cast<float>(kGammaLut - 1)) ? kGammaLut - 1 : static_cast<int>(lin);  // NaN: top, as _mm_min_ps gives
        h.zero_lut.push_back(m.gamma_lut[static_cast<size_t>(q)]);
      }
    }
  }
}

SonarRenderer::~SonarRenderer() = default;

const std::vector<double>& SonarRenderer::bearings_rad(SonarMount mount) const {
  return impl_->heads[static_cast<int>(mount)].bearings;
}
const SonarGeometry& SonarRenderer::geometry(SonarMount mount) const { return impl_->heads[static_cast<int>(mount)].geo; }
uint64_t SonarRenderer::rays_per_ping(SonarMount mount) const {
  return static_cast<uint64_t>(geometry(mount).beams) * static_cast<uint64_t>(impl_->cfg.beam_samples * impl_->cfg.elevation_samples);
}
double SonarRenderer::absorption_db_per_m(SonarMount mount) const {
  return impl_->heads[static_cast<int>(mount)].absorption_db_per_m;
}

std::optional<double> SonarRenderer::cast(const Vec3& o, const Vec3& d, double max_m) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(d.x());
  rh.ray.dir_y = static_cast<float>(d.y());
  rh.ray.dir_z = static_cast<float>(d.z());
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = static_cast<float>(max_m);
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return static_cast<double>(rh.ray.tfar);
}

namespace {

// Per-thread scratch of accumulate/render, reused from ping to ping (no allocation or page
// faults per ping once warm). render() is const and may run on several threads at once:
// each thread has its own.
struct Scratch {
  std::vector<float> accum, spread, best, best_spread;
  std::vector<uint8_t> sem;
  std::vector<uint32_t> obj;
  std::vector<int> col_lo, col_hi;  // per row: the columns anything was deposited in (lo > hi: none)
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

}  // namespace

std::vector<float> SonarRenderer::accumulate(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                                                  bool with_labels, SonarRender& out) const {
  const Impl& m = *impl_;
  const HeadTables& h = m.heads[static_cast<int>(mount)];
  const SonarModelConfig& cfg = m.cfg;
  const int rows = h.geo.range_bins, cols = h.geo.beams;
  const size_t npix = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  Scratch& sc = scratch();
  std::vector<float> accum = std::move(sc.accum);
  accum.assign(npix, 0.0f);
  float* const acc = accum.data();
  std::vector<int>& col_lo = sc.col_lo;
  std::vector<int>& col_hi = sc.col_hi;
  col_lo.assign(static_cast<size_t>(rows), cols);
  col_hi.assign(static_cast<size_t>(rows), -1);
  // Labels before the beam pattern: straight into the output without it, else into scratch.
  const bool spread_labels = with_labels && !h.k_main.empty();
  std::vector<uint8_t>* sem_out = nullptr;
  std::vector<uint32_t>* obj_out = nullptr;
  float* best = nullptr;
  if (with_labels) {
    sc.best.assign(npix, 0.0f);
    best = sc.best.data();
    out.labels.stamp = stamp;
    out.labels.mount = mount;
    out.labels.ping_id = ping_id;
    out.labels.rows = static_cast<uint16_t>(rows);
    out.labels.cols = static_cast<uint16_t>(cols);
    sem_out = spread_labels ? &sc.sem : &out.labels.semantic;
    obj_out = spread_labels ? &sc.obj : &out.labels.object_id;
    sem_out->assign(npix, 0);
    obj_out->assign(npix, 0);
  }
  uint8_t* const lab_sem = with_labels ? sem_out->data() : nullptr;
  uint32_t* const lab_obj = with_labels ? obj_out->data() : nullptr;
  const Eigen::Matrix3f R = T_W_S.rotation().cast<float>();
  const Eigen::Matrix3f Rt = R.transpose();
  const Eigen::Vector3f o = T_W_S.translation().cast<float>();
  const float inv_res = static_cast<float>(1.0 / h.geo.range_resolution_m);
  const float tfar = static_cast<float>(h.spec.max_range_m + 0.5 * h.geo.range_resolution_m);
  // Field profile switches.
  const bool lambert = cfg.seabed_lambert;
  const float mu = static_cast<float>(cfg.seabed_mu);
  const double tex_scale = 1.0 / cfg.seabed_texture_scale_m, rel_scale = 1.0 / cfg.seabed_relief_scale_m;
  const float rel_slope = static_cast<float>(std::tan(cfg.seabed_relief_deg * kRadPerDeg));
  LatticeCell cell_rx, cell_ry, cell_tex;
  // Mirrors for one-bounce multipath: the surface z = 0 and the seabed plane.
  struct Mirror {
    float z0, coeff;
  };
  Mirror mirrors[2];
  int n_mirrors = 0;
  if (cfg.surface_reflection > 0.0 && o.z() < 0.0f) mirrors[n_mirrors++] = {0.0f, static_cast<float>(cfg.surface_reflection)};
  if (cfg.seabed_reflection > 0.0 && cfg.seafloor_depth_m > 0.0 && o.z() > static_cast<float>(-cfg.seafloor_depth_m))
    mirrors[n_mirrors++] = {static_cast<float>(-cfg.seafloor_depth_m), static_cast<float>(cfg.seabed_reflection)};
  // A ghost is deposited only where it can reach a tenth of the noise floor at its range.
  const float noise_ref = static_cast<float>(std::max(cfg.noise_floor, 1e-12) * 0.1);
  const float ap_lut_scale = static_cast<float>(20.0 / h.spec.aperture_deg);  // G for this head's aperture
  const float* const row_signal = h.row_signal.data();
  const float* const row_noise = h.row_noise.data();
  auto ap_gain = [&m, ap_lut_scale](float sphi) {
    const float x = std::clamp(sphi * ap_lut_scale, -1.0f, 1.0f);
    const int i = std::min(kApLut - 1, static_cast<int>((x + 1.0f) * (0.5f * kApLut)));
    return m.gap_lut[static_cast<size_t>(i)];
  };
  auto touch = [&col_lo, &col_hi](int bin, int col) {
    int& lo = col_lo[static_cast<size_t>(bin)];
    int& hi = col_hi[static_cast<size_t>(bin)];
    if (col < lo) lo = col;
    if (col > hi) hi = col;
  };
  auto deposit = [&](float range_m, int beam, float value) {
    const int bin = static_cast<int>(range_m * inv_res + 0.5f) - 1;
    if (bin < 0 || bin >= rows || beam < 0 || beam >= cols) return;
    if (value * row_signal[bin] < noise_ref * row_noise[bin]) return;
    acc[static_cast<size_t>(bin) * static_cast<size_t>(cols) + static_cast<size_t>(beam)] += value;
    touch(bin, beam);
  };
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  // Embree's 16-wide packet queries load the valid mask and the SoA ray/hit packet with
  // aligned 512-bit accesses: both must be 64-byte aligned (RTCRayHit16 is declared
  // RTC_ALIGN(64), a plain int[16] on the stack is not; ASan caught the misaligned load).
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  static_assert(alignof(RTCRayHit16) >= 64, "RTCRayHit16 must be 64-byte aligned");
  // The fields Embree does not write back stay as set here for every packet.
  for (int k = 0; k < 16; ++k) {
    rh.ray.org_x[k] = o.x();
    rh.ray.org_y[k] = o.y();
    rh.ray.org_z[k] = o.z();
    rh.ray.tnear[k] = 0.0f;
    rh.ray.time[k] = 0.0f;
    rh.ray.mask[k] = 0xFFFFFFFFu;
    rh.ray.id[k] = static_cast<unsigned>(k);
    rh.ray.flags[k] = 0;
  }
  for (int j = 0; j < cols; ++j) {
    for (int base = 0; base < h.rays_per_beam; base += 16) {
      const size_t r0 = static_cast<size_t>(j) * static_cast<size_t>(h.rays_per_beam) + static_cast<size_t>(base);
      for (int k = 0; k < 16; ++k) {
        const size_t r = r0 + static_cast<size_t>(k);
        const Eigen::Vector3f d = R * Eigen::Vector3f(h.dx[r], h.dy[r], h.dz[r]);
        valid[k] = h.weight[r] > 0.0f ? -1 : 0;
        rh.ray.dir_x[k] = d.x();
        rh.ray.dir_y[k] = d.y();
        rh.ray.dir_z[k] = d.z();
        rh.ray.tfar[k] = tfar;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, m.scene, &ctx, &rh);
      for (int k = 0; k < 16; ++k) {
        if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
        const float t = rh.ray.tfar[k];
        const int bin = static_cast<int>(t * inv_res + 0.5f) - 1;
        if (bin < 0 || bin >= rows) continue;
        const size_t tri = rh.hit.primID[k];
        const size_t ray = r0 + static_cast<size_t>(k);
        const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
        const Eigen::Vector3f p = o + t * d;
        float contrib;
        if (lambert && m.semantic[tri] == static_cast<uint8_t>(SemanticClass::kSeafloor)) {
          // Lambert's law mu cos^2(theta) on a normal perturbed by the relief field, times
          // the grain texture: both functions of the world position only.
          Eigen::Vector3f n = m.normal[tri];
          if (rel_slope > 0.0f) {
            const double px = p.x() * rel_scale, py = p.y() * rel_scale;
            n += rel_slope * Eigen::Vector3f(value_noise_cached(px, py, kReliefXStream, cell_rx),
                                             value_noise_cached(px, py, kReliefYStream, cell_ry), 0.0f);
            n /= n.norm();
          }
          const float c = std::min(1.0f, std::abs(n.dot(d)));
          const float tv = value_noise_cached(p.x() * tex_scale, p.y() * tex_scale, kTextureStream, cell_tex);
          const int ti = std::clamp(static_cast<int>((tv + 4.0f) * (kTexLut / 8.0f)), 0, kTexLut - 1);
          contrib = h.weight[ray] * mu * c * c * m.texture_lut[static_cast<size_t>(ti)];
        } else {
          const float c = std::min(1.0f, std::abs(m.normal[tri].dot(d)));
          const int ci = std::min(kCosTable - 1, static_cast<int>(c * kCosTable));
          contrib = h.weight[ray] * m.reflect[tri] * m.cos_pow[static_cast<size_t>(ci)];
        }
        const size_t px = static_cast<size_t>(bin) * static_cast<size_t>(cols) + static_cast<size_t>(j);
        acc[px] += contrib;
        touch(bin, j);
        if (with_labels && contrib > best[px]) {
          best[px] = contrib;
          lab_sem[px] = m.semantic[tri];
          lab_obj[px] = m.object[tri];
        }
        // One-bounce multipath through each mirror plane (no occlusion test on the bounce):
        // out direct / back via the mirror and the reverse, both at (t + t')/2, one in this
        // beam and one in the beam of the image point; and both ways via the mirror at t'.
        if (n_mirrors == 0) continue;
        const float ghost_ref = noise_ref * row_noise[bin];
        const float rs_bin = row_signal[bin];
        for (int mi = 0; mi < n_mirrors; ++mi) {
          const Mirror& mr = mirrors[mi];
          // Upper bound of `cross` below (G(phi) <= its largest value; every step is
          // monotonic): when even that is below the threshold the ghost is skipped, as it
          // would be after the full computation.
          if (contrib * mr.coeff * h.ghost_bound[ray] * rs_bin < ghost_ref) continue;
          const Eigen::Vector3f q_W(p.x() - o.x(), p.y() - o.y(), 2.0f * mr.z0 - p.z() - o.z());
          const float t2 = q_W.norm();
          if (!(t2 > 0.0f)) continue;
          const Eigen::Vector3f q = Rt * q_W;  // image point in the sonar frame
          const float g_ratio = ap_gain(q.z() / t2) / h.gain_ap[ray];
          const float cross = contrib * mr.coeff * std::sqrt(g_ratio);
          const float twice = contrib * mr.coeff * mr.coeff * g_ratio;
          const float r_cross = 0.5f * (t + t2);
          if (cross * rs_bin < ghost_ref) continue;  // the strongest ghost is below a tenth of the noise floor (ranges only grow)
          const int jb = beam_of(h, q.y(), q.x());
          deposit(r_cross, j, cross);
          deposit(r_cross, jb, cross);
          deposit(t2, jb, twice);
        }
      }
    }
  }
  // Azimuth beam pattern (field profile): each echo spreads over the main lobe's beams and,
  // when strong enough to show above the noise floor, into the side lobes.
  if (!h.k_main.empty()) {
    std::vector<float> spread = std::move(sc.spread);
    spread.assign(npix, 0.0f);
    const int W = 2 * h.main_half + 1, mh = h.main_half;
    // Labels follow the main lobe (the target as the device resolves it); side lobes and
    // multipath ghosts keep the label of what the beam really looks at (often water).
    uint8_t* sem = nullptr;
    uint32_t* obj = nullptr;
    float* best_spread = nullptr;
    if (with_labels) {
      out.labels.semantic.assign(npix, 0);
      out.labels.object_id.assign(npix, 0);
      sem = out.labels.semantic.data();
      obj = out.labels.object_id.data();
      sc.best_spread.assign(npix, 0.0f);
      best_spread = sc.best_spread.data();
    }
    // Every destination cell receives its contributions in increasing source beam order,
    // as before: rows are independent, and within a row sources are taken left to right.
    for (int i = 0; i < rows; ++i) {
      const int jlo = col_lo[static_cast<size_t>(i)], jhi = col_hi[static_cast<size_t>(i)];
      if (jlo > jhi) continue;  // nothing in this row
      const size_t row0 = static_cast<size_t>(i) * static_cast<size_t>(cols);
      const float* src = acc + row0;
      float* dst = spread.data() + row0;
      const float side_min = h.side_min[static_cast<size_t>(i)];
      for (int j = jlo; j <= jhi; ++j) {
        const float v = src[j];
        if (v == 0.0f) continue;
        const float* k = h.k_main.data() + static_cast<size_t>(j) * static_cast<size_t>(W);
        const int lo = std::max(0, j - mh), hi = std::min(cols - 1, j + mh);
        for (int b = lo; b <= hi; ++b) dst[b] += v * k[b - j + mh];
        if (with_labels) {
          const size_t src_px = row0 + static_cast<size_t>(j);
          const float own = best[src_px];
          if (own > 0.0f) {
            for (int b = lo; b <= hi; ++b) {
              const size_t px = row0 + static_cast<size_t>(b);
              const float c = own * k[b - j + mh];
              if (c > best_spread[px]) {
                best_spread[px] = c;
                sem[px] = lab_sem[src_px];
                obj[px] = lab_obj[src_px];
              }
            }
          }
        }
        if (v >= side_min) {
          for (const auto& [off, w] : h.k_side[static_cast<size_t>(j)]) dst[j + off] += v * w;
        }
      }
    }
    accum.swap(spread);
    sc.spread = std::move(spread);
  }
  return accum;
}

EchoImage SonarRenderer::echo(const SE3& T_W_S, SonarMount mount) const {
  SonarRender unused;
  EchoImage e;
  const HeadTables& h = impl_->heads[static_cast<int>(mount)];
  e.rows = h.geo.range_bins;
  e.cols = h.geo.beams;
  e.range_resolution_m = h.geo.range_resolution_m;
  e.bearings_rad = h.bearings;
  e.echo = accumulate(T_W_S, mount, Time{}, 0, false, unused);
  e.row_signal = h.row_signal;
  e.row_noise = h.row_noise;
  return e;
}

SonarRender SonarRenderer::render(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                                  bool with_labels) const {
  const Impl& m = *impl_;
  const HeadTables& h = m.heads[static_cast<int>(mount)];
  const SonarModelConfig& cfg = m.cfg;
  const int rows = h.geo.range_bins, cols = h.geo.beams;
  const size_t npix = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  SonarRender out;
  std::vector<float> accum = accumulate(T_W_S, mount, stamp, ping_id, with_labels, out);
  // Speckle, noise floor, TVG, gain, gamma, 8-bit: one 64-bit draw per two pixels.
  SonarPing& p = out.ping;
  p.part_number = mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
  p.mount = mount;
  p.stamp = stamp;
  p.ping_id = ping_id;
  p.range_resolution_m = h.geo.range_resolution_m;
  p.frequency_hz = h.spec.frequency_hz;
  p.gain_percent = cfg.gain_percent;
  p.bearings_rad = h.bearings;
  p.rows = static_cast<uint16_t>(rows);
  p.cols = static_cast<uint16_t>(cols);
  p.bytes_per_pixel = 1;
  p.image.resize(npix);
  Rng rng(derive_seed(m.seed, mount == SonarMount::kHorizontal ? kSpeckleStreamHorizontal : kSpeckleStreamVertical, ping_id));
  const float gain = static_cast<float>(cfg.gain) * (kGammaLut - 1);
  const float noise_floor = static_cast<float>(cfg.noise_floor);
  const float* const acc = accum.data();
  const float* const speckle = m.speckle.data();
  const float* const noise = m.noise.data();
  const uint8_t* const gamma_lut = m.gamma_lut.data();
  // With a range-independent noise gain, an empty pixel's byte depends on its noise draw
  // only: zero_lut holds it (the same arithmetic with a zero signal).
  const uint8_t* const zero_lut = h.zero_lut.empty() ? nullptr : h.zero_lut.data();
  uint8_t* const img = p.image.data();
  // signal = (accum * row_signal) * speckle; lin = (signal + (noise_floor * row_noise) * noise) * gain.
  auto pixel = [&](float a, float rs, float nf, uint32_t b) -> uint8_t {
    if (zero_lut != nullptr && a == 0.0f) return zero_lut[(b >> 12) & 0xFFF];
    const float signal = a * rs * speckle[b & 0xFFF];
    const float lin = (signal + nf * noise[(b >> 12) & 0xFFF]) * gain;
    const int q = !(lin < static_cast<float>(kGammaLut - 1)) ? kGammaLut - 1 : static_cast<int>(lin);  // NaN: top, as _mm_min_ps gives
    return gamma_lut[q];
  };
#if defined(__SSE2__)
  if (cols % 4 == 0) {  // four pixels (two draws) at a time; the same IEEE single operations
    const __m128 gain4 = _mm_set1_ps(gain), top4 = _mm_set1_ps(static_cast<float>(kGammaLut - 1));
    alignas(16) int32_t q[4];
    for (int r = 0; r < rows; ++r) {
      const size_t row0 = static_cast<size_t>(r) * static_cast<size_t>(cols);
      const __m128 rs4 = _mm_set1_ps(h.row_signal[static_cast<size_t>(r)]);
      const __m128 nf4 = _mm_set1_ps(noise_floor * h.row_noise[static_cast<size_t>(r)]);
      const float* a = acc + row0;
      uint8_t* o = img + row0;
      for (int c = 0; c < cols; c += 4) {
        const uint64_t b0 = rng.next_u64(), b1 = rng.next_u64();
        const auto u0 = static_cast<uint32_t>(b0), u1 = static_cast<uint32_t>(b0 >> 32);
        const auto u2 = static_cast<uint32_t>(b1), u3 = static_cast<uint32_t>(b1 >> 32);
        const __m128 a4 = _mm_loadu_ps(a + c);
        if (zero_lut != nullptr && _mm_movemask_ps(_mm_cmpeq_ps(a4, _mm_setzero_ps())) == 0xF) {
          o[c] = zero_lut[(u0 >> 12) & 0xFFF];
          o[c + 1] = zero_lut[(u1 >> 12) & 0xFFF];
          o[c + 2] = zero_lut[(u2 >> 12) & 0xFFF];
          o[c + 3] = zero_lut[(u3 >> 12) & 0xFFF];
          continue;
        }
        const __m128 sp4 = _mm_setr_ps(speckle[u0 & 0xFFF], speckle[u1 & 0xFFF], speckle[u2 & 0xFFF], speckle[u3 & 0xFFF]);
        const __m128 nz4 = _mm_setr_ps(noise[(u0 >> 12) & 0xFFF], noise[(u1 >> 12) & 0xFFF], noise[(u2 >> 12) & 0xFFF],
                                       noise[(u3 >> 12) & 0xFFF]);
        const __m128 signal = _mm_mul_ps(_mm_mul_ps(a4, rs4), sp4);
        const __m128 lin = _mm_mul_ps(_mm_add_ps(signal, _mm_mul_ps(nf4, nz4)), gain4);
        // lin >= top ? top : int(lin), for the finite non-negative lin here.
        _mm_store_si128(reinterpret_cast<__m128i*>(q), _mm_cvttps_epi32(_mm_min_ps(lin, top4)));
        o[c] = gamma_lut[q[0]];
        o[c + 1] = gamma_lut[q[1]];
        o[c + 2] = gamma_lut[q[2]];
        o[c + 3] = gamma_lut[q[3]];
      }
    }
  } else
#endif
  if (cols % 2 == 0) {  // every row starts on a fresh draw: pixel pairs (low, high 32 bits)
    for (int r = 0; r < rows; ++r) {
      const size_t row0 = static_cast<size_t>(r) * static_cast<size_t>(cols);
      const float rs = h.row_signal[static_cast<size_t>(r)];
      const float nf = noise_floor * h.row_noise[static_cast<size_t>(r)];
      const float* a = acc + row0;
      uint8_t* o = img + row0;
      for (int c = 0; c < cols; c += 2) {
        const uint64_t bits = rng.next_u64();
        o[c] = pixel(a[c], rs, nf, static_cast<uint32_t>(bits));
        o[c + 1] = pixel(a[c + 1], rs, nf, static_cast<uint32_t>(bits >> 32));
      }
    }
  } else {
    uint64_t bits = 0;
    size_t i = 0;
    for (int r = 0; r < rows; ++r) {
      const float rs = h.row_signal[static_cast<size_t>(r)];
      const float nf = noise_floor * h.row_noise[static_cast<size_t>(r)];
      for (int c = 0; c < cols; ++c, ++i) {
        if ((i & 1) == 0) bits = rng.next_u64();
        img[i] = pixel(acc[i], rs, nf, static_cast<uint32_t>(bits));
        bits >>= 32;
      }
    }
  }
  scratch().accum = std::move(accum);
  return out;
}

}  // namespace orthosonar::sim
