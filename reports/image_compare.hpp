#pragma once
// Image comparison for golden tests and the report (OpenCV only, no VTK, so tests can
// call it cheaply).
#include <string>

#include <opencv2/core.hpp>

namespace orthosonar::reports {

// Mean absolute per-pixel difference of the two images converted to grayscale and
// downscaled (area averaging) to 160x120, in [0, 1]: 0 for identical images, 1 for
// black against white. Images of different sizes are both brought to 160x120, so a
// layout change still compares. Returns 1 when either image is empty.
// Downscaling makes the score tolerant to sub-pixel jitter (a point landing one pixel
// over) while a moved structure still shows; a golden test compares it to a tolerance.
double image_difference(const cv::Mat& a, const cv::Mat& b);

// Variance of the grayscale intensities (0..255 scale); a blank render is ~0.
double pixel_variance(const cv::Mat& image);

// Two images next to each other at the height of the taller one, each with a caption
// bar on top ("golden", "current").
cv::Mat side_by_side(const cv::Mat& left, const std::string& left_caption, const cv::Mat& right,
                     const std::string& right_caption);

}  // namespace orthosonar::reports
