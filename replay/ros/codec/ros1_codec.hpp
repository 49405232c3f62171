#pragma once
// The ros1msg encoding of our events (SPEC §11): schema texts that mirror what the field
// vehicle publishes, and exact (bit-for-bit) encode/decode of every payload type.
// Schema texts follow the ROS 1 convention for dependent definitions (a line of 80 '='
// then "MSG: pkg/Type"), so the mcap tooling and Foxglove decode the messages.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/canonical.hpp"
#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::replay::ros1 {

struct SchemaDef {
  uint16_t id;             // MCAP schema id (1..7; 0 means "no schema" in MCAP)
  std::string_view name;   // e.g. "sensor_msgs/Imu"
  std::string_view text;   // full ros1msg definition including dependencies
};

const SchemaDef& schema_for(Channel c);
// The ROS frame_id written into each message header.
std::string_view frame_id_for(Channel c);

// Appends the ros1 serialisation of `event` (header seq = event.sequence, header stamp =
// the payload's stamp). Fails when the payload type does not belong to event.channel,
// a stamp is outside the ros1 `time` range, or sizes are inconsistent.
Status encode(const Event& event, CanonicalWriter& out);

// Decodes one message of channel `c`. `header_seq` receives the header's seq field.
Result<Payload> decode(Channel c, const uint8_t* data, size_t size, uint32_t* header_seq = nullptr);

// Bearing in 1/100 degree as int16, the Oculus wire convention (saturating).
int16_t bearing_centideg(double rad);

}  // namespace orthosonar::replay::ros1
