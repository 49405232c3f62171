#pragma once
// Rendered-image expectations of golden scenarios (issue 8): one small top view per
// mapping system (points coloured by height, truth mesh overlay, trajectories), rendered
// from a run's output directory with the reports library, stored as PNG beside the
// scenario and compared with reports::image_difference.
// Rendering needs an X display (run under `xvfb-run -a`); one thread at a time.
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/result.hpp"

namespace orthosonar::verify {

// Default `tolerances.image_difference` of a scenario: the largest reports::image_difference
// score (mean absolute grayscale difference at 160x120, in [0, 1]) accepted between the
// stored and the current render. Measured on the four golden scenarios (480x360 top views,
// Xvfb + Mesa llvmpipe; table in docs/VERIFICATION.md): two renders of the same map score
// exactly 0 (40 comparisons: repeated runs, separate processes and X servers, 1/2/4
// threads); renders of different maps of the same scene and system score 0.00103 to 0.0174
// (keyframe distance 2.5 m instead of 3, seed 2, 50 s instead of 60). 0.0005 is half the
// smallest real change and the stability bound of reports/render_test.cpp; renderer jitter
// passes up to the size of ~180 of the 172800 pixels turned white (200 score 0.00053-0.00056).
inline constexpr double kDefaultImageDifference = 0.0005;

struct GoldenImageConfig {
  // Rendered at render_*_px, then area-downscaled to the stored *_px. The legend, colour
  // bar and title have fixed pixel sizes, so rendering larger keeps them from covering
  // half of a small image; the stored PNGs stay small because they are committed.
  int render_width_px = 960;
  int render_height_px = 720;
  int width_px = 480;
  int height_px = 360;
  double point_size_px = 3.0;   // in the render, before downscaling
  double line_width_px = 3.0;
};

// The top view of every system in `systems`, rendered from the output directory `run_dir`
// (written by write_run_outputs), keyed by system name. Errors: no display (the message
// says to run under `xvfb-run -a`), an unreadable directory, a system without a map.
Result<std::map<std::string, cv::Mat>> render_golden_views(const std::string& run_dir,
                                                           const std::vector<std::string>& systems,
                                                           const std::string& scenario_name,
                                                           const GoldenImageConfig& config = {});

// File name of a system's stored view: "<system>_top.png".
std::string golden_image_name(const std::string& system);

// PNG I/O with errors naming the file (an empty image read is an error).
Result<cv::Mat> read_png(const std::string& path);
Status write_png(const std::string& path, const cv::Mat& image);

}  // namespace orthosonar::verify
