// CFAR feature extraction (cfar.hpp): the public entry points, which dispatch on the
// pixel type to the float path (cfar_float.cpp) or the integer path (cfar_integer.cpp).
#include "core/perception/cfar.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception {

double cfar_alpha(int n_train, double pfa) {
  const double n = static_cast<double>(n_train);
  return n * (std::pow(pfa, -1.0 / n) - 1.0);
}

std::vector<Detection> cfar_detect(const SonarPing& ping, const CfarConfig& config) {
  const int rows = ping.rows, cols = ping.cols;
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (ping.bytes_per_pixel == 1) {
    if (ping.image.size() < n) return {};
    return detail::detect_integer(ping.image.data(), rows, cols, config);
  }
  if (ping.image.size() < 2 * n) return {};
  std::vector<uint16_t> wide(n);
  for (size_t i = 0; i < n; ++i)
    wide[i] = static_cast<uint16_t>(ping.image[2 * i] | (ping.image[2 * i + 1] << 8));
  return detail::detect_integer(wide.data(), rows, cols, config);
}

std::vector<Detection> cfar_detect(const float* image, int rows, int cols, const CfarConfig& config) {
  return detail::detect_float(image, rows, cols, config);
}

const char* to_string(CfarMethod m) {
  switch (m) {
    case CfarMethod::kSoca: return "soca";
    case CfarMethod::kCa: return "ca";
    case CfarMethod::kGoca: return "goca";
  }
  return "?";
}

const char* to_string(CfarWindow w) {
  switch (w) {
    case CfarWindow::kCross: return "cross";
    case CfarWindow::kRange: return "range";
  }
  return "?";
}

}  // namespace orthosonar::perception
