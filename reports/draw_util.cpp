#include "reports/draw_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace orthosonar::reports {

cv::Scalar to_bgr(const Rgb& rgb) { return cv::Scalar(255.0 * rgb[2], 255.0 * rgb[1], 255.0 * rgb[0]); }

void draw_text(cv::Mat& image, const std::string& text, cv::Point anchor, double scale, cv::Scalar colour,
               int thickness, Align align) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  int x = anchor.x;
  if (align == Align::kCentre) x -= size.width / 2;
  if (align == Align::kRight) x -= size.width;
  cv::putText(image, text, cv::Point(x, anchor.y + size.height / 2), cv::FONT_HERSHEY_SIMPLEX, scale, colour,
              thickness, cv::LINE_AA);
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> out;
  if (!(hi > lo) || target < 1) return {lo};
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push_back(std::abs(v) < 1e-12 ? 0.0 : v);
  return out;
}

std::string format_tick(double value, double step) {
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 6);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

void draw_colour_bar(cv::Mat& image, cv::Rect area, ColourMap map, double lo, double hi, const std::string& title) {
  const cv::Scalar ink(40, 40, 40);
  const int bar_w = std::max(12, area.width / 4);
  const int top = area.y + 40, bottom = area.y + area.height - 20;
  for (int y = top; y <= bottom; ++y) {
    const double t = static_cast<double>(bottom - y) / std::max(1, bottom - top);
    cv::line(image, {area.x, y}, {area.x + bar_w, y}, to_bgr(colour_at(map, t)));
  }
  cv::rectangle(image, cv::Rect(area.x, top, bar_w + 1, bottom - top + 1), ink, 1);
  draw_text(image, title, {area.x + area.width / 2, area.y + 14}, 0.6, ink, 1, Align::kCentre);
  if (!(hi > lo)) return;
  const auto ticks = nice_ticks(lo, hi, 5);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : std::max(1e-6, hi - lo);
  for (double v : ticks) {
    const int y = bottom - static_cast<int>(std::lround((v - lo) / (hi - lo) * (bottom - top)));
    cv::line(image, {area.x + bar_w, y}, {area.x + bar_w + 6, y}, ink, 1);
    draw_text(image, format_tick(v, step), {area.x + bar_w + 10, y}, 0.55, ink, 1, Align::kLeft);
  }
}

void draw_plot_axes(cv::Mat& img, cv::Rect area, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                    const std::function<cv::Point(const Eigen::Vector2d&)>& px, const std::string& x_label,
                    const std::string& y_label, const std::string& title) {
  const cv::Scalar ink(40, 40, 40), grid(228, 228, 228);
  const auto xt = nice_ticks(lo.x(), hi.x(), 10);
  const auto yt = nice_ticks(lo.y(), hi.y(), 8);
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ys = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double x : xt) {
    const int u = px({x, lo.y()}).x;
    cv::line(img, {u, area.y}, {u, area.y + area.height}, grid, 1);
    draw_text(img, format_tick(x, xs), {u, area.y + area.height + 18}, 0.55, ink);
  }
  for (double y : yt) {
    const int v = px({lo.x(), y}).y;
    cv::line(img, {area.x, v}, {area.x + area.width, v}, grid, 1);
    draw_text(img, format_tick(y, ys), {area.x - 8, v}, 0.55, ink, 1, Align::kRight);
  }
  cv::rectangle(img, area, ink, 1);
  draw_text(img, x_label, {area.x + area.width / 2, area.y + area.height + 50}, 0.7, ink);
  {
    cv::Mat label(30, 200, CV_8UC3, cv::Scalar(255, 255, 255));
    draw_text(label, y_label, {100, 14}, 0.7, ink);
    cv::Mat rotated;
    cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    rotated.copyTo(img(cv::Rect(4, area.y + area.height / 2 - 100, rotated.cols, rotated.rows)));
  }
  draw_text(img, title, {area.x, 28}, 0.9, ink, 2, Align::kLeft);
}

}  // namespace orthosonar::reports
