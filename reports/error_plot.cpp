#include "reports/error_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "reports/draw_util.hpp"

namespace orthosonar::reports {

namespace {

// The truth's position at t (linear between the two poses around it); t within its span.
Eigen::Vector3d truth_at(const Trajectory& truth, double t) {
  const auto it = std::lower_bound(truth.begin(), truth.end(), t,
                                   [](const TumPose& p, double s) { return p.t_s < s; });
  if (it == truth.begin()) return it->position;
  if (it == truth.end()) return truth.back().position;
  const TumPose& b = *it;
  const TumPose& a = *(it - 1);
  const double span = b.t_s - a.t_s;
  const double w = span > 0.0 ? (t - a.t_s) / span : 0.0;
  return a.position + w * (b.position - a.position);
}

}  // namespace

ErrorSeries trajectory_error_series(const Trajectory& estimate, const Trajectory& truth, const std::string& label,
                                    Rgb colour, bool with_z) {
  ErrorSeries s{label, {}, colour};
  if (truth.empty()) return s;
  const double t0 = truth.front().t_s, t1 = truth.back().t_s;
  for (const auto& p : estimate) {
    if (p.t_s < t0 || p.t_s > t1) continue;
    Eigen::Vector3d d = p.position - truth_at(truth, p.t_s);
    if (!with_z) d.z() = 0.0;
    s.t_error.emplace_back(p.t_s - t0, d.norm());
  }
  return s;
}

Result<cv::Mat> draw_error_over_time(const std::vector<ErrorSeries>& series, int width_px, int height_px,
                                     const std::string& title) {
  Eigen::Vector2d lo(1e300, 0.0), hi(-1e300, 0.0);
  int drawable = 0;
  for (const auto& s : series) {
    if (s.t_error.size() < 2) continue;
    ++drawable;
    for (const auto& p : s.t_error) {
      lo.x() = std::min(lo.x(), p.x());
      hi.x() = std::max(hi.x(), p.x());
      hi.y() = std::max(hi.y(), p.y());
    }
  }
  if (drawable == 0) return Error{"error plot: no trajectory with two or more poses inside the truth's span"};
  if (!(hi.x() > lo.x())) hi.x() = lo.x() + 1.0;
  hi.y() = std::max(hi.y() * 1.1, 0.01);

  cv::Mat img(height_px, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40);
  const cv::Rect area(90, 60, width_px - 90 - 30, height_px - 60 - 80);
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(area.x + static_cast<int>(std::lround((p.x() - lo.x()) / (hi.x() - lo.x()) * area.width)),
                     area.y + area.height - static_cast<int>(std::lround(p.y() / hi.y() * area.height)));
  };
  draw_plot_axes(img, area, lo, hi, px, "time (s)", "error (m)", title);
  int legend_y = area.y + 24;
  for (const auto& s : series) {
    if (s.t_error.size() < 2) continue;
    std::vector<cv::Point> pts;
    pts.reserve(s.t_error.size());
    double sum_sq = 0.0;
    for (const auto& p : s.t_error) {
      pts.push_back(px(p));
      sum_sq += p.y() * p.y();
    }
    cv::polylines(img, pts, false, to_bgr(s.colour), 2, cv::LINE_AA);
    char rms[64];
    std::snprintf(rms, sizeof rms, " (RMS %.3f m, final %.3f m)", std::sqrt(sum_sq / static_cast<double>(s.t_error.size())),
                  s.t_error.back().y());
    cv::line(img, {area.x + 16, legend_y}, {area.x + 56, legend_y}, to_bgr(s.colour), 3, cv::LINE_AA);
    draw_text(img, s.label + rms, {area.x + 66, legend_y}, 0.65, ink, 1, Align::kLeft);
    legend_y += 28;
  }
  return img;
}

}  // namespace orthosonar::reports
