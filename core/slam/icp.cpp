#include "core/slam/icp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace orthosonar::slam {

Grid2d::Grid2d(const std::vector<Eigen::Vector2d>& points, double cell_m)
    : points_(&points), cell_m_(cell_m) {
  entries_.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    entries_.push_back({static_cast<long long>(std::floor(points[i].x() / cell_m)),
                        static_cast<long long>(std::floor(points[i].y() / cell_m)),
                        static_cast<long>(i)});
  }
  std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
    if (a.cx != b.cx) return a.cx < b.cx;
    if (a.cy != b.cy) return a.cy < b.cy;
    return a.index < b.index;
  });
  if (entries_.empty() || entries_.size() >= std::numeric_limits<uint32_t>::max()) return;
  long long max_cx = entries_.front().cx, max_cy = entries_.front().cy;
  min_cx_ = entries_.front().cx;
  min_cy_ = entries_.front().cy;
  for (const Entry& e : entries_) {
    min_cy_ = std::min(min_cy_, e.cy);
    max_cy = std::max(max_cy, e.cy);
    max_cx = std::max(max_cx, e.cx);
  }
  // A dense table only where it stays small next to the points (no overflow: each side is
  // checked before the product).
  const long long kMaxSide = 1 << 16;
  const long long max_cells = std::max<long long>(1 << 16, 16 * static_cast<long long>(entries_.size()));
  if (max_cx - min_cx_ >= kMaxSide || max_cy - min_cy_ >= kMaxSide) return;
  nx_ = max_cx - min_cx_ + 1;
  ny_ = max_cy - min_cy_ + 1;
  if (nx_ * ny_ > max_cells) return;
  // Entries are sorted by (cx, cy), which is the order of k: starts_[k] is the first entry
  // whose cell index is >= k.
  starts_.assign(static_cast<size_t>(nx_ * ny_ + 1), 0);
  size_t e = 0;
  for (long long k = 0; k <= nx_ * ny_; ++k) {
    while (e < entries_.size() && (entries_[e].cx - min_cx_) * ny_ + (entries_[e].cy - min_cy_) < k) ++e;
    starts_[static_cast<size_t>(k)] = static_cast<uint32_t>(e);
  }
}

template <class F>
void Grid2d::for_cell(long long cx, long long cy, F&& f) const {
  if (!starts_.empty()) {
    const long long dx = cx - min_cx_, dy = cy - min_cy_;
    if (dx < 0 || dy < 0 || dx >= nx_ || dy >= ny_) return;
    const auto k = static_cast<size_t>(dx * ny_ + dy);
    for (uint32_t i = starts_[k]; i < starts_[k + 1]; ++i) f(entries_[i].index);
    return;
  }
  auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(cx, cy),
                             [](const Entry& e, const std::pair<long long, long long>& k) {
                               return e.cx != k.first ? e.cx < k.first : e.cy < k.second;
                             });
  for (; it != entries_.end() && it->cx == cx && it->cy == cy; ++it) f(it->index);
}

long Grid2d::nearest(const Eigen::Vector2d& q, double max_dist, double* dist2) const {
  const auto r = static_cast<long long>(std::ceil(max_dist / cell_m_));
  const auto qx = static_cast<long long>(std::floor(q.x() / cell_m_));
  const auto qy = static_cast<long long>(std::floor(q.y() / cell_m_));
  long best = -1;
  double best_d2 = max_dist * max_dist;
  for (long long cx = qx - r; cx <= qx + r; ++cx) {
    for (long long cy = qy - r; cy <= qy + r; ++cy) {
      for_cell(cx, cy, [&](long i) {
        const double d2 = ((*points_)[static_cast<size_t>(i)] - q).squaredNorm();
        if (d2 < best_d2 || (d2 == best_d2 && best >= 0 && i < best) ||
            (d2 == best_d2 && best < 0)) {
          best_d2 = d2;
          best = i;
        }
      });
    }
  }
  if (dist2 != nullptr) *dist2 = best_d2;
  return best;
}

template <class F>
void Grid2d::for_each_within(const Eigen::Vector2d& q, double radius, F&& f) const {
  const auto r = static_cast<long long>(std::ceil(radius / cell_m_));
  const auto qx = static_cast<long long>(std::floor(q.x() / cell_m_));
  const auto qy = static_cast<long long>(std::floor(q.y() / cell_m_));
  const double r2 = radius * radius;
  for (long long cx = qx - r; cx <= qx + r; ++cx) {
    for (long long cy = qy - r; cy <= qy + r; ++cy) {
      for_cell(cx, cy, [&](long i) {
        if (((*points_)[static_cast<size_t>(i)] - q).squaredNorm() <= r2) f(i);
      });
    }
  }
}

size_t Grid2d::count_within(const Eigen::Vector2d& q, double radius) const {
  size_t n = 0;
  for_each_within(q, radius, [&](long) { ++n; });
  return n;
}

std::vector<long> Grid2d::within(const Eigen::Vector2d& q, double radius) const {
  std::vector<long> out;
  for_each_within(q, radius, [&](long i) { out.push_back(i); });
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<Eigen::Vector2d> line_normal(const std::vector<Eigen::Vector2d>& target, const Grid2d& grid,
                                           size_t j, double radius_m, double line_ratio) {
  const auto nb = grid.within(target[j], radius_m);
  if (nb.size() < 3) return std::nullopt;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (long k : nb) mean += target[static_cast<size_t>(k)];
  mean /= static_cast<double>(nb.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (long k : nb) {
    const Eigen::Vector2d d = target[static_cast<size_t>(k)] - mean;
    cov += d * d.transpose();
  }
  // Closed-form eigen-decomposition of the symmetric 2x2 (no iterative solver).
  const double a = cov(0, 0), b = cov(0, 1), d = cov(1, 1);
  const double half_tr = 0.5 * (a + d), disc = std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  const double small = half_tr - disc, large = half_tr + disc;
  if (!(large > 0.0 && small <= line_ratio * large)) return std::nullopt;
  // Eigenvector of the smaller eigenvalue: (b, small - a), or (small - d, b).
  Eigen::Vector2d v(b, small - a);
  if (v.squaredNorm() < 1e-24) v = Eigen::Vector2d(small - d, b);
  if (v.squaredNorm() < 1e-24) v = Eigen::Vector2d(a <= d ? 1.0 : 0.0, a <= d ? 0.0 : 1.0);
  return v.normalized();
}

FitInformation icp_fit_information(const std::vector<Eigen::Vector2d>& source,
                                   const std::vector<Eigen::Vector2d>& target, const SE2& T,
                                   const FitInformationConfig& config) {
  FitInformation out;
  if (source.empty() || target.empty()) return out;
  const Grid2d grid(target, std::max(config.max_correspondence_m, config.normal_radius_m));
  const double c = std::cos(T.theta), s = std::sin(T.theta);
  for (const Eigen::Vector2d& p : source) {
    const Eigen::Vector2d q = T * p;
    const long j = grid.nearest(q, config.max_correspondence_m);
    if (j < 0) continue;
    ++out.correspondences;
    // d(T p)/dθ = R(θ) perp(p), perp(p) = (-p_y, p_x).
    const Eigen::Vector2d dtheta(-s * p.x() - c * p.y(), c * p.x() - s * p.y());
    Eigen::Matrix<double, 2, 3> J;
    J << 1.0, 0.0, dtheta.x(), 0.0, 1.0, dtheta.y();
    const std::optional<Eigen::Vector2d> normal =
        line_normal(target, grid, static_cast<size_t>(j), config.normal_radius_m, config.line_ratio);
    if (normal) {
      const Eigen::RowVector3d row = normal->transpose() * J;
      out.hessian += row.transpose() * row;
      ++out.line_rows;
    } else {
      out.hessian += J.transpose() * J;
    }
  }
  return out;
}

namespace {

constexpr double kRotationScaleM = 10.0;   // metres per radian when comparing steps
constexpr double kCosAccelerate = 0.985;   // successive steps within 10 degrees
constexpr double kMaxAccelerate = 25.0;    // at most 25 steps ahead

struct Match {
  double d2;
  size_t source;
  size_t target;
};

// Closed-form 2D rigid alignment (Kabsch/Umeyama without scale): T with T * s ≈ t.
SE2 align(const std::vector<Eigen::Vector2d>& src, const std::vector<Eigen::Vector2d>& tgt,
          const std::vector<Match>& m, bool fix_rotation) {
  Eigen::Vector2d ms = Eigen::Vector2d::Zero(), mt = Eigen::Vector2d::Zero();
  for (const Match& c : m) {
    ms += src[c.source];
    mt += tgt[c.target];
  }
  const double n = static_cast<double>(m.size());
  ms /= n;
  mt /= n;
  if (fix_rotation) return SE2{mt.x() - ms.x(), mt.y() - ms.y(), 0.0};
  double sxx = 0.0, sxy = 0.0;  // sum of dot and cross products of centred pairs
  for (const Match& c : m) {
    const Eigen::Vector2d a = src[c.source] - ms, b = tgt[c.target] - mt;
    sxx += a.x() * b.x() + a.y() * b.y();
    sxy += a.x() * b.y() - a.y() * b.x();
  }
  const double theta = std::atan2(sxy, sxx);
  SE2 T{0.0, 0.0, theta};
  const Eigen::Vector2d t = mt - T.rotation() * ms;
  T.x = t.x();
  T.y = t.y();
  return T;
}

// One Gauss-Newton step of the point-to-line metric (Censi 2008) about the moved source:
// the increment T with T * moved ≈ target along each line's normal (one row), or in both
// directions where the target is not a line (two rows). A wall leaves its along-direction
// unobserved; the small damping keeps the step there at zero (the initial guess's).
SE2 align_point_to_line(const std::vector<Eigen::Vector2d>& moved, const std::vector<Eigen::Vector2d>& tgt,
                        const std::vector<Match>& m, const std::vector<std::optional<Eigen::Vector2d>>& normals,
                        bool fix_rotation) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const Match& c : m) {
    const Eigen::Vector2d& p = moved[c.source];
    const Eigen::Vector2d r = p - tgt[c.target];
    Eigen::Matrix<double, 2, 3> J;
    J << 1.0, 0.0, -p.y(), 0.0, 1.0, p.x();
    if (const auto& n = normals[c.target]) {
      const Eigen::RowVector3d row = n->transpose() * J;
      H += row.transpose() * row;
      g += row.transpose() * n->dot(r);
    } else {
      H += J.transpose() * J;
      g += J.transpose() * r;
    }
  }
  if (fix_rotation) {
    H.row(2).setZero();
    H.col(2).setZero();
    H(2, 2) = 1.0;
    g(2) = 0.0;
  }
  H += 1e-9 * (H.trace() + 1.0) * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d d = H.ldlt().solve(-g);
  if (!d.allFinite()) return SE2{};
  return SE2{d.x(), d.y(), d.z()};
}

}  // namespace

IcpResult icp_2d(const std::vector<Eigen::Vector2d>& source,
                 const std::vector<Eigen::Vector2d>& target, const SE2& initial,
                 const IcpConfig& config) {
  IcpResult result;
  result.T_target_source = initial;
  if (source.empty() || target.empty()) return result;
  const Grid2d grid(target, config.max_correspondence_m);
  const auto keep_max = static_cast<size_t>(
      std::floor(config.trim_fraction * static_cast<double>(source.size())));
  std::vector<Match> matches;
  matches.reserve(source.size());
  SE2 T = initial;
  Eigen::Vector3d prev_step = Eigen::Vector3d::Zero();
  const bool to_line = config.metric == IcpConfig::Metric::kPointToLine;
  // Point-to-line: each target point's line normal, found the first time it is matched.
  std::vector<std::optional<Eigen::Vector2d>> normals;
  std::vector<uint8_t> have_normal;
  if (to_line) {
    normals.resize(target.size());
    have_normal.assign(target.size(), 0);
  }
  std::vector<double> d2s;
  const auto trimmed_cost = [&](const SE2& X) {
    d2s.clear();
    for (const auto& p : source) {
      double d2 = 0.0;
      if (grid.nearest(X * p, config.max_correspondence_m, &d2) >= 0) d2s.push_back(d2);
    }
    std::sort(d2s.begin(), d2s.end());
    const double cap = config.max_correspondence_m * config.max_correspondence_m;
    double sum = 0.0;  // a source point without a match costs the full gate
    for (size_t i = 0; i < keep_max; ++i) sum += i < d2s.size() ? d2s[i] : cap;
    return sum;
  };
  for (int it = 0; it < config.max_iterations; ++it) {
    matches.clear();
    for (size_t i = 0; i < source.size(); ++i) {
      double d2 = 0.0;
      const long j = grid.nearest(T * source[i], config.max_correspondence_m, &d2);
      if (j >= 0) matches.push_back({d2, i, static_cast<size_t>(j)});
    }
    // Trimmed ICP: keep the closest fraction of the source's points.
    std::sort(matches.begin(), matches.end(), [](const Match& a, const Match& b) {
      return a.d2 != b.d2 ? a.d2 < b.d2 : a.source < b.source;
    });
    size_t keep = std::min(keep_max, matches.size());
    const double floor2 = config.trim_floor_m * config.trim_floor_m;
    while (keep < matches.size() && matches[keep].d2 <= floor2) ++keep;
    matches.resize(keep);
    result.iterations = it + 1;
    if (matches.size() < std::max<size_t>(config.min_correspondences, 3)) {
      result.converged = false;
      result.inliers = matches.size();
      result.T_target_source = T;
      return result;
    }
    // Solve for the increment that maps the currently transformed source onto the target.
    std::vector<Eigen::Vector2d> moved(source.size());
    for (const Match& m : matches) moved[m.source] = T * source[m.source];
    if (to_line) {
      for (const Match& m : matches) {
        if (have_normal[m.target]) continue;
        normals[m.target] = line_normal(target, grid, m.target, config.line_radius_m, config.line_ratio);
        have_normal[m.target] = 1;
      }
    }
    const SE2 dT = to_line ? align_point_to_line(moved, target, matches, normals, config.fix_rotation)
                           : align(moved, target, matches, config.fix_rotation);
    const SE2 before = T;
    T = dT * T;
    // Besl & McKay's accelerated ICP: when successive steps in (x, y, L·θ) point the same
    // way and shrink, jump ahead by the geometric tail of the sequence (capped). Plain
    // point-to-point ICP crawls on sparse sonar clouds and stops near its initial guess.
    if (config.accelerate && !to_line) {  // Gauss-Newton on lines does not crawl
      const Eigen::Vector3d step(T.x - before.x, T.y - before.y,
                                 kRotationScaleM * wrap_angle(T.theta - before.theta));
      const double n = step.norm(), np = prev_step.norm();
      if (n > 0.0 && np > 0.0 && n < np && step.dot(prev_step) > kCosAccelerate * n * np) {
        const double rho = n / np;
        const double ahead = std::min(rho / (1.0 - rho), kMaxAccelerate);
        const SE2 jump{T.x + ahead * step.x(), T.y + ahead * step.y(),
                       wrap_angle(T.theta + ahead * step.z() / kRotationScaleM)};
        // Only when it lowers the trimmed cost (the jump must not throw the fit away).
        if (trimmed_cost(jump) < trimmed_cost(T)) T = jump;
        prev_step.setZero();  // two plain steps before the next jump
      } else {
        prev_step = step;
      }
    }
    double sum = 0.0;
    for (const Match& m : matches) sum += (T * source[m.source] - target[m.target]).squaredNorm();
    result.inliers = matches.size();
    result.rmse = std::sqrt(sum / static_cast<double>(matches.size()));
    if (std::hypot(dT.x, dT.y) < config.converged_translation_m &&
        std::abs(dT.theta) < config.converged_rotation_rad) {
      result.converged = true;
      break;
    }
  }
  result.T_target_source = T;
  return result;
}

}  // namespace orthosonar::slam
