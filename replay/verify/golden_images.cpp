// Rendered top views of golden scenarios and their PNG files (see golden_images.hpp).
#include "replay/verify/golden_images.hpp"

#include <filesystem>

#include <opencv2/imgproc.hpp>

#include "hal/codec/image_codec.hpp"
#include "reports/camera.hpp"
#include "reports/map_views.hpp"
#include "reports/render.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::verify {

std::string golden_image_name(const std::string& system) { return system + "_top.png"; }

Result<std::map<std::string, cv::Mat>> render_golden_views(const std::string& run_dir,
                                                           const std::vector<std::string>& systems,
                                                           const std::string& scenario_name,
                                                           const GoldenImageConfig& config) {
  if (auto d = reports::check_display(); !d) return d.error();
  auto run = reports::load_run(run_dir);
  if (!run) return Error{run_dir + ": " + run.error().message};
  // The camera comes from the scene (mesh, truth trajectory), never from the maps, so the
  // stored and the current render frame the same region whatever the map holds.
  const reports::Bounds bounds = reports::run_bounds(*run);
  reports::RenderConfig rc;
  rc.width_px = config.render_width_px;
  rc.height_px = config.render_height_px;
  rc.point_size_px = config.point_size_px;
  rc.line_width_px = config.line_width_px;
  std::map<std::string, cv::Mat> out;
  for (const auto& name : systems) {
    const reports::SystemOutput* system = nullptr;
    for (const auto& s : run->systems)
      if (s.name == name) system = &s;
    if (!system || !system->has_map) return Error{run_dir + ": no map for system " + name};
    auto image = reports::render_map_view(*run, system->map_W, reports::View::kTop, bounds,
                                          scenario_name + " " + name + " (top)", rc);
    if (!image) return Error{scenario_name + " " + name + ": " + image.error().message};
    cv::Mat small;
    cv::resize(*image, small, cv::Size(config.width_px, config.height_px), 0, 0, cv::INTER_AREA);
    out.emplace(name, std::move(small));
  }
  return out;
}

Result<cv::Mat> read_png(const std::string& path) {
  if (!std::filesystem::exists(path)) return Error{path + ": not found"};
  return codec::read_image(path, codec::DecodeAs::kBgr);
}

Status write_png(const std::string& path, const cv::Mat& image) {
  std::error_code ec;
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec) return Error{parent.string() + ": " + ec.message()};
  return codec::write_png(path, image);
}

}  // namespace orthosonar::verify
