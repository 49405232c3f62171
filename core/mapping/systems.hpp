#pragma once
// The two geometric mapping systems (SPEC §6): sonar fusion mapping (paper §V-C) and
// submapping (paper §VII). Inference mapping lives in core/inference.
#include <memory>
#include <string>
#include <vector>

#include "core/mapping/mapping_system.hpp"
#include "core/mapping/submap.hpp"

namespace orthosonar::mapping {

// Fused points of one pair in V, in the fusion's order.
std::vector<Eigen::Vector3f> fused_points_V(const perception::FusionResult& fused);

// Map = ∪ T_W_k · z_k: the fused cloud of each keyframe's own pair (the first pair at or
// after the keyframe's stamp), placed by the keyframe's SLAM pose.
class FusionMapping final : public MappingSystem {
 public:
  std::string name() const override { return "fusion"; }
  void on_pair(const PairInput& pair) override;
  void on_keyframe(const KeyframeInput& keyframe) override;
  void on_poses_updated(const std::vector<SE3>& T_W_K_slam) override;
  std::vector<Eigen::Vector3f> map_points_W() const override;
  std::optional<std::vector<Eigen::Vector3f>> map_points_W_with(const std::vector<SE3>& T_W_K) const override;
  std::vector<std::pair<std::string, RuntimeStats>> runtime() const override;
  void set_clock(const StageClock* clock) override { clock_ = clock; }
  int64_t memory_bytes() const override;

 private:
  std::vector<Eigen::Vector3f> assemble(const std::vector<SE3>& T_W_K) const;
  struct Frame {
    Time stamp;
    SE3 T_W_K_dr = SE3::Identity();
    bool has_cloud = false;
    std::vector<Eigen::Vector3f> p_K;  // the keyframe pair's points, in V at the keyframe
  };
  std::vector<Frame> frames_;
  std::vector<SE3> T_W_K_;
  const StageClock* clock_ = nullptr;
  RuntimeStats map_update_;
};

// Map = ∪ T_W_k · S_k with every fused pair stored in its keyframe's submap.
class Submapping final : public MappingSystem {
 public:
  std::string name() const override { return "submap"; }
  void on_pair(const PairInput& pair) override;
  void on_keyframe(const KeyframeInput& keyframe) override;
  void on_poses_updated(const std::vector<SE3>& T_W_K_slam) override;
  std::vector<Eigen::Vector3f> map_points_W() const override;
  std::optional<std::vector<Eigen::Vector3f>> map_points_W_with(const std::vector<SE3>& T_W_K) const override;
  std::vector<std::pair<std::string, RuntimeStats>> runtime() const override;
  void set_clock(const StageClock* clock) override { clock_ = clock; }
  int64_t memory_bytes() const override { return store_.memory_bytes() + static_cast<int64_t>(T_W_K_.capacity() * sizeof(SE3)); }
  const SubmapStore& store() const { return store_; }
  // Pairs that arrived before the first keyframe (no submap to hold them).
  int64_t dropped_pairs() const { return dropped_; }

 private:
  SubmapStore store_;
  std::vector<SE3> T_W_K_;
  const StageClock* clock_ = nullptr;
  RuntimeStats construction_;
  int64_t dropped_ = 0;
};

// "fusion" or "submap"; nullptr for any other name.
std::unique_ptr<MappingSystem> make_geometric_system(const std::string& name);

}  // namespace orthosonar::mapping
