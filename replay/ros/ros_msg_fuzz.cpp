// libFuzzer harness: ROS message definitions and the ros1 / CDR decoders (ros_msg.hpp).
// The first byte picks a known type and an encoding (type index * 2 + 0 ros1 / 1 cdr), the
// rest is decoded as one message of it; the whole input is also parsed as a definition text.
#include <vector>

#include "hal/fuzz_support.hpp"
#include "replay/ros/msg_types.hpp"
#include "replay/ros/ros_msg.hpp"

using namespace orthosonar::replay::rosmsg;

namespace {
// Index 2k: type k's ROS 1 schema (ros1 encoding); 2k + 1: its ROS 2 schema (CDR).
const std::vector<Schema>& schemas() {
  static const std::vector<Schema> all = [] {
    std::vector<Schema> v;
    for (const KnownType& k : known_types()) {
      v.push_back(Schema::parse(k.name, k.ros1, Dialect::kRos1).value());
      v.push_back(Schema::parse(k.name, k.ros2, Dialect::kRos2).value());
    }
    return v;
  }();
  return all;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t pick = data[0] % schemas().size();
  (void)decode(schemas()[pick], pick % 2 == 0 ? Encoding::kRos1 : Encoding::kCdr, data + 1, size - 1);
  auto parsed = Schema::parse("fuzz/Root", orthosonar::fuzz::text(data, size),
                              data[0] % 2 == 0 ? Dialect::kRos1 : Dialect::kRos2);
  if (parsed) (void)parsed->md5();
  return 0;
}
