// Image expectations of golden scenarios (issue 8): `orthosonar golden --check` renders
// one top view per mapping system and compares it with the PNG stored beside the
// scenario. Proven through the CLI on a temporary copy of a real scenario (a 60 s
// reduced-resolution mission, ~2 s a run): an unchanged copy passes; a stored image
// replaced by a flipped one fails naming scenario, system, score and tolerance and leaves
// a side-by-side comparison; without an X display the image check fails (never passes
// silently) unless --no-images is given.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"
#include "golden/cli_runner.hpp"
#include "reports/image_compare.hpp"
#include "reports/render.hpp"

namespace fs = std::filesystem;

namespace {

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(env_or("ORTHOSONAR_TEST_OUT", fs::temp_directory_path().string())) / "golden_images" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

using Run = orthosonar::testing::CliRun;

// Command lines are built by appending, never by `"literal" + std::string` chains: GCC 12
// at -O3 reports a false -Wrestrict inside those (issue 16).
std::string quoted(const fs::path& p) {
  std::string q;
  q.reserve(p.native().size() + 2);
  q.push_back('\'');
  q.append(p.string());
  q.push_back('\'');
  return q;
}

// "golden <verb> '<scenario>' -o '<out>' --bounds '<repository>/golden/bounds.yaml'": the
// scenario copies live outside golden/scenarios/, so the repository's absolute bounds are
// named explicitly (they hold for the copies, which run the same missions).
std::string golden_args(const std::string& verb, const fs::path& scenario, const fs::path& out) {
  std::string a("golden ");
  a.append(verb);
  a.push_back(' ');
  a.append(quoted(scenario));
  a.append(" -o ");
  a.append(quoted(out));
  a.append(" --bounds ");
  a.append(quoted(fs::path(env_or("ORTHOSONAR_SOURCE", ".")) / "golden" / "bounds.yaml"));
  return a;
}

// `prefix` goes before the CLI (e.g. "env -u DISPLAY").
Run cli(const std::string& args, const std::string& prefix = "") {
  return orthosonar::testing::run_cli(args, true, prefix);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A copy of golden/scenarios/marina1.yaml in `dir`, with image expectations recorded by
// `golden --update` (the stored expectations of the real file are never touched).
fs::path recorded_copy(const fs::path& dir) {
  const fs::path source = fs::path(env_or("ORTHOSONAR_SOURCE", ".")) / "golden" / "scenarios" / "marina1.yaml";
  REQUIRE(fs::exists(source));
  const fs::path copy = dir / "marina1.yaml";
  fs::copy_file(source, copy);
  const Run u = cli(golden_args("--update", copy, dir / "out"));
  INFO(u.out);
  REQUIRE(u.code == 0);
  REQUIRE(fs::exists(dir / "marina1" / "fusion_top.png"));
  REQUIRE(fs::exists(dir / "marina1" / "submap_top.png"));
  std::ifstream in(copy);
  std::stringstream yaml;
  yaml << in.rdbuf();
  REQUIRE(contains(yaml.str(), "images:"));
  REQUIRE(contains(yaml.str(), "fusion: marina1/fusion_top.png"));
  REQUIRE(contains(yaml.str(), "image_difference:"));
  return copy;
}

void require_display() {
  const orthosonar::Status s = orthosonar::reports::check_display();
  if (!s) FAIL(s.error().message);
}

}  // namespace

TEST_CASE("golden check passes an unchanged image and fails a changed one with a side-by-side", "[golden]") {
  require_display();
  const fs::path dir = fresh_dir("changed_image");
  const fs::path scenario = recorded_copy(dir);
  const fs::path out = dir / "out";

  const Run same = cli(golden_args("--check", scenario, out));
  INFO(same.out);
  CHECK(same.code == 0);
  CHECK(contains(same.out, "PASS marina1"));
  CHECK(contains(same.out, "image fusion: difference"));

  // Replace the stored fusion view by its upside-down copy: same pixels, moved structure.
  const fs::path stored = dir / "marina1" / "fusion_top.png";
  auto read = orthosonar::codec::read_image(stored.string(), orthosonar::codec::DecodeAs::kBgr);
  REQUIRE(read.ok());
  const cv::Mat image = *read;
  cv::Mat flipped;
  cv::flip(image, flipped, 0);
  INFO("flipped score " << orthosonar::reports::image_difference(image, flipped));
  REQUIRE(orthosonar::codec::write_png(stored.string(), flipped).ok());

  const Run changed = cli(golden_args("--check", scenario, out));
  INFO(changed.out);
  CHECK(changed.code == 1);
  CHECK(contains(changed.out, "FAIL marina1"));
  CHECK(contains(changed.out, "image differs: scenario marina1, system fusion: difference"));
  CHECK(contains(changed.out, "> tolerance"));
  CHECK_FALSE(contains(changed.out, "system submap: difference"));  // the untouched system still passes
  CHECK(fs::exists(out / "marina1" / "threads1_run1" / "fusion_top_comparison.png"));
  CHECK(fs::exists(out / "marina1" / "threads1_run1" / "fusion_top.png"));

  // Digest and metrics alone still match: --no-images is the explicit way to skip images.
  const Run skipped = cli(golden_args("--check --no-images", scenario, out));
  INFO(skipped.out);
  CHECK(skipped.code == 0);
  CHECK(contains(skipped.out, "image checks skipped"));

  // --update reports the changed image with its score, then the copy passes again.
  const Run update = cli(golden_args("--update", scenario, out));
  INFO(update.out);
  CHECK(update.code == 0);
  CHECK(contains(update.out, "image fusion"));
  CHECK(contains(update.out, "(CHANGED, tolerance"));
  CHECK(cli(golden_args("--check", scenario, out)).code == 0);
}

TEST_CASE("golden check without an X display fails and says to run under xvfb-run", "[golden]") {
  require_display();  // to record the copy
  const fs::path dir = fresh_dir("no_display");
  const fs::path scenario = recorded_copy(dir);
  const fs::path out = dir / "out";

  const Run r = cli(golden_args("--check", scenario, out), "env -u DISPLAY");
  INFO(r.out);
  CHECK(r.code == 1);
  CHECK(contains(r.out, "FAIL marina1"));
  CHECK(contains(r.out, "xvfb-run -a"));

  const Run skipped = cli(golden_args("--check --no-images", scenario, out), "env -u DISPLAY");
  INFO(skipped.out);
  CHECK(skipped.code == 0);
}
