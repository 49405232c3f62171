#include "reports/trajectory_plot.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "reports/draw_util.hpp"

namespace orthosonar::reports {

Result<cv::Mat> draw_trajectory_plot(const std::vector<PlotSeries>& series, const PlotConfig& config) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
  int drawable = 0;
  for (const auto& s : series) {
    if (s.xy_m.size() < 2) continue;
    ++drawable;
    for (const auto& p : s.xy_m) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if (drawable == 0) return Error{"trajectory plot: no trajectory with two or more poses"};
  const Eigen::Vector2d pad = ((hi - lo) * 0.05).cwiseMax(Eigen::Vector2d::Constant(1.0));
  lo -= pad;
  hi += pad;

  cv::Mat img(config.height_px, config.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40);
  const cv::Rect area(90, 60, config.width_px - 90 - 30, config.height_px - 60 - 80);
  // Equal aspect: one metre is the same number of pixels on both axes.
  const double scale = std::min(area.width / (hi.x() - lo.x()), area.height / (hi.y() - lo.y()));
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  const double half_w = 0.5 * area.width / scale, half_h = 0.5 * area.height / scale;
  lo = mid - Eigen::Vector2d(half_w, half_h);
  hi = mid + Eigen::Vector2d(half_w, half_h);
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(area.x + static_cast<int>(std::lround((p.x() - lo.x()) * scale)),
                     area.y + area.height - static_cast<int>(std::lround((p.y() - lo.y()) * scale)));
  };

  draw_plot_axes(img, area, lo, hi, px, "x (m)", "y (m)", config.title);

  int legend_y = area.y + 24;
  for (const auto& s : series) {
    if (s.xy_m.size() < 2) continue;
    std::vector<cv::Point> pts;
    pts.reserve(s.xy_m.size());
    for (const auto& p : s.xy_m) pts.push_back(px(p));
    cv::polylines(img, pts, false, to_bgr(s.colour), 2, cv::LINE_AA);
    cv::circle(img, pts.front(), 7, to_bgr(s.colour), 2, cv::LINE_AA);            // start
    cv::drawMarker(img, pts.back(), to_bgr(s.colour), cv::MARKER_SQUARE, 12, 2);  // end
    cv::line(img, {area.x + 16, legend_y}, {area.x + 56, legend_y}, to_bgr(s.colour), 3, cv::LINE_AA);
    draw_text(img, s.label, {area.x + 66, legend_y}, 0.65, ink, 1, Align::kLeft);
    legend_y += 28;
  }
  draw_text(img, "o start   [] end", {area.x + 16, legend_y}, 0.55, ink, 1, Align::kLeft);
  return img;
}

}  // namespace orthosonar::reports
