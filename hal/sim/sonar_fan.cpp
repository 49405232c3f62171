#include "hal/sim/sonar_fan.hpp"
#include "hal/codec/image_codec.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace orthosonar::sim {

cv::Point2d FanView::pixel(double range_m, double angle_rad) const {
  const double fwd = range_m * std::cos(angle_rad) / metres_per_px;
  const double side = range_m * std::sin(angle_rad) / metres_per_px;
  if (horizontal) return {0.5 * image.cols - 0.5 - side, image.rows - 0.5 - fwd};
  return {fwd - 0.5, 0.5 * image.rows - 0.5 - side};
}

cv::Mat fan_image(const SonarPing& ping, int width_px) { return fan_view(ping, width_px).image; }

FanView fan_view(const SonarPing& ping, int width_px) {
  const double rmax = ping.max_range_m();
  const auto& b = ping.bearings_rad;
  const double bmin = b.front(), bmax = b.back();
  const bool horizontal = ping.mount == SonarMount::kHorizontal;
  // Extent of the fan in its own plane: forward 0..rmax, lateral +-rmax sin(max bearing).
  const double lateral = rmax * std::max(std::sin(std::max(std::abs(bmin), std::abs(bmax))), 0.05);
  const double scale = (2.0 * lateral) / width_px;  // metres per pixel
  const int other = static_cast<int>(std::ceil(rmax / scale));
  const int w = horizontal ? width_px : other;
  const int h = horizontal ? other : width_px;
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(24));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      // (forward, side) with side positive left (h) or up (v).
      const double fwd = horizontal ? (h - 0.5 - v) * scale : (u + 0.5) * scale;
      const double side = horizontal ? (0.5 * w - u - 0.5) * scale : (0.5 * h - v - 0.5) * scale;
      const double r = std::hypot(fwd, side);
      const double a = std::atan2(side, fwd);
      if (a < bmin || a > bmax) continue;
      const int row = static_cast<int>(std::lround(r / ping.range_resolution_m)) - 1;
      if (row < 0 || row >= ping.rows) continue;
      const auto it = std::lower_bound(b.begin(), b.end(), a);
      int col = static_cast<int>(it - b.begin());
      if (col > 0 && (col == ping.cols || a - b[static_cast<size_t>(col - 1)] < b[static_cast<size_t>(col)] - a)) --col;
      const uint16_t val = ping.at(row, col);
      img.at<uint8_t>(v, u) = static_cast<uint8_t>(ping.bytes_per_pixel == 1 ? val : val >> 8);
    }
  }
  return {img, scale, horizontal};
}

Status write_fan_png(const SonarPing& ping, const std::string& path, int width_px, bool with_polar) {
  if (ping.rows == 0 || ping.cols < 2 || ping.bearings_rad.size() != ping.cols) {
    return Error{"write_fan_png: ping has no image or no bearing table"};
  }
  cv::Mat out = fan_image(ping, width_px);
  if (with_polar) {
    // The raw image, range increasing upwards, beams left (+bearing) to right, scaled to height.
    cv::Mat polar(ping.rows, ping.cols, CV_8UC1);
    for (int r = 0; r < ping.rows; ++r) {
      for (int c = 0; c < ping.cols; ++c) {
        polar.at<uint8_t>(ping.rows - 1 - r, ping.cols - 1 - c) = static_cast<uint8_t>(ping.at(r, c));
      }
    }
    cv::Mat scaled;
    cv::resize(polar, scaled, cv::Size(std::max(1, ping.cols * out.rows / ping.rows), out.rows), 0, 0, cv::INTER_NEAREST);
    cv::Mat both;
    cv::hconcat(out, scaled, both);
    out = both;
  }
  return codec::write_png(path, out);
}

}  // namespace orthosonar::sim
