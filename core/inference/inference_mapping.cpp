#include "core/inference/inference_mapping.hpp"

#include "core/memory.hpp"

#include "core/perception/fusion.hpp"

namespace orthosonar::inference {

InferenceMapping::InferenceMapping(const InferenceConfig& config, Classifier classifier, bool submapping)
    : inference_(config, std::move(classifier)), submapping_(submapping) {}

std::vector<Eigen::Vector3f> InferenceMapping::infer(const mapping::PairInput& pair) {
  if (replay_ != nullptr && submapping_) {
    const auto it = replay_->clouds.find(pair.stamp.ns());
    if (it != replay_->clouds.end()) return it->second;
    ++cache_misses_;
    return {};
  }
  std::vector<Eigen::Vector3f> cloud = infer_uncached(pair);
  if (record_ != nullptr && submapping_) record_->clouds[pair.stamp.ns()] = cloud;
  return cloud;
}

std::vector<Eigen::Vector3f> InferenceMapping::infer_uncached(const mapping::PairInput& pair) {
  std::vector<Eigen::Vector3f> cloud;
  for (const auto& p : pair.fused->points) cloud.push_back(p.p_V);
  counts_.fused_points += cloud.size();
  if (pair.h == nullptr) return cloud;
  FrameResult r;
  {
    mapping::ScopedStage timer(clock_, per_frame_);
    r = inference_.process(*pair.h, detection_pixels(*pair.fused), fused_observations(*pair.h, *pair.fused));
  }
  ++counts_.frames;
  counts_.clusters += r.stats.clusters;
  counts_.known += r.stats.known;
  counts_.unknown += r.stats.unknown;
  counts_.registration_failures += r.stats.registration_failures;
  counts_.bayes_updates += r.stats.bayes_updates;
  counts_.inferred_points += r.stats.inferred_points;
  counts_.bad_images += r.stats.bad_image;
  for (const Prediction& pred : r.predictions)
    if (pred.known) ++counts_.known_by_class[pred.semantic];
  cloud.insert(cloud.end(), r.inferred_V.begin(), r.inferred_V.end());
  return cloud;
}

void InferenceMapping::on_keyframe(const mapping::KeyframeInput& keyframe) {
  if (submapping_) {
    store_.begin(keyframe.keyframe_id, keyframe.T_W_V_dr);
    return;
  }
  Frame f;
  f.stamp = keyframe.stamp;
  f.T_W_K_dr = keyframe.T_W_V_dr;
  frames_.resize(static_cast<size_t>(keyframe.keyframe_id), Frame{});
  frames_.push_back(std::move(f));
}

void InferenceMapping::on_pair(const mapping::PairInput& pair) {
  if (pair.fused == nullptr) return;
  if (submapping_) {
    const std::vector<Eigen::Vector3f> cloud = infer(pair);  // every frame
    mapping::ScopedStage timer(clock_, map_update_);
    if (!store_.add(pair.T_W_V_dr, cloud)) ++counts_.dropped_pairs;
    return;
  }
  // Keyframe mode: only the keyframe's own pair (the first at or after its stamp).
  if (frames_.empty() || frames_.back().has_cloud || pair.stamp < frames_.back().stamp) return;
  const std::vector<Eigen::Vector3f> cloud = infer(pair);
  mapping::ScopedStage timer(clock_, map_update_);
  Frame& f = frames_.back();
  mapping::transform_append(f.T_W_K_dr.inverse() * pair.T_W_V_dr, cloud, f.p_K);
  f.has_cloud = true;
}

void InferenceMapping::on_poses_updated(const std::vector<SE3>& T_W_K_slam) { T_W_K_ = T_W_K_slam; }

std::vector<Eigen::Vector3f> InferenceMapping::map_points_W() const {
  if (submapping_) return store_.assemble(T_W_K_);
  std::vector<Eigen::Vector3f> out;
  for (size_t k = 0; k < frames_.size(); ++k) {
    const SE3& T = k < T_W_K_.size() ? T_W_K_[k] : frames_[k].T_W_K_dr;
    mapping::transform_append(T, frames_[k].p_K, out);
  }
  return out;
}

std::vector<std::pair<std::string, mapping::RuntimeStats>> InferenceMapping::runtime() const {
  return {{"inference_per_frame", per_frame_},
          {submapping_ ? "inference_submap_construction" : "inference_map_update", map_update_}};
}

std::vector<std::pair<std::string, int64_t>> InferenceMapping::system_counts() const {
  // Frames replayed from a sweep's cache were inferred elsewhere; nothing to report.
  if (replay_ != nullptr) return {};
  const auto n = [](size_t v) { return static_cast<int64_t>(v); };
  std::vector<std::pair<std::string, int64_t>> out = {
      {"inference_frames", n(counts_.frames)},
      {"inference_clusters", n(counts_.clusters)},
      {"inference_known", n(counts_.known)},
      {"inference_unknown", n(counts_.unknown)},
      {"inference_registration_failures", n(counts_.registration_failures)},
      {"inference_bayes_updates", n(counts_.bayes_updates)},
      {"inference_inferred_points", n(counts_.inferred_points)},
      {"inference_bad_images", n(counts_.bad_images)}};
  for (const auto& [c, k] : counts_.known_by_class)
    out.emplace_back(std::string("inference_known_") + semantic_class_name(c), n(k));
  return out;
}

Result<std::unique_ptr<mapping::MappingSystem>> make_inference_system_from_model(
    const InferenceConfig& config, bool submapping, const std::string& model_bytes) {
  Result<Classifier> model = Classifier::deserialize(model_bytes, config.classifier);
  if (!model) return model.error();
  std::unique_ptr<mapping::MappingSystem> system =
      std::make_unique<InferenceMapping>(config, std::move(model).value(), submapping);
  return system;
}

int64_t InferenceMapping::memory_bytes() const {
  int64_t n = heap_bytes(frames_) + heap_bytes(T_W_K_) + store_.memory_bytes();
  for (const auto& f : frames_) n += heap_bytes(f.p_K);
  return n;
}

}  // namespace orthosonar::inference
