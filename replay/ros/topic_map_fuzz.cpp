// libFuzzer harness: topics.yaml (`orthosonar import --map`).
#include <string>

#include "hal/fuzz_support.hpp"
#include "replay/ros/topic_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto map = orthosonar::replay::ros::parse_topic_map(std::string(orthosonar::fuzz::text(data, size)), "fuzz.yaml");
  // What the map writes must parse again.
  if (map.ok()) (void)orthosonar::replay::ros::parse_topic_map(orthosonar::replay::ros::topic_map_yaml(*map, false), "again.yaml");
  return 0;
}
