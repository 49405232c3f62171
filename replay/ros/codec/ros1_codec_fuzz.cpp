// libFuzzer harness: the ROS 1 message codec (every channel's message definition).
#include "hal/fuzz_support.hpp"
#include "replay/ros/codec/ros1_codec.hpp"

using namespace orthosonar;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  // The first byte picks the channel (message type); the rest is the serialised message.
  const auto channel = static_cast<Channel>(data[0] % kChannelCount);
  uint32_t seq = 0;
  (void)replay::ros1::decode(channel, data + 1, size - 1, &seq);
  return 0;
}
