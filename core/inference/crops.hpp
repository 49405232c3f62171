#pragma once
// Classifier inputs (SPEC §8): a cluster's bounding box, padded, cropped from the
// horizontal image and resized to input_px x input_px; and the training augmentations
// (Gaussian noise, flips, rotations) drawn from orthosonar::Rng.
#include <opencv2/core.hpp>

#include "core/events.hpp"
#include "core/inference/dbscan.hpp"
#include "core/random.hpp"

namespace orthosonar::inference {

struct CropConfig {
  int pad_px = 5;      // bounding-box padding on every side (clipped to the image)
  int output_px = 40;  // crop side after resizing
};

// The padded bounding box of `cluster` from `h`, resized (area interpolation when
// shrinking, linear when growing) and scaled to [0, 1] by the crop's maximum, as CV_32F.
// Dividing by the maximum makes the input independent of range-dependent gain.
cv::Mat crop_cluster(const SonarPing& h, const Cluster& cluster, const CropConfig& config = {});

struct AugmentConfig {
  double noise_sigma = 0.05;      // additive Gaussian noise, in [0, 1] intensity units
  double max_rotation_deg = 30.0; // uniform in [-max, max]
  bool flips = true;              // horizontal and vertical flips, each with probability 1/2
};

// One augmented copy of a crop (same size, CV_32F clamped to [0, 1]).
cv::Mat augment_crop(const cv::Mat& crop, Rng& rng, const AugmentConfig& config = {});

}  // namespace orthosonar::inference
