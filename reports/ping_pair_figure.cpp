#include "reports/ping_pair_figure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "hal/sim/sonar_fan.hpp"
#include "reports/draw_util.hpp"

namespace orthosonar::reports {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Speckle is dark on a raw image: stretch so the 99.5th percentile of the fan is white.
cv::Mat stretched_bgr(const cv::Mat& gray) {
  std::vector<int> hist(256, 0);
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c) ++hist[gray.at<uint8_t>(r, c)];
  const double total = static_cast<double>(gray.total());
  int top = 255;
  for (double seen = 0.0; top > 1; --top) {
    seen += hist[static_cast<size_t>(top)];
    if (seen >= 0.005 * total) break;
  }
  cv::Mat scaled;
  gray.convertTo(scaled, CV_8U, 255.0 / std::max(top, 1));
  cv::Mat bgr;
  cv::cvtColor(scaled, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

struct Panel {
  cv::Mat image;
  std::string title;
};

Panel panel(const SonarPing& ping, const std::vector<perception::Detection>& detections,
            const std::vector<perception::FusedPoint>& fused, double overlap_deg, int width_px, const char* name) {
  const sim::FanView fan = sim::fan_view(ping, width_px);
  cv::Mat img = stretched_bgr(fan.image);
  const bool h = ping.mount == SonarMount::kHorizontal;
  const cv::Scalar detection(255, 200, 0), edge(0, 215, 255), point(40, 40, 255);
  // The shared aperture: bearing on h, elevation on v, within ±overlap_deg.
  for (double a : {-overlap_deg, overlap_deg}) {
    const cv::Point2d from = fan.pixel(0.0, a * kDegToRad), to = fan.pixel(ping.max_range_m(), a * kDegToRad);
    cv::line(img, from, to, edge, 1, cv::LINE_AA);
  }
  for (const auto& d : detections) {
    const cv::Point2d p = fan.pixel(ping.range_of_row(d.row), ping.bearings_rad[static_cast<size_t>(d.col)]);
    cv::circle(img, p, 1, detection, cv::FILLED);
  }
  for (const auto& f : fused) {
    const cv::Point2d p = fan.pixel(f.range_m, h ? f.bearing_rad : f.elevation_rad);
    cv::circle(img, p, 5, point, 1, cv::LINE_AA);
  }
  const std::string title = std::string(name) + ": " + std::to_string(detections.size()) + " detections" +
                            ", " + std::to_string(fused.size()) + " fused";
  return {img, title};
}

}  // namespace

Result<cv::Mat> draw_ping_pair(const outputs::PingPairRecord& pair, int width_px) {
  for (const SonarPing* p : {&pair.h, &pair.v})
    if (p->rows == 0 || p->cols < 2 || p->bearings_rad.size() != p->cols)
      return Error{"ping pair figure: a ping has no image or no bearing table"};
  // Side by side: the horizontal fan (wide, from above) on the left, the vertical one (tall,
  // from the side, forward to the right) on the right, both with the same range scale.
  const int margin = 20;
  const int h_width = std::max(200, (width_px - 3 * margin) * 64 / 100);
  Panel h = panel(pair.h, pair.detections_h, pair.fused, pair.overlap_deg, h_width, "horizontal (from above)");
  // fan_view's width is across the fan: for the vertical ping, its height. Same metres per
  // pixel as the horizontal fan.
  auto half_aperture = [](const SonarPing& p) {
    return std::max(std::sin(std::max(std::abs(p.bearings_rad.front()), std::abs(p.bearings_rad.back()))), 0.05);
  };
  const double m_per_px = 2.0 * pair.h.max_range_m() * half_aperture(pair.h) / h_width;
  const int v_across = std::max(40, static_cast<int>(std::lround(2.0 * pair.v.max_range_m() * half_aperture(pair.v) / m_per_px)));
  Panel v = panel(pair.v, pair.detections_v, pair.fused, pair.overlap_deg, v_across, "vertical (from the side)");
  const int title_h = 34, legend_h = 40;
  const int width = margin + h.image.cols + margin + v.image.cols + margin;
  const int height = title_h + std::max(h.image.rows + legend_h + margin, v.image.rows) + margin;
  cv::Mat out(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40);
  int x = margin;
  for (const Panel* p : {&h, &v}) {
    draw_text(out, p->title, {x, title_h / 2}, 0.55, ink, 1, Align::kLeft);
    p->image.copyTo(out(cv::Rect(x, title_h, p->image.cols, p->image.rows)));
    x += p->image.cols + margin;
  }
  const int y = title_h + h.image.rows + margin + legend_h / 2;  // under the horizontal fan
  cv::circle(out, {30, y}, 2, cv::Scalar(255, 200, 0), cv::FILLED);
  draw_text(out, "CFAR detection", {42, y}, 0.55, ink, 1, Align::kLeft);
  cv::circle(out, {220, y}, 5, cv::Scalar(40, 40, 255), 1, cv::LINE_AA);
  draw_text(out, "fused point", {232, y}, 0.55, ink, 1, Align::kLeft);
  cv::line(out, {380, y}, {410, y}, cv::Scalar(0, 215, 255), 2);
  draw_text(out, "shared aperture (+-" + std::to_string(static_cast<int>(std::lround(pair.overlap_deg))) + " deg)",
            {418, y}, 0.55, ink, 1, Align::kLeft);
  return out;
}

}  // namespace orthosonar::reports
