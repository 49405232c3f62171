#pragma once
// "What the sonars saw": one ping pair as perception saw it (the output directory's
// ping_pair/), both images as fans (horizontal from above, vertical from the side), every
// CFAR detection as a dot, the shared aperture's edges as lines, and each fused point
// circled where it came from on both images.
#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "replay/outputs/ping_pair_io.hpp"

namespace orthosonar::reports {

// About width_px wide (BGR). Fails on a pair without images or bearing tables.
Result<cv::Mat> draw_ping_pair(const outputs::PingPairRecord& pair, int width_px = 1280);

}  // namespace orthosonar::reports
