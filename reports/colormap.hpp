#pragma once
// Colour maps shared by the VTK renders and the OpenCV figures, so a colour bar in one
// means the same as in the other. Input t in [0, 1] (clamped); output RGB in [0, 1].
#include <array>

namespace orthosonar::reports {

using Rgb = std::array<double, 3>;

enum class ColourMap {
  kHeight,    // perceptually ordered purple -> blue -> green -> yellow (viridis-like)
  kDistance,  // blue (agrees) -> yellow -> red (far from the other cloud)
  kCoverage,  // the paper's heat maps: blue (low) -> orange (high)
};

Rgb colour_at(ColourMap map, double t);

}  // namespace orthosonar::reports
