#pragma once
// Serialising a Value tree by a Schema (the counterpart of rosmsg::decode): each field
// of the definition, in the definition's order, from the message's field of that name,
// or its zero value when the message has none. Writing by the definition rather than by
// hand keeps an exported message in step with the exact text its connection record or
// MCAP schema carries.
#include "core/result.hpp"
#include "replay/ros/ros_msg.hpp"

namespace orthosonar::replay::rosmsg {

// Errors name the field path: a value of the wrong kind, a fixed-length array of the
// wrong length, a number out of its field's range.
Status encode(const Schema& schema, const Value& message, Writer& out);

}  // namespace orthosonar::replay::rosmsg
