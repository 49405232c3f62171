#pragma once
// Mapping systems 3 and 4 (SPEC §6, §8):
//  - "inference" (paper §VI-D): at each keyframe's pair, the fused points plus the points
//    whose height was inferred, placed by the keyframe's SLAM pose, like fusion mapping.
//  - "inference_submap" (beyond the paper): inference on every pair; each pair's cloud
//    (fused + inferred) is stored in the current keyframe's submap with T_k_t = DR(k)⁻¹ DR(t),
//    and the map is ∪ T_W_k S_k, exactly like submapping.
// Both keep one ObjectInference (classifier + per-class height models). Runtime stages:
// "inference_per_frame" (one call of ObjectInference::process) and "map_update".
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/inference/object_inference.hpp"
#include "core/mapping/mapping_system.hpp"
#include "core/mapping/submap.hpp"
#include "core/result.hpp"

namespace orthosonar::inference {

// Totals of FrameStats over the frames processed.
struct InferenceCounts {
  size_t frames = 0;
  size_t clusters = 0;
  size_t known = 0;
  size_t unknown = 0;
  size_t registration_failures = 0;
  size_t bayes_updates = 0;
  size_t inferred_points = 0;
  size_t fused_points = 0;
  size_t dropped_pairs = 0;  // submapping: pairs before the first keyframe
  size_t bad_images = 0;     // frames whose h image did not match its rows x cols
  std::map<SemanticClass, size_t> known_by_class;  // accepted clusters per class
};

// Fused + inferred points per pair (V frame), keyed by the pair's stamp in ns. In submapping
// mode every pair is inferred in stamp order whatever the keyframe setting, so one pass
// can fill this and every cell of a sweep can reuse it (replay/run/sweep.cpp).
struct InferenceFrameCache {
  std::map<int64_t, std::vector<Eigen::Vector3f>> clouds;
};

class InferenceMapping final : public mapping::MappingSystem {
 public:
  InferenceMapping(const InferenceConfig& config, Classifier classifier, bool submapping);
  std::string name() const override { return submapping_ ? "inference_submap" : "inference"; }
  void on_pair(const mapping::PairInput& pair) override;
  void on_keyframe(const mapping::KeyframeInput& keyframe) override;
  void on_poses_updated(const std::vector<SE3>& T_W_K_slam) override;
  std::vector<Eigen::Vector3f> map_points_W() const override;
  std::vector<std::pair<std::string, mapping::RuntimeStats>> runtime() const override;
  void set_clock(const mapping::StageClock* clock) override { clock_ = clock; }
  std::vector<std::pair<std::string, int64_t>> system_counts() const override;
  int64_t memory_bytes() const override;
  const InferenceCounts& counts() const { return counts_; }
  // Submapping mode only. record: every inferred pair's cloud is also written to `cache`.
  // replay: clouds come from `cache` (a pair missing there is an error, reported by
  // cache_misses()), and the classifier is not run. The cache must outlive the system.
  void record_frames_to(InferenceFrameCache* cache) { record_ = cache; }
  void replay_frames_from(const InferenceFrameCache* cache) { replay_ = cache; }
  size_t cache_misses() const { return cache_misses_; }
  const ObjectInference& inference() const { return inference_; }

 private:
  // Fused + inferred points of one pair, in V.
  std::vector<Eigen::Vector3f> infer(const mapping::PairInput& pair);  // through the cache, if any
  std::vector<Eigen::Vector3f> infer_uncached(const mapping::PairInput& pair);

  struct Frame {
    Time stamp;
    SE3 T_W_K_dr = SE3::Identity();
    bool has_cloud = false;
    std::vector<Eigen::Vector3f> p_K;
  };
  ObjectInference inference_;
  bool submapping_;
  std::vector<Frame> frames_;          // keyframe mode
  mapping::SubmapStore store_;         // submap mode
  std::vector<SE3> T_W_K_;
  const mapping::StageClock* clock_ = nullptr;
  mapping::RuntimeStats per_frame_, map_update_;
  InferenceCounts counts_;
  InferenceFrameCache* record_ = nullptr;
  const InferenceFrameCache* replay_ = nullptr;
  size_t cache_misses_ = 0;
};

// A system from a serialized model (Classifier::serialize bytes). The caller must have
// called InferenceRuntime::configure first. Errors when the model cannot be read.
Result<std::unique_ptr<mapping::MappingSystem>> make_inference_system_from_model(
    const InferenceConfig& config, bool submapping, const std::string& model_bytes);

}  // namespace orthosonar::inference
