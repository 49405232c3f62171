// `orthosonar import`'s input: a ROS 1 bag or an MCAP recording opened by its magic and visited in file order.
#include "replay/ros/import_detail.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "replay/mcap/mcap_generic.hpp"
#include "replay/ros/msg_types.hpp"
#include "replay/ros/rosbag.hpp"

namespace orthosonar::replay::ros::detail {
namespace {

bool starts_with(const uint8_t* p, size_t n, std::string_view s) {
  return n >= s.size() && std::memcmp(p, s.data(), s.size()) == 0;
}

}  // namespace

Status Recording::visit(const OnChannel& on_channel, const OnMessage& on_message) {
  if (format == "ros1 bag") {
    auto bag = rosbag::BagReader::open(path);
    if (!bag) return bag.error();
    const auto& info = (*bag)->info();
    complete = info.complete;
    if (!info.complete)
      recovery = "kept " + std::to_string(info.bytes_recovered) + " of " + std::to_string(info.file_bytes) +
                 " bytes: " + info.detail;
    for (const auto& c : (*bag)->connections()) {
      SrcChannel s;
      s.topic = c.topic;
      s.type = normalise_type(c.type);
      s.definition = c.message_definition;
      s.encoding_name = "ros1";
      if (s.definition.empty()) s.definition = std::string(rosmsg::definition(s.type, rosmsg::Dialect::kRos1));
      if (auto st = on_channel(c.id, s); !st) return st;
    }
    return (*bag)->for_each([&](const rosbag::Connection& c, const rosbag::MessageView& m) {
      return on_message(SrcMessage{c.id, m.time_ns, m.data, m.size, m.chunk_offset, m.offset});
    });
  }
  RecoveryReport rec;
  Status s = mcap::visit_messages(
      path,
      [&](const mcap::RawChannel& c, const mcap::RawSchema* schema) {
        SrcChannel s;
        s.topic = c.topic;
        s.encoding_name = c.message_encoding;
        if (schema != nullptr) {
          s.type = normalise_type(schema->name);
          s.definition = schema->data;
          if (schema->encoding == "ros2msg") s.dialect = rosmsg::Dialect::kRos2;
          else if (schema->encoding == "ros1msg") s.dialect = rosmsg::Dialect::kRos1;
          else s.unusable = "schema encoding '" + schema->encoding + "' (ros1msg or ros2msg expected)";
        } else {
          s.unusable = "no schema";
        }
        if (c.message_encoding == "cdr") s.encoding = rosmsg::Encoding::kCdr;
        else if (c.message_encoding == "ros1") s.encoding = rosmsg::Encoding::kRos1;
        else if (s.unusable.empty()) s.unusable = "message encoding '" + c.message_encoding + "' (ros1 or cdr expected)";
        if (s.unusable.empty() && s.definition.empty())
          s.definition = std::string(rosmsg::definition(s.type, s.dialect));
        return on_channel(c.id, s);
      },
      [&](const mcap::RawMessage& m) {
        return on_message(SrcMessage{m.channel_id, m.log_time_ns, m.data, m.size, m.chunk_offset, m.offset});
      },
      &rec);
  complete = rec.complete;
  if (!rec.complete)
    recovery = "kept " + std::to_string(rec.bytes_recovered) + " of " + std::to_string(rec.bytes_total) +
               " bytes: " + rec.detail;
  return s;
}

Result<Recording> open_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  uint8_t head[13] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto n = static_cast<size_t>(in.gcount());
  Recording r;
  r.path = path;
  std::error_code ec;
  r.bytes = std::filesystem::file_size(path, ec);
  if (starts_with(head, n, "#ROSBAG V2.0\n")) {
    r.format = "ros1 bag";
  } else if (starts_with(head, n, "\x89MCAP0\r\n")) {
    r.format = "mcap";
  } else if (starts_with(head, n, "#ROSBAG V")) {
    return Error{path + ": a ROS bag of another format version (only 2.0, the format of ROS 1 since 2010, is read)"};
  } else {
    return Error{path + ": neither a ROS 1 bag (\"#ROSBAG V2.0\") nor an MCAP file (magic \\x89MCAP0) at byte 0"};
  }
  return r;
}

std::string where(const Recording& rec, const SrcChannel& c, uint64_t index, const SrcMessage& m) {
  std::string s = rec.path + ": " + c.topic + " message " + std::to_string(index);
  if (m.chunk_offset != 0)
    s += " (chunk at byte " + std::to_string(m.chunk_offset) + ", offset " + std::to_string(m.offset) + ")";
  else
    s += " (byte " + std::to_string(m.offset) + ")";
  return s;
}

}  // namespace orthosonar::replay::ros::detail
