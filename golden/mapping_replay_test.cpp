// End-to-end determinism of the mapping pipeline on a short reduced-resolution simulated
// mission, in-process through the run API (replay/run/run.hpp): the same fixture replayed
// five times and with 1, 2, 4 and 8 threads gives one digest, and the output directory
// follows the outputs contract. The CLI's verify (exit codes, naming a tampered output) is
// checked through the executable, as a user runs it.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "replay/fixture/testing.hpp"
#include "golden/cli_runner.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/run.hpp"

namespace fs = std::filesystem;

namespace {

// Each test case runs as its own ctest process, possibly in parallel with the others, so
// each gets its own directory (and its own fixture) under golden_mapping/.
fs::path mapping_test_dir() {
  return orthosonar::replay::testing::case_dir("golden_mapping", Catch::getResultCapture().getCurrentTestName());
}

using Run = orthosonar::testing::CliRun;

Run mapping_cli(const std::string& args) { return orthosonar::testing::run_cli(args, false); }

const fs::path& fixture() {
  static const fs::path f = [] {
    const fs::path path = mapping_test_dir() / "harbor_short.mcap";
    orthosonar::run::MissionSpec spec;
    spec.scene = "harbor";
    spec.duration_s = 15.0;
    spec.resolution = orthosonar::sim::Resolution::kReduced;
    spec.seed = 1;
    auto made = orthosonar::run::ensure_mission_fixture(spec, path.string());
    REQUIRE(made.ok());
    return path;
  }();
  return f;
}

}  // namespace

TEST_CASE("replay gives one digest over 5 runs and with 1 2 4 and 8 threads", "[golden]") {
  const std::string f = fixture().string();
  std::string first;
  int i = 0;
  // Five replays with one thread, then two, four and eight (SPEC §9): one digest.
  for (int threads : {1, 1, 1, 1, 1, 2, 4, 8}) {
    orthosonar::run::RunOptions o;
    o.threads_override = threads;
    auto r = orthosonar::run::run_fixture(f, o);
    REQUIRE(r.ok());
    const std::string digest = r->digest.overall_hex;
    REQUIRE(digest.size() == 64);
    if (first.empty()) {
      first = digest;
      REQUIRE(orthosonar::run::write_run_outputs(*r, o, (mapping_test_dir() / "replay_0").string()).ok());
    }
    INFO("run " << i++ << ", " << threads << " threads");
    CHECK(digest == first);
  }
  // The outputs contract.
  const fs::path out = mapping_test_dir() / "replay_0";
  for (const char* name : {"digest.json", "summary.json", "keyframes.csv", "traj_dr.tum", "traj_slam.tum",
                           "traj_truth.tum", "scene_mesh.ply", "fusion/map.pcd", "fusion/map.ply", "fusion/map.bt",
                           "fusion/metrics.json", "submap/map.pcd", "submap/map.ply", "submap/map.bt",
                           "submap/metrics.json", "factors.csv"})
    CHECK(fs::exists(out / name));
  // A simulated fixture has truth: each geometric map is also measured with the true
  // keyframe poses, and every factor but the prior has its true relative pose and error.
  for (const char* name : {"fusion/metrics.json", "submap/metrics.json"}) {
    std::ifstream in(out / name);
    const nlohmann::json m = nlohmann::json::parse(in);
    INFO(name);
    REQUIRE(m.at("true_pose_mae_m").is_number());
    // (This 15 s mission may fuse no points: then both errors are 0, as mae_m is.)
    CHECK((m.at("true_pose_mae_m").get<double>() > 0.0) == (m.at("counts").at("map_points").get<int64_t>() > 0));
    CHECK(m.at("true_pose_rmse_m").get<double>() >= m.at("true_pose_mae_m").get<double>());
  }
  int64_t factor_rows = 0;
  {
    std::ifstream in(out / "factors.csv");
    std::string line;
    REQUIRE(std::getline(in, line));
    CHECK(line.rfind("kind,from,to,x,y,theta,", 0) == 0);
    while (std::getline(in, line)) {
      ++factor_rows;
      const bool prior = line.rfind("prior,", 0) == 0;
      INFO(line);
      CHECK(std::count(line.begin(), line.end(), ',') == 18);
      CHECK((line.back() == ',') == prior);  // err_theta empty only for the prior
    }
  }
  // summary.json's account of the SLAM factors agrees with the run's counts: one prior, a DR
  // factor per keyframe after the first, the accepted loops, and reasons that add up.
  {
    std::ifstream in(out / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    const nlohmann::json& sf = summary.at("slam_factors");
    const int64_t keyframes = summary.at("counts").at("keyframes").get<int64_t>();
    REQUIRE(keyframes > 1);
    CHECK(sf.at("prior").at("total") == 1);
    int64_t factors = 0;
    for (const auto& [kind, v] : sf.items()) factors += v.at("total").get<int64_t>();
    CHECK(factors == factor_rows);
    CHECK(sf.at("odometry_dr").at("total").get<int64_t>() == keyframes - 1);
    const int64_t loops = summary.at("counts").at("loop_closures").get<int64_t>();
    CHECK((sf.contains("loop_closure") ? sf.at("loop_closure").at("accepted").get<int64_t>() : 0) == loops);
    for (const auto& [kind, v] : sf.items()) {
      int64_t n = 0;
      for (const auto& [reason, c] : v.at("reasons").items()) n += c.get<int64_t>();
      INFO(kind);
      CHECK(n == v.at("total").get<int64_t>());
      CHECK(v.at("accepted").get<int64_t>() <= n);
    }
  }
  // The CLI gives the library's digest.
  const Run cli = mapping_cli("replay " + f + " -q --threads 2 -o " + (mapping_test_dir() / "replay_cli").string());
  REQUIRE(cli.code == 0);
  CHECK(orthosonar::testing::last_line(cli.out) == first);
}

TEST_CASE("verify accepts the digest and names a tampered output", "[golden]") {
  const std::string f = fixture().string();
  const fs::path out = mapping_test_dir() / "verify_base";
  REQUIRE(mapping_cli("replay " + f + " -q -o " + out.string()).code == 0);
  const fs::path digest = out / "digest.json";
  CHECK(mapping_cli("verify " + f + " --expect " + digest.string()).code == 0);

  std::ifstream in(digest);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto at = text.find("\"submap/map\": \"");
  REQUIRE(at != std::string::npos);
  const size_t hex = at + std::string("\"submap/map\": \"").size();
  text[hex] = text[hex] == '0' ? '1' : '0';
  const fs::path tampered = mapping_test_dir() / "tampered_digest.json";
  std::ofstream(tampered) << text;
  const Run r = mapping_cli("verify " + f + " --expect " + tampered.string());
  CHECK(r.code == 1);
  CHECK(r.out.find("submap/map") != std::string::npos);
  CHECK(r.out.find("fusion/map:") == std::string::npos);
  CHECK(mapping_cli("verify " + f + " --expect " + (mapping_test_dir() / "no_such_digest.json").string()).code == 2);
}
