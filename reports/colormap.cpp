#include "reports/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace orthosonar::reports {
namespace {

// Piecewise-linear interpolation between evenly spaced control colours.
Rgb ramp(const std::vector<Rgb>& stops, double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  const double x = t * static_cast<double>(stops.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), stops.size() - 2);
  const double f = x - static_cast<double>(i);
  Rgb out{};
  for (size_t c = 0; c < 3; ++c) out[c] = stops[i][c] + (stops[i + 1][c] - stops[i][c]) * f;
  return out;
}

}  // namespace

Rgb colour_at(ColourMap map, double t) {
  static const std::vector<Rgb> height = {{0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530},
                                          {0.207, 0.372, 0.553}, {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551},
                                          {0.135, 0.659, 0.518}, {0.267, 0.749, 0.441}, {0.478, 0.821, 0.318},
                                          {0.741, 0.873, 0.150}, {0.993, 0.906, 0.144}};
  static const std::vector<Rgb> distance = {{0.15, 0.45, 1.0}, {0.35, 0.85, 0.95}, {1.0, 0.95, 0.25},
                                            {1.0, 0.55, 0.1}, {0.9, 0.1, 0.1}};
  static const std::vector<Rgb> coverage = {{0.16, 0.30, 0.70}, {0.45, 0.62, 0.85}, {0.93, 0.90, 0.82},
                                            {0.98, 0.70, 0.40}, {0.93, 0.45, 0.10}};
  switch (map) {
    case ColourMap::kHeight: return ramp(height, t);
    case ColourMap::kDistance: return ramp(distance, t);
    case ColourMap::kCoverage: return ramp(coverage, t);
  }
  return {0, 0, 0};
}

}  // namespace orthosonar::reports
