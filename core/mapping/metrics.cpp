#include "core/mapping/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <tuple>

namespace orthosonar::mapping {
namespace {

struct Keyed {
  std::array<int64_t, 3> key;
  Eigen::Vector3f p;
};

bool keyed_before(const Keyed& a, const Keyed& b) {
  if (a.key != b.key) return a.key < b.key;
  return std::tie(a.p.x(), a.p.y(), a.p.z()) < std::tie(b.p.x(), b.p.y(), b.p.z());
}

std::vector<Keyed> keyed_points(const std::vector<Eigen::Vector3f>& points, double voxel_m) {
  std::vector<Keyed> k;
  k.reserve(points.size());
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    k.push_back({{static_cast<int64_t>(std::floor(static_cast<double>(p.x()) / voxel_m)),
                  static_cast<int64_t>(std::floor(static_cast<double>(p.y()) / voxel_m)),
                  static_cast<int64_t>(std::floor(static_cast<double>(p.z()) / voxel_m))},
                 p});
  }
  // A total order on (voxel, coordinates): sums below then run in an order that does not
  // depend on the input order.
  std::sort(k.begin(), k.end(), keyed_before);
  return k;
}

}  // namespace

std::vector<Eigen::Vector3f> voxel_centroids(const std::vector<Eigen::Vector3f>& points,
                                             const VoxelConfig& config) {
  const auto k = keyed_points(points, config.voxel_m);
  std::vector<Eigen::Vector3f> out;
  size_t i = 0;
  while (i < k.size()) {
    size_t j = i;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    while (j < k.size() && k[j].key == k[i].key) sum += k[j++].p.cast<double>();
    out.push_back((sum / static_cast<double>(j - i)).cast<float>());
    i = j;
  }
  return out;
}

int64_t coverage_voxels(const std::vector<Eigen::Vector3f>& points, const VoxelConfig& config) {
  const auto k = keyed_points(points, config.voxel_m);
  int64_t n = 0;
  for (size_t i = 0; i < k.size(); ++i)
    if (i == 0 || k[i].key != k[i - 1].key) ++n;
  return n;
}

AccuracyStats accuracy(const std::vector<Eigen::Vector3f>& points, const MeshDistance& mesh) {
  AccuracyStats s;
  if (mesh.empty() || points.empty()) return s;
  double sum = 0.0, sum_sq = 0.0;
  for (const auto& p : points) {
    const double d = mesh.distance(p.cast<double>());
    sum += d;
    sum_sq += d * d;
  }
  s.count = static_cast<int64_t>(points.size());
  s.mae_m = sum / static_cast<double>(s.count);
  s.rmse_m = std::sqrt(sum_sq / static_cast<double>(s.count));
  return s;
}

SE3 truth_pose(const TruthPose& p) {
  SE3 T = SE3::Identity();
  T.linear() = p.q_W_V.normalized().toRotationMatrix();
  T.translation() = p.p_W;
  return T;
}

namespace {

// The truth poses either side of `t` and t's fraction of the way from a to b (a == b when a
// truth pose has t's stamp); nullopt outside their span.
struct TruthBracket {
  const TruthPose* a;
  const TruthPose* b;
  double s;
};
std::optional<TruthBracket> truth_bracket(const std::vector<TruthPose>& truth, Time t) {
  if (truth.empty() || t < truth.front().stamp || t > truth.back().stamp) return std::nullopt;
  const auto it = std::lower_bound(truth.begin(), truth.end(), t,
                                   [](const TruthPose& p, Time s) { return p.stamp < s; });
  if (it->stamp == t) return TruthBracket{&*it, &*it, 0.0};
  const TruthPose& b = *it;
  const TruthPose& a = *(it - 1);
  return TruthBracket{&a, &b, static_cast<double>((t - a.stamp).ns()) / static_cast<double>((b.stamp - a.stamp).ns())};
}

}  // namespace

std::optional<Vec3> truth_position_at(const std::vector<TruthPose>& truth, Time t) {
  const auto br = truth_bracket(truth, t);
  if (!br) return std::nullopt;
  if (br->a == br->b) return br->a->p_W;
  return Vec3(br->a->p_W + br->s * (br->b->p_W - br->a->p_W));
}

std::optional<SE3> truth_pose_at(const std::vector<TruthPose>& truth, Time t) {
  const auto br = truth_bracket(truth, t);
  if (!br) return std::nullopt;
  if (br->a == br->b) return truth_pose(*br->a);
  return interpolate(truth_pose(*br->a), truth_pose(*br->b), br->s);
}

void TruthTrack::add(const TruthPose& p) {
  const auto it = std::lower_bound(poses_.begin(), poses_.end(), p.stamp,
                                   [](const TruthPose& q, Time s) { return q.stamp < s; });
  if (it != poses_.end() && it->stamp == p.stamp) {
    *it = p;
  } else {
    poses_.insert(it, p);
  }
}

std::optional<SE3> TruthTrack::at(Time t) const {
  if (poses_.empty()) return std::nullopt;
  if (t <= poses_.front().stamp) return truth_pose(poses_.front());
  if (t >= poses_.back().stamp) return truth_pose(poses_.back());
  return truth_pose_at(poses_, t);
}

void TruthTrack::forget_before(Time t) {
  const auto after = std::upper_bound(poses_.begin(), poses_.end(), t,
                                      [](Time s, const TruthPose& q) { return s < q.stamp; });
  if (after - poses_.begin() > 1) poses_.erase(poses_.begin(), after - 1);
}

std::optional<double> absolute_trajectory_error(const std::vector<StampedPosition>& estimate,
                                                const std::vector<TruthPose>& truth) {
  double sum_sq = 0.0;
  int64_t n = 0;
  for (const auto& e : estimate) {
    const auto p = truth_position_at(truth, e.stamp);
    if (!p) continue;
    sum_sq += (e.p_W - *p).squaredNorm();
    ++n;
  }
  if (n == 0) return std::nullopt;
  return std::sqrt(sum_sq / static_cast<double>(n));
}

std::optional<HeadingErrorStats> heading_error(const std::vector<StampedPose>& estimate,
                                               const std::vector<TruthPose>& truth) {
  HeadingErrorStats st;
  double sum = 0.0, sum_sq = 0.0;
  for (const auto& e : estimate) {
    const auto T = truth_pose_at(truth, e.stamp);
    if (!T) continue;
    const double d = wrap_angle(yaw_of(Quat(e.T_W_V.rotation())) - yaw_of(Quat(T->rotation()))) * 180.0 / std::numbers::pi;
    sum += d;
    sum_sq += d * d;
    st.max_abs_deg = std::max(st.max_abs_deg, std::abs(d));
    ++st.count;
  }
  if (st.count == 0) return std::nullopt;
  st.rms_deg = std::sqrt(sum_sq / static_cast<double>(st.count));
  st.mean_deg = sum / static_cast<double>(st.count);
  return st;
}

}  // namespace orthosonar::mapping
