#pragma once
// The standard 3D views of a run, built on render_scene: a system's map coloured by
// height with the truth mesh and the three trajectories, and the difference view (a map
// coloured by each point's distance to another map). One fixed camera per scene.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/result.hpp"
#include "reports/camera.hpp"
#include "reports/render.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::reports {

// The region every view of this run shows: mesh + truth trajectory (never the clouds,
// unless there is nothing else).
Bounds run_bounds(const RunData& run);

// Height colour range shared by all views of a run (so colours compare): the shown
// region's z span.
std::pair<double, double> height_range(const Bounds& bounds);

// A map (or, with `map` empty, just the mesh and trajectories) in the given view.
Result<cv::Mat> render_map_view(const RunData& run, const std::vector<Eigen::Vector3f>& map_W, View view,
                                const Bounds& bounds, const std::string& title, const RenderConfig& config = {});

// `current_W` coloured by the distance (m, clamped at max_distance_m) of each point to
// `reference_W`; the truth mesh as overlay, no trajectories.
Result<cv::Mat> render_difference_view(const RunData& run, const std::vector<Eigen::Vector3f>& current_W,
                                       const std::vector<Eigen::Vector3f>& reference_W, double max_distance_m,
                                       View view, const Bounds& bounds, const std::string& title,
                                       const RenderConfig& config = {});

// `map_W` coloured by each point's distance (m) to the run's truth mesh (exact point to
// triangle, clamped at max_distance_m), the mesh as overlay, with the trajectories: where
// the map is wrong. Fails without a mesh.
Result<cv::Mat> render_mesh_error_view(const RunData& run, const std::vector<Eigen::Vector3f>& map_W,
                                       double max_distance_m, View view, const Bounds& bounds,
                                       const std::string& title, const RenderConfig& config = {});

const char* view_name(View view);

}  // namespace orthosonar::reports
