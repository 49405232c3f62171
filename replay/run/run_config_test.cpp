// Run configuration documents that are not what any key reader expects.
#include "replay/run/run_config.hpp"

#include <catch2/catch.hpp>

using namespace orthosonar;
using namespace orthosonar::run;

// Found by fuzz_run_config (2026-12-01): "? :" (a YAML complex key with no key) threw
// yaml-cpp's TypedBadConversion out of apply_config_yaml, ending the process.
TEST_CASE("config keys that are not plain names are errors, not exceptions", "[unit]") {
  for (const std::string text : {"? :\n", "? [a, b]\n: 1\n", "fusion:\n  ? {x: 1}\n  : 2\n", "[1, 2]: 3\n"}) {
    RunConfig config;
    const RunConfig before = config;
    Status s = Status::Ok();
    REQUIRE_NOTHROW(s = apply_config_yaml(text, config));
    INFO(text);
    REQUIRE_FALSE(s.ok());
    CHECK(s.error().message.find("config:") == 0);
    CHECK(config_to_json(config) == config_to_json(before));  // nothing half-applied
  }
  RunConfig config;
  CHECK(apply_config_yaml("threads: 2\n", config).ok());
  CHECK(config.threads == 2);
}
