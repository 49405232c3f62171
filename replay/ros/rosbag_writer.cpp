// ROS 1 bags, writing: records, chunks (none, bz2 or lz4) with their index data, and the index section.
#include "replay/ros/rosbag.hpp"
#include "replay/ros/rosbag_detail.hpp"

#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string_view>
#include <utility>

namespace orthosonar::replay::rosbag {
using namespace detail;
namespace {

using Bytes = std::vector<uint8_t>;

std::string le(uint64_t v, size_t width) {
  std::string s(width, '\0');
  for (size_t i = 0; i < width; ++i) s[i] = static_cast<char>(v >> (8 * i));
  return s;
}
std::string time_field(uint64_t ns) { return le(ns / 1'000'000'000u, 4) + le(ns % 1'000'000'000u, 4); }

// A header block; the fields in the order given, which is by name as roscpp (a std::map) writes them.
Bytes header(std::initializer_list<std::pair<std::string_view, std::string_view>> fields) {
  Bytes b;
  for (const auto& [name, value] : fields) {
    const std::string len = le(name.size() + 1 + value.size(), 4);
    b.insert(b.end(), len.begin(), len.end());
    b.insert(b.end(), name.begin(), name.end());
    b.push_back('=');
    b.insert(b.end(), value.begin(), value.end());
  }
  return b;
}
// Appends a record: header_len, header, data_len, data.
void record(Bytes& out, const Bytes& h, const uint8_t* data, size_t n) {
  const std::string hl = le(h.size(), 4), dl = le(n, 4);
  out.insert(out.end(), hl.begin(), hl.end());
  out.insert(out.end(), h.begin(), h.end());
  out.insert(out.end(), dl.begin(), dl.end());
  if (n > 0) out.insert(out.end(), data, data + n);
}
std::string op_field(uint8_t op) { return std::string(1, static_cast<char>(op)); }

class Writer final : public BagWriter {
 public:
  Writer(std::string path, BagWriterOptions o, std::FILE* f) : path_(std::move(path)), o_(std::move(o)), f_(f) {}
  ~Writer() override { (void)close(); }

  Result<uint32_t> add_connection(const std::string& topic, const std::string& type, const std::string& md5sum,
                                  const std::string& message_definition, const std::string& callerid,
                                  bool latching) override {
    if (f_ == nullptr) return Error{path_ + ": bag already closed"};
    const auto id = static_cast<uint32_t>(conns_.size());
    // The connection header as rosbag record stores the publisher's: fields by name.
    Bytes data;
    const std::string latch = latching ? "1" : "0";
    if (!callerid.empty()) data = header({{"callerid", callerid}, {"latching", latch}});
    else if (latching) data = header({{"latching", latch}});
    const Bytes rest = header({{"md5sum", md5sum}, {"message_definition", message_definition}, {"topic", topic}, {"type", type}});
    data.insert(data.end(), rest.begin(), rest.end());
    Bytes rec;
    record(rec, header({{"conn", le(id, 4)}, {"op", op_field(kConnection)}, {"topic", topic}}), data.data(), data.size());
    conns_.push_back({std::move(rec), false});
    return id;
  }

  Status write(uint32_t conn, uint64_t time_ns, const uint8_t* data, size_t size) override {
    if (f_ == nullptr) return Error{path_ + ": bag already closed"};
    if (conn >= conns_.size()) return Error{path_ + ": write to unknown connection " + std::to_string(conn)};
    if (time_ns / 1'000'000'000u > UINT32_MAX) return Error{path_ + ": time " + std::to_string(time_ns) + " ns past ROS time"};
    if (size > kMaxChunkBytes / 2) return Error{path_ + ": message of " + std::to_string(size) + " bytes (at most 512 MiB)"};
    // The reader caps chunks at 1 GiB: a huge message closes the open chunk first.
    if (chunk_open_ && chunk_.size() + size > kMaxChunkBytes / 2)
      if (auto s = close_chunk(); !s) return s;
    if (!chunk_open_) {
      chunk_open_ = true;
      info_ = {pos_, time_ns, time_ns, {}};
    }
    if (!conns_[conn].in_chunk) {  // its connection record, once, in the first chunk that uses it
      chunk_.insert(chunk_.end(), conns_[conn].record.begin(), conns_[conn].record.end());
      conns_[conn].in_chunk = true;
    }
    index_[conn].push_back({time_ns, static_cast<uint32_t>(chunk_.size())});
    ++info_.counts[conn];
    info_.start = std::min(info_.start, time_ns);
    info_.end = std::max(info_.end, time_ns);
    record(chunk_, header({{"conn", le(conn, 4)}, {"op", op_field(kMessageData)}, {"time", time_field(time_ns)}}), data, size);
    if (chunk_.size() > o_.chunk_threshold) return close_chunk();
    return {};
  }

  Status close() override {
    if (f_ == nullptr) return closed_;
    if (chunk_open_) (void)close_chunk();
    const uint64_t index_pos = pos_;
    Bytes out;
    for (const auto& k : conns_) out.insert(out.end(), k.record.begin(), k.record.end());
    for (const auto& c : chunks_) {
      Bytes counts;
      for (const auto& [conn, n] : c.counts) {
        const std::string e = le(conn, 4) + le(n, 4);
        counts.insert(counts.end(), e.begin(), e.end());
      }
      record(out, header({{"chunk_pos", le(c.pos, 8)}, {"count", le(c.counts.size(), 4)}, {"end_time", time_field(c.end)},
                          {"op", op_field(kChunkInfo)}, {"start_time", time_field(c.start)}, {"ver", le(1, 4)}}),
             counts.data(), counts.size());
    }
    emit(out);
    if (std::fseek(f_, static_cast<long>(kVersionLine.size()), SEEK_SET) != 0) failed_ = true;
    emit(bag_header(index_pos, conns_.size(), chunks_.size()));
    if (std::fclose(f_) != 0) failed_ = true;
    f_ = nullptr;
    if (failed_) closed_ = Error{path_ + ": cannot write: " + std::strerror(errno)};
    return closed_;
  }

  static Bytes bag_header(uint64_t index_pos, uint64_t conn_count, uint64_t chunk_count) {
    const Bytes h = header({{"chunk_count", le(chunk_count, 4)}, {"conn_count", le(conn_count, 4)},
                            {"index_pos", le(index_pos, 8)}, {"op", op_field(kBagHeader)}});
    const std::string padding(kBagHeaderBytes - h.size(), ' ');
    Bytes out;
    record(out, h, reinterpret_cast<const uint8_t*>(padding.data()), padding.size());
    return out;
  }

  void emit(const Bytes& b) {
    if (!b.empty() && std::fwrite(b.data(), 1, b.size(), f_) != b.size()) failed_ = true;
    pos_ += b.size();
  }

  uint64_t pos_ = 0;

 private:
  // Writes the open chunk (compressed) and after it one index data record per connection.
  Status close_chunk() {
    const Bytes* data = &chunk_;
    const auto& c = o_.compression;
    if (c == "bz2") {
      auto n = static_cast<unsigned>(chunk_.size() + chunk_.size() / 100 + 601);  // bzlib's documented bound
      packed_.resize(n);
      if (BZ2_bzBuffToBuffCompress(reinterpret_cast<char*>(packed_.data()), &n,
                                   const_cast<char*>(reinterpret_cast<const char*>(chunk_.data())),
                                   static_cast<unsigned>(chunk_.size()), 9, 0, 0) != BZ_OK)
        return fail("bz2 compression failed");
      packed_.resize(n);
      data = &packed_;
    } else if (c == "lz4") {
      // roslz4 reads independent blocks with a content checksum and no content size.
      LZ4F_preferences_t prefs{};
      prefs.frameInfo.blockMode = LZ4F_blockIndependent;
      prefs.frameInfo.contentChecksumFlag = LZ4F_contentChecksumEnabled;
      packed_.resize(LZ4F_compressFrameBound(chunk_.size(), &prefs));
      const size_t n = LZ4F_compressFrame(packed_.data(), packed_.size(), chunk_.data(), chunk_.size(), &prefs);
      if (LZ4F_isError(n)) return fail("lz4 compression failed");
      packed_.resize(n);
      data = &packed_;
    }
    Bytes out;
    record(out, header({{"compression", c}, {"op", op_field(kChunk)}, {"size", le(chunk_.size(), 4)}}), data->data(), data->size());
    for (auto& [conn, entries] : index_) {
      std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
      Bytes d;
      for (const Entry& e : entries) {
        const std::string s = time_field(e.time) + le(e.offset, 4);
        d.insert(d.end(), s.begin(), s.end());
      }
      record(out, header({{"conn", le(conn, 4)}, {"count", le(entries.size(), 4)}, {"op", op_field(kIndexData)}, {"ver", le(1, 4)}}),
             d.data(), d.size());
    }
    emit(out);
    chunks_.push_back(std::move(info_));
    chunk_.clear();
    index_.clear();
    chunk_open_ = false;
    return failed_ ? fail(std::string("cannot write: ") + std::strerror(errno)) : Status{};
  }
  Status fail(const std::string& what) {
    failed_ = true;
    return Error{path_ + ": " + what};
  }

  struct Conn {
    Bytes record;            // its connection record
    bool in_chunk = false;   // written into a chunk already
  };
  struct Entry {
    uint64_t time;
    uint32_t offset;
  };
  struct ChunkInfo {
    uint64_t pos = 0, start = 0, end = 0;
    std::map<uint32_t, uint32_t> counts;  // messages per connection
  };
  std::string path_;
  BagWriterOptions o_;
  std::FILE* f_ = nullptr;
  std::vector<Conn> conns_;
  bool chunk_open_ = false;
  Bytes chunk_, packed_;
  std::map<uint32_t, std::vector<Entry>> index_;  // the open chunk's, per connection
  ChunkInfo info_;                                 // the open chunk's
  std::vector<ChunkInfo> chunks_;
  bool failed_ = false;
  Status closed_;
};

}  // namespace

Result<std::unique_ptr<BagWriter>> BagWriter::open(const std::string& path, const BagWriterOptions& options) {
  const auto& c = options.compression;
  if (c != "none" && c != "bz2" && c != "lz4")
    return Error{path + ": unknown bag compression '" + c + "' (none, bz2 or lz4)"};
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return Error{path + ": cannot create: " + std::strerror(errno)};
  auto w = std::make_unique<Writer>(path, options, f);
  Bytes start(kVersionLine.begin(), kVersionLine.end());
  const Bytes h = Writer::bag_header(0, 0, 0);
  start.insert(start.end(), h.begin(), h.end());
  w->emit(start);
  return std::unique_ptr<BagWriter>(std::move(w));
}

}  // namespace orthosonar::replay::rosbag
