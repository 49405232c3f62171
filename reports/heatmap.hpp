#pragma once
// Coverage heat maps in the paper's layout (Fig. "Simulation coverage results"): one
// panel per mapping system, side by side; rows are keyframe rotations (deg), columns
// keyframe distances (m); each cell coloured blue (low) to orange (high) on one scale
// shared by all panels, with its value printed; the colour bar at the right.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::reports {

enum class HeatmapMetric { kCoverage, kMae, kRmse, kAteSlam };

struct HeatmapConfig {
  HeatmapMetric metric = HeatmapMetric::kCoverage;
  int cell_w_px = 100;
  int cell_h_px = 64;
};

struct HeatmapCell {
  std::string system;
  double rotation_deg = 0.0;
  double distance_m = 0.0;
  bool has_value = false;  // false: no grid cell for this combination (grey, "-") or no value (grey, "n/a")
  double value = 0.0;
  std::string text;        // what is printed in the cell
  cv::Rect rect;           // where the cell is in the image
};

struct Heatmap {
  cv::Mat image;                    // BGR
  std::vector<std::string> systems; // panel order (contract order, then others by name)
  std::vector<double> rotations_deg;  // row order, top to bottom (ascending)
  std::vector<double> distances_m;    // column order, left to right (ascending)
  std::vector<HeatmapCell> cells;     // panel-major, then row, then column
  double min_value = 0.0, max_value = 0.0;
};

// Fails on an empty grid or a grid with two cells for the same (system, rotation, distance).
Result<Heatmap> draw_heatmap(const Grid& grid, const HeatmapConfig& config = {});

const char* metric_label(HeatmapMetric metric);

}  // namespace orthosonar::reports
