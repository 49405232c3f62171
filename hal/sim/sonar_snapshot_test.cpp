// Snapshots at a chosen pose (`simulate --snapshot-pose`): the profile comparison is the
// clean and field renders side by side, and the per-mount PNGs are written.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

#include "hal/sim/sonar_snapshot.hpp"

namespace orthosonar::sim {
namespace {

TEST_CASE("simulate snapshot: clean and field profiles side by side", "[sim][simulate]") {
  auto scene = builtin_scene("aircraft", 1);
  REQUIRE(scene.ok());
  SimConfig cfg;
  cfg.resolution = Resolution::kReduced;
  const SE3 T_W_V = snapshot_vehicle_pose(*scene, 0.0, 0.0, 90.0);
  CHECK(T_W_V.translation().z() == Approx(-scene->vehicle_depth_m));
  const cv::Mat all = profile_comparison_image(*scene, cfg, T_W_V);
  REQUIRE(all.type() == CV_8UC3);
  REQUIRE(all.cols % 2 == 0);
  // Two rows of two cells; the clean and field halves of the image differ.
  const cv::Mat left = all(cv::Rect(0, 0, all.cols / 2, all.rows));
  const cv::Mat right = all(cv::Rect(all.cols / 2, 0, all.cols / 2, all.rows));
  CHECK(cv::norm(left, right, cv::NORM_L1) > 0.0);
  CHECK(all.cols >= 1600);
}

TEST_CASE("simulate snapshot: one fan PNG per mount", "[sim][simulate]") {
  auto scene = builtin_scene("aircraft", 1);
  REQUIRE(scene.ok());
  SimConfig cfg;
  cfg.resolution = Resolution::kReduced;
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = (env && *env ? std::filesystem::path(env) : std::filesystem::temp_directory_path()) / "sim_snapshot";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto paths = write_pose_snapshots(*scene, cfg, snapshot_vehicle_pose(*scene, 0.0, 0.0, 0.0), dir.string());
  REQUIRE(paths.ok());
  REQUIRE(paths->size() == 2);
  CHECK(paths->at(0) == (dir / "aircraft_horizontal.png").string());
  for (const auto& p : *paths) CHECK(std::filesystem::file_size(p) > 1000);
  CHECK_FALSE(write_pose_snapshots(*scene, cfg, SE3(), (dir / "missing" / "dir").string()).ok());
}

}  // namespace
}  // namespace orthosonar::sim
