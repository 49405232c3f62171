// One raw Oculus ping file read, decoded and converted (oculus_ping_file.hpp).
#include "hal/drivers/oculus_ping_file.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "hal/drivers/test_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

TEST_CASE("a real M1200d ping file reads as a vertical SonarPing", "[hal]") {
  const std::string path = testing::testdata("oculus/m1200d_one_ping_8bit.raw");
  auto f = oculus::read_oculus_ping_file(path, "--real-ping");
  REQUIRE(f.ok());
  CHECK(f->raw.n_beams == 256);
  CHECK(f->ping.cols == 256);
  CHECK(f->ping.rows == f->raw.n_ranges);
  CHECK(f->ping.mount == SonarMount::kVertical);
}

TEST_CASE("a missing or cut ping file is an error naming the option and the path", "[hal]") {
  auto missing = oculus::read_oculus_ping_file("no/such/ping.raw", "--real-ping");
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().message.rfind("--real-ping 'no/such/ping.raw': cannot open", 0) == 0);
  const auto raw = testing::read_file(testing::testdata("oculus/m1200d_one_ping_8bit.raw"));
  const std::string cut = (std::filesystem::temp_directory_path() / "orthosonar_cut_ping.raw").string();
  {
    std::ofstream out(cut, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(raw.data()), 1000);
  }
  auto bad = oculus::read_oculus_ping_file(cut, "--x");
  std::filesystem::remove(cut);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.rfind("--x '" + cut + "': not an Oculus ping result", 0) == 0);
}
