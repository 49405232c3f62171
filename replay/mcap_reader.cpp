#include "replay/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include <zstd.h>

#include "replay/mcap_format.hpp"
#include "replay/ros1_codec.hpp"

namespace orthosonar::replay::mcap {
namespace {

constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;
constexpr uint64_t kReleaseBytes = uint64_t{8} << 20;       // the scan releases what it read in steps of this
constexpr uint64_t kMaxLooseRunBytes = uint64_t{8} << 20;   // a run of loose messages: at most this many bytes
constexpr uint64_t kMaxLooseRunNs = 1'000'000'000;          // ... and this span of log time

std::string hex(uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

Error at(const std::string& path, uint64_t offset, const std::string& what) {
  return Error{path + ": " + what + " at byte offset " + std::to_string(offset)};
}

std::optional<Channel> channel_for_topic(const std::string& topic) {
  for (int c = 0; c < kChannelCount; ++c)
    if (topic == channel_topic(static_cast<Channel>(c))) return static_cast<Channel>(c);
  return std::nullopt;
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

struct Schema {
  std::string name, encoding;
};

// Decodes one Message record body (after opcode and length).
Status decode_message(const std::string& path, const Layout& layout, const uint8_t* p, uint64_t n,
                      uint64_t chunk_offset, uint64_t offset, std::vector<LocatedEvent>& out) {
  ByteReader r(p, n);
  const uint16_t id = r.u16();
  const uint32_t seq = r.u32();
  const uint64_t log_time = r.u64();
  r.u64();  // publish time
  LocatedEvent le{{}, chunk_offset, offset};
  auto where = [&](const std::string& what) {
    if (chunk_offset == 0) return at(path, offset, what);
    return Error{path + ": " + what + " at offset " + std::to_string(offset) +
                 " inside the chunk at byte offset " + std::to_string(chunk_offset)};
  };
  if (!r.ok()) return where("truncated message record");
  const auto it = layout.channels.find(id);
  if (it == layout.channels.end()) return where("message on undefined channel id " + std::to_string(id));
  if (log_time > static_cast<uint64_t>(INT64_MAX)) return where("log time out of range");
  auto payload = ros1::decode(it->second.channel, r.here(), r.remaining());
  if (!payload) return where("cannot decode " + it->second.topic + " message: " + payload.error().message);
  le.event.stamp = Time::from_ns(static_cast<int64_t>(log_time));
  le.event.channel = it->second.channel;
  le.event.sequence = seq;
  le.event.payload = std::move(payload.value());
  out.push_back(std::move(le));
  return {};
}

class Scanner {
 public:
  Scanner(const MappedFile& f) : f_(f), path_(f.path()) {}

  Result<Layout> run(bool count_messages) {
    const uint8_t* d = f_.data();
    const size_t size = f_.size();
    L_.recovery.bytes_total = size;
    if (size < kMagicSize || std::memcmp(d, kMagic, 5) != 0 || std::memcmp(d + 6, kMagic + 6, 2) != 0)
      return at(path_, 0, "not an MCAP file: bad magic");
    if (d[5] != kMagic[5])
      return at(path_, 5, std::string("unsupported MCAP version '") + static_cast<char>(d[5]) + "'");
    // A complete file's summary is checked before any of it is used.
    if (size >= 2 * kMagicSize + 2 * kRecordPrefix + 20 &&
        std::memcmp(d + size - kMagicSize, kMagic, kMagicSize) == 0) {
      const uint64_t fpos = size - kMagicSize - kRecordPrefix - 20;
      ByteReader fr(d + fpos, kRecordPrefix + 20);
      if (fr.u8() == static_cast<uint8_t>(Op::kFooter) && fr.u64() == 20)
        if (auto s = footer_record(fpos, d + fpos + kRecordPrefix, 20); !s) return s.error();
    }
    uint64_t pos = kMagicSize;
    bool footer = false, data_end = false;
    uint64_t good_end = pos;
    while (!footer) {
      if (size - pos < kRecordPrefix) {
        truncated(pos, size - pos == 0 ? "file ends without a footer"
                                       : "file ends inside a record header");
        break;
      }
      const uint8_t op = d[pos];
      ByteReader lr(d + pos + 1, 8);
      const uint64_t len = lr.u64();
      if (op == 0 || (op > kMaxOpcode && op < 0x80))
        return at(path_, pos, "unsupported record opcode " + hex(op));
      if (len > size - pos - kRecordPrefix) {
        truncated(pos, "record (opcode " + hex(op) + ", " + std::to_string(len) +
                           " bytes) runs past the end of the file");
        break;
      }
      if (pos == kMagicSize && op != static_cast<uint8_t>(Op::kHeader))
        return at(path_, pos, "first record is not a Header");
      const uint8_t* body = d + pos + kRecordPrefix;
      if (op == static_cast<uint8_t>(Op::kDataEnd)) {
        ByteReader r(body, len);
        const uint32_t stored = r.u32();
        if (!r.ok()) return at(path_, pos, "truncated Data End record");
        const uint32_t actual = data_crc_;  // of [0, pos): advance() kept it up to date
        if (stored != 0 && stored != actual)
          return at(path_, pos, "data section CRC mismatch (stored " + hex(stored) + ", computed " +
                                    hex(actual) + ")");
        data_end = true;
      } else if (op == static_cast<uint8_t>(Op::kFooter)) {
        if (auto s = footer_record(pos, body, len); !s) return s.error();
        footer = true;
      } else if (auto s = record(op, pos, body, len, data_end); !s) {
        return s.error();
      }
      pos += kRecordPrefix + len;
      good_end = pos;
      advance(pos, !data_end);
    }
    f_.release(0, size);  // the summary read above, and the tail of the data section
    L_.recovery.bytes_recovered = footer ? size : good_end;
    if (!footer && count_messages) {
      // A truncated recording: decode what is left so the count is honest and every
      // recovered chunk is CRC-checked.
      std::vector<LocatedEvent> events;
      std::vector<uint8_t> scratch;
      for (const auto& c : L_.chunks) {
        events.clear();
        if (auto s = read_chunk(f_, L_, c, events, scratch); !s) return s.error();
        L_.recovery.messages_recovered += events.size();
      }
      L_.recovery.messages_recovered += L_.loose_message_count;
    }
    return std::move(L_);
  }

 private:
  // Bytes up to `end` are scanned: adds them to the data section CRC (while in the data
  // section) and releases them from memory every few MiB, so a long recording is read
  // once, front to back, and never resident as a whole.
  void advance(uint64_t end, bool in_data_section) {
    if (in_data_section) {
      data_crc_ = crc32(data_crc_, f_.data() + crc_end_, end - crc_end_);
      crc_end_ = end;
    }
    if (end - released_ >= kReleaseBytes) {
      f_.release(released_, end - released_);
      released_ = end;
    }
  }

  void truncated(uint64_t pos, const std::string& why) {
    L_.recovery.complete = false;
    L_.recovery.detail = path_ + ": " + why + " at byte offset " + std::to_string(pos) +
                         " (file size " + std::to_string(f_.size()) + "); recovered the records before it";
  }

  Status footer_record(uint64_t pos, const uint8_t* body, uint64_t len) {
    ByteReader r(body, len);
    const uint64_t summary_start = r.u64();
    r.u64();
    const uint32_t stored = r.u32();
    if (!r.ok()) return at(path_, pos, "truncated Footer record");
    const uint64_t end = pos + kRecordPrefix + len;
    if (f_.size() - end < kMagicSize) {
      truncated(end, "file ends inside the trailing magic");
      return {};
    }
    if (std::memcmp(f_.data() + end, kMagic, kMagicSize) != 0 || f_.size() - end != kMagicSize)
      return at(path_, end, "bad trailing magic");
    if (stored != 0 && summary_start != 0) {
      if (summary_start > pos) return at(path_, pos, "footer summary_start past the footer");
      const uint32_t actual = crc32(0, f_.data() + summary_start, pos + kRecordPrefix + 16 - summary_start);
      if (actual != stored)
        return at(path_, pos, "summary CRC mismatch (stored " + hex(stored) + ", computed " + hex(actual) + ")");
    }
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
      case Op::kSchema: {
        const uint16_t id = r.u16();
        Schema s{r.str(), r.str()};
        const uint32_t dl = r.u32();
        r.take(dl);
        if (!r.ok()) return at(path_, pos, "truncated Schema record");
        if (id == 0) return at(path_, pos, "schema id 0 is reserved");
        schemas_[id] = s;
        break;
      }
      case Op::kChannel: return channel(pos, r);
      case Op::kMessage:
        if (in_summary) return at(path_, pos, "Message record in the summary section");
        return loose_message(pos, body, len);
      case Op::kChunk: {
        if (in_summary) return at(path_, pos, "Chunk record in the summary section");
        ChunkRef c;
        c.offset = pos;
        c.start_ns = r.u64();
        c.end_ns = r.u64();
        c.uncompressed_size = r.u64();
        c.uncompressed_crc = r.u32();
        c.compression = r.str();
        c.compressed_size = r.u64();
        c.records_offset = pos + kRecordPrefix + r.pos();
        if (!r.ok() || c.compressed_size != r.remaining()) return at(path_, pos, "malformed Chunk record");
        if (c.compression != "" && c.compression != "zstd")
          return at(path_, pos, "unsupported chunk compression '" + c.compression + "'");
        if (c.uncompressed_size > kMaxChunkBytes)
          return at(path_, pos, "chunk claims " + std::to_string(c.uncompressed_size) + " uncompressed bytes");
        if (c.start_ns > c.end_ns) return at(path_, pos, "chunk start time after its end time");
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
      default: break;  // indexes: the linear scan does not need them
    }
    if (!r.ok()) return at(path_, pos, "malformed record (opcode " + hex(op) + ")");
    return {};
  }

  Status channel(uint64_t pos, ByteReader& r) {
    ChannelRef c;
    c.id = r.u16();
    const uint16_t schema_id = r.u16();
    c.topic = r.str();
    const std::string encoding = r.str();
    std::map<std::string, std::string> meta;
    if (!read_map(r, meta) || !r.ok()) return at(path_, pos, "malformed Channel record");
    const auto s = schemas_.find(schema_id);
    if (s == schemas_.end())
      return at(path_, pos, "channel " + c.topic + " uses undefined schema id " + std::to_string(schema_id));
    c.schema_name = s->second.name;
    const auto ch = channel_for_topic(c.topic);
    if (!ch) return at(path_, pos, "unknown topic '" + c.topic + "'");
    c.channel = *ch;
    if (s->second.name != ros1::schema_for(*ch).name || s->second.encoding != kSchemaEncoding ||
        encoding != kMessageEncoding)
      return at(path_, pos, "unknown schema '" + s->second.name + "' (" + s->second.encoding + "/" +
                                encoding + ") for topic " + c.topic);
    const auto old = L_.channels.find(c.id);
    if (old != L_.channels.end() && (old->second.topic != c.topic || old->second.schema_name != c.schema_name))
      return at(path_, pos, "channel id " + std::to_string(c.id) + " redefined");
    L_.channels[c.id] = std::move(c);
    return {};
  }

  // A Message record outside chunks: checks its header and channel now (decoding waits
  // for read_chunk) and adds it to the current run of loose messages, or starts a run.
  Status loose_message(uint64_t pos, const uint8_t* body, uint64_t len) {
    ByteReader r(body, len);
    const uint16_t id = r.u16();
    r.u32();
    const uint64_t log_time = r.u64();
    r.u64();
    if (!r.ok()) return at(path_, pos, "truncated message record");
    if (L_.channels.find(id) == L_.channels.end())
      return at(path_, pos, "message on undefined channel id " + std::to_string(id));
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
  uint32_t data_crc_ = 0;
  uint64_t crc_end_ = 0;   // data_crc_ covers [0, crc_end_)
  uint64_t released_ = 0;  // [0, released_) released
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

Result<Layout> scan(const MappedFile& file, bool count_messages) {
  return Scanner(file).run(count_messages);
}

Status read_chunk(const MappedFile& file, const Layout& layout, const ChunkRef& c,
                  std::vector<LocatedEvent>& out, std::vector<uint8_t>& scratch) {
  const std::string& path = file.path();
  // The chunk's file bytes are not needed once it is decoded (decoded events are copies).
  struct Release {
    const MappedFile& f;
    const ChunkRef& c;
    ~Release() { f.release(c.offset, c.records_offset + c.compressed_size - c.offset); }
  } release{file, c};
  const uint8_t* src = file.data() + c.records_offset;
  const uint8_t* records = src;
  if (c.compression == "zstd") {
    // The frame states its size (our writer always records it): check before allocating.
    const unsigned long long fcs = ZSTD_getFrameContentSize(src, c.compressed_size);
    if (fcs == ZSTD_CONTENTSIZE_ERROR || (fcs != ZSTD_CONTENTSIZE_UNKNOWN && fcs != c.uncompressed_size))
      return at(path, c.offset, "chunk is not a zstd frame of the stated size");
    scratch.resize(c.uncompressed_size);
    const size_t n = ZSTD_decompress(scratch.data(), scratch.size(), src, c.compressed_size);
    if (ZSTD_isError(n)) return at(path, c.offset, std::string("chunk does not decompress (") + ZSTD_getErrorName(n) + ")");
    if (n != c.uncompressed_size) return at(path, c.offset, "chunk decompresses to the wrong size");
    records = scratch.data();
  } else if (c.compressed_size != c.uncompressed_size) {
    return at(path, c.offset, "uncompressed chunk with inconsistent sizes");
  }
  const uint64_t size = c.uncompressed_size;
  if (c.uncompressed_crc != 0) {
    const uint32_t actual = crc32(0, records, size);
    if (actual != c.uncompressed_crc)
      return at(path, c.offset, "chunk CRC mismatch (stored " + hex(c.uncompressed_crc) + ", computed " + hex(actual) + ")");
  }
  uint64_t pos = 0;
  const size_t first = out.size();
  while (pos < size) {
    ByteReader r(records + pos, size - pos);
    const uint8_t op = r.u8();
    const uint64_t len = r.u64();
    if (!r.ok() || len > r.remaining())
      return Error{path + ": record runs past the end of the chunk at offset " + std::to_string(pos) +
                   " inside the chunk at byte offset " + std::to_string(c.offset)};
    if (op == static_cast<uint8_t>(Op::kMessage)) {
      // Loose messages are located by file offset, as outside chunks they are.
      const Status s = c.loose ? decode_message(path, layout, r.here(), len, 0, c.records_offset + pos, out)
                               : decode_message(path, layout, r.here(), len, c.offset, pos, out);
      if (!s) return s;
    } else if (op != static_cast<uint8_t>(Op::kSchema) && op != static_cast<uint8_t>(Op::kChannel)) {
      return Error{path + ": unexpected opcode " + hex(op) + " at offset " + std::to_string(pos) +
                   " inside the chunk at byte offset " + std::to_string(c.offset)};
    }
    pos += kRecordPrefix + len;
  }
  for (size_t i = first; i < out.size(); ++i) {
    const auto t = static_cast<uint64_t>(out[i].event.stamp.ns());
    if (t < c.start_ns || t > c.end_ns)
      return Error{path + ": message log time outside its chunk's time range at " + describe_location(out[i])};
  }
  return {};
}

}  // namespace orthosonar::replay::mcap
