#include "core/perception/fusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/perception/assignment.hpp"
#include "core/perception/elevation.hpp"

namespace orthosonar::perception {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The smallest intensity v with #(x <= v) >= q * n, by histogram (O(n), no sort).
double percentile(const SonarPing& p, double q) {
  const size_t n = static_cast<size_t>(p.rows) * p.cols;
  if (n == 0) return 0.0;
  std::vector<uint32_t> hist(p.bytes_per_pixel == 1 ? 256 : 65536, 0);
  if (p.bytes_per_pixel == 1) {
    // Four interleaved tallies: speckle repeats a few values, and one table's increments of
    // the same bin wait on each other (this loop was 15 % of a full-resolution replay).
    uint32_t part[4][256] = {};
    const uint8_t* px = p.image.data();
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
      ++part[0][px[i]];
      ++part[1][px[i + 1]];
      ++part[2][px[i + 2]];
      ++part[3][px[i + 3]];
    }
    for (; i < n; ++i) ++part[0][px[i]];
    for (size_t v = 0; v < 256; ++v) hist[v] = part[0][v] + part[1][v] + part[2][v] + part[3][v];
  } else {
    for (size_t i = 0; i < n; ++i) ++hist[static_cast<size_t>(p.image[2 * i] | (p.image[2 * i + 1] << 8))];
  }
  const double need = std::clamp(q, 0.0, 1.0) * static_cast<double>(n);
  uint64_t acc = 0;
  for (size_t v = 0; v < hist.size(); ++v) {
    acc += hist[v];
    if (static_cast<double>(acc) >= need && acc > 0) return static_cast<double>(v);
  }
  return static_cast<double>(hist.size() - 1);
}

// Per-pair normaliser: divide by the percentile, clamp to 1 (SPEC §4.3). A dark image
// (percentile 0) falls back to its maximum so that structure still spans [0, 1].
double normaliser(const SonarPing& p, double q) {
  double v = percentile(p, q);
  if (v <= 0.0) v = percentile(p, 1.0);
  return v > 0.0 ? 1.0 / v : 1.0;
}

bool valid(const SonarPing& p) {
  const size_t n = static_cast<size_t>(p.rows) * p.cols * p.bytes_per_pixel;
  return p.rows > 0 && p.cols > 0 && p.image.size() >= n && p.bearings_rad.size() >= p.cols &&
         p.range_resolution_m > 0.0;
}

struct Candidate {
  int row, col;
  long bin;         // common range bin
  float intensity;  // raw intensity of the detection (normalised where a point is made)
};

// Normalised patch×patch values around (row, col), zero outside the image.
// Layout: patch[(du + h) * side + (dv + h)], du along rows (range), dv along columns.
void patch_of(const SonarPing& p, int row, int col, int half, double inv, float* out) {
  const int side = 2 * half + 1;
  for (int du = -half; du <= half; ++du) {
    for (int dv = -half; dv <= half; ++dv) {
      const int r = row + du, c = col + dv;
      float x = 0.0f;
      if (r >= 0 && r < p.rows && c >= 0 && c < p.cols)
        x = static_cast<float>(std::min(1.0, p.at(r, c) * inv));
      out[(du + half) * side + (dv + half)] = x;
    }
  }
}

// rot90 of a v patch, counter-clockwise as displayed with row 0 on top (numpy's
// np.rot90(k=1), as in the authors' Python): out(a, b) = in(b, side-1-a). In offsets:
// rot(du, dv) = v(range offset dv, φ offset −du). So the h range axis meets the v φ axis
// (reversed) and the h θ axis meets the v range axis. See docs/PERCEPTION.md.
void rot90(const float* in, int side, float* out) {
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) out[a * side + b] = in[b * side + (side - 1 - a)];
}

}  // namespace

double RowMedians::operator()(int row) {
  double& m = median_[static_cast<size_t>(row)];
  if (m >= 0.0) return m;
  const size_t k = static_cast<size_t>(p_.cols - 1) / 2;  // the lower median's rank
  if (p_.bytes_per_pixel == 1) {
    // 8-bit: the rank by counting, the value nth_element finds without its data-dependent
    // branches (nth_element here was 3.6 % of a full-resolution replay).
    uint32_t count[256] = {};
    const uint8_t* line = p_.image.data() + static_cast<size_t>(row) * p_.cols;
    for (int c = 0; c < p_.cols; ++c) ++count[line[c]];
    size_t acc = 0;
    int v = 0;
    for (; v < 255; ++v) {
      acc += count[v];
      if (acc > k) break;
    }
    m = v;
    return m;
  }
  scratch_.resize(p_.cols);
  for (int c = 0; c < p_.cols; ++c) scratch_[static_cast<size_t>(c)] = p_.at(row, c);
  const auto mid = scratch_.begin() + (p_.cols - 1) / 2;
  std::nth_element(scratch_.begin(), mid, scratch_.end());
  m = *mid;
  return m;
}

double RowMedians::local_floor(int row, int half) {
  double f = 0.0;
  for (int r = std::max(0, row - half); r <= std::min(p_.rows - 1, row + half); ++r) f = std::max(f, (*this)(r));
  return f;
}

std::vector<Detection> cfar_detect_within(const SonarPing& p, const CfarConfig& cfg, double max_abs_bearing_rad) {
  const auto& b = p.bearings_rad;
  int c0 = p.cols, c1 = -1;
  for (int c = 0; c < p.cols; ++c) {
    if (std::abs(b[static_cast<size_t>(c)]) <= max_abs_bearing_rad) {
      c0 = std::min(c0, c);
      c1 = std::max(c1, c);
    }
  }
  if (c1 < c0) return {};
  // A cell's training and guard cells, and its neighbours for min_neighbours, lie within
  // guard + train + 1 columns: with that margin the strip gives the full image's answer.
  const int margin = std::max(0, cfg.guard_cells) + std::max(0, cfg.train_cells) + 1;
  const int s0 = std::max(0, c0 - margin), s1 = std::min(p.cols - 1, c1 + margin);
  std::vector<Detection> out;
  if (s0 == 0 && s1 == p.cols - 1) {
    out = cfar_detect(p, cfg);
  } else {
    SonarPing strip;
    strip.rows = p.rows;
    strip.cols = static_cast<uint16_t>(s1 - s0 + 1);
    strip.bytes_per_pixel = p.bytes_per_pixel;
    strip.range_resolution_m = p.range_resolution_m;
    strip.bearings_rad.assign(b.begin() + s0, b.begin() + s1 + 1);
    const size_t bpp = p.bytes_per_pixel, w = static_cast<size_t>(strip.cols) * bpp;
    strip.image.resize(static_cast<size_t>(p.rows) * w);
    for (int r = 0; r < p.rows; ++r) {
      const uint8_t* src = p.image.data() + (static_cast<size_t>(r) * p.cols + static_cast<size_t>(s0)) * bpp;
      std::copy(src, src + w, strip.image.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(r) * w));
    }
    out = cfar_detect(strip, cfg);
    for (Detection& d : out) d.col += s0;
  }
  std::erase_if(out, [&](const Detection& d) { return d.col < c0 || d.col > c1; });
  return out;
}

SE3 default_T_V_h() { return se3_from_xyz_rpy(0.35, 0.0, 0.0, 0.0, 0.0, 0.0); }
SE3 default_T_V_v() { return se3_from_xyz_rpy(0.35, 0.0, -0.10, std::numbers::pi / 2, 0.0, 0.0); }

FusionResult fuse_pair(const SonarPing& h, const SonarPing& v, const FusionConfig& config) {
  FusionResult res;
  if (!valid(h) || !valid(v)) return res;
  res.detections_h = cfar_detect(h, config.cfar_h);                    // step 1
  const double lim = config.overlap_deg * kDeg + 1e-9;                   // step 2
  // Only the overlap of the vertical image is ever used: search just that strip (the same
  // detections there as a whole-image search; docs/PERCEPTION.md "Field images").
  res.detections_v = cfar_detect_within(v, config.cfar_v, lim);
  const double res_c = std::max(h.range_resolution_m, v.range_resolution_m);
  // Step 3's normalisers cost a pass over each whole image: computed when the first range
  // bin has candidates on both images (most pairs of a field mission have none).
  double inv_h = 0.0, inv_v = 0.0;
  bool normalised = false;
  const double peak_window = config.peak_window_deg * kDeg;
  RowMedians medians_h(h), medians_v(v);
  auto gather = [&](const SonarPing& p, const std::vector<Detection>& dets, RowMedians& medians) {
    std::vector<Candidate> out;
    const auto& b = p.bearings_rad;
    for (size_t k = 0; k < dets.size(); ++k) {
      const Detection& d = dets[k];
      if (std::abs(b[static_cast<size_t>(d.col)]) > lim) continue;
      if (peak_window > 0.0) {
        // Row-major list: the row's other detections are the neighbours in the list. Ties
        // keep the lower column.
        bool peak = true;
        for (size_t n = k; n-- > 0 && dets[n].row == d.row &&
                           std::abs(b[static_cast<size_t>(d.col)] - b[static_cast<size_t>(dets[n].col)]) <= peak_window;) {
          if (dets[n].intensity >= d.intensity) peak = false;
        }
        for (size_t n = k + 1; peak && n < dets.size() && dets[n].row == d.row &&
                               std::abs(b[static_cast<size_t>(dets[n].col)] - b[static_cast<size_t>(d.col)]) <= peak_window;
             ++n) {
          if (dets[n].intensity > d.intensity) peak = false;
        }
        if (!peak) continue;
      }
      if (config.noise_floor_factor > 0.0 &&
          d.intensity < config.noise_floor_factor * medians.local_floor(d.row, config.noise_floor_rows))
        continue;
      const long bin = std::lround(p.range_of_row(d.row) / res_c);
      out.push_back({d.row, d.col, bin, d.intensity});
    }
    return out;  // row-major, so bins are non-decreasing
  };
  const std::vector<Candidate> ch = gather(h, res.detections_h, medians_h);
  const std::vector<Candidate> cv = gather(v, res.detections_v, medians_v);
  res.candidates_h = ch.size();
  res.candidates_v = cv.size();

  const int half = std::max(0, config.patch / 2);
  const int side = 2 * half + 1, area = side * side;
  std::vector<float> ph, pv, tmp(static_cast<size_t>(area));
  size_t i0 = 0, j0 = 0;
  while (i0 < ch.size() && j0 < cv.size()) {                             // step 4
    if (ch[i0].bin < cv[j0].bin) { ++i0; continue; }
    if (cv[j0].bin < ch[i0].bin) { ++j0; continue; }
    const long bin = ch[i0].bin;
    size_t i1 = i0, j1 = j0;
    while (i1 < ch.size() && ch[i1].bin == bin) ++i1;
    while (j1 < cv.size() && cv[j1].bin == bin) ++j1;
    const auto nh = static_cast<Eigen::Index>(i1 - i0), nv = static_cast<Eigen::Index>(j1 - j0);
    ++res.subproblems;
    if (!normalised) {                                                   // step 3
      inv_h = normaliser(h, config.normalise_percentile);
      inv_v = normaliser(v, config.normalise_percentile);
      normalised = true;
    }
    ph.assign(static_cast<size_t>(nh * area), 0.0f);
    pv.assign(static_cast<size_t>(nv * area), 0.0f);
    for (Eigen::Index i = 0; i < nh; ++i) {
      const Candidate& c = ch[i0 + static_cast<size_t>(i)];
      patch_of(h, c.row, c.col, half, inv_h, ph.data() + i * area);
    }
    for (Eigen::Index j = 0; j < nv; ++j) {
      const Candidate& c = cv[j0 + static_cast<size_t>(j)];
      patch_of(v, c.row, c.col, half, inv_v, tmp.data());
      if (config.rotate_v_patch) {
        rot90(tmp.data(), side, pv.data() + j * area);
      } else {
        std::copy(tmp.begin(), tmp.end(), pv.begin() + j * area);
      }
    }
    Eigen::MatrixXd cost(nh, nv);                                        // step 5, Eq. 5
    for (Eigen::Index i = 0; i < nh; ++i) {
      const float* a = ph.data() + i * area;
      for (Eigen::Index j = 0; j < nv; ++j) {
        const float* b = pv.data() + j * area;
        double s = 0.0;
        for (int k = 0; k < area; ++k) {
          const double d = static_cast<double>(a[k]) - static_cast<double>(b[k]);
          s += d * d;
        }
        cost(i, j) = std::sqrt(s);
      }
    }
    const std::vector<int> match = solve_assignment(cost);              // step 6
    const double total = cost.sum();
    const auto bin_first = static_cast<uint32_t>(res.bin_elevations_rad.size());
    bool bin_listed = false;
    for (Eigen::Index i = 0; i < nh; ++i) {
      const int j = match[static_cast<size_t>(i)];
      if (j < 0) continue;
      ++res.matches;
      double conf = 1.0;                                                 // step 7, Eq. 6
      if (nv > 1) {
        double second = std::numeric_limits<double>::infinity();
        for (Eigen::Index k = 0; k < nv; ++k)
          if (k != j) second = std::min(second, cost(i, k));
        conf = total > 0.0 ? (second - cost(i, j)) / total : 0.0;
      }
      if (conf < config.min_confidence) {
        ++res.culled_low_confidence;
        continue;
      }
      const Candidate& a = ch[i0 + static_cast<size_t>(i)];
      const Candidate& b = cv[j0 + static_cast<size_t>(j)];
      const double range = 0.5 * (h.range_of_row(a.row) + v.range_of_row(b.row));  // Eq. 3
      const double theta = h.bearings_rad[static_cast<size_t>(a.col)];
      double phi = v.bearings_rad[static_cast<size_t>(b.col)];
      FusedPoint fp;
      const RunExtent run = measure_run(h, a.row, a.col, a.intensity, medians_h, config);
      fp.run_near_m = static_cast<float>(run.near_m);
      fp.run_far_m = static_cast<float>(run.far_m);
      if (config.slope_run_ratio > 0.0) {
        if (const auto e = elevation_from_run(h, v, res.detections_v, a.row, run, range, lim, config)) {
          phi = *e;
          fp.elevation_from = FusedPoint::Elevation::sloped_face;
          ++res.sloped_face;
        }
      }
      fp.elevation_sigma_rad = static_cast<float>(
          elevation_sigma(config, fp.elevation_from, run.far_m - run.near_m, range, phi, lim));
      const Vec3 p_V = config.T_V_h * spherical_to_cartesian(range, theta, phi);    // Eq. 1
      fp.p_V = p_V.cast<float>();
      fp.range_m = static_cast<float>(range);
      fp.bearing_rad = static_cast<float>(theta);
      fp.elevation_rad = static_cast<float>(phi);
      fp.intensity_h = static_cast<float>(std::min(1.0, a.intensity * inv_h));
      fp.intensity_v = static_cast<float>(std::min(1.0, b.intensity * inv_v));
      fp.confidence = static_cast<float>(conf);
      if (!bin_listed) {
        for (Eigen::Index k = 0; k < nv; ++k)
          res.bin_elevations_rad.push_back(static_cast<float>(v.bearings_rad[static_cast<size_t>(cv[j0 + static_cast<size_t>(k)].col)]));
        bin_listed = true;
      }
      fp.bin_first = bin_first;
      fp.bin_count = static_cast<uint32_t>(nv);
      res.points.push_back(fp);
    }
    i0 = i1;
    j0 = j1;
  }
  return res;
}

std::vector<Eigen::Vector3d> points_V_at_elevation(const SonarPing& h, const std::vector<Detection>& dets,
                                                   const SE3& T_V_h, double elevation_rad) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(dets.size());
  for (const Detection& d : dets) {
    if (d.col < 0 || static_cast<size_t>(d.col) >= h.bearings_rad.size()) continue;
    out.push_back(T_V_h * spherical_to_cartesian(h.range_of_row(d.row),
                                                 h.bearings_rad[static_cast<size_t>(d.col)], elevation_rad));
  }
  return out;
}

std::vector<Eigen::Vector2d> planar_points_V(const SonarPing& h, const std::vector<Detection>& dets,
                                             const SE3& T_V_h) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(dets.size());
  for (const Eigen::Vector3d& p : points_V_at_elevation(h, dets, T_V_h, 0.0)) out.emplace_back(p.x(), p.y());
  return out;
}

}  // namespace orthosonar::perception
