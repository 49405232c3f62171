#include "replay/outputs/ping_pair_io.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

using namespace orthosonar;
namespace fs = std::filesystem;

namespace {

SonarPing test_ping(SonarMount mount, uint8_t bytes_per_pixel) {
  SonarPing p;
  p.mount = mount;
  p.device_id = mount == SonarMount::kHorizontal ? 101 : 102;
  p.part_number = 1042;
  p.ping_id = 77;
  p.stamp = Time::from_ns(12'345'678'901);
  p.range_resolution_m = 0.05;
  p.frequency_hz = 1.2e6;
  p.rows = 40;
  p.cols = 16;
  p.bytes_per_pixel = bytes_per_pixel;
  for (int c = 0; c < p.cols; ++c) p.bearings_rad.push_back(-1.1 + 2.2 * c / (p.cols - 1));
  p.image.resize(static_cast<size_t>(p.rows) * p.cols * bytes_per_pixel);
  for (size_t i = 0; i < p.image.size(); ++i) p.image[i] = static_cast<uint8_t>((i * 37 + 11) % 251);
  return p;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("orthosonar_ping_pair_" + name);
  fs::remove_all(d);
  return d;
}

}  // namespace

TEST_CASE("ping_pair/ round-trips both images, detections and fused points", "[outputs][ping_pair]") {
  for (uint8_t bpp : {uint8_t{1}, uint8_t{2}}) {
    const fs::path dir = fresh_dir("round_trip_" + std::to_string(bpp));
    const SonarPing h = test_ping(SonarMount::kHorizontal, bpp), v = test_ping(SonarMount::kVertical, bpp);
    perception::FusionResult f;
    f.detections_h = {{3, 4, 90.0f}, {39, 15, 200.0f}};
    f.detections_v = {{0, 0, 17.0f}};
    perception::FusedPoint p;
    p.range_m = 1.5f;
    p.bearing_rad = 0.1f;
    p.elevation_rad = -0.05f;
    p.confidence = 0.7f;
    p.p_V = Eigen::Vector3f(1.8f, 0.15f, -0.1f);
    p.elevation_from = perception::FusedPoint::Elevation::sloped_face;
    p.elevation_sigma_rad = 0.0125f;
    perception::FusedPoint q = p;
    q.elevation_from = perception::FusedPoint::Elevation::v_return;
    f.points = {p, q};
    REQUIRE(outputs::write_ping_pair(dir.string(), h, v, f, 10.0).ok());
    auto r = outputs::read_ping_pair(dir.string());
    REQUIRE(r.ok());
    CHECK(r->h == h);
    CHECK(r->v == v);
    REQUIRE(r->detections_h.size() == 2);
    CHECK(r->detections_h[1].row == 39);
    CHECK(r->detections_h[1].col == 15);
    CHECK(r->detections_v.size() == 1);
    REQUIRE(r->fused.size() == 2);
    CHECK(r->fused[0].range_m == 1.5f);
    CHECK(r->fused[0].p_V.isApprox(p.p_V));
    CHECK(r->fused[0].elevation_from == perception::FusedPoint::Elevation::sloped_face);
    CHECK(r->fused[0].elevation_sigma_rad == 0.0125f);
    CHECK(r->fused[1].elevation_from == perception::FusedPoint::Elevation::v_return);
    CHECK(r->overlap_deg == 10.0);
  }
}

TEST_CASE("a bad ping_pair/ is an error naming the file and the field", "[outputs][ping_pair]") {
  const fs::path dir = fresh_dir("bad");
  const SonarPing h = test_ping(SonarMount::kHorizontal, 1), v = test_ping(SonarMount::kVertical, 1);
  REQUIRE(outputs::write_ping_pair(dir.string(), h, v, {}, 10.0).ok());
  const fs::path json_path = dir / "ping_pair.json";
  nlohmann::json good;
  std::ifstream(json_path) >> good;
  auto rewrite = [&](const nlohmann::json& j) { std::ofstream(json_path, std::ios::trunc) << j.dump(); };
  struct Case {
    const char* name;
    std::function<void(nlohmann::json&)> edit;
    const char* field;
  };
  const std::vector<Case> cases = {
      {"detection outside", [](nlohmann::json& j) { j["detections_h"] = {{40, 0, 1.0}}; }, "detections_h[0]"},
      {"bearing table", [](nlohmann::json& j) { j["vertical"]["bearings_rad"] = {0.0, 0.1}; }, "vertical.bearings_rad"},
      {"wrong size", [](nlohmann::json& j) { j["horizontal"]["rows"] = 41; }, "horizontal.png"},
      {"missing key", [](nlohmann::json& j) { j["horizontal"].erase("stamp_ns"); }, "horizontal"},
      {"overlap", [](nlohmann::json& j) { j["overlap_deg"] = -1; }, "overlap_deg"},
      {"elevation source",
       [](nlohmann::json& j) {
         j["fused_points"] = {{{"range_m", 1.0}, {"bearing_rad", 0.0}, {"elevation_rad", 0.0}, {"confidence", 1.0},
                               {"elevation_from", "guess"}, {"p_V", {1.0, 0.0, 0.0}}}};
       },
       "fused_points[0].elevation_from"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    nlohmann::json j = good;
    c.edit(j);
    rewrite(j);
    auto r = outputs::read_ping_pair(dir.string());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message.find(c.field) != std::string::npos);
  }
  fs::remove(dir / "vertical.png");
  rewrite(good);
  auto r = outputs::read_ping_pair(dir.string());
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("vertical.png") != std::string::npos);
}
