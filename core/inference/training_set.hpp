#pragma once
// Labelled crops for training the classifier (SPEC §8): the same DBSCAN clusters the
// pipeline classifies, each labelled with the majority SemanticClass of its pixels from the
// simulator's per-pixel labels; then a stratified held-out split and augmentation
// (Gaussian noise, flips, rotations) of the training part up to a per-class target.
// Pure functions of their inputs and seed. No I/O.
#include <cstdint>
#include <vector>

#include "core/events.hpp"
#include "core/inference/classifier.hpp"
#include "core/inference/crops.hpp"
#include "core/inference/dbscan.hpp"

namespace orthosonar::inference {

struct LabelledCluster {
  cv::Mat crop;
  SemanticClass semantic = SemanticClass::kNone;
  double majority_fraction = 0.0;  // share of the cluster's pixels with that class
  uint32_t ping_id = 0;
};

struct CropExtractionConfig {
  DbscanConfig dbscan;
  CropConfig crop;
  double min_majority = 0.6;  // skip clusters whose label is ambiguous
};

// Clusters of `detections` in the h image with their majority label (kNone majorities
// and ambiguous clusters are skipped). `labels` must have the ping's geometry.
std::vector<LabelledCluster> labelled_clusters(const SonarPing& h, const SonarLabels& labels,
                                               const std::vector<PixelRC>& detections,
                                               const CropExtractionConfig& config = {});

struct TrainingSetConfig {
  double holdout_fraction = 0.2;     // per class, of the original (unaugmented) crops
  int min_per_class = 12;            // classes with fewer originals are left out
  int max_per_class = 600;           // originals kept per class (random subset)
  int target_per_class = 400;        // training crops per class after augmentation
  AugmentConfig augment;
};

struct TrainingSet {
  std::vector<SemanticClass> classes;  // label index -> class, ascending class value
  std::vector<LabelledCrop> train;     // augmented
  std::vector<LabelledCrop> holdout;   // originals only
  std::vector<size_t> originals;       // per class, before the split
};

TrainingSet build_training_set(const std::vector<LabelledCluster>& clusters, const TrainingSetConfig& config,
                               uint64_t seed);

}  // namespace orthosonar::inference
