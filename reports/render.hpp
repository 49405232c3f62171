#pragma once
// Offscreen VTK renders of a map: points coloured by a scalar (height by default) with a
// colour bar, the ground-truth mesh as a translucent overlay, trajectories with a
// legend, a title. VTK stays inside render.cpp; callers get an OpenCV BGR image.
// Needs an X display (run under `xvfb-run -a` on a headless machine); without one the
// render returns an Error instead of letting VTK abort the process. Call from one thread
// at a time (one X connection per process is shared by all renders).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/mesh.hpp"
#include "core/result.hpp"
#include "reports/camera.hpp"
#include "reports/colormap.hpp"

namespace orthosonar::reports {

struct RenderTrajectory {
  std::string label;
  std::vector<Eigen::Vector3d> points_W;
  Rgb colour{1.0, 1.0, 1.0};
};

struct RenderScene {
  std::vector<Eigen::Vector3f> points_W;
  std::vector<float> scalars;              // one per point; empty: colour by height (z)
  ColourMap colour_map = ColourMap::kHeight;
  std::string scalar_title = "height z (m)";
  std::optional<std::pair<double, double>> scalar_range;  // default: the data's range
  const TriangleMesh* mesh = nullptr;      // ground truth overlay, not owned
  std::vector<RenderTrajectory> trajectories;
  std::string title;
};

struct RenderConfig {
  int width_px = 1280;
  int height_px = 960;
  double point_size_px = 3.0;
  double mesh_opacity = 0.22;
  double line_width_px = 3.0;
};

// Ok when an X display is available for offscreen OpenGL; otherwise an Error that says
// to run under `xvfb-run -a`.
Status check_display();

Result<cv::Mat> render_scene(const RenderScene& scene, const Camera& camera, const RenderConfig& config = {});

// Trajectory colours used by every figure (truth, dead reckoning, SLAM).
Rgb truth_colour();
Rgb dr_colour();
Rgb slam_colour();

}  // namespace orthosonar::reports
