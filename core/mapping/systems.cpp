#include "core/mapping/systems.hpp"

#include "core/memory.hpp"
#include "core/perception/fusion.hpp"

namespace orthosonar::mapping {

std::vector<Eigen::Vector3f> fused_points_V(const perception::FusionResult& fused) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(fused.points.size());
  for (const auto& p : fused.points) out.push_back(p.p_V);
  return out;
}

void FusionMapping::on_keyframe(const KeyframeInput& keyframe) {
  Frame f;
  f.stamp = keyframe.stamp;
  f.T_W_K_dr = keyframe.T_W_V_dr;
  frames_.resize(static_cast<size_t>(keyframe.keyframe_id), Frame{});
  frames_.push_back(std::move(f));
}

void FusionMapping::on_pair(const PairInput& pair) {
  if (frames_.empty() || frames_.back().has_cloud || pair.stamp < frames_.back().stamp) return;
  if (pair.fused == nullptr) return;
  ScopedStage timer(clock_, map_update_);
  Frame& f = frames_.back();
  // The pair's own frame V differs from the keyframe's only when the pair came later than
  // the keyframe stamp; register it by DR as submapping would.
  const SE3 T_K_V = f.T_W_K_dr.inverse() * pair.T_W_V_dr;
  transform_append(T_K_V, fused_points_V(*pair.fused), f.p_K);
  f.has_cloud = true;
}

void FusionMapping::on_poses_updated(const std::vector<SE3>& T_W_K_slam) { T_W_K_ = T_W_K_slam; }

std::vector<Eigen::Vector3f> FusionMapping::assemble(const std::vector<SE3>& T_W_K) const {
  std::vector<Eigen::Vector3f> out;
  for (size_t k = 0; k < frames_.size(); ++k) {
    const SE3& T = k < T_W_K.size() ? T_W_K[k] : frames_[k].T_W_K_dr;
    transform_append(T, frames_[k].p_K, out);
  }
  return out;
}

std::vector<Eigen::Vector3f> FusionMapping::map_points_W() const { return assemble(T_W_K_); }

int64_t FusionMapping::memory_bytes() const {
  int64_t n = heap_bytes(frames_) + heap_bytes(T_W_K_);
  for (const auto& f : frames_) n += heap_bytes(f.p_K);
  return n;
}

std::optional<std::vector<Eigen::Vector3f>> FusionMapping::map_points_W_with(const std::vector<SE3>& T_W_K) const {
  return assemble(T_W_K);
}

std::vector<std::pair<std::string, RuntimeStats>> FusionMapping::runtime() const {
  return {{"fusion_map_update", map_update_}};
}

void Submapping::on_keyframe(const KeyframeInput& keyframe) {
  store_.begin(keyframe.keyframe_id, keyframe.T_W_V_dr);
}

void Submapping::on_pair(const PairInput& pair) {
  if (pair.fused == nullptr) return;
  ScopedStage timer(clock_, construction_);
  if (!store_.add(pair.T_W_V_dr, fused_points_V(*pair.fused))) ++dropped_;
}

void Submapping::on_poses_updated(const std::vector<SE3>& T_W_K_slam) { T_W_K_ = T_W_K_slam; }

std::vector<Eigen::Vector3f> Submapping::map_points_W() const { return store_.assemble(T_W_K_); }

std::optional<std::vector<Eigen::Vector3f>> Submapping::map_points_W_with(const std::vector<SE3>& T_W_K) const {
  return store_.assemble(T_W_K);
}

std::vector<std::pair<std::string, RuntimeStats>> Submapping::runtime() const {
  return {{"submap_construction", construction_}};
}

std::unique_ptr<MappingSystem> make_geometric_system(const std::string& name) {
  if (name == "fusion") return std::make_unique<FusionMapping>();
  if (name == "submap") return std::make_unique<Submapping>();
  return nullptr;
}

}  // namespace orthosonar::mapping
