// Fixtures are self-contained (issue 16): `orthosonar simulate --scene-file` embeds the
// scene (mesh, route, classes) as MCAP attachments, and replay uses them, never the path.
// A fixture copied to another folder with its scene file deleted replays to the same
// digest with the truth mesh found; a fixture written the old way (metadata naming the
// scene file, no attachments) still replays, to the same digest while its file exists.
#include <catch2/catch.hpp>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "replay/fixture/testing.hpp"
#include "golden/cli_runner.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/simulator.hpp"
#include "replay/fixture/fixture.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;

namespace {

fs::path embedded_test_dir() {
  return orthosonar::replay::testing::case_dir("golden_embedded_scene", Catch::getResultCapture().getCurrentTestName(), true);
}

constexpr double kDuration = 12.0;

// A small site: a generated seafloor, a quay wall (an OBJ box, seafloor to surface) across
// the first leg of the route 17 m ahead of the start, and a route file. The route starts
// away from the origin, so a replay that missed the scene would start dead reckoning
// elsewhere and give another digest.
fs::path write_site(const fs::path& dir) {
  fs::create_directories(dir);
  TriangleMesh box;
  box.vertices = {{-0.5f, -8, -9}, {0.5f, -8, -9}, {0.5f, 8, -9}, {-0.5f, 8, -9},
                  {-0.5f, -8, 1},  {0.5f, -8, 1},  {0.5f, 8, 1},  {-0.5f, 8, 1}};
  box.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  box.object_id.assign(12, 1);
  box.semantic.assign(12, SemanticClass::kOther);
  REQUIRE(sim::write_mesh_obj(box, (dir / "wall.obj").string()).ok());
  std::ofstream(dir / "route.csv") << "# x, y\n-12, 3.5\n2, 3.5\n2, -3.5\n-12, -3.5\n-12, 3.5\n";
  std::ofstream(dir / "quay.yaml")
      << "name: quay\nseed: 2\nvehicle_depth_m: 3\nseafloor_depth_m: 8\n"
         "seafloor: {x_min_m: -40, x_max_m: 40, y_min_m: -25, y_max_m: 25, relief_m: 0.3}\n"
         "objects:\n"
         "  - mesh: wall.obj\n    class: seawall\n    pose: [5, 1, 0, 0, 0, 0]\n    scale: 1.0\n"
         "route_file: route.csv\n";
  return dir / "quay.yaml";
}

using Run = orthosonar::testing::CliRun;
Run embedded_cli(const std::string& args) { return orthosonar::testing::run_cli(args, true); }

nlohmann::json read_json(const fs::path& p) {
  std::ifstream f(p);
  REQUIRE(f.good());
  return nlohmann::json::parse(f);
}

struct Replayed {
  std::string digest;
  nlohmann::json summary, metrics;
};

Replayed replay_cli(const fs::path& fixture, const fs::path& out) {
  const Run r = embedded_cli("replay '" + fixture.string() + "' -q --systems fusion -o '" + out.string() + "'");
  INFO(r.out);
  REQUIRE(r.code == 0);
  return {orthosonar::testing::last_line(r.out), read_json(out / "summary.json"), read_json(out / "fusion" / "metrics.json")};
}

}  // namespace

TEST_CASE("embedded scene: a copied fixture replays without its scene file", "[golden][embed]") {
  const fs::path dir = embedded_test_dir();
  const fs::path yaml = write_site(dir / "site");
  const fs::path a = dir / "a" / "quay.mcap";
  fs::create_directories(a.parent_path());
  const Run sim = embedded_cli("simulate --scene-file '" + yaml.string() + "' --duration " + std::to_string(kDuration) +
                      " --resolution reduced -q -o '" + a.string() + "'");
  INFO(sim.out);
  REQUIRE(sim.code == 0);

  // The fixture holds the scene; its metadata names no folder.
  {
    auto src = replay::FixtureSource::open(a.string());
    REQUIRE(src.ok());
    CHECK((*src)->metadata().at("scene") == "file:quay.yaml");
    REQUIRE((*src)->attachments().size() == 2);
    CHECK((*src)->attachments()[0].name == sim::kEmbeddedSceneYaml);
    CHECK((*src)->attachments()[1].name == sim::kEmbeddedSceneMesh);
    for (const auto& att : (*src)->attachments()) {
      CHECK(att.create_time_ns == 0);
      const std::string text(att.data.begin(), att.data.end());
      CHECK(text.find(dir.string()) == std::string::npos);
    }
  }

  const Replayed first = replay_cli(a, dir / "out_a");
  REQUIRE(first.digest.size() == 64);
  CHECK(first.metrics["mae_m"].is_number());  // the truth mesh was found
  CHECK(first.summary["ground_truth_mesh"].get<std::string>().find("embedded") != std::string::npos);

  // Another folder, the scene file gone: the same digest, the mesh still found.
  const fs::path b = dir / "b" / "copied.mcap";
  fs::create_directories(b.parent_path());
  fs::copy_file(a, b);
  fs::remove_all(dir / "site");
  fs::remove_all(a.parent_path());
  const Replayed moved = replay_cli(b, dir / "out_b");
  CHECK(moved.digest == first.digest);
  CHECK(moved.metrics["mae_m"] == first.metrics["mae_m"]);
  CHECK(moved.metrics["ate_dr_m"] == first.metrics["ate_dr_m"]);

  // The same site simulated from another folder gives a byte-identical fixture.
  const fs::path yaml2 = write_site(dir / "elsewhere" / "deeper");
  const fs::path c = dir / "c.mcap";
  REQUIRE(embedded_cli("simulate --scene-file '" + yaml2.string() + "' --duration " + std::to_string(kDuration) +
              " --resolution reduced -q -o '" + c.string() + "'")
              .code == 0);
  std::ifstream fb(b, std::ios::binary), fc(c, std::ios::binary);
  const std::string bytes_b((std::istreambuf_iterator<char>(fb)), {}), bytes_c((std::istreambuf_iterator<char>(fc)), {});
  CHECK(bytes_b == bytes_c);
}

TEST_CASE("embedded scene: an old-style fixture (no attachments) still replays", "[golden][embed]") {
  const fs::path dir = embedded_test_dir();
  const fs::path yaml = write_site(dir / "site");
  // New style, through the CLI.
  const fs::path fresh = dir / "new.mcap";
  REQUIRE(embedded_cli("simulate --scene-file '" + yaml.string() + "' --duration " + std::to_string(kDuration) +
              " --resolution reduced -q -o '" + fresh.string() + "'")
              .code == 0);
  // Old style, as the simulator wrote fixtures before scenes were embedded: the same
  // events, metadata naming the scene file by its absolute path, no attachments.
  const fs::path old = dir / "old.mcap";
  {
    auto scene = sim::load_scene_file(yaml.string());
    REQUIRE(scene.ok());
    sim::SimConfig cfg;
    cfg.duration_s = kDuration;
    cfg.seed = 1;  // simulate's default
    cfg.resolution = sim::Resolution::kReduced;
    sim::Simulator simulator(std::move(*scene), cfg);
    auto md = simulator.metadata();
    md["scene"] = simulator.scene().origin;  // "file:<absolute path>"
    REQUIRE(md["scene"].rfind("file:/", 0) == 0);
    auto w = replay::FixtureWriter::open(old.string(), md);
    REQUIRE(w.ok());
    for (;;) {
      auto p = simulator.next();
      REQUIRE(!p.error);
      if (p.end_of_stream || !p.event) break;
      REQUIRE((*w)->write(*p.event).ok());
    }
    REQUIRE((*w)->close().ok());
    auto src = replay::FixtureSource::open(old.string());
    REQUIRE(src.ok());
    CHECK((*src)->attachments().empty());
  }
  const Replayed embedded = replay_cli(fresh, dir / "out_new");
  const Replayed legacy = replay_cli(old, dir / "out_old");
  // While the scene file exists, the old fixture gives the new one's digest and metrics.
  CHECK(legacy.digest == embedded.digest);
  CHECK(legacy.metrics["mae_m"] == embedded.metrics["mae_m"]);
  CHECK(legacy.summary["ground_truth_mesh"].get<std::string>().find("quay.yaml") != std::string::npos);

  // Scene file gone: the old fixture still replays (no crash); the summary says why there
  // is no truth mesh, and the accuracy metrics are absent.
  fs::remove_all(dir / "site");
  const Replayed orphan = replay_cli(old, dir / "out_orphan");
  CHECK(orphan.digest.size() == 64);
  CHECK(orphan.metrics["mae_m"].is_null());
  CHECK(orphan.summary["ground_truth_mesh"].get<std::string>().find("quay.yaml") != std::string::npos);
  // A built-in scene's old-style fixture needs no file at all.
  // (hal/sim scene_embed_test covers scene_from_fixture's fallback to the built-in name.)
}
