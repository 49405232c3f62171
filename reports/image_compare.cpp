#include "reports/image_compare.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace orthosonar::reports {
namespace {

cv::Mat gray_small(const cv::Mat& image) {
  cv::Mat gray;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4) cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  else gray = image;
  cv::Mat g8;
  if (gray.depth() != CV_8U) gray.convertTo(g8, CV_8U);
  else g8 = gray;
  cv::Mat small;
  cv::resize(g8, small, cv::Size(160, 120), 0, 0, cv::INTER_AREA);
  cv::Mat f;
  small.convertTo(f, CV_32F, 1.0 / 255.0);
  return f;
}

cv::Mat to_bgr(const cv::Mat& image) {
  cv::Mat out;
  if (image.channels() == 1) cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  else if (image.channels() == 4) cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
  else out = image;
  return out;
}

cv::Mat captioned(const cv::Mat& image, const std::string& caption, int height) {
  const int bar = 48;
  cv::Mat bgr = to_bgr(image);
  cv::Mat out(height + bar, bgr.cols, CV_8UC3, cv::Scalar(255, 255, 255));
  bgr.copyTo(out(cv::Rect(0, bar, bgr.cols, bgr.rows)));
  int baseline = 0;
  const auto size = cv::getTextSize(caption, cv::FONT_HERSHEY_SIMPLEX, 1.0, 2, &baseline);
  cv::putText(out, caption, cv::Point((bgr.cols - size.width) / 2, bar - 14), cv::FONT_HERSHEY_SIMPLEX, 1.0,
              cv::Scalar(30, 30, 30), 2, cv::LINE_AA);
  return out;
}

}  // namespace

double image_difference(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return 1.0;
  cv::Mat diff;
  cv::absdiff(gray_small(a), gray_small(b), diff);
  return cv::mean(diff)[0];
}

double pixel_variance(const cv::Mat& image) {
  if (image.empty()) return 0.0;
  cv::Mat gray;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4) cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  else gray = image;
  cv::Scalar mean, sd;
  cv::meanStdDev(gray, mean, sd);
  return sd[0] * sd[0];
}

cv::Mat side_by_side(const cv::Mat& left, const std::string& left_caption, const cv::Mat& right,
                     const std::string& right_caption) {
  const int height = std::max(left.rows, right.rows);
  cv::Mat l = captioned(left, left_caption, height);
  cv::Mat r = captioned(right, right_caption, height);
  cv::Mat gap(l.rows, 8, CV_8UC3, cv::Scalar(200, 200, 200));
  cv::Mat out;
  cv::hconcat(std::vector<cv::Mat>{l, gap, r}, out);
  return out;
}

}  // namespace orthosonar::reports
