// perception-check's driver (perception_check.hpp): inputs checked before any measurement,
// the --cloud file names.
#include "replay/run/perception_check.hpp"

#include <catch2/catch.hpp>

using namespace orthosonar;
using namespace orthosonar::run;

TEST_CASE("perception-check: one cloud file per profile", "[unit]") {
  CHECK(cloud_path_for("out/c.ply", "field", 1) == "out/c.ply");
  CHECK(cloud_path_for("out/c.ply", "field", 2) == "out/c_field.ply");
  CHECK(cloud_path_for("out.d/c", "clean", 2) == "out.d/c_clean");
  CHECK(cloud_path_for("c", "clean", 2) == "c_clean");
}

TEST_CASE("perception-check: bad inputs are errors naming them, before any measurement", "[unit]") {
  PerceptionCheckOptions o;
  o.profile = "murky";
  auto bad_profile = PerceptionCheck::open(o);
  REQUIRE_FALSE(bad_profile.ok());
  CHECK(bad_profile.error().message.find("--profile: ") == 0);
  CHECK(bad_profile.error().message.find("murky") != std::string::npos);
  o = {};
  o.scene = "atlantis";
  auto bad_scene = PerceptionCheck::open(o);
  REQUIRE_FALSE(bad_scene.ok());
  CHECK(bad_scene.error().message.find("atlantis") != std::string::npos);
  o = {};
  o.real_pings = {"no/such/ping.raw"};
  auto bad_ping = PerceptionCheck::open(o);
  REQUIRE_FALSE(bad_ping.ok());
  CHECK(bad_ping.error().message.find("--real-ping 'no/such/ping.raw'") == 0);
  o = {};
  o.resolution = "reduced";
  auto good = PerceptionCheck::open(o);
  REQUIRE(good.ok());
  CHECK_FALSE(good->is_fixture());
  CHECK(good->scene().name == "harbor");
  CHECK(good->resolution() == sim::Resolution::kReduced);
}
