#include "replay/outputs/map_writers.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <octomap/OcTree.h>

using namespace orthosonar;

namespace {
std::filesystem::path out_dir() {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  auto d = std::filesystem::path(env ? env : std::filesystem::temp_directory_path().string()) / "outputs";
  std::filesystem::create_directories(d);
  return d;
}
}  // namespace

TEST_CASE("PCD and PLY round trip", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-0.5f, 0.25f, 7}};
  for (const char* name : {"m.pcd", "m.ply"}) {
    const auto path = (out_dir() / name).string();
    const Status s = std::string(name).ends_with(".pcd") ? outputs::write_pcd(path, pts) : outputs::write_ply(path, pts);
    REQUIRE(s.ok());
    const auto back = outputs::read_cloud(path);
    REQUIRE(back.ok());
    CHECK(*back == pts);
  }
  CHECK_FALSE(outputs::write_pcd("/nonexistent-dir/x.pcd", pts).ok());
}

TEST_CASE("OctoMap file marks the points occupied", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1.05f, 2.05f, -3.05f}, {4, 4, 4}};
  const auto path = (out_dir() / "m.bt").string();
  REQUIRE(outputs::write_octomap(path, pts, 0.1).ok());
  octomap::OcTree tree(path);
  CHECK(tree.getResolution() == Approx(0.1));
  auto* n = tree.search(1.05, 2.05, -3.05);
  REQUIRE(n != nullptr);
  CHECK(tree.isNodeOccupied(n));
  CHECK(tree.search(-7.0, -7.0, -7.0) == nullptr);
  CHECK(tree.getNumLeafNodes() == 2);
}
