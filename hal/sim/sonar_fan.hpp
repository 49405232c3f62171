#pragma once
// Cartesian ("fan") views of sonar pings for people: docs, reports, debugging. Horizontal
// pings are drawn looking down (forward up, left to the left); vertical pings from the
// side (forward to the right, up up). Each pixel samples the nearest range bin and beam of
// the ping's own bearing table; outside the fan is dark grey.
#include <string>

#include <opencv2/core.hpp>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::sim {

// An 8-bit single-channel image about width_px wide.
cv::Mat fan_image(const SonarPing& ping, int width_px = 800);

// The same image with its geometry, to draw on it: where a return at (range, bearing) on a
// horizontal ping, or (range, elevation) on a vertical one, lands (pixel centre, sub-pixel).
struct FanView {
  cv::Mat image;
  double metres_per_px = 1.0;
  bool horizontal = true;
  cv::Point2d pixel(double range_m, double angle_rad) const;
};
FanView fan_view(const SonarPing& ping, int width_px = 800);
// The fan image written as PNG (with the raw polar image beside it when with_polar).
Status write_fan_png(const SonarPing& ping, const std::string& path, int width_px = 800, bool with_polar = false);

}  // namespace orthosonar::sim
