#pragma once
// ROS 1 bag files, format 2.0 (wiki.ros.org/Bags/Format/2.0): a reader for what `rosbag
// record` leaves (indexed; or unindexed, as a recorder killed before closing leaves it,
// read by a scan of the records) with chunks uncompressed, bz2 (libbz2) or lz4 (roslz4:
// the LZ4 frame format, liblz4), and a writer for export. Container level only: the
// messages stay serialised (replay/ros/ros_msg.hpp decodes them).
// Errors name the file, the byte offset and the field at fault.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::replay::rosbag {

// A connection record: one topic published with one type.
struct Connection {
  uint32_t id = 0;
  std::string topic;
  std::string type;                // e.g. "sensor_msgs/Imu"
  std::string md5sum;              // 32 hex digits
  std::string message_definition;  // full text, dependencies after lines of 80 '='
  std::string callerid;            // may be empty
  bool latching = false;
};

// One message, valid only during the callback that receives it.
struct MessageView {
  uint32_t conn = 0;            // Connection::id
  uint64_t time_ns = 0;         // the record's receive time (sec * 1e9 + nsec)
  const uint8_t* data = nullptr;
  size_t size = 0;
  uint64_t chunk_offset = 0;    // file offset of the chunk holding it (0: outside chunks)
  uint64_t offset = 0;          // offset of its record (inside the uncompressed chunk, or in the file)
};

struct BagInfo {
  uint64_t file_bytes = 0;
  bool indexed = false;                 // the header's index_pos points at connection and chunk info records
  std::vector<std::string> compressions;  // distinct chunk compressions, file order ("none", "bz2", "lz4")
  uint64_t chunk_count = 0;
  uint64_t message_count = 0;           // from the chunk infos when indexed, else counted by the scan
  uint64_t start_ns = 0, end_ns = 0;    // receive times, first and last
  // A bag cut short (a recorder killed mid-chunk, a copy interrupted): everything up to
  // the last complete chunk or record is kept and `complete` is false; `detail` says
  // where and why reading stopped (byte offset), `bytes_recovered` how far it got.
  bool complete = true;
  uint64_t bytes_recovered = 0;
  std::string detail;
};

class BagReader {
 public:
  // Maps the file, checks the "#ROSBAG V2.0\n" line and the bag header record, and finds
  // the connections: from the index section when the header points at one, otherwise by a
  // scan of the whole file (decompressing chunks to find connection records inside them).
  static Result<std::unique_ptr<BagReader>> open(const std::string& path);
  virtual ~BagReader() = default;
  virtual const std::string& path() const = 0;
  virtual const BagInfo& info() const = 0;
  virtual const std::vector<Connection>& connections() const = 0;  // ordered by id
  // Visits every message in file order (chunk by chunk, one decompressed chunk in memory
  // at a time). Stops at the first error from `fn` and returns it. A chunk whose data is
  // corrupt (bad compression, a record running past its end) is an error naming the
  // chunk's file offset; a bag truncated inside a chunk visits the complete chunks only
  // (info().complete says so).
  virtual Status for_each(const std::function<Status(const Connection&, const MessageView&)>& fn) = 0;
};

struct BagWriterOptions {
  std::string compression = "none";     // "none", "bz2" or "lz4"
  uint64_t chunk_threshold = 768 * 1024;  // close a chunk once its uncompressed data reach this size
};

// Writes a bag as `rosbag record` does: a 4096-byte bag header record (rewritten at
// close with index_pos, conn_count and chunk_count), chunks each followed by one index
// data record per connection in it, then the connection records and chunk info records.
// Bytes are a pure function of the calls (no clock).
class BagWriter {
 public:
  static Result<std::unique_ptr<BagWriter>> open(const std::string& path, const BagWriterOptions& options = {});
  virtual ~BagWriter() = default;
  // Returns the new connection's id (0, 1, ...).
  virtual Result<uint32_t> add_connection(const std::string& topic, const std::string& type,
                                          const std::string& md5sum, const std::string& message_definition,
                                          const std::string& callerid = "", bool latching = false) = 0;
  virtual Status write(uint32_t conn, uint64_t time_ns, const uint8_t* data, size_t size) = 0;
  // Writes the index section and rewrites the header. The destructor closes too, ignoring errors.
  virtual Status close() = 0;
};

}  // namespace orthosonar::replay::rosbag
