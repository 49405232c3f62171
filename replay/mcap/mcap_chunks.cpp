// The MCAP record layer both readers share (replay/mcap/mcap_chunks.hpp): error locations,
// top-level record prefixes, Schema / Channel / Message / Chunk records, and a chunk's
// records decompressed (zstd, lz4) with sizes checked before allocating and CRC-checked.
#include "replay/mcap/mcap_chunks.hpp"
#include "replay/mcap/zstd_frame.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <sstream>
#include <thread>

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

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
  if (in_data_section) crc_end_ = end;
  if (end - released_ >= kReleaseBytes) {
    f_.release(released_, end - released_);
    released_ = end;
  }
}

uint32_t Progress::data_crc() const {
  // CRC-32 of [0, crc_end_), computed when the Data End record asks (the scan itself only
  // reads record heads), in two halves on two threads, joined with zlib's crc32_combine
  // (the pass over a 789 MB fixture was the largest serial step of a replay's start).
  const uint64_t n = crc_end_;
  constexpr uint64_t kSplitAbove = uint64_t{64} << 20;
  if (n < kSplitAbove) return f_.crc32(0, 0, n);
  const uint64_t half = n / 2;
  uint32_t second = 0;
  std::thread t;
  try {
    t = std::thread([&] { second = f_.crc32(0, half, n - half); });
  } catch (const std::exception&) {
    return f_.crc32(0, 0, n);  // no thread to be had
  }
  const uint32_t first = f_.crc32(0, 0, half);
  t.join();
  return static_cast<uint32_t>(::crc32_combine(first, second, static_cast<z_off_t>(n - half)));
}

Status Progress::check_data_end(uint64_t pos, const uint8_t* body, uint64_t len) const {
  ByteReader r(body, len);
  const uint32_t stored = r.u32();
  if (!r.ok()) return at(f_.path(), pos, "truncated Data End record");
  if (stored == 0) return {};  // not set: nothing to check
  // The caller advanced to the record before this one: crc_end_ is pos.
  if (const uint32_t actual = data_crc(); stored != actual)
    return at(f_.path(), pos, "data section CRC mismatch (stored " + hex(stored) + ", computed " + hex(actual) + ")");
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
  // Compressed bytes are read once, by the decompressor: read them with pread rather than
  // fault them in through the map (issue 37: the map's page faults and the releases after
  // them were a fifth of the reading thread's time).
  thread_local std::vector<uint8_t> compressed;
  if (!c.compression.empty()) src = file.bytes(c.records_offset, c.compressed_size, compressed);
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
      const auto n = zstd_decompress(src, c.compressed_size, scratch.data(), scratch.size());
      if (!n.ok()) return at(path, c.offset, "chunk does not decompress (" + n.error().message + ")");
      if (*n != c.uncompressed_size) return at(path, c.offset, "chunk decompresses to the wrong size");
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

}  // namespace orthosonar::replay::mcap
