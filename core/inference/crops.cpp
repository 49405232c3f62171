#include "core/inference/crops.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace orthosonar::inference {

cv::Mat crop_cluster(const SonarPing& h, const Cluster& cluster, const CropConfig& config) {
  const int r0 = std::max(0, cluster.row_min - config.pad_px);
  const int r1 = std::min(static_cast<int>(h.rows) - 1, cluster.row_max + config.pad_px);
  const int c0 = std::max(0, cluster.col_min - config.pad_px);
  const int c1 = std::min(static_cast<int>(h.cols) - 1, cluster.col_max + config.pad_px);
  const int rows = std::max(1, r1 - r0 + 1), cols = std::max(1, c1 - c0 + 1);
  cv::Mat box(rows, cols, CV_32F, cv::Scalar(0));
  float peak = 0.0f;
  for (int r = 0; r < rows && r0 + r < h.rows; ++r) {
    float* out = box.ptr<float>(r);
    for (int c = 0; c < cols && c0 + c < h.cols; ++c) {
      out[c] = static_cast<float>(h.at(r0 + r, c0 + c));
      peak = std::max(peak, out[c]);
    }
  }
  if (peak > 0.0f) box *= 1.0 / peak;
  cv::Mat out;
  const bool shrink = rows > config.output_px || cols > config.output_px;
  cv::resize(box, out, cv::Size(config.output_px, config.output_px), 0, 0,
             shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

cv::Mat augment_crop(const cv::Mat& crop, Rng& rng, const AugmentConfig& config) {
  cv::Mat img = crop.clone();
  if (config.flips) {
    if (rng.uniform() < 0.5) cv::flip(img, img, 1);
    if (rng.uniform() < 0.5) cv::flip(img, img, 0);
  }
  const double angle = rng.uniform(-config.max_rotation_deg, config.max_rotation_deg);
  if (angle != 0.0) {
    const cv::Point2f centre(static_cast<float>(img.cols - 1) * 0.5f, static_cast<float>(img.rows - 1) * 0.5f);
    const cv::Mat R = cv::getRotationMatrix2D(centre, angle, 1.0);
    cv::warpAffine(img, img, R, img.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  for (int r = 0; r < img.rows; ++r) {
    float* p = img.ptr<float>(r);
    for (int c = 0; c < img.cols; ++c) {
      const double v = p[c] + config.noise_sigma * rng.normal();
      p[c] = static_cast<float>(std::clamp(v, 0.0, 1.0));
    }
  }
  return img;
}

}  // namespace orthosonar::inference
