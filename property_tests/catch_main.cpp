// The one Catch2 main shared by every test executable (compiled once). Before running, it
// supplies the test environment that ctest cannot pass reliably to discovered tests
// (Catch's discovery flattens property lists): where tests may write, the repository, the
// CLI. Test data live in the repository (testdata/). Values already in the environment win.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

int main(int argc, char* argv[]) {
  ::setenv("ORTHOSONAR_SOURCE", ORTHOSONAR_SOURCE_DIR, 0);
  ::setenv("ORTHOSONAR_TEST_OUT", ORTHOSONAR_BINARY_DIR "/test_out", 0);
  ::setenv("ORTHOSONAR_CLI", ORTHOSONAR_CLI_PATH, 0);
  // rapidcheck draws a fresh seed per run unless told otherwise; a suite that gates CI must
  // give the same verdict on every run (SPEC §9 applies to the tests too). Explore other
  // seeds with RC_PARAMS="seed=N" (or "reproduce=..."), or over many with tools/property-seeds
  // (ctest property:seeds-1-10); a found counterexample goes into docs/VERIFICATION.md and,
  // once fixed, into a regression test.
  ::setenv("RC_PARAMS", "seed=20261130", 0);
  std::error_code ec;
  std::filesystem::create_directories(std::getenv("ORTHOSONAR_TEST_OUT"), ec);
  return Catch::Session().run(argc, argv);
}
