#include "replay/digest/digest.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "replay/fixture/testing.hpp"

using namespace orthosonar::replay;

TEST_CASE("sha256 matches the FIPS 180-2 test vector", "[unit]") {
  const std::string abc = "abc";
  CHECK(sha256_hex(reinterpret_cast<const uint8_t*>(abc.data()), abc.size()) ==
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST_CASE("digest is independent of add order and sensitive to every byte", "[unit]") {
  DigestBuilder a, b, c;
  a.add("poses", {1, 2, 3});
  a.add("map", {4, 5});
  b.add("map", {4, 5});
  b.add("poses", {1, 2, 3});
  c.add("poses", {1, 2, 3});
  c.add("map", {4, 6});
  const auto da = a.finish(), db = b.finish(), dc = c.finish();
  CHECK(da == db);
  CHECK(da.overall_hex != dc.overall_hex);
  CHECK(differing_outputs(da, dc) == std::vector<std::string>{"map"});
  CHECK(differing_outputs(da, db).empty());
  DigestBuilder d;
  d.add("poses", {1, 2, 3});
  CHECK(differing_outputs(da, d.finish()) == std::vector<std::string>{"map"});
}

TEST_CASE("digest json round trips and rejects malformed files", "[unit]") {
  DigestBuilder a;
  a.add("keyframes", {9, 9, 9});
  a.add("fusion/map", {1});
  const auto d = a.finish();
  const std::string dir = testing::test_dir("digest");
  REQUIRE(write_digest_json(dir + "/digest.json", d).ok());
  const auto back = read_digest_json(dir + "/digest.json");
  REQUIRE(back.ok());
  CHECK(*back == d);
  testing::write_bytes(dir + "/bad.json", {'{', '}'});
  const auto bad = read_digest_json(dir + "/bad.json");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("bad.json") != std::string::npos);
  CHECK_FALSE(read_digest_json(dir + "/missing.json").ok());
}
