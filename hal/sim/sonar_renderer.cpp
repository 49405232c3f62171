#include "hal/sim/sonar_renderer.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/random.hpp"
#include "hal/sim/embree_device.hpp"

namespace orthosonar::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
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

}  // namespace

struct SonarRenderer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  SonarModelConfig cfg;
  SonarGeometry geo;
  uint64_t seed = 0;
  std::vector<double> bearings;
  int rays_per_beam = 0;
  // Ray pattern in the sonar frame, beam-major, and each ray's weight (aperture pattern,
  // normalised per beam).
  std::vector<float> dx, dy, dz, weight;
  std::vector<Eigen::Vector3f> normal;  // unit normal per triangle
  std::vector<float> reflect;           // reflectivity per triangle
  std::vector<uint8_t> semantic;
  std::vector<uint32_t> object;
  std::vector<float> row_gain;          // spreading loss * TVG * bin-width normalisation
  std::vector<float> cos_pow;           // cos(incidence)^k on [0, 1]
  std::vector<float> speckle, noise;
  std::vector<uint8_t> gamma_lut;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

SonarRenderer::SonarRenderer(const TriangleMesh& mesh, const SonarModelConfig& cfg, Resolution resolution, uint64_t seed)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cfg = cfg;
  m.geo = sonar_geometry(cfg, resolution);
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
  // Bearing table like the device's: int16 in 1/100 degree, denser near the centre.
  const int nb = m.geo.beams;
  const double half = 0.5 * cfg.swath_deg;
  for (int j = 0; j < nb; ++j) {
    const double u = -1.0 + 2.0 * (j + 0.5) / nb;
    const double deg = half * ((1.0 - cfg.bearing_cubic) * u + cfg.bearing_cubic * u * u * u);
    const auto centi = static_cast<int16_t>(std::lround(deg * 100.0));
    m.bearings.push_back(centi * 0.01 * kDeg);
  }
  // Ray pattern: beam_samples across the beam width, elevation_samples stratified (jittered
  // within strata) across the aperture. The pattern is fixed per beam (the device's
  // geometry) and differs between beams, so no stripes line up across the image.
  const int S = cfg.beam_samples, E = cfg.elevation_samples;
  m.rays_per_beam = ((S * E + 15) / 16) * 16;
  const double ap = cfg.aperture_deg * kDeg, sigma = cfg.aperture_sigma_deg * kDeg;
  for (int j = 0; j < nb; ++j) {
    const double lo = j > 0 ? m.bearings[static_cast<size_t>(j - 1)] : 2 * m.bearings[0] - m.bearings[1];
    const double hi = j + 1 < nb ? m.bearings[static_cast<size_t>(j + 1)]
                                 : 2 * m.bearings[static_cast<size_t>(nb - 1)] - m.bearings[static_cast<size_t>(nb - 2)];
    const double width = 0.5 * (hi - lo) * cfg.beam_width_factor;
    Rng rng(derive_seed(kRayPatternStream, static_cast<uint64_t>(j)));
    std::vector<double> w;
    for (int s = 0; s < S; ++s) {
      for (int e = 0; e < E; ++e) {
        const double th = m.bearings[static_cast<size_t>(j)] + width * ((s + rng.uniform()) / S - 0.5);
        const double ph = -0.5 * ap + ap * (e + rng.uniform()) / E;
        m.dx.push_back(static_cast<float>(std::cos(ph) * std::cos(th)));
        m.dy.push_back(static_cast<float>(std::cos(ph) * std::sin(th)));
        m.dz.push_back(static_cast<float>(std::sin(ph)));
        w.push_back(std::exp(-0.5 * (ph / sigma) * (ph / sigma)));
      }
    }
    double sum = 0;
    for (double x : w) sum += x;
    for (double x : w) m.weight.push_back(static_cast<float>(x / sum));
    for (int pad = S * E; pad < m.rays_per_beam; ++pad) {  // padding rays (masked off)
      m.dx.push_back(1.0f);
      m.dy.push_back(0.0f);
      m.dz.push_back(0.0f);
      m.weight.push_back(0.0f);
    }
  }
  const double res = m.geo.range_resolution_m;
  for (int i = 0; i < m.geo.range_bins; ++i) {
    const double r = res * (i + 1);
    m.row_gain.push_back(static_cast<float>(std::pow(r, -cfg.spreading_exponent) *
                                            std::pow(r / cfg.tvg_reference_m, cfg.tvg_exponent) *
                                            std::pow(cfg.tvg_reference_m, cfg.spreading_exponent) * (0.05 / res)));
  }
  for (int i = 0; i < kCosTable; ++i) {
    m.cos_pow.push_back(static_cast<float>(std::pow((i + 0.5) / kCosTable, cfg.incidence_exponent)));
  }
  m.speckle = erlang_table(cfg.speckle_looks);
  m.noise = erlang_table(1);
  for (int i = 0; i < kGammaLut; ++i) {
    const double v = std::pow(static_cast<double>(i) / (kGammaLut - 1), cfg.gamma);
    m.gamma_lut.push_back(static_cast<uint8_t>(std::lround(255.0 * v)));
  }
}

SonarRenderer::~SonarRenderer() = default;

const std::vector<double>& SonarRenderer::bearings_rad() const { return impl_->bearings; }
const SonarGeometry& SonarRenderer::geometry() const { return impl_->geo; }
uint64_t SonarRenderer::rays_per_ping() const {
  return static_cast<uint64_t>(impl_->geo.beams) * static_cast<uint64_t>(impl_->cfg.beam_samples * impl_->cfg.elevation_samples);
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

SonarRender SonarRenderer::render(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                                  bool with_labels) const {
  const Impl& m = *impl_;
  const int rows = m.geo.range_bins, cols = m.geo.beams;
  const size_t npix = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  std::vector<float> accum(npix, 0.0f);
  std::vector<float> best;
  SonarRender out;
  if (with_labels) {
    best.assign(npix, 0.0f);
    out.labels.stamp = stamp;
    out.labels.mount = mount;
    out.labels.ping_id = ping_id;
    out.labels.rows = static_cast<uint16_t>(rows);
    out.labels.cols = static_cast<uint16_t>(cols);
    out.labels.semantic.assign(npix, 0);
    out.labels.object_id.assign(npix, 0);
  }
  const Eigen::Matrix3f R = T_W_S.rotation().cast<float>();
  const Eigen::Vector3f o = T_W_S.translation().cast<float>();
  const float inv_res = static_cast<float>(1.0 / m.geo.range_resolution_m);
  const float tfar = static_cast<float>(m.cfg.max_range_m + 0.5 * m.geo.range_resolution_m);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  // Embree's 16-wide packet queries load the valid mask and the SoA ray/hit packet with
  // aligned 512-bit accesses: both must be 64-byte aligned (RTCRayHit16 is declared
  // RTC_ALIGN(64), a plain int[16] on the stack is not; ASan caught the misaligned load).
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  static_assert(alignof(RTCRayHit16) >= 64, "RTCRayHit16 must be 64-byte aligned");
  for (int j = 0; j < cols; ++j) {
    for (int base = 0; base < m.rays_per_beam; base += 16) {
      const size_t r0 = static_cast<size_t>(j) * static_cast<size_t>(m.rays_per_beam) + static_cast<size_t>(base);
      for (int k = 0; k < 16; ++k) {
        const size_t r = r0 + static_cast<size_t>(k);
        const Eigen::Vector3f d = R * Eigen::Vector3f(m.dx[r], m.dy[r], m.dz[r]);
        valid[k] = m.weight[r] > 0.0f ? -1 : 0;
        rh.ray.org_x[k] = o.x();
        rh.ray.org_y[k] = o.y();
        rh.ray.org_z[k] = o.z();
        rh.ray.dir_x[k] = d.x();
        rh.ray.dir_y[k] = d.y();
        rh.ray.dir_z[k] = d.z();
        rh.ray.tnear[k] = 0.0f;
        rh.ray.tfar[k] = tfar;
        rh.ray.time[k] = 0.0f;
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.id[k] = static_cast<unsigned>(k);
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, m.scene, &ctx, &rh);
      for (int k = 0; k < 16; ++k) {
        if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
        const int bin = static_cast<int>(rh.ray.tfar[k] * inv_res + 0.5f) - 1;
        if (bin < 0 || bin >= rows) continue;
        const size_t tri = rh.hit.primID[k];
        const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
        const float c = std::min(1.0f, std::abs(m.normal[tri].dot(d)));
        const int ci = std::min(kCosTable - 1, static_cast<int>(c * kCosTable));
        const float contrib = m.weight[r0 + static_cast<size_t>(k)] * m.reflect[tri] * m.cos_pow[static_cast<size_t>(ci)];
        const size_t px = static_cast<size_t>(bin) * static_cast<size_t>(cols) + static_cast<size_t>(j);
        accum[px] += contrib;
        if (with_labels && contrib > best[px]) {
          best[px] = contrib;
          out.labels.semantic[px] = m.semantic[tri];
          out.labels.object_id[px] = m.object[tri];
        }
      }
    }
  }
  // Speckle, noise floor, TVG, gain, gamma, 8-bit: one 64-bit draw per two pixels.
  SonarPing& p = out.ping;
  p.part_number = mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
  p.mount = mount;
  p.stamp = stamp;
  p.ping_id = ping_id;
  p.range_resolution_m = m.geo.range_resolution_m;
  p.frequency_hz = mount == SonarMount::kHorizontal ? m.cfg.frequency_h_hz : m.cfg.frequency_v_hz;
  p.gain_percent = m.cfg.gain_percent;
  p.bearings_rad = m.bearings;
  p.rows = static_cast<uint16_t>(rows);
  p.cols = static_cast<uint16_t>(cols);
  p.bytes_per_pixel = 1;
  p.image.resize(npix);
  Rng rng(derive_seed(m.seed, mount == SonarMount::kHorizontal ? kSpeckleStreamHorizontal : kSpeckleStreamVertical, ping_id));
  const float gain = static_cast<float>(m.cfg.gain) * (kGammaLut - 1);
  const float noise_floor = static_cast<float>(m.cfg.noise_floor);
  uint64_t bits = 0;
  for (size_t i = 0; i < npix; ++i) {
    if ((i & 1) == 0) bits = rng.next_u64();
    const size_t s_idx = static_cast<size_t>(bits & 0xFFF), n_idx = static_cast<size_t>((bits >> 12) & 0xFFF);
    bits >>= 32;
    const size_t row = i / static_cast<size_t>(cols);
    const float signal = accum[i] * m.row_gain[row] * m.speckle[s_idx];
    const float lin = (signal + noise_floor * m.noise[n_idx]) * gain;
    const int q = lin >= static_cast<float>(kGammaLut - 1) ? kGammaLut - 1 : static_cast<int>(lin);
    p.image[i] = m.gamma_lut[static_cast<size_t>(q)];
  }
  return out;
}

}  // namespace orthosonar::sim
