#include "core/mapping/submap.hpp"

#include "core/memory.hpp"

#include <algorithm>
#include <cassert>

namespace orthosonar::mapping {

void transform_append(const SE3& T, const std::vector<Eigen::Vector3f>& in,
                      std::vector<Eigen::Vector3f>& out) {
  // Float arithmetic with the rotation and translation rounded once: ~1e-6 m error at
  // 100 m, far below the 0.1 m voxel, and fast enough for every timestep.
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  // Grow geometrically (an exact reserve per call would copy the whole vector every step).
  if (out.capacity() < out.size() + in.size()) out.reserve(std::max(2 * out.capacity(), out.size() + in.size()));
  for (const auto& p : in) out.push_back(R * p + t);
}

void SubmapStore::begin(int keyframe_id, const SE3& T_W_K_dr) {
  assert(keyframe_id == size());
  (void)keyframe_id;
  Submap s;
  s.T_W_K_dr = T_W_K_dr;
  s.T_K_W_dr = T_W_K_dr.inverse();
  submaps_.push_back(std::move(s));
}

bool SubmapStore::add(const SE3& T_W_V_dr, const std::vector<Eigen::Vector3f>& p_V) {
  if (submaps_.empty()) return false;
  Submap& s = submaps_.back();
  const SE3 T_K_V = s.T_K_W_dr * T_W_V_dr;  // T_k_t = DR(k)^-1 DR(t)
  transform_append(T_K_V, p_V, s.p_K);
  return true;
}

const std::vector<Eigen::Vector3f>& SubmapStore::points_K(int k) const {
  return submaps_[static_cast<size_t>(k)].p_K;
}

std::vector<Eigen::Vector3f> SubmapStore::assemble(const std::vector<SE3>& T_W_K) const {
  std::vector<Eigen::Vector3f> out;
  out.reserve(total_points());
  for (size_t k = 0; k < submaps_.size(); ++k) {
    const SE3& T = k < T_W_K.size() ? T_W_K[k] : submaps_[k].T_W_K_dr;
    transform_append(T, submaps_[k].p_K, out);
  }
  return out;
}

int64_t SubmapStore::memory_bytes() const {
  int64_t n = heap_bytes(submaps_);
  for (const auto& s : submaps_) n += heap_bytes(s.p_K);
  return n;
}

size_t SubmapStore::total_points() const {
  size_t n = 0;
  for (const auto& s : submaps_) n += s.p_K.size();
  return n;
}

}  // namespace orthosonar::mapping
