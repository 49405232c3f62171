// The sonar renderer's per-mount tables: the device's bearing table and fan, the
// stratified ray pattern with its aperture weights, the range gains (spreading,
// absorption, TVG) and the azimuth beam pattern as a scatter kernel.
#include "hal/sim/sonar_renderer_detail.hpp"

namespace orthosonar::sim::detail {
namespace {

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

}  // namespace

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
  const bool footprint = cfg.range_footprint;  // its per-ray tables only when it is used
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
        if (footprint) {
          h.ex.push_back(static_cast<float>(-std::sin(ph) * std::cos(th)));
          h.ey.push_back(static_cast<float>(-std::sin(ph) * std::sin(th)));
          h.ez.push_back(static_cast<float>(std::cos(ph)));
          const double stratum_lo = -0.5 * ap + ap * e / E, stratum_hi = -0.5 * ap + ap * (e + 1) / E;
          h.lo_cos.push_back(static_cast<float>(std::cos(stratum_lo - ph)));
          h.lo_sin.push_back(static_cast<float>(std::sin(stratum_lo - ph)));
          h.hi_cos.push_back(static_cast<float>(std::cos(stratum_hi - ph)));
          h.hi_sin.push_back(static_cast<float>(std::sin(stratum_hi - ph)));
        }
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
      if (footprint) {
        h.ex.push_back(0.0f);
        h.ey.push_back(0.0f);
        h.ez.push_back(1.0f);
        h.lo_cos.push_back(1.0f);
        h.lo_sin.push_back(0.0f);
        h.hi_cos.push_back(1.0f);
        h.hi_sin.push_back(0.0f);
      }
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
    h.reach = h.main_half;
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
        h.reach = std::max(h.reach, std::abs(k));
      }
    }
    // Side lobes matter only where they can reach a tenth of the noise floor.
    for (int i = 0; i < h.geo.range_bins; ++i) {
      const double noise = std::max(cfg.noise_floor, 1e-12) * h.row_noise[static_cast<size_t>(i)];
      h.side_min.push_back(static_cast<float>(0.1 * noise / (std::max<double>(h.side_peak, 1e-30) * h.row_signal[static_cast<size_t>(i)])));
    }
  }
}

}  // namespace orthosonar::sim::detail
