#include "core/inference/synthetic_crops.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/imgproc.hpp>

namespace orthosonar::inference {

cv::Mat synthetic_crop(int shape, int px, Rng& rng) {
  cv::Mat img(px, px, CV_32F, cv::Scalar(0));
  const double s = px / 40.0;
  const float bright = static_cast<float>(rng.uniform(0.6, 1.0));
  const cv::Point2d c(px * rng.uniform(0.35, 0.65), px * rng.uniform(0.35, 0.65));
  if (shape == 0) {
    const double r = s * rng.uniform(5.0, 9.0);
    const double start = rng.uniform(-30.0, 30.0);
    cv::ellipse(img, cv::Point(static_cast<int>(c.x), static_cast<int>(c.y)),
                cv::Size(static_cast<int>(r), static_cast<int>(r)), 0.0, 200.0 + start, 340.0 + start,
                cv::Scalar(bright), std::max(1, static_cast<int>(2 * s)));
  } else {
    const double angle = rng.uniform(-0.4, 0.4);
    const double len = px * rng.uniform(0.8, 1.2);
    const cv::Point2d d(std::cos(angle), std::sin(angle));
    const int thick = std::max(1, static_cast<int>(rng.uniform(1.5, 3.0) * s));
    if (shape == 1) {
      cv::line(img, c - d * len, c + d * len, cv::Scalar(bright), thick);
    } else {
      const cv::Point2d n(-d.y, d.x);
      const double period = s * rng.uniform(5.0, 8.0), amp = s * rng.uniform(2.0, 3.5);
      for (double t = -len; t < len; t += 1.0) {
        const double off = amp * std::sin(2.0 * std::numbers::pi * t / period);
        const cv::Point2d a = c + d * t + n * off;
        const cv::Point2d b = c + d * (t + 1.0) + n * amp * std::sin(2.0 * std::numbers::pi * (t + 1.0) / period);
        cv::line(img, a, b, cv::Scalar(bright), thick);
      }
    }
  }
  // Multiplicative speckle plus a weak noise floor, like the simulator's image formation.
  for (int r = 0; r < px; ++r) {
    float* p = img.ptr<float>(r);
    for (int col = 0; col < px; ++col) {
      const double v = p[col] * rng.exponential(1.0) * 0.7 + 0.05 * rng.uniform();
      p[col] = static_cast<float>(std::clamp(v, 0.0, 1.0));
    }
  }
  return img;
}

std::vector<LabelledCrop> synthetic_crop_set(int per_class, int px, uint64_t seed) {
  Rng rng(seed);
  std::vector<LabelledCrop> out;
  for (int i = 0; i < per_class; ++i) {
    for (int shape = 0; shape < kSyntheticShapeCount; ++shape) out.push_back({synthetic_crop(shape, px, rng), shape});
  }
  return out;
}

SyntheticFrame synthetic_piling_frame(const std::vector<SyntheticPiling>& pilings, double z_h_m, uint32_t ping_id,
                                      int rows, int cols, double overlap_deg, int thickness_rows) {
  SyntheticFrame f;
  SonarPing& h = f.h;
  h.part_number = kPartM750d;
  h.ping_id = ping_id;
  h.rows = static_cast<uint16_t>(rows);
  h.cols = static_cast<uint16_t>(cols);
  h.range_resolution_m = 0.05;
  const double half = 65.0 * std::numbers::pi / 180.0;
  for (int c = 0; c < cols; ++c) h.bearings_rad.push_back(-half + 2.0 * half * c / (cols - 1));
  h.image.assign(static_cast<size_t>(rows) * static_cast<size_t>(cols), 0);
  for (size_t i = 0; i < h.image.size(); ++i) h.image[i] = static_cast<uint8_t>(10 + (i * 7919u) % 13u);
  std::vector<PixelRC> pix;
  for (int c = 0; c < cols; ++c) {
    const double th = h.bearings_rad[static_cast<size_t>(c)];
    const Vec2 d(std::cos(th), std::sin(th));
    double best = INFINITY;
    for (const SyntheticPiling& p : pilings) {  // ray-circle intersection, nearest root
      const Vec2 o(p.x_m, p.y_m);
      const double b = d.dot(o), disc = b * b - (o.squaredNorm() - p.radius_m * p.radius_m);
      if (disc >= 0.0 && b - std::sqrt(disc) > 0.0) best = std::min(best, b - std::sqrt(disc));
    }
    if (!std::isfinite(best)) continue;
    const int row0 = static_cast<int>(std::lround(best / h.range_resolution_m)) - 1;
    for (int r = row0; r < row0 + thickness_rows && r < rows; ++r) {
      if (r < 0) continue;
      h.image[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] = 200;
      pix.push_back({r, c});
    }
  }
  std::sort(pix.begin(), pix.end());
  f.detections = pix;
  for (const PixelRC& p : pix) {
    const double th = h.bearings_rad[static_cast<size_t>(p.col)];
    if (std::abs(th) > overlap_deg * std::numbers::pi / 180.0) continue;
    const double R = h.range_of_row(p.row);
    if (std::abs(z_h_m) >= R) continue;
    FusedObservation o;
    o.pixel = p;
    o.z_h_m = z_h_m;
    o.p_V = spherical_to_cartesian(R, th, std::asin(z_h_m / R)).cast<float>();
    f.fused.push_back(o);
  }
  return f;
}

}  // namespace orthosonar::inference
