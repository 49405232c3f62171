#include "replay/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <sstream>

#include <lz4frame.h>
#include <zstd.h>

#include "replay/mcap_chunks.hpp"
#include "replay/mcap_format.hpp"
#include "replay/ros1_codec.hpp"

namespace orthosonar::replay::mcap {
namespace detail {
namespace {

// An LZ4 sequence encodes at most 255 more output bytes per input byte, so a frame cannot
// expand more than 255-fold (plus a little for tiny frames): a chunk claiming more is
// rejected before its buffer is allocated (the frame's content size field is optional).
constexpr uint64_t kLz4MaxRatio = 255;
constexpr uint64_t kLz4Slack = 4096;

// zstd's densest block is a 4-byte RLE block of 128 KiB (a 32768-fold expansion), so a
// chunk claiming more than that from its compressed bytes is rejected before any buffer
// is allocated. A frame without its (optional) content size is decompressed streaming, the
// buffer growing only as output arrives, never past the chunk's declared size.
constexpr uint64_t kZstdMaxRatio = 32768;
constexpr uint64_t kZstdSlack = 4096;

// Decompresses a zstd frame that does not state its content size into `out`: exactly
// c.uncompressed_size bytes, or an error naming the chunk.
Status zstd_frame_streaming(const std::string& path, const ChunkRef& c, const uint8_t* src, std::vector<uint8_t>& out) {
  ZSTD_DStream* raw = ZSTD_createDStream();
  if (raw == nullptr) return at(path, c.offset, "cannot create a zstd decompression stream for the chunk");
  const std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> ds(raw, ZSTD_freeDStream);
  const size_t declared = static_cast<size_t>(c.uncompressed_size);
  out.clear();
  out.resize(std::min<size_t>(declared, size_t{1} << 20));
  ZSTD_inBuffer in{src, static_cast<size_t>(c.compressed_size), 0};
  size_t produced = 0;
  for (;;) {
    if (produced == out.size() && out.size() < declared) out.resize(std::min(declared, 2 * out.size()));
    // With the declared size reached, one byte of room shows a frame that goes on.
    uint8_t extra = 0;
    const bool full = produced == declared;
    ZSTD_outBuffer o = full ? ZSTD_outBuffer{&extra, 1, 0} : ZSTD_outBuffer{out.data(), out.size(), produced};
    const size_t in_before = in.pos, out_before = o.pos;
    const size_t r = ZSTD_decompressStream(ds.get(), &o, &in);
    if (ZSTD_isError(r)) return at(path, c.offset, std::string("chunk does not decompress (") + ZSTD_getErrorName(r) + ")");
    if (full && o.pos > 0)
      return at(path, c.offset, "zstd chunk decompresses to more than its stated " + std::to_string(declared) + " bytes");
    if (!full) produced = o.pos;
    if (r == 0 && in.pos == in.size) break;  // the last frame is complete
    if (in.pos == in_before && o.pos == out_before)  // no progress: the input ended inside a frame
      return at(path, c.offset, "zstd chunk frame ends early (after " + std::to_string(produced) + " of " +
                                    std::to_string(declared) + " bytes)");
  }
  if (produced != declared)
    return at(path, c.offset, "zstd chunk decompresses to " + std::to_string(produced) + " bytes, the chunk states " +
                                  std::to_string(declared));
  return {};
}

// Decompresses an LZ4 frame (MCAP's "lz4") of exactly c.uncompressed_size bytes into `out`.
Status lz4_frame(const std::string& path, const ChunkRef& c, const uint8_t* src, std::vector<uint8_t>& out) {
  if (c.uncompressed_size > kLz4MaxRatio * c.compressed_size + kLz4Slack)
    return at(path, c.offset, "lz4 chunk claims " + std::to_string(c.uncompressed_size) + " uncompressed bytes from " +
                                  std::to_string(c.compressed_size) + " compressed (more than lz4 can expand)");
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    return at(path, c.offset, "cannot create an lz4 decompression context for the chunk");
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> dctx(raw, LZ4F_freeDecompressionContext);
  auto fail = [&](const std::string& what) { return at(path, c.offset, "lz4 chunk " + what); };
  LZ4F_frameInfo_t info{};
  size_t in = static_cast<size_t>(c.compressed_size);
  size_t hint = LZ4F_getFrameInfo(dctx.get(), &info, src, &in);
  if (LZ4F_isError(hint)) return fail(std::string("is not an lz4 frame (") + LZ4F_getErrorName(hint) + ")");
  if (info.contentSize != 0 && info.contentSize != c.uncompressed_size)
    return fail("frame states " + std::to_string(info.contentSize) + " bytes, the chunk " +
                std::to_string(c.uncompressed_size));
  out.resize(static_cast<size_t>(c.uncompressed_size));
  size_t in_pos = in, out_pos = 0;
  while (hint != 0) {
    size_t dst_n = out.size() - out_pos;
    size_t src_n = static_cast<size_t>(c.compressed_size) - in_pos;
    hint = LZ4F_decompress(dctx.get(), out.data() + out_pos, &dst_n, src + in_pos, &src_n, nullptr);
    if (LZ4F_isError(hint)) return fail(std::string("does not decompress (") + LZ4F_getErrorName(hint) + ")");
    in_pos += src_n;
    out_pos += dst_n;
    if (hint != 0 && dst_n == 0 && src_n == 0) {
      // No progress: either the output is full but the frame goes on, or the input ended.
      if (out_pos == out.size())
        return fail("decompresses to more than its stated " + std::to_string(c.uncompressed_size) + " bytes");
      return fail("frame ends early (after " + std::to_string(out_pos) + " of " +
                  std::to_string(c.uncompressed_size) + " bytes)");
    }
  }
  if (out_pos != out.size())
    return fail("decompresses to " + std::to_string(out_pos) + " bytes, not its stated " +
                std::to_string(c.uncompressed_size));
  if (in_pos != c.compressed_size) return fail("has " + std::to_string(c.compressed_size - in_pos) + " bytes after its frame");
  return {};
}

}  // namespace

std::string hex(uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

Error at(const std::string& path, uint64_t offset, const std::string& what) {
  return Error{path + ": " + what + " at byte offset " + std::to_string(offset)};
}

Error at(const std::string& path, Loc l, const std::string& what) {
  if (l.chunk == 0) return at(path, l.offset, what);
  return Error{path + ": " + what + " at offset " + std::to_string(l.offset) + " inside the chunk at byte offset " +
               std::to_string(l.chunk)};
}

std::string cut_detail(const MappedFile& f, uint64_t pos, const std::string& why) {
  return f.path() + ": " + why + " at byte offset " + std::to_string(pos) + " (file size " + std::to_string(f.size()) +
         "); recovered the records before it";
}

Status check_magic(const MappedFile& f) {
  const uint8_t* d = f.data();
  if (f.size() < kMagicSize || std::memcmp(d, kMagic, 5) != 0 || std::memcmp(d + 6, kMagic + 6, 2) != 0)
    return at(f.path(), 0, "not an MCAP file: bad magic");
  if (d[5] != kMagic[5])
    return at(f.path(), 5, std::string("unsupported MCAP version '") + static_cast<char>(d[5]) + "'");
  return {};
}

uint64_t trailing_footer(const MappedFile& f) {
  const uint8_t* d = f.data();
  const size_t size = f.size();
  if (size < 2 * kMagicSize + 2 * kRecordPrefix + 20 || std::memcmp(d + size - kMagicSize, kMagic, kMagicSize) != 0)
    return 0;
  const uint64_t fpos = size - kMagicSize - kRecordPrefix - 20;
  ByteReader fr(d + fpos, kRecordPrefix + 20);
  return fr.u8() == static_cast<uint8_t>(Op::kFooter) && fr.u64() == 20 ? fpos : 0;
}

Result<std::string> check_trailing_magic(const MappedFile& f, uint64_t end) {
  if (f.size() - end < kMagicSize) return std::string("file ends inside the trailing magic");
  if (std::memcmp(f.data() + end, kMagic, kMagicSize) != 0 || f.size() - end != kMagicSize)
    return at(f.path(), end, "bad trailing magic");
  return std::string();
}

Result<RecordHead> record_head(const MappedFile& f, uint64_t pos, uint64_t footer_pos) {
  const size_t size = f.size();
  RecordHead h;
  if (size - pos < kRecordPrefix) {
    h.cut = size - pos == 0 ? "file ends without a footer" : "file ends inside a record header";
    return h;
  }
  const uint8_t* d = f.data();
  h.op = d[pos];
  ByteReader lr(d + pos + 1, 8);
  h.len = lr.u64();
  h.body = d + pos + kRecordPrefix;
  const std::string& path = f.path();
  if (h.op == 0 || (h.op > kMaxOpcode && h.op < 0x80)) return at(path, pos, "unsupported record opcode " + hex(h.op));
  auto what = [&] { return "record (opcode " + hex(h.op) + ", " + std::to_string(h.len) + " bytes)"; };
  if (h.len > size - pos - kRecordPrefix) {
    // A recording cut short, unless the file ends with its footer: then the length lies.
    if (footer_pos != 0) return at(path, pos, what() + " runs past the end of the file");
    h.cut = what() + " runs past the end of the file";
    return h;
  }
  if (footer_pos != 0 && h.op != static_cast<uint8_t>(Op::kFooter) && pos + kRecordPrefix + h.len > footer_pos)
    return at(path, pos, what() + " runs into the footer");
  if (pos == kMagicSize && h.op != static_cast<uint8_t>(Op::kHeader)) return at(path, pos, "first record is not a Header");
  return h;
}

void Progress::advance(uint64_t end, bool in_data_section) {
  if (in_data_section) {
    data_crc_ = crc32(data_crc_, f_.data() + crc_end_, end - crc_end_);
    crc_end_ = end;
  }
  if (end - released_ >= kReleaseBytes) {
    f_.release(released_, end - released_);
    released_ = end;
  }
}

Status Progress::check_data_end(uint64_t pos, const uint8_t* body, uint64_t len) const {
  ByteReader r(body, len);
  const uint32_t stored = r.u32();
  if (!r.ok()) return at(f_.path(), pos, "truncated Data End record");
  // data_crc_ covers [0, pos): the caller advanced to the record before this one.
  if (stored != 0 && stored != data_crc_)
    return at(f_.path(), pos, "data section CRC mismatch (stored " + hex(stored) + ", computed " + hex(data_crc_) + ")");
  return {};
}

bool read_map(ByteReader& r, std::map<std::string, std::string>& out) {
  const uint32_t len = r.u32();
  const uint8_t* p = r.take(len);
  if (p == nullptr) return false;
  ByteReader m(p, len);
  while (m.ok() && m.remaining() > 0) {
    std::string k = m.str();
    std::string v = m.str();
    if (m.ok()) out[k] = v;
  }
  return m.ok();
}

Status parse_schema(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawSchema& out) {
  ByteReader r(body, len);
  out.id = r.u16();
  out.name = r.str();
  out.encoding = r.str();
  const uint32_t dl = r.u32();
  const uint8_t* data = r.take(dl);
  if (!r.ok()) return at(path, loc, "truncated Schema record");
  if (out.id == 0) return at(path, loc, "schema id 0 is reserved");
  out.data.assign(reinterpret_cast<const char*>(data), dl);
  return {};
}

Status parse_channel(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawChannel& out) {
  ByteReader r(body, len);
  out.id = r.u16();
  out.schema_id = r.u16();
  out.topic = r.str();
  out.message_encoding = r.str();
  out.metadata.clear();
  if (!read_map(r, out.metadata) || !r.ok()) return at(path, loc, "malformed Channel record");
  return {};
}

Status parse_message(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawMessage& out) {
  ByteReader r(body, len);
  out.channel_id = r.u16();
  out.sequence = r.u32();
  out.log_time_ns = r.u64();
  out.publish_time_ns = r.u64();
  if (!r.ok()) return at(path, loc, "truncated message record");
  out.data = r.here();
  out.size = r.remaining();
  return {};
}

Status parse_chunk(const std::string& path, uint64_t pos, const uint8_t* body, uint64_t len, ChunkRef& c) {
  ByteReader r(body, len);
  c.offset = pos;
  c.start_ns = r.u64();
  c.end_ns = r.u64();
  c.uncompressed_size = r.u64();
  c.uncompressed_crc = r.u32();
  c.compression = r.str();
  c.compressed_size = r.u64();
  c.records_offset = pos + kRecordPrefix + r.pos();
  if (!r.ok() || c.compressed_size != r.remaining()) return at(path, pos, "malformed Chunk record");
  if (c.compression != "" && c.compression != "zstd" && c.compression != "lz4")
    return at(path, pos, "unsupported chunk compression '" + c.compression + "'");
  if (c.uncompressed_size > kMaxChunkBytes)
    return at(path, pos, "chunk claims " + std::to_string(c.uncompressed_size) + " uncompressed bytes");
  if (c.start_ns > c.end_ns) return at(path, pos, "chunk start time after its end time");
  return {};
}

// The records of a chunk (or a run of loose messages): decompressed into `scratch` when
// compressed, and CRC-checked.
Result<const uint8_t*> chunk_records(const MappedFile& file, const ChunkRef& c, std::vector<uint8_t>& scratch) {
  const std::string& path = file.path();
  const uint8_t* src = file.data() + c.records_offset;
  const uint8_t* records = src;
  if (c.compression == "zstd") {
    if (c.uncompressed_size > kZstdMaxRatio * c.compressed_size + kZstdSlack)
      return at(path, c.offset, "zstd chunk claims " + std::to_string(c.uncompressed_size) + " uncompressed bytes from " +
                                    std::to_string(c.compressed_size) + " compressed (more than zstd can expand)");
    // The frame states its size (our writer always records it): check before allocating.
    const unsigned long long fcs = ZSTD_getFrameContentSize(src, c.compressed_size);
    if (fcs == ZSTD_CONTENTSIZE_ERROR || (fcs != ZSTD_CONTENTSIZE_UNKNOWN && fcs != c.uncompressed_size))
      return at(path, c.offset, "chunk is not a zstd frame of the stated size");
    if (fcs == ZSTD_CONTENTSIZE_UNKNOWN) {
      if (auto s = zstd_frame_streaming(path, c, src, scratch); !s) return s.error();
    } else {
      scratch.resize(c.uncompressed_size);
      const size_t n = ZSTD_decompress(scratch.data(), scratch.size(), src, c.compressed_size);
      if (ZSTD_isError(n)) return at(path, c.offset, std::string("chunk does not decompress (") + ZSTD_getErrorName(n) + ")");
      if (n != c.uncompressed_size) return at(path, c.offset, "chunk decompresses to the wrong size");
    }
    records = scratch.data();
  } else if (c.compression == "lz4") {
    if (auto s = lz4_frame(path, c, src, scratch); !s) return s.error();
    records = scratch.data();
  } else if (c.compressed_size != c.uncompressed_size) {
    return at(path, c.offset, "uncompressed chunk with inconsistent sizes");
  }
  if (c.uncompressed_crc != 0) {
    const uint32_t actual = crc32(0, records, c.uncompressed_size);
    if (actual != c.uncompressed_crc)
      return at(path, c.offset, "chunk CRC mismatch (stored " + hex(c.uncompressed_crc) + ", computed " + hex(actual) + ")");
  }
  return records;
}

}  // namespace detail

namespace {

using namespace detail;

constexpr uint64_t kMaxLooseRunBytes = uint64_t{8} << 20;   // a run of loose messages: at most this many bytes
constexpr uint64_t kMaxLooseRunNs = 1'000'000'000;          // ... and this span of log time

struct Schema {
  std::string name, encoding;
};

std::optional<Channel> channel_for_topic(const std::string& topic) {
  for (int c = 0; c < kChannelCount; ++c)
    if (topic == channel_topic(static_cast<Channel>(c))) return static_cast<Channel>(c);
  return std::nullopt;
}

// Decodes one Message record body (after opcode and length).
Status decode_message(const std::string& path, const Layout& layout, const uint8_t* p, uint64_t n, Loc loc,
                      std::vector<LocatedEvent>& out) {
  RawMessage m;
  if (auto s = parse_message(path, loc, p, n, m); !s) return s;
  const auto it = layout.channels.find(m.channel_id);
  if (it == layout.channels.end()) return at(path, loc, "message on undefined channel id " + std::to_string(m.channel_id));
  if (m.log_time_ns > static_cast<uint64_t>(INT64_MAX)) return at(path, loc, "log time out of range");
  auto payload = ros1::decode(it->second.channel, m.data, m.size);
  if (!payload) return at(path, loc, "cannot decode " + it->second.topic + " message: " + payload.error().message);
  LocatedEvent le{{}, loc.chunk, loc.offset};
  le.event.stamp = Time::from_ns(static_cast<int64_t>(m.log_time_ns));
  le.event.channel = it->second.channel;
  le.event.sequence = m.sequence;
  le.event.payload = std::move(payload.value());
  out.push_back(std::move(le));
  return {};
}

class Scanner {
 public:
  Scanner(const MappedFile& f) : f_(f), path_(f.path()) {}

  Result<Layout> run() {
    const uint8_t* d = f_.data();
    const size_t size = f_.size();
    L_.recovery.bytes_total = size;
    if (auto s = check_magic(f_); !s) return s.error();
    // A complete file's summary is checked (CRC) and read before the data section: when it
    // lists every channel, chunks are only located now and read when replayed; otherwise
    // the data section is read by a linear scan.
    if (const uint64_t fpos = trailing_footer(f_); fpos != 0) {
      if (auto s = footer_record(fpos, d + fpos + kRecordPrefix, 20); !s) return s.error();
      footer_pos_ = fpos;
      if (summary_start_ != 0) {
        L_.read.summary_present = true;
        if (auto s = read_summary(summary_start_, fpos); !s) return s.error();
      }
    }
    linear_ = !summary_used_;
    uint64_t pos = kMagicSize;
    bool footer = false, data_end = false;
    uint64_t good_end = pos;
    while (!footer) {
      auto head = record_head(f_, pos, footer_pos_);
      if (!head) return head.error();
      if (!head->cut.empty()) {
        truncated(pos, head->cut);
        break;
      }
      const uint8_t op = head->op;
      const uint64_t len = head->len;
      const uint8_t* body = head->body;
      if (op == static_cast<uint8_t>(Op::kDataEnd)) {
        if (auto s = progress_.check_data_end(pos, body, len); !s) return s.error();
        data_end = true;
      } else if (op == static_cast<uint8_t>(Op::kFooter)) {
        if (auto s = footer_record(pos, body, len); !s) return s.error();
        footer = true;
      } else if (auto s = record(op, pos, body, len, data_end); !s) {
        return s.error();
      }
      pos += kRecordPrefix + len;
      good_end = pos;
      progress_.advance(pos, !data_end);
    }
    if (!footer && !linear_) {
      // Defensive (a file ending with its footer reaches it or fails above): what was read
      // is counted like a truncated recording's, every chunk kept CRC-checked.
      linear_ = true;
      chunk_messages_ = 0;
      for (const auto& c : L_.chunks)
        if (auto s = harvest(c); !s) return s.error();
    }
    f_.release(0, size);  // the summary read above, and the tail of the data section
    L_.recovery.bytes_recovered = footer ? size : good_end;
    L_.read.read_by_linear_scan = linear_;
    L_.read.truncated_bytes = size - L_.recovery.bytes_recovered;
    L_.read.chunk_count = L_.chunks.size();
    L_.read.loose_message_count = L_.loose_message_count;
    for (const auto& c : L_.chunks)
      if (std::find(L_.read.compressions.begin(), L_.read.compressions.end(), c.compression) ==
          L_.read.compressions.end())
        L_.read.compressions.push_back(c.compression);
    L_.message_count = linear_ ? chunk_messages_ + L_.loose_message_count : L_.statistics->message_count;
    L_.recovery.messages_recovered = L_.message_count;
    bool any = false;  // the sensor time the recovered messages span (chunk and run headers)
    for (const auto* refs : {&L_.chunks, &L_.loose_runs})
      for (const auto& c : *refs) {
        if (c.end_ns < c.start_ns) continue;
        L_.recovery.first_ns = any ? std::min(L_.recovery.first_ns, c.start_ns) : c.start_ns;
        L_.recovery.last_ns = any ? std::max(L_.recovery.last_ns, c.end_ns) : c.end_ns;
        any = true;
      }
    return std::move(L_);
  }

 private:
  void truncated(uint64_t pos, const std::string& why) {
    L_.recovery.complete = false;
    L_.recovery.detail = cut_detail(f_, pos, why);
  }

  Status footer_record(uint64_t pos, const uint8_t* body, uint64_t len) {
    ByteReader r(body, len);
    const uint64_t summary_start = r.u64();
    r.u64();
    const uint32_t stored = r.u32();
    if (!r.ok()) return at(path_, pos, "truncated Footer record");
    const uint64_t end = pos + kRecordPrefix + len;
    auto cut = check_trailing_magic(f_, end);
    if (!cut) return cut.error();
    if (!cut->empty()) {
      truncated(end, *cut);
      return {};
    }
    if (summary_start != 0 && (summary_start > pos || summary_start < kMagicSize))
      return at(path_, pos, "footer summary_start " + std::to_string(summary_start) + " outside the file's records");
    if (stored != 0 && summary_start != 0) {
      const uint32_t actual = crc32(0, f_.data() + summary_start, pos + kRecordPrefix + 16 - summary_start);
      if (actual != stored)
        return at(path_, pos, "summary CRC mismatch (stored " + hex(stored) + ", computed " + hex(actual) + ")");
    }
    summary_start_ = summary_start;
    return {};
  }

  // Reads the Schema, Channel and Statistics records of the summary section [start, end)
  // and decides whether it can stand in for a linear scan: its Statistics record must
  // count messages per channel and every channel counted must have its Channel record.
  Status read_summary(uint64_t start, uint64_t end) {
    const uint8_t* d = f_.data();
    for (uint64_t pos = start; pos < end;) {
      if (end - pos < kRecordPrefix) return at(path_, pos, "summary record header runs into the footer");
      const uint8_t op = d[pos];
      ByteReader lr(d + pos + 1, 8);
      const uint64_t len = lr.u64();
      if (len > end - pos - kRecordPrefix)
        return at(path_, pos, "summary record (opcode " + hex(op) + ", " + std::to_string(len) + " bytes) runs into the footer");
      if (op == static_cast<uint8_t>(Op::kSchema) || op == static_cast<uint8_t>(Op::kChannel) ||
          op == static_cast<uint8_t>(Op::kStatistics))
        if (auto s = record(op, pos, d + pos + kRecordPrefix, len, true); !s) return s;
      pos += kRecordPrefix + len;
    }
    std::string note;
    if (!L_.statistics) {
      note = "the summary has no Statistics record";
    } else if (L_.statistics->channel_counts.empty() && L_.statistics->message_count != 0) {
      note = "the summary's Statistics record does not count messages per channel";
    } else {
      for (const auto& [id, n] : L_.statistics->channel_counts)
        if (L_.channels.find(id) == L_.channels.end()) {
          note = "channel id " + std::to_string(id) + " has no Channel record in the summary";
          break;
        }
    }
    summary_used_ = note.empty();
    L_.read.summary_note = note;
    return {};
  }

  Status record(uint8_t op, uint64_t pos, const uint8_t* body, uint64_t len, bool in_summary) {
    ByteReader r(body, len);
    switch (static_cast<Op>(op)) {
      case Op::kHeader:
        if (pos != kMagicSize) return at(path_, pos, "second Header record");
        L_.profile = r.str();
        L_.library = r.str();
        break;
      case Op::kSchema: return schema(Loc{0, pos}, body, len);
      case Op::kChannel: return channel(Loc{0, pos}, body, len);
      case Op::kMessage:
        if (in_summary) return at(path_, pos, "Message record in the summary section");
        return loose_message(pos, body, len);
      case Op::kChunk: {
        if (in_summary) return at(path_, pos, "Chunk record in the summary section");
        ChunkRef c;
        if (auto s = parse_chunk(path_, pos, body, len, c); !s) return s;
        // A linear scan reads the chunk now, in file order: the Schema and Channel records
        // inside it define channels for the records after it.
        if (linear_)
          if (auto s = harvest(c); !s) return s;
        L_.chunks.push_back(std::move(c));
        break;
      }
      case Op::kMetadata: {
        const std::string name = r.str();
        std::map<std::string, std::string> m;
        if (!read_map(r, m) || !r.ok()) return at(path_, pos, "malformed Metadata record");
        if (name == kMetadataName)
          for (auto& [k, v] : m) L_.metadata[k] = v;
        break;
      }
      case Op::kAttachment: {
        if (in_summary) return at(path_, pos, "Attachment record in the summary section");
        Attachment a;
        a.log_time_ns = r.u64();
        a.create_time_ns = r.u64();
        a.name = r.str();
        a.media_type = r.str();
        const uint64_t size = r.u64();
        if (!r.ok()) return at(path_, pos, "malformed Attachment record");
        if (size > kMaxAttachmentBytes || size > r.remaining())
          return at(path_, pos, "attachment '" + a.name + "' claims " + std::to_string(size) + " data bytes (record has " +
                                    std::to_string(r.remaining()) + ", limit " + std::to_string(kMaxAttachmentBytes) + ")");
        const uint8_t* data = r.take(size);
        const size_t crc_end = r.pos();
        const uint32_t stored = r.u32();
        if (!r.ok()) return at(path_, pos, "attachment '" + a.name + "' has no CRC field");
        if (const uint32_t actual = crc32(0, body, crc_end); stored != 0 && stored != actual)
          return at(path_, pos, "attachment '" + a.name + "' CRC mismatch (stored " + hex(stored) + ", computed " +
                                    hex(actual) + ")");
        a.data.assign(data, data + size);
        L_.attachments.push_back(std::move(a));
        break;
      }
      case Op::kStatistics: {
        Statistics s;
        s.message_count = r.u64();
        r.u16();
        r.u32();
        r.u32();
        r.u32();
        s.chunk_count = r.u32();
        s.start_ns = r.u64();
        s.end_ns = r.u64();
        const uint32_t ml = r.u32();
        const uint8_t* mp = r.take(ml);
        if (!r.ok() || ml % 10 != 0) return at(path_, pos, "malformed Statistics record");
        ByteReader m(mp, ml);
        while (m.remaining() > 0) {
          const uint16_t id = m.u16();
          s.channel_counts[id] = m.u64();
        }
        L_.statistics = s;
        break;
      }
      case Op::kMessageIndex: L_.read.message_indexes = true; break;
      case Op::kChunkIndex: L_.read.chunk_indexes = true; break;
      default: break;  // other indexes: the scan does not need them
    }
    if (!r.ok()) return at(path_, pos, "malformed record (opcode " + hex(op) + ")");
    return {};
  }

  Status schema(Loc loc, const uint8_t* body, uint64_t len) {
    RawSchema s;
    if (auto st = parse_schema(path_, loc, body, len, s); !st) return st;
    schemas_[s.id] = Schema{std::move(s.name), std::move(s.encoding)};
    return {};
  }

  Status channel(Loc loc, const uint8_t* body, uint64_t len) {
    RawChannel raw;
    if (auto st = parse_channel(path_, loc, body, len, raw); !st) return st;
    ChannelRef c;
    c.id = raw.id;
    c.topic = std::move(raw.topic);
    const std::string& encoding = raw.message_encoding;
    const auto s = schemas_.find(raw.schema_id);
    if (s == schemas_.end())
      return at(path_, loc, "channel " + c.topic + " uses undefined schema id " + std::to_string(raw.schema_id));
    c.schema_name = s->second.name;
    const auto ch = channel_for_topic(c.topic);
    if (!ch) return at(path_, loc, "unknown topic '" + c.topic + "'");
    c.channel = *ch;
    if (s->second.name != ros1::schema_for(*ch).name || s->second.encoding != kSchemaEncoding ||
        encoding != kMessageEncoding)
      return at(path_, loc, "unknown schema '" + s->second.name + "' (" + s->second.encoding + "/" +
                                encoding + ") for topic " + c.topic);
    const auto old = L_.channels.find(c.id);
    if (old != L_.channels.end() && (old->second.topic != c.topic || old->second.schema_name != c.schema_name))
      return at(path_, loc, "channel id " + std::to_string(c.id) + " redefined");
    L_.channels[c.id] = std::move(c);
    return {};
  }

  // Linear scan: decompresses and CRC-checks a chunk, takes the Schema and Channel records
  // inside it, and checks and counts its messages (decoding their payloads waits for
  // read_chunk). The decompressed bytes live in scratch_ until the next chunk.
  Status harvest(const ChunkRef& c) {
    auto records = chunk_records(f_, c, scratch_);
    if (!records) return records.error();
    return for_each_record(path_, c, *records, [&](const InnerRecord& rec, uint64_t pos) -> Status {
      const Loc loc{c.offset, pos};
      switch (static_cast<Op>(rec.op)) {
        case Op::kSchema: return schema(loc, rec.body, rec.len);
        case Op::kChannel: return channel(loc, rec.body, rec.len);
        case Op::kMessage: {
          RawMessage m;
          if (auto s = parse_message(path_, loc, rec.body, rec.len, m); !s) return s;
          if (L_.channels.find(m.channel_id) == L_.channels.end())
            return at(path_, loc, "message on undefined channel id " + std::to_string(m.channel_id));
          if (m.log_time_ns < c.start_ns || m.log_time_ns > c.end_ns)
            return at(path_, loc, "message log time outside its chunk's time range");
          ++chunk_messages_;
          return {};
        }
        default: return at(path_, loc, "unexpected opcode " + hex(rec.op));
      }
    });
  }

  // A Message record outside chunks: checks its header and channel now (decoding waits
  // for read_chunk) and adds it to the current run of loose messages, or starts a run.
  Status loose_message(uint64_t pos, const uint8_t* body, uint64_t len) {
    RawMessage m;
    if (auto s = parse_message(path_, Loc{0, pos}, body, len, m); !s) return s;
    if (L_.channels.find(m.channel_id) == L_.channels.end())
      return at(path_, pos, "message on undefined channel id " + std::to_string(m.channel_id));
    const uint64_t log_time = m.log_time_ns;
    if (log_time > static_cast<uint64_t>(INT64_MAX)) return at(path_, pos, "log time out of range");
    const uint64_t end = pos + kRecordPrefix + len;
    ChunkRef* run = L_.loose_runs.empty() ? nullptr : &L_.loose_runs.back();
    if (run != nullptr) {
      const uint64_t lo = std::min(run->start_ns, log_time), hi = std::max(run->end_ns, log_time);
      if (run->records_offset + run->compressed_size != pos || end - run->records_offset > kMaxLooseRunBytes ||
          hi - lo > kMaxLooseRunNs)
        run = nullptr;
    }
    if (run == nullptr) {
      ChunkRef c;
      c.offset = c.records_offset = pos;
      c.start_ns = c.end_ns = log_time;
      c.loose = true;
      run = &L_.loose_runs.emplace_back(std::move(c));
    }
    run->start_ns = std::min(run->start_ns, log_time);
    run->end_ns = std::max(run->end_ns, log_time);
    run->compressed_size = run->uncompressed_size = end - run->records_offset;
    ++run->message_count;
    ++L_.loose_message_count;
    return {};
  }

  const MappedFile& f_;
  const std::string& path_;
  Layout L_;
  std::map<uint16_t, Schema> schemas_;
  uint64_t footer_pos_ = 0;      // of the footer, when the file ends with one (0: not found)
  uint64_t summary_start_ = 0;   // from the footer (0: no summary)
  bool summary_used_ = false;    // read_summary found it complete
  bool linear_ = false;          // chunks are read (harvest) as the scan meets them
  uint64_t chunk_messages_ = 0;  // messages inside chunks, counted by harvest
  std::vector<uint8_t> scratch_;
  Progress progress_{f_};
};

}  // namespace

std::string describe_location(const LocatedEvent& e) {
  if (e.chunk_offset == 0) return "byte offset " + std::to_string(e.offset);
  return "offset " + std::to_string(e.offset) + " inside the chunk at byte offset " + std::to_string(e.chunk_offset);
}

Result<std::unique_ptr<MappedFile>> MappedFile::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    return Error{path + ": cannot stat"};
  }
  std::unique_ptr<MappedFile> f(new MappedFile());
  f->path_ = path;
  f->size_ = static_cast<size_t>(st.st_size);
  if (f->size_ > 0) {
    void* p = ::mmap(nullptr, f->size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      return Error{path + ": cannot map: " + std::strerror(errno)};
    }
    ::madvise(p, f->size_, MADV_SEQUENTIAL);
    f->data_ = static_cast<const uint8_t*>(p);
  }
  ::close(fd);
  return f;
}

void MappedFile::release(uint64_t offset, uint64_t n) const {
  if (data_ == nullptr || offset >= size_ || n == 0) return;
  static const uint64_t page = static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  const uint64_t begin = offset / page * page;
  const uint64_t end = std::min<uint64_t>(size_, offset + std::min<uint64_t>(n, size_ - offset));
  // A read-only file mapping: dropped pages read back the same bytes from the file.
  ::madvise(const_cast<uint8_t*>(data_) + begin, end - begin, MADV_DONTNEED);
}

MappedFile::~MappedFile() {
  if (data_ != nullptr) ::munmap(const_cast<uint8_t*>(data_), size_);
}

Result<Layout> scan(const MappedFile& file) { return Scanner(file).run(); }

Status read_chunk(const MappedFile& file, const Layout& layout, const ChunkRef& c,
                  std::vector<LocatedEvent>& out, std::vector<uint8_t>& scratch) {
  const std::string& path = file.path();
  // The chunk's file bytes are not needed once it is decoded (decoded events are copies).
  struct Release {
    const MappedFile& f;
    const ChunkRef& c;
    ~Release() { f.release(c.offset, c.records_offset + c.compressed_size - c.offset); }
  } release{file, c};
  auto records = chunk_records(file, c, scratch);
  if (!records) return records.error();
  const size_t first = out.size();
  const Status s = for_each_record(path, c, *records, [&](const InnerRecord& rec, uint64_t pos) -> Status {
    // Loose messages are located by file offset, as outside chunks they are.
    const Loc loc = c.loose ? Loc{0, c.records_offset + pos} : Loc{c.offset, pos};
    if (rec.op == static_cast<uint8_t>(Op::kMessage)) return decode_message(path, layout, rec.body, rec.len, loc, out);
    if (rec.op == static_cast<uint8_t>(Op::kChannel)) {
      // Other writers repeat Channel records inside chunks; the scan took them from the
      // summary (or from this chunk, on a linear scan): they must agree.
      ByteReader r(rec.body, rec.len);
      const uint16_t id = r.u16();
      r.u16();
      const std::string topic = r.str();
      if (!r.ok()) return at(path, loc, "malformed Channel record");
      const auto it = layout.channels.find(id);
      if (it != layout.channels.end() && it->second.topic != topic)
        return at(path, loc, "channel id " + std::to_string(id) + " redefined (topic " + topic + ", was " +
                                 it->second.topic + ")");
      return {};
    }
    if (rec.op == static_cast<uint8_t>(Op::kSchema)) return {};
    return at(path, loc, "unexpected opcode " + hex(rec.op));
  });
  if (!s) return s;
  for (size_t i = first; i < out.size(); ++i) {
    const auto t = static_cast<uint64_t>(out[i].event.stamp.ns());
    if (t < c.start_ns || t > c.end_ns)
      return Error{path + ": message log time outside its chunk's time range at " + describe_location(out[i])};
  }
  return {};
}

}  // namespace orthosonar::replay::mcap
