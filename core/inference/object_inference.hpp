#pragma once
// Inference on one horizontal frame (SPEC §8, paper §VI): DBSCAN clusters of the h
// detections -> crops -> MC-dropout classification -> per class: registration to the
// class reference frame, Bayes update of P(z | R, θ) from the fused 3D points inside the
// object (Eq. 8), then two-sided MAP heights (Eqs. 9-10) for the object's 2D-only pixels.
// Heights z are in the horizontal sonar frame h (z up, relative to the working depth).
//
// State: the per-class reference clouds and height distributions persist across frames
// (the paper keeps them for the whole mission). Classification of a frame depends only on
// (config.seed, the ping's ping_id) and the image, never on earlier frames.
// Not thread-safe. No I/O.
#include <cstdint>
#include <map>
#include <vector>

#include <Eigen/Core>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/inference/classifier.hpp"
#include "core/inference/crops.hpp"
#include "core/inference/dbscan.hpp"
#include "core/inference/height_model.hpp"
#include "core/inference/object_registry.hpp"

namespace orthosonar::perception {
struct FusionResult;
}

namespace orthosonar::inference {

struct InferenceConfig {
  DbscanConfig dbscan;
  CropConfig crop;
  ClassifierConfig classifier;  // mc_samples, accept_probability (architecture: the model's)
  HeightModelConfig height;
  RegistrationConfig registration;
  uint64_t seed = 0;            // per-frame MC-dropout seed = derive_seed(seed, stream, ping_id)
  SE3 T_V_h = se3_from_xyz_rpy(0.35, 0.0, 0.0, 0.0, 0.0, 0.0);  // SPEC §1 default
};

// A fused 3D point attached to the horizontal pixel it came from.
struct FusedObservation {
  PixelRC pixel;
  double z_h_m = 0.0;                              // height in the h frame: R sin φ
  Eigen::Vector3f p_V = Eigen::Vector3f::Zero();  // the fused point in V
};

// Fused points of a pair with their h pixel: row from the range, column = the nearest
// bearing of the h ping's own table.
std::vector<FusedObservation> fused_observations(const SonarPing& h, const perception::FusionResult& fused);
// The CFAR detections of the h image as pixels.
std::vector<PixelRC> detection_pixels(const perception::FusionResult& fused);

struct FrameStats {
  size_t detections = 0;
  size_t clusters = 0;
  size_t known = 0;                  // clusters with an accepted class
  size_t unknown = 0;
  size_t registration_failures = 0;
  size_t bayes_updates = 0;
  size_t inferred_points = 0;
  size_t bad_image = 0;              // 1: the ping's image does not match rows x cols (skipped)
};

struct FrameResult {
  std::vector<Eigen::Vector3f> inferred_V;  // new 3D points from MAP heights, in V
  std::vector<Prediction> predictions;      // one per cluster, in cluster order
  std::vector<Cluster> clusters;
  FrameStats stats;
};

class ObjectInference {
 public:
  ObjectInference(const InferenceConfig& config, Classifier classifier);
  FrameResult process(const SonarPing& h, const std::vector<PixelRC>& detections,
                      const std::vector<FusedObservation>& fused);
  // The height model of a class (nullptr before its first 3D observation).
  const HeightModel* height_model(SemanticClass c) const;
  const Classifier& classifier() const { return classifier_; }
  const InferenceConfig& config() const { return config_; }

 private:
  struct ClassState {
    ClassReference reference;
    HeightModel heights;
  };
  InferenceConfig config_;
  Classifier classifier_;
  std::map<SemanticClass, ClassState> classes_;
};

}  // namespace orthosonar::inference
