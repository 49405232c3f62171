#include "reports/heatmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "reports/draw_util.hpp"

namespace orthosonar::reports {

const char* metric_label(HeatmapMetric metric) {
  switch (metric) {
    case HeatmapMetric::kCoverage: return "coverage (voxels)";
    case HeatmapMetric::kMae: return "MAE (m)";
    case HeatmapMetric::kRmse: return "RMSE (m)";
    case HeatmapMetric::kAteSlam: return "ATE SLAM (m)";
  }
  return "?";
}

namespace {

double value_of(const GridCell& c, HeatmapMetric m) {
  switch (m) {
    case HeatmapMetric::kCoverage: return c.coverage_voxels;
    case HeatmapMetric::kMae: return c.mae_m;
    case HeatmapMetric::kRmse: return c.rmse_m;
    case HeatmapMetric::kAteSlam: return c.ate_slam_m;
  }
  return 0.0;
}

std::string value_text(double v, HeatmapMetric m) {
  char buf[64];
  if (m == HeatmapMetric::kCoverage) std::snprintf(buf, sizeof buf, "%.0f", v);
  else std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

Result<Heatmap> draw_heatmap(const Grid& grid, const HeatmapConfig& config) {
  if (grid.cells.empty()) return Error{"heat map: the grid has no cells"};
  Heatmap hm;
  std::map<std::tuple<std::string, double, double>, double> values;
  std::vector<std::string> others;
  for (const auto& c : grid.cells) {
    const double v = value_of(c, config.metric);
    if (!values.emplace(std::make_tuple(c.system, c.rotation_deg, c.distance_m), v).second)
      return Error{"heat map: two cells for system '" + c.system + "' at " + number_text(c.rotation_deg) + " deg, " +
                   number_text(c.distance_m) + " m"};
    hm.rotations_deg.push_back(c.rotation_deg);
    hm.distances_m.push_back(c.distance_m);
    const auto& known = system_names();
    if (std::find(known.begin(), known.end(), c.system) == known.end()) others.push_back(c.system);
  }
  for (const auto& s : system_names())
    if (std::any_of(grid.cells.begin(), grid.cells.end(), [&](const GridCell& c) { return c.system == s; }))
      hm.systems.push_back(s);
  std::sort(others.begin(), others.end());
  others.erase(std::unique(others.begin(), others.end()), others.end());
  hm.systems.insert(hm.systems.end(), others.begin(), others.end());
  for (auto* axis : {&hm.rotations_deg, &hm.distances_m}) {
    std::sort(axis->begin(), axis->end());
    axis->erase(std::unique(axis->begin(), axis->end()), axis->end());
  }
  hm.min_value = 1e300;
  hm.max_value = -1e300;
  for (const auto& [k, v] : values) {
    if (!std::isfinite(v)) continue;
    hm.min_value = std::min(hm.min_value, v);
    hm.max_value = std::max(hm.max_value, v);
  }
  if (hm.min_value > hm.max_value) hm.min_value = hm.max_value = 0.0;  // no finite value at all

  const int cw = config.cell_w_px, ch = config.cell_h_px;
  const int rows = static_cast<int>(hm.rotations_deg.size()), cols = static_cast<int>(hm.distances_m.size());
  const int left = 70, top = 90, gap = 40, bar_w = 190, bottom = 70;
  const int panel_w = cols * cw;
  const int panels = static_cast<int>(hm.systems.size());
  const int width = left + panels * panel_w + (panels - 1) * (gap + left / 2) + gap + bar_w;
  const int height = top + rows * ch + bottom;
  hm.image = cv::Mat(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40);
  const std::string title = (grid.scene.empty() ? std::string("sweep") : grid.scene) + ": " + metric_label(config.metric) +
                            " per keyframe setting";
  draw_text(hm.image, title, {16, 24}, 0.8, ink, 2, Align::kLeft);

  const double span = hm.max_value - hm.min_value;
  for (int p = 0; p < panels; ++p) {
    const int x0 = left + p * (panel_w + gap + left / 2);
    draw_text(hm.image, hm.systems[static_cast<size_t>(p)], {x0 + panel_w / 2, top - 22}, 0.75, ink, 2);
    for (int r = 0; r < rows; ++r) {
      const int y = top + r * ch;
      draw_text(hm.image, number_text(hm.rotations_deg[static_cast<size_t>(r)]), {x0 - 10, y + ch / 2}, 0.6, ink, 1,
                Align::kRight);
      for (int c = 0; c < cols; ++c) {
        HeatmapCell cell;
        cell.system = hm.systems[static_cast<size_t>(p)];
        cell.rotation_deg = hm.rotations_deg[static_cast<size_t>(r)];
        cell.distance_m = hm.distances_m[static_cast<size_t>(c)];
        cell.rect = cv::Rect(x0 + c * cw, y, cw, ch);
        const auto it = values.find({cell.system, cell.rotation_deg, cell.distance_m});
        cv::Scalar fill(215, 215, 215);
        cell.text = "-";
        if (it != values.end() && !std::isfinite(it->second)) {
          cell.text = "n/a";
        } else if (it != values.end()) {
          cell.has_value = true;
          cell.value = it->second;
          cell.text = value_text(cell.value, config.metric);
          const double t = span > 0 ? (cell.value - hm.min_value) / span : 0.5;
          fill = to_bgr(colour_at(ColourMap::kCoverage, t));
        }
        cv::rectangle(hm.image, cell.rect, fill, cv::FILLED);
        cv::rectangle(hm.image, cell.rect, cv::Scalar(255, 255, 255), 2);
        draw_text(hm.image, cell.text, {x0 + c * cw + cw / 2, y + ch / 2}, 0.62, ink, 2);
        hm.cells.push_back(cell);
      }
    }
    for (int c = 0; c < cols; ++c)
      draw_text(hm.image, number_text(hm.distances_m[static_cast<size_t>(c)]), {x0 + c * cw + cw / 2, top + rows * ch + 16},
                0.6, ink, 1);
    draw_text(hm.image, "keyframe distance (m)", {x0 + panel_w / 2, top + rows * ch + 48}, 0.6, ink, 1);
  }
  // The row axis title, rotated, left of the first panel.
  {
    const std::string t = "rotation (deg)";
    cv::Mat label(30, rows * ch, CV_8UC3, cv::Scalar(255, 255, 255));
    draw_text(label, t, {label.cols / 2, 14}, 0.55, ink, 1);
    cv::Mat rotated;
    cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    rotated.copyTo(hm.image(cv::Rect(2, top, rotated.cols, rotated.rows)));
  }
  const int bar_x = width - bar_w;
  draw_colour_bar(hm.image, cv::Rect(bar_x, top - 40, bar_w - 10, rows * ch + 40), ColourMap::kCoverage, hm.min_value,
                  hm.max_value, metric_label(config.metric));
  return hm;
}

}  // namespace orthosonar::reports
