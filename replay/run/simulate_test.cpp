// simulate_to_fixture (`orthosonar simulate`): the fixture holds every simulated event and
// no .partial is left; snapshots land at the asked times; a fixture that cannot be opened
// is an error naming it.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

#include "replay/fixture/fixture.hpp"
#include "replay/run/simulate.hpp"

namespace orthosonar::run {
namespace {

std::filesystem::path simulate_test_dir(const std::string& name) {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = (env && *env ? std::filesystem::path(env) : std::filesystem::temp_directory_path()) / "run" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

sim::Simulator short_mission() {
  auto scene = sim::builtin_scene("aircraft", 1);
  REQUIRE(scene.ok());
  sim::SimConfig cfg;
  cfg.duration_s = 3.0;
  cfg.resolution = sim::Resolution::kReduced;
  return sim::Simulator(std::move(*scene), cfg);
}

TEST_CASE("simulate: the fixture holds every event, snapshots at the asked times", "[simulate]") {
  const auto dir = simulate_test_dir("simulate_fixture");
  sim::Simulator simulator = short_mission();
  SimulateOptions o;
  o.out = (dir / "m.mcap").string();
  o.snapshot_dir = (dir / "snaps").string();
  o.snapshot_at_s = {2.0, 1.0};
  auto counts = simulate_to_fixture(simulator, o);
  REQUIRE(counts.ok());
  CHECK_FALSE(std::filesystem::exists(o.out + ".partial"));
  uint64_t sum = 0;
  for (uint64_t c : counts->per_channel) sum += c;
  CHECK(sum == counts->events);
  CHECK(counts->per_channel[static_cast<size_t>(Channel::kSonarHorizontal)] > 0);
  auto source = replay::FixtureSource::open(o.out);
  REQUIRE(source.ok());
  uint64_t read = 0;
  for (;;) {
    hal::Pulled p = (*source)->next();
    REQUIRE_FALSE(p.error);
    if (p.end_of_stream) break;
    ++read;
  }
  CHECK(read == counts->events);
  CHECK(std::filesystem::exists(dir / "snaps" / "aircraft_horizontal_00001.0s.png"));
  CHECK(std::filesystem::exists(dir / "snaps" / "aircraft_vertical_00002.0s.png"));
}

TEST_CASE("simulate: an unwritable fixture is an error naming it", "[simulate]") {
  const auto dir = simulate_test_dir("simulate_unwritable");
  sim::Simulator simulator = short_mission();
  SimulateOptions o;
  o.out = (dir / "no_such_dir" / "m.mcap").string();
  auto counts = simulate_to_fixture(simulator, o);
  REQUIRE_FALSE(counts.ok());
  CHECK(counts.error().message.find("no_such_dir") != std::string::npos);
}

}  // namespace
}  // namespace orthosonar::run
