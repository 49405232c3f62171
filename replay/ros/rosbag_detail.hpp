#pragma once
// Internal to orthosonar_ros: the ROS 1 bag format (2.0) that the reader (rosbag.cpp) and the writer (rosbag_writer.cpp) share.
//
// Every record is
//   header_len u32 | header: fields (field_len u32, "name=value") | data_len u32 | data
// and the field "op" says what it is. The layout rosbag writes (and this writer too):
//   "#ROSBAG V2.0\n", bag header record (padded to 4096 bytes),
//   chunks, each followed by one index data record per connection in it,
//   connection records and chunk info records (the index section, at index_pos).
#include <cstdint>
#include <string_view>

namespace orthosonar::replay::rosbag::detail {

constexpr std::string_view kVersionLine = "#ROSBAG V2.0\n";
constexpr uint32_t kBagHeaderBytes = 4096;  // header + data (padding) of the bag header record
constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;
enum Op : uint8_t { kMessageData = 2, kBagHeader = 3, kIndexData = 4, kChunk = 5, kChunkInfo = 6, kConnection = 7 };

}  // namespace orthosonar::replay::rosbag::detail
