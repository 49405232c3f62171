#pragma once
// Submaps (SPEC §6, paper §VII): every fused cloud z_t observed between keyframe k and
// k+1 is stored in keyframe k's frame as T_k_t · z_t with T_k_t = DR(k)⁻¹ · DR(t), so
// S_k = ∪ T_k_t z_t, and the map is ∪ T_W_k · S_k for the current SLAM poses T_W_k.
// Moving a keyframe moves its submap rigidly; no image is ever reprocessed.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace orthosonar::mapping {

class SubmapStore {
 public:
  // Opens submap k (ids must be 0, 1, 2, ... in order) at its DR pose; closes the previous.
  void begin(int keyframe_id, const SE3& T_W_K_dr);
  // Stores a cloud (points in V) observed at DR pose T_W_V_dr into the open submap.
  // Returns false (and stores nothing) when no submap is open yet.
  bool add(const SE3& T_W_V_dr, const std::vector<Eigen::Vector3f>& p_V);
  int size() const { return static_cast<int>(submaps_.size()); }
  // Points of submap k in its keyframe frame, in insertion order.
  const std::vector<Eigen::Vector3f>& points_K(int k) const;
  // ∪ T_W_K[k] · S_k, submap by submap. Submaps without a pose (k >= T_W_K.size()) are
  // placed by their DR pose.
  std::vector<Eigen::Vector3f> assemble(const std::vector<SE3>& T_W_K) const;
  size_t total_points() const;
  int64_t memory_bytes() const;  // the points and the submaps' poses (core/memory.hpp)

 private:
  struct Submap {
    SE3 T_W_K_dr = SE3::Identity();
    SE3 T_K_W_dr = SE3::Identity();
    std::vector<Eigen::Vector3f> p_K;
  };
  std::vector<Submap> submaps_;
};

// Applies T to every point (double arithmetic, stored as float).
void transform_append(const SE3& T, const std::vector<Eigen::Vector3f>& in,
                      std::vector<Eigen::Vector3f>& out);

}  // namespace orthosonar::mapping
