#pragma once
// Synthetic labelled crops with a known answer, for tests and for exercising training
// without a simulator: three shape families that mimic what a horizontal sonar sees.
//   0 "piling": a short bright arc (the near face of a round post) with a dark shadow behind
//   1 "dock":   a long straight bright edge across the crop
//   2 "seawall": a long edge with periodic corrugation
// Position, size, orientation, brightness and speckle vary; all draws come from Rng.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/events.hpp"
#include "core/inference/classifier.hpp"
#include "core/inference/object_inference.hpp"
#include "core/random.hpp"

namespace orthosonar::inference {

inline constexpr int kSyntheticShapeCount = 3;

// One crop of shape family `shape` (0..2), side px, CV_32F in [0, 1].
cv::Mat synthetic_crop(int shape, int px, Rng& rng);
// n crops per family, labels 0..2, in family-interleaved order.
std::vector<LabelledCrop> synthetic_crop_set(int per_class, int px, uint64_t seed);

// A horizontal frame with round pilings (vertical cylinders) at known positions in the
// h frame: each beam's first intersection with a piling marks `thickness_rows` range bins
// (intensity 200 over a weak floor). Detections are exactly those pixels; fused
// observations exist for piling pixels with |θ| <= overlap_deg, all at height z_h_m.
struct SyntheticPiling {
  double x_m = 10.0, y_m = 0.0, radius_m = 0.4;
};
struct SyntheticFrame {
  SonarPing h;
  std::vector<PixelRC> detections;
  std::vector<FusedObservation> fused;
};
SyntheticFrame synthetic_piling_frame(const std::vector<SyntheticPiling>& pilings, double z_h_m, uint32_t ping_id,
                                      int rows = 600, int cols = 512, double overlap_deg = 10.0,
                                      int thickness_rows = 3);

}  // namespace orthosonar::inference
