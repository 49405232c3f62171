// libFuzzer harness: ROS 1 bag files (bag header, index section, chunks none/bz2/lz4,
// connection and message records, truncation recovery) through BagReader, every message.
#include "hal/fuzz_support.hpp"
#include "replay/ros/rosbag.hpp"

using namespace orthosonar;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile file(".bag");
  auto bag = replay::rosbag::BagReader::open(file.write(data, size));
  if (!bag.ok()) return 0;
  uint64_t bytes = (*bag)->connections().size();
  (void)(*bag)->for_each([&](const replay::rosbag::Connection& c, const replay::rosbag::MessageView& m) -> Status {
    bytes += c.topic.size() + m.size + (m.size > 0 ? m.data[m.size - 1] : 0);
    return {};
  });
  (void)bytes;
  return 0;
}
