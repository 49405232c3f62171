// ROS 1 bags, reading: the record walk, the index (connections, chunk infos), chunks and their bz2 / lz4 decompression.
//
// Bag format 2.0 (wiki.ros.org/Bags/Format/2.0), the layout of rosbag_detail.hpp.
// Messages and their connections' first connection records live inside the chunks.
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
#include <optional>
#include <string_view>
#include <utility>

#include "replay/fixture/mcap_reader.hpp"

namespace orthosonar::replay::rosbag {
using namespace detail;
namespace {

constexpr uint64_t kReleaseBytes = uint64_t{8} << 20;  // walks drop the mapped pages read in steps of this
// An LZ4 sequence encodes at most 255 output bytes per input byte: a chunk claiming more is
// rejected before its buffer is allocated. bz2 has no useful bound (a run of one byte
// compresses a millionfold), so its buffer grows with the output actually produced.
constexpr uint64_t kLz4MaxRatio = 255, kLz4Slack = 4096;

uint32_t get32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}
uint64_t to_ns(uint64_t time_field) {  // the 8 bytes sec, nsec as one little-endian value
  return (time_field & 0xffffffffu) * 1'000'000'000u + (time_field >> 32);
}

// Where a record is: a file offset, or an offset inside a chunk's uncompressed data (chunk:
// the chunk record's file offset, never 0 as the file starts with the version line).
struct Loc {
  uint64_t chunk = 0, offset = 0;
};
Error at(const std::string& path, Loc l, const std::string& what) {
  if (l.chunk == 0) return Error{path + ": " + what + " at byte offset " + std::to_string(l.offset)};
  return Error{path + ": " + what + " at offset " + std::to_string(l.offset) + " inside the chunk at byte offset " +
               std::to_string(l.chunk)};
}

// The fields this reader uses, from a record header or from a connection record's data
// (the connection header, in the same field format). Other fields are ignored.
struct Fields {
  using F = std::optional<std::string_view>;
  F op, conn, time, topic, compression, size, index_pos, conn_count, chunk_count, ver, count, chunk_pos, start_time,
      end_time, type, md5sum, message_definition, callerid, latching;
};
constexpr std::pair<std::string_view, Fields::F Fields::*> kFieldNames[] = {
    {"op", &Fields::op}, {"conn", &Fields::conn}, {"time", &Fields::time}, {"topic", &Fields::topic},
    {"compression", &Fields::compression}, {"size", &Fields::size}, {"index_pos", &Fields::index_pos},
    {"conn_count", &Fields::conn_count}, {"chunk_count", &Fields::chunk_count}, {"ver", &Fields::ver},
    {"count", &Fields::count}, {"chunk_pos", &Fields::chunk_pos}, {"start_time", &Fields::start_time},
    {"end_time", &Fields::end_time}, {"type", &Fields::type}, {"md5sum", &Fields::md5sum},
    {"message_definition", &Fields::message_definition}, {"callerid", &Fields::callerid},
    {"latching", &Fields::latching}};

// Splits a header block into its fields; returns why it cannot ("" when it can).
std::string parse_fields(const uint8_t* p, uint64_t n, Fields& f) {
  f = {};
  for (uint64_t i = 0; i < n;) {
    if (n - i < 4) return "header field length cut off";
    const uint32_t len = get32(p + i);
    i += 4;
    if (len > n - i) return "header field of " + std::to_string(len) + " bytes runs past its header";
    const std::string_view field(reinterpret_cast<const char*>(p + i), len);
    const size_t eq = field.find('=');
    if (eq == std::string_view::npos) return "header field without '='";
    for (const auto& [name, member] : kFieldNames)
      if (field.substr(0, eq) == name) f.*member = field.substr(eq + 1);
    i += len;
  }
  return {};
}

// Reads fields as little-endian integers of an exact width; the first fault is kept.
struct Check {
  std::string err;
  uint64_t u(const Fields::F& f, const char* name, size_t width) {
    if (!f || f->size() != width) {
      if (err.empty())
        err = !f ? std::string("no '") + name + "' field"
                 : "field '" + std::string(name) + "' has " + std::to_string(f->size()) + " bytes, not " +
                       std::to_string(width);
      return 0;
    }
    uint64_t v = 0;
    for (size_t i = width; i-- > 0;) v = v << 8 | static_cast<uint8_t>((*f)[i]);
    return v;
  }
  std::string_view s(const Fields::F& f, const char* name) {
    if (!f && err.empty()) err = std::string("no '") + name + "' field";
    return f.value_or(std::string_view{});
  }
};

struct Record {
  Fields h;
  uint8_t op = 0;
  const uint8_t* data = nullptr;
  uint32_t data_len = 0;
  uint64_t end = 0;  // offset just past the record
};
enum class Got { kOk, kPastEnd, kBad };

// The record at buf[pos]: kPastEnd when a length runs past `n` (the caller decides whether
// that is a truncated file or a corrupt chunk), kBad (with `why`) for a malformed header.
Got read_record(const uint8_t* buf, uint64_t n, uint64_t pos, Record& r, std::string& why) {
  if (n - pos < 4) return Got::kPastEnd;
  const uint64_t header_len = get32(buf + pos);
  if (n - pos - 4 < header_len + 4) return Got::kPastEnd;
  const uint64_t data_len = get32(buf + pos + 4 + header_len);
  if (n - pos - 8 - header_len < data_len) return Got::kPastEnd;
  if (why = parse_fields(buf + pos + 4, header_len, r.h); !why.empty()) return Got::kBad;
  Check c;
  r.op = static_cast<uint8_t>(c.u(r.h.op, "op", 1));
  if (!c.err.empty()) return why = c.err + " in a record header", Got::kBad;
  r.data = buf + pos + 8 + header_len;
  r.data_len = static_cast<uint32_t>(data_len);
  r.end = pos + 8 + header_len + data_len;
  return Got::kOk;
}

// The reader's buffer of decompressed chunk bytes. It only grows (reused chunk after chunk),
// keeping its bytes, and does not zero what it adds: the decompressors write it and only
// [0, size) of a chunk is read, so the lz4 slack below costs no page faults until a block
// is decoded into it (zeroing it cost 4 MiB per bag opened, a third of `import`'s time on a
// small lz4 bag under the sanitizers).
class RosbagChunkBuffer {
 public:
  size_t size() const { return size_; }
  uint8_t* data() { return data_.get(); }
  const uint8_t* data() const { return data_.get(); }
  void resize(size_t n) {
    if (n <= size_) return;
    auto grown = std::make_unique_for_overwrite<uint8_t[]>(n);
    if (size_ > 0) std::memcpy(grown.get(), data_.get(), size_);
    data_ = std::move(grown);
    size_ = n;
  }

 private:
  std::unique_ptr<uint8_t[]> data_;
  size_t size_ = 0;
};

// The largest block of an lz4 frame, from its header (4 MiB when the header is unreadable:
// LZ4F_decompress then says why).
size_t rosbag_lz4_block_max(const uint8_t* src, size_t n) {
  if (n < 6 || src[0] != 0x04 || src[1] != 0x22 || src[2] != 0x4D || src[3] != 0x18) return size_t{4} << 20;
  const unsigned id = (src[5] >> 4) & 7u;  // BD byte: 4 = 64 KiB, 5 = 256 KiB, 6 = 1 MiB, 7 = 4 MiB
  return id >= 4 ? size_t{1} << (8 + 2 * id) : size_t{4} << 20;
}

// One lz4 context per reader, reset for every chunk: it keeps its block buffers (up to
// 4 MiB each) from chunk to chunk instead of allocating them again.
using RosbagLz4Context = std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)>;

// Decompresses a roslz4 chunk (an LZ4 frame) of exactly `size` bytes into out[0, size).
std::string unlz4(const uint8_t* src, size_t n, size_t size, RosbagChunkBuffer& out, RosbagLz4Context& dctx) {
  if (size > kLz4MaxRatio * n + kLz4Slack)
    return "lz4 chunk claims " + std::to_string(size) + " bytes from " + std::to_string(n) +
           " compressed (more than lz4 can expand)";
  if (!dctx) {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) return "cannot create an lz4 context";
    dctx.reset(raw);
  } else {
    LZ4F_resetDecompressionContext(dctx.get());
  }
  // Room for one more block (the frame's block size: 64 KiB to 4 MiB) lets LZ4F decode
  // every block in place.
  const size_t cap = size + rosbag_lz4_block_max(src, n);
  if (out.size() < cap) out.resize(cap);  // never shrinks: the buffer is reused chunk after chunk
  size_t in = 0, done = 0, hint = 1;
  while (hint != 0) {
    size_t dst_n = cap - done, src_n = n - in;
    hint = LZ4F_decompress(dctx.get(), out.data() + done, &dst_n, src + in, &src_n, nullptr);
    if (LZ4F_isError(hint)) return std::string("lz4 chunk does not decompress (") + LZ4F_getErrorName(hint) + ")";
    in += src_n;
    done += dst_n;
    if (hint != 0 && dst_n == 0 && src_n == 0)
      return done >= size ? "lz4 chunk decompresses to more than its stated " + std::to_string(size) + " bytes"
                          : "lz4 chunk ends early (after " + std::to_string(done) + " of " + std::to_string(size) + " bytes)";
  }
  if (done != size) return "lz4 chunk decompresses to " + std::to_string(done) + " bytes, not its stated " + std::to_string(size);
  if (in != n) return "lz4 chunk has " + std::to_string(n - in) + " bytes after its frame";
  return {};
}

// Decompresses a bz2 chunk of exactly `size` bytes into out[0, size), growing the buffer
// only as output is produced.
std::string unbz2(const uint8_t* src, size_t n, size_t size, RosbagChunkBuffer& out) {
  bz_stream s{};
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) return "cannot create a bz2 context";
  const std::unique_ptr<bz_stream, int (*)(bz_stream*)> guard(&s, BZ2_bzDecompressEnd);
  s.next_in = const_cast<char*>(reinterpret_cast<const char*>(src));
  s.avail_in = static_cast<unsigned>(n);
  const size_t limit = size + 1;  // one byte more shows a stream longer than stated
  size_t done = 0;
  for (int rc = BZ_OK; rc != BZ_STREAM_END;) {
    size_t cap = std::min(out.size(), limit);
    if (done == cap) {
      if (cap == limit) return "bz2 chunk decompresses to more than its stated " + std::to_string(size) + " bytes";
      out.resize(std::min(limit, std::max<size_t>(2 * cap, 1 << 20)));
      cap = std::min(out.size(), limit);
    }
    s.next_out = reinterpret_cast<char*>(out.data() + done);
    s.avail_out = static_cast<unsigned>(cap - done);
    const unsigned in_before = s.avail_in;
    rc = BZ2_bzDecompress(&s);
    const size_t produced = cap - done - s.avail_out;
    done += produced;
    if (rc != BZ_OK && rc != BZ_STREAM_END)
      return "bz2 chunk does not decompress (bzlib error " + std::to_string(rc) + ")";
    if (rc == BZ_OK && produced == 0 && in_before == s.avail_in && s.avail_out != 0)
      return "bz2 chunk ends early (after " + std::to_string(done) + " of " + std::to_string(size) + " bytes)";
  }
  if (done != size) return "bz2 chunk decompresses to " + std::to_string(done) + " bytes, not its stated " + std::to_string(size);
  if (s.avail_in != 0) return "bz2 chunk has " + std::to_string(s.avail_in) + " bytes after its stream";
  return {};
}

using Visit = std::function<Status(const Connection&, const MessageView&)>;

class Reader final : public BagReader {
 public:
  const std::string& path() const override { return file_->path(); }
  const BagInfo& info() const override { return info_; }
  const std::vector<Connection>& connections() const override { return conns_; }
  Status for_each(const Visit& fn) override { return walk(&fn); }

  Status open() {
    const uint8_t* b = file_->data();
    const uint64_t n = file_->size();
    info_.file_bytes = n;
    if (n < kVersionLine.size() || std::memcmp(b, kVersionLine.data(), kVersionLine.size()) != 0) {
      const bool other = n >= 9 && std::memcmp(b, "#ROSBAG V", 9) == 0;
      return at(path(), {}, other ? "unsupported bag version (only '#ROSBAG V2.0' is read)"
                                  : "not a ROS bag (no '#ROSBAG V2.0' line)");
    }
    const uint64_t pos = kVersionLine.size();
    Record r;
    std::string why;
    const Got got = read_record(b, n, pos, r, why);
    if (got == Got::kPastEnd) return at(path(), {0, pos}, "bag header record runs past the end of the file");
    if (got == Got::kBad) return at(path(), {0, pos}, why + " in the bag header record");
    if (r.op != kBagHeader) return at(path(), {0, pos}, "first record has op " + std::to_string(r.op) + ", not a bag header");
    Check c;
    const uint64_t index_pos = c.u(r.h.index_pos, "index_pos", 8);
    const uint64_t conn_count = c.u(r.h.conn_count, "conn_count", 4);
    const uint64_t chunk_count = c.u(r.h.chunk_count, "chunk_count", 4);
    if (!c.err.empty()) return at(path(), {0, pos}, c.err + " in the bag header record");
    data_begin_ = r.end;
    if (index_pos != 0) {
      const std::string bad = read_index(index_pos, conn_count, chunk_count);
      if (bad.empty()) {
        info_.indexed = true;
        info_.bytes_recovered = n;
        data_end_ = index_pos;
        return {};
      }
      info_ = BagInfo{};
      info_.file_bytes = n;
      conns_.clear();
      info_.detail = "index section at byte offset " + std::to_string(index_pos) + " unusable (" + bad + "); read by a scan";
    } else {
      info_.detail = "no index (index_pos 0: the writer did not close the bag); read by a scan";
    }
    return walk(nullptr);
  }

  std::unique_ptr<mcap::MappedFile> file_;

 private:
  const Connection* find(uint32_t id) const {
    auto it = std::lower_bound(conns_.begin(), conns_.end(), id, [](const Connection& k, uint32_t v) { return k.id < v; });
    return it != conns_.end() && it->id == id ? &*it : nullptr;
  }

  // A connection record (from the index or, on a scan, anywhere): the first one of an id counts.
  Status connection(const Record& r, Loc loc) {
    Check c;
    Connection k;
    k.id = static_cast<uint32_t>(c.u(r.h.conn, "conn", 4));
    k.topic = c.s(r.h.topic, "topic");
    Fields d;
    if (std::string why = parse_fields(r.data, r.data_len, d); !why.empty() && c.err.empty()) c.err = why;
    k.type = c.s(d.type, "type");
    k.md5sum = c.s(d.md5sum, "md5sum");
    if (!c.err.empty()) return at(path(), loc, c.err + " in a connection record");
    k.message_definition = d.message_definition.value_or("");
    k.callerid = d.callerid.value_or("");
    k.latching = d.latching == "1";
    if (find(k.id) == nullptr) {
      auto it = std::lower_bound(conns_.begin(), conns_.end(), k.id, [](const Connection& a, uint32_t v) { return a.id < v; });
      conns_.insert(it, std::move(k));
    }
    return {};
  }

  // A message data record: visited (fn), or counted (scan).
  Status message(const Record& r, Loc loc, const Visit* fn) {
    Check c;
    const auto id = static_cast<uint32_t>(c.u(r.h.conn, "conn", 4));
    const uint64_t t = to_ns(c.u(r.h.time, "time", 8));
    if (!c.err.empty()) return at(path(), loc, c.err + " in a message data record");
    const Connection* k = find(id);
    if (k == nullptr) return at(path(), loc, "message for connection " + std::to_string(id) + ", which has no connection record before it");
    if (fn != nullptr) return (*fn)(*k, MessageView{id, t, r.data, r.data_len, loc.chunk, loc.offset});
    if (info_.message_count++ == 0) info_.start_ns = info_.end_ns = t;
    info_.start_ns = std::min(info_.start_ns, t);
    info_.end_ns = std::max(info_.end_ns, t);
    return {};
  }

  // The uncompressed bytes of the chunk record `r` at file offset `pos`: the file's own
  // ("none") or chunk_ (decompressed, the buffer reused).
  Result<std::pair<const uint8_t*, size_t>> chunk_data(const Record& r, uint64_t pos, std::string& compression) {
    Check c;
    const uint64_t size = c.u(r.h.size, "size", 4);
    compression = c.s(r.h.compression, "compression");
    if (!c.err.empty()) return at(path(), {0, pos}, c.err + " in a chunk record");
    if (size > kMaxChunkBytes)
      return at(path(), {0, pos}, "chunk states " + std::to_string(size) + " uncompressed bytes (more than 1 GiB)");
    std::string why;
    if (compression == "none") {
      if (size != r.data_len)
        why = "uncompressed chunk states " + std::to_string(size) + " bytes but holds " + std::to_string(r.data_len);
      else
        return std::pair{r.data, size_t{size}};
    } else if (compression == "lz4") {
      why = unlz4(r.data, r.data_len, size, chunk_, lz4_);
    } else if (compression == "bz2") {
      why = unbz2(r.data, r.data_len, size, chunk_);
    } else {
      why = "unknown chunk compression '" + compression + "'";
    }
    if (!why.empty()) return at(path(), {0, pos}, why);
    return std::pair{static_cast<const uint8_t*>(chunk_.data()), size_t{size}};
  }

  Status walk_chunk(const uint8_t* p, uint64_t n, uint64_t chunk_pos, const Visit* fn) {
    for (uint64_t pos = 0; pos < n;) {
      Record r;
      std::string why;
      const Loc loc{chunk_pos, pos};
      const Got got = read_record(p, n, pos, r, why);
      if (got == Got::kPastEnd) return at(path(), loc, "record runs past the end of its chunk");
      if (got == Got::kBad) return at(path(), loc, why);
      if (r.op == kMessageData) {
        if (auto s = message(r, loc, fn); !s) return s;
      } else if (r.op != kConnection) {
        return at(path(), loc, "record with op " + std::to_string(r.op) + " inside a chunk");
      } else if (fn == nullptr) {
        if (auto s = connection(r, loc); !s) return s;
      }
      pos = r.end;
    }
    return {};
  }

  Status truncated(uint64_t pos, const std::string& why) {
    info_.complete = false;
    info_.bytes_recovered = data_end_ = pos;
    info_.detail = why + " at byte offset " + std::to_string(pos) + ": kept the " + std::to_string(pos) +
                   " bytes before it (" + info_.detail + ")";
    return {};
  }

  // Walks the records after the bag header. A scan (fn null) goes to the end of the file,
  // taking connections, counting chunks and messages, and stops at a truncation; a visit
  // goes to data_end_ (the index section, or where the scan stopped) calling fn.
  Status walk(const Visit* fn) {
    const uint8_t* b = file_->data();
    const uint64_t end = fn != nullptr ? data_end_ : file_->size();
    uint64_t pos = data_begin_, released = 0;
    while (pos < end) {
      Record r;
      std::string why;
      const Got got = read_record(b, end, pos, r, why);
      if (got == Got::kPastEnd) {
        if (fn == nullptr) return truncated(pos, "record runs past the end of the file");
        return at(path(), {0, pos}, "record runs past the end of the data section");
      }
      if (got == Got::kBad) return at(path(), {0, pos}, why);
      if (r.op == kChunk) {
        std::string compression;
        // rosbag writes a chunk's header with sizes 0 and fills them in when it closes the
        // chunk: a compressed chunk still at 0 is where a killed recorder stopped; an
        // uncompressed one's records follow it and are read as records outside chunks.
        if (r.data_len == 0 && fn == nullptr) {
          const std::string c(r.h.compression.value_or("?"));
          if (c != "none") return truncated(pos, "unterminated " + c + " chunk");
          info_.detail += "; an unterminated uncompressed chunk at byte offset " + std::to_string(pos) +
                          ": its records were read as records outside chunks";
        }
        auto data = chunk_data(r, pos, compression);
        if (!data) return data.error();
        if (fn == nullptr) {
          ++info_.chunk_count;
          auto& cs = info_.compressions;
          if (std::find(cs.begin(), cs.end(), compression) == cs.end()) cs.push_back(compression);
        }
        if (auto s = walk_chunk(data->first, data->second, pos, fn); !s) return s;
        if (r.end - released >= kReleaseBytes) {  // resident: the chunks in use, not the file
          file_->release(released, r.end - released);
          released = r.end;
        }
      } else if (r.op == kMessageData) {
        if (auto s = message(r, {0, pos}, fn); !s) return s;
      } else if (r.op == kConnection) {
        if (fn == nullptr)
          if (auto s = connection(r, {0, pos}); !s) return s;
      } else if (r.op != kIndexData && r.op != kChunkInfo) {
        return at(path(), {0, pos}, "unexpected record with op " + std::to_string(r.op));
      }
      pos = r.end;
    }
    if (fn == nullptr) info_.bytes_recovered = data_end_ = pos;
    return {};
  }

  // Takes connections and chunk infos from the index section; returns why it cannot ("").
  std::string read_index(uint64_t index_pos, uint64_t conn_count, uint64_t chunk_count) {
    const uint8_t* b = file_->data();
    const uint64_t n = file_->size();
    if (index_pos < data_begin_ || index_pos > n) return "index_pos outside the file";
    if (conn_count + chunk_count > (n - index_pos) / 8) return "fewer bytes than the records it counts";
    uint64_t pos = index_pos;
    auto next = [&](uint8_t op, Record& r) -> std::string {
      std::string why;
      const Got got = read_record(b, n, pos, r, why);
      const std::string where = " at byte offset " + std::to_string(pos);
      if (got == Got::kPastEnd) return "record runs past the end of the file" + where;
      if (got == Got::kBad) return why + where;
      if (r.op != op) return "record with op " + std::to_string(r.op) + where + ", expected " + std::to_string(op);
      pos = r.end;
      return {};
    };
    Record r;
    for (uint64_t i = 0; i < conn_count; ++i) {
      const uint64_t at_pos = pos;
      if (std::string why = next(kConnection, r); !why.empty()) return why;
      if (auto s = connection(r, {0, at_pos}); !s) return s.error().message;
    }
    for (uint64_t i = 0; i < chunk_count; ++i) {
      const uint64_t at_pos = pos;
      if (std::string why = next(kChunkInfo, r); !why.empty()) return why;
      Check c;
      const uint64_t ver = c.u(r.h.ver, "ver", 4), chunk_pos = c.u(r.h.chunk_pos, "chunk_pos", 8);
      const uint64_t start = to_ns(c.u(r.h.start_time, "start_time", 8)), end = to_ns(c.u(r.h.end_time, "end_time", 8));
      const uint64_t count = c.u(r.h.count, "count", 4);
      const std::string where = " in the chunk info record at byte offset " + std::to_string(at_pos);
      if (!c.err.empty()) return c.err + where;
      if (ver != 1) return "version " + std::to_string(ver) + where;
      if (r.data_len != 8 * count) return "data length does not match its count" + where;
      for (uint64_t j = 0; j < count; ++j) info_.message_count += get32(r.data + 8 * j + 4);
      Record chunk;
      std::string why;
      if (chunk_pos < data_begin_ || chunk_pos >= index_pos || read_record(b, index_pos, chunk_pos, chunk, why) != Got::kOk ||
          chunk.op != kChunk || !chunk.h.compression)
        return "no chunk record at its chunk_pos" + where;
      const std::string compression(*chunk.h.compression);
      auto& cs = info_.compressions;
      if (std::find(cs.begin(), cs.end(), compression) == cs.end()) cs.push_back(compression);
      info_.start_ns = i == 0 ? start : std::min(info_.start_ns, start);
      info_.end_ns = i == 0 ? end : std::max(info_.end_ns, end);
    }
    info_.chunk_count = chunk_count;
    return {};
  }

  BagInfo info_;
  std::vector<Connection> conns_;  // ordered by id
  uint64_t data_begin_ = 0, data_end_ = 0;
  RosbagChunkBuffer chunk_;
  RosbagLz4Context lz4_{nullptr, LZ4F_freeDecompressionContext};
};

}  // namespace

Result<std::unique_ptr<BagReader>> BagReader::open(const std::string& path) {
  auto file = mcap::MappedFile::open(path);
  if (!file) return file.error();
  auto r = std::make_unique<Reader>();
  r->file_ = std::move(file.value());
  if (auto s = r->open(); !s) return s.error();
  return std::unique_ptr<BagReader>(std::move(r));
}

}  // namespace orthosonar::replay::rosbag
