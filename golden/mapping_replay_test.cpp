// End-to-end determinism of the mapping pipeline through the CLI, on a short
// reduced-resolution simulated mission: the same fixture replayed three times and with 1
// and 2 threads gives one digest; verify accepts it and rejects a tampered digest naming
// the output; the output directory follows the outputs contract.
#include <catch2/catch.hpp>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "golden/cli_runner.hpp"

namespace fs = std::filesystem;

namespace {

// Each test case runs as its own ctest process, possibly in parallel with the others, so
// each gets its own directory (and its own fixture) under golden_mapping/.
fs::path test_dir() {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  std::string name = Catch::getResultCapture().getCurrentTestName();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  fs::path d = fs::path(env ? env : fs::temp_directory_path().string()) / "golden_mapping" / name;
  fs::create_directories(d);
  return d;
}

using Run = orthosonar::testing::CliRun;

Run run(const std::string& args) { return orthosonar::testing::run_cli(args, false); }

std::string last_line(const std::string& s) {
  std::istringstream in(s);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

const fs::path& fixture() {
  static const fs::path f = [] {
    const fs::path path = test_dir() / "harbor_short.mcap";
    const Run r = run("simulate --scene harbor --duration 15 --resolution reduced -q -o " + path.string());
    REQUIRE(r.code == 0);
    return path;
  }();
  return f;
}

}  // namespace

TEST_CASE("replay gives one digest over 5 runs and with 1 2 and 4 threads", "[golden]") {
  const std::string f = fixture().string();
  std::string first;
  int i = 0;
  // Five replays with one thread, then two and four threads (issue 4, SPEC §9): one digest.
  for (const char* threads : {"1", "1", "1", "1", "1", "2", "4"}) {
    const fs::path out = test_dir() / ("replay_" + std::to_string(i++));
    const Run r = run("replay " + f + " -q --threads " + threads + " -o " + out.string());
    REQUIRE(r.code == 0);
    const std::string digest = last_line(r.out);
    REQUIRE(digest.size() == 64);
    if (first.empty()) first = digest;
    CHECK(digest == first);
  }
  // The outputs contract.
  const fs::path out = test_dir() / "replay_0";
  for (const char* name : {"digest.json", "summary.json", "keyframes.csv", "traj_dr.tum", "traj_slam.tum",
                           "traj_truth.tum", "scene_mesh.ply", "fusion/map.pcd", "fusion/map.ply", "fusion/map.bt",
                           "fusion/metrics.json", "submap/map.pcd", "submap/map.ply", "submap/map.bt",
                           "submap/metrics.json"})
    CHECK(fs::exists(out / name));
}

TEST_CASE("verify accepts the digest and names a tampered output", "[golden]") {
  const std::string f = fixture().string();
  const fs::path out = test_dir() / "verify_base";
  REQUIRE(run("replay " + f + " -q -o " + out.string()).code == 0);
  const fs::path digest = out / "digest.json";
  CHECK(run("verify " + f + " --expect " + digest.string()).code == 0);

  std::ifstream in(digest);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto at = text.find("\"submap/map\": \"");
  REQUIRE(at != std::string::npos);
  const size_t hex = at + std::string("\"submap/map\": \"").size();
  text[hex] = text[hex] == '0' ? '1' : '0';
  const fs::path tampered = test_dir() / "tampered_digest.json";
  std::ofstream(tampered) << text;
  const Run r = run("verify " + f + " --expect " + tampered.string());
  CHECK(r.code == 1);
  CHECK(r.out.find("submap/map") != std::string::npos);
  CHECK(r.out.find("fusion/map:") == std::string::npos);
  CHECK(run("verify " + f + " --expect " + (test_dir() / "no_such_digest.json").string()).code == 2);
}
