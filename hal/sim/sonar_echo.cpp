// The sonar renderer's echo stage: rays cast with Embree, each first hit's echo
// (reflectivity, incidence, seabed relief and grain texture, multipath ghosts) spread by
// the beam pattern and accumulated per range bin, with labels when asked for.
#include "hal/sim/sonar_renderer_detail.hpp"

namespace orthosonar::sim {

using namespace detail;

namespace {

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

Scratch& detail::scratch(SonarMount mount) {
  thread_local Scratch s[2];
  return s[mount == SonarMount::kHorizontal ? 0 : 1];
}

std::vector<float> SonarRenderer::accumulate(const SE3& T_W_S, SonarMount mount, Time stamp, uint32_t ping_id,
                                                  bool with_labels, SonarRender& out) const {
  const Impl& m = *impl_;
  const HeadTables& h = m.heads[static_cast<int>(mount)];
  const SonarModelConfig& cfg = m.cfg;
  const int rows = h.geo.range_bins, cols = h.geo.beams;
  const size_t npix = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  Scratch& sc = scratch(mount);
  std::vector<float> accum = std::move(sc.accum);
  take_zeroed(accum, npix);
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
  const bool footprint = cfg.range_footprint;
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
        auto put = [&](int b, float c) {
          const size_t px = static_cast<size_t>(b) * static_cast<size_t>(cols) + static_cast<size_t>(j);
          acc[px] += c;
          touch(b, j);
          if (with_labels && c > best[px]) {
            best[px] = c;
            lab_sem[px] = m.semantic[tri];
            lab_obj[px] = m.object[tri];
          }
        };
        if (footprint) {
          // The ray stands for its elevation stratum [phi + dlo, phi + dhi] (phi jittered
          // within it). The direction at phi + delta is cos(delta) d + sin(delta) e, so on
          // the hit's plane (normal n; A = n . d, B = n . e) the range there is
          // r(delta) = t A / (cos(delta) A + sin(delta) B), monotonic over the stratum.
          // Where the denominator changes sign the stratum's edge leaves the plane: cut at
          // the fan's range. The echo is shared over the bins of [r_lo, r_hi] by overlap;
          // a footprint within a hundredth of a bin stays in the hit's bin.
          const Eigen::Vector3f e = R * Eigen::Vector3f(h.ex[ray], h.ey[ray], h.ez[ray]);
          const Eigen::Vector3f& n = m.normal[tri];
          const float A = n.dot(d), B = n.dot(e);
          const float den_lo = h.lo_cos[ray] * A + h.lo_sin[ray] * B, den_hi = h.hi_cos[ray] * A + h.hi_sin[ray] * B;
          const float r_at_lo = den_lo * A > 0.0f ? t * A / den_lo : tfar;
          const float r_at_hi = den_hi * A > 0.0f ? t * A / den_hi : tfar;
          const float r_lo = std::min({t, r_at_lo, r_at_hi}), r_hi = std::min(std::max({t, r_at_lo, r_at_hi}), tfar);
          const float u_lo = r_lo * inv_res - 0.5f, u_hi = r_hi * inv_res - 0.5f;
          const float len = u_hi - u_lo;
          if (!(len > 0.01f)) {
            put(bin, contrib);
          } else {
            const int b_lo = std::max(0, static_cast<int>(std::floor(u_lo)));
            const int b_hi = std::min(rows - 1, static_cast<int>(std::floor(u_hi)));
            const float per = contrib / len;
            for (int k = b_lo; k <= b_hi; ++k) {
              const float kf = static_cast<float>(k);
              const float overlap = std::min(u_hi, kf + 1.0f) - std::max(u_lo, kf);
              if (overlap > 0.0f) put(k, per * overlap);
            }
          }
        } else {
          put(bin, contrib);
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
    take_zeroed(spread, npix);
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
    // The unspread echoes go back to the scratch cleared; the returned image may be
    // non-zero within the pattern's reach of a deposit (render() clears that).
    clear_rows(accum, cols, col_lo, col_hi, 0);
    accum.swap(spread);
    sc.spread = std::move(spread);
  }
  return accum;
}

}  // namespace orthosonar::sim
