// The sonar renderer (sonar_renderer.hpp): the Embree scene and the per-mount tables
// built once, and the image assembly of a ping: range gains, speckle, the noise floor,
// TVG, gain, gamma and 8-bit quantisation of the accumulated echoes (sonar_echo.cpp).
#include "hal/sim/sonar_renderer_detail.hpp"

namespace orthosonar::sim {

using namespace detail;

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
  // Back to the scratch all zero, for the next ping of this mount on this thread: the image
  // is non-zero at most within the beam pattern's reach of this ping's deposits.
  Scratch& sc = scratch(mount);
  clear_rows(accum, cols, sc.col_lo, sc.col_hi, h.reach);
  sc.accum = std::move(accum);
  return out;
}

}  // namespace orthosonar::sim
