#pragma once
// Small OpenCV drawing helpers shared by the 2D figures (heat maps, trajectory plots).
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "reports/colormap.hpp"

namespace orthosonar::reports {

cv::Scalar to_bgr(const Rgb& rgb);

enum class Align { kLeft, kCentre, kRight };
// Text with its baseline-centre (kCentre) / left end / right end at `anchor`'s x and its
// vertical middle at anchor's y.
void draw_text(cv::Mat& image, const std::string& text, cv::Point anchor, double scale, cv::Scalar colour,
               int thickness = 1, Align align = Align::kCentre);

// "Nice" tick positions (1, 2, 5 x 10^k steps) covering [lo, hi], about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target);

// Formats a number with no more decimals than needed for `step`.
std::string format_tick(double value, double step);

// The frame of a 2D plot inside `area`: grid lines and tick labels for [lo, hi] on both
// axes (px maps data to pixels), the axis labels and the title above.
void draw_plot_axes(cv::Mat& image, cv::Rect area, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                    const std::function<cv::Point(const Eigen::Vector2d&)>& px, const std::string& x_label,
                    const std::string& y_label, const std::string& title);

// A vertical colour bar with ticks from lo to hi inside `area` (bar on the left part).
void draw_colour_bar(cv::Mat& image, cv::Rect area, ColourMap map, double lo, double hi, const std::string& title);

}  // namespace orthosonar::reports
