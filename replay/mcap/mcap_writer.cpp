// The one MCAP writer of the codebase, for any topics, schemas and encodings: fixtures,
// exports and run results all go through GenericWriter (the reader of other writers' files,
// visit_messages, is mcap_visit.cpp).
#include "replay/mcap/mcap_generic.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <utility>

#include <zstd.h>

#include "core/canonical.hpp"
#include "replay/mcap/mcap_chunks.hpp"
#include "replay/mcap/mcap_format.hpp"
#include "replay/mcap/mapped_file.hpp"

namespace orthosonar::replay::mcap {
namespace {

void put_record(CanonicalWriter& out, Op op, const CanonicalWriter& content) {
  out.put_u8(static_cast<uint8_t>(op));
  out.put_u64(content.size());
  out.put_bytes(content.bytes());
}

void put_map(CanonicalWriter& c, const std::map<std::string, std::string>& m) {
  CanonicalWriter body;
  for (const auto& [k, v] : m) {
    body.put_string(k);
    body.put_string(v);
  }
  c.put_u32(static_cast<uint32_t>(body.size()));
  c.put_bytes(body.bytes());
}

struct SchemaEntry {
  std::string name, encoding, data;
  bool written = false;
};

struct ChannelEntry {
  uint16_t schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
  bool written = false;
};

struct IndexEntry {  // a Metadata or Attachment record, for its summary index record
  uint64_t offset = 0, length = 0, log_time = 0, create_time = 0, data_size = 0;
  std::string name, media_type;
};

struct ChunkIndexEntry {
  uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0;
  std::map<uint16_t, uint64_t> index_offsets;
  uint64_t index_length = 0;
  std::string compression;
  uint64_t compressed_size = 0, uncompressed_size = 0;
};

class Writer final : public GenericWriter {
 public:
  Writer(std::FILE* f, std::string path, GenericWriterOptions o) : f_(f), path_(std::move(path)), opt_(std::move(o)) {}
  ~Writer() override {
    if (f_ != nullptr) (void)close();
    if (cctx_ != nullptr) ZSTD_freeCCtx(cctx_);
  }

  Status start() {
    CanonicalWriter out, c;
    out.put_bytes(kMagic, kMagicSize);
    c.put_string(opt_.profile);
    c.put_string(opt_.library);
    put_record(out, Op::kHeader, c);
    if (auto s = emit(out.bytes()); !s) return s;
    return flush();
  }

  uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data) override {
    if (schemas_.size() >= UINT16_MAX) {
      (void)fail("more than " + std::to_string(UINT16_MAX) + " schemas");
      return 0;
    }
    schemas_.push_back({name, encoding, data});
    return static_cast<uint16_t>(schemas_.size());
  }

  uint16_t add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                       const std::map<std::string, std::string>& metadata) override {
    if (channels_.size() + opt_.first_channel_id > UINT16_MAX) {
      (void)fail("more than " + std::to_string(UINT16_MAX) + " channels");
      return 0;
    }
    channels_.push_back({schema_id, topic, message_encoding, metadata});
    return static_cast<uint16_t>(opt_.first_channel_id + channels_.size() - 1);
  }

  Status write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns, uint64_t publish_time_ns,
               const uint8_t* data, size_t size) override {
    if (f_ == nullptr) return reject("write after close");
    if (!error_.empty()) return Error{error_};
    ChannelEntry* ch = channel(channel_id);
    if (ch == nullptr) return reject("write on unknown channel id " + std::to_string(channel_id));
    if (ch->schema_id > schemas_.size())
      return reject("channel " + ch->topic + " uses undefined schema id " + std::to_string(ch->schema_id));
    // Schema and Channel records go in the data section (outside chunks) on first use, so
    // a truncated file still defines every channel its complete chunks use.
    if (!ch->written)
      if (auto s = write_channel(channel_id, *ch); !s) return s;
    if (chunk_open_ && closes_chunk(log_time_ns))
      if (auto s = flush_chunk(); !s) return s;
    if (!chunk_open_) {
      chunk_open_ = true;
      chunk_first_ns_ = chunk_start_ = chunk_end_ = log_time_ns;
    }
    chunk_start_ = std::min(chunk_start_, log_time_ns);
    chunk_end_ = std::max(chunk_end_, log_time_ns);
    chunk_index_[channel_id].push_back({log_time_ns, chunk_.size()});
    CanonicalWriter& c = chunk_;
    c.put_u8(static_cast<uint8_t>(Op::kMessage));
    c.put_u64(2 + 4 + 8 + 8 + size);
    c.put_u16(channel_id);
    c.put_u32(sequence);
    c.put_u64(log_time_ns);
    c.put_u64(publish_time_ns);
    c.put_bytes(data, size);
    if (message_count_ == 0) first_ns_ = last_ns_ = log_time_ns;
    ++message_count_;
    ++channel_counts_[channel_id];
    first_ns_ = std::min(first_ns_, log_time_ns);
    last_ns_ = std::max(last_ns_, log_time_ns);
    if (chunk_.size() >= opt_.chunk_max_bytes) return flush_chunk();
    return {};
  }

  Status metadata(const std::string& name, const std::map<std::string, std::string>& values) override {
    if (f_ == nullptr) return reject("metadata after close");
    if (!error_.empty()) return Error{error_};
    CanonicalWriter c, out;
    c.put_string(name);
    put_map(c, values);
    put_record(out, Op::kMetadata, c);
    IndexEntry ix{offset_, out.size(), 0, 0, 0, name, {}};
    if (auto s = emit(out.bytes()); !s) return s;
    metadata_.push_back(std::move(ix));
    return flush();
  }

  Status attach(const Attachment& a) override {
    if (f_ == nullptr) return reject("attach after close");
    if (!error_.empty()) return Error{error_};
    if (a.name.empty()) return reject("attachment without a name");
    if (a.data.size() > kMaxAttachmentBytes)
      return reject("attachment '" + a.name + "' has " + std::to_string(a.data.size()) + " bytes (at most " +
                    std::to_string(kMaxAttachmentBytes) + ")");
    CanonicalWriter c;
    c.put_u64(a.log_time_ns);
    c.put_u64(a.create_time_ns);
    c.put_string(a.name);
    c.put_string(a.media_type);
    c.put_u64(a.data.size());
    c.put_bytes(a.data.data(), a.data.size());
    c.put_u32(crc32(0, c.bytes().data(), c.size()));  // CRC of every preceding field
    CanonicalWriter out;
    put_record(out, Op::kAttachment, c);
    IndexEntry ix{offset_, out.size(), a.log_time_ns, a.create_time_ns, a.data.size(), a.name, a.media_type};
    if (auto s = emit(out.bytes()); !s) return s;
    attachments_.push_back(std::move(ix));
    return flush();
  }

  Status close() override {
    if (f_ == nullptr) return error_.empty() ? Status{} : Status{Error{error_}};
    Status s = finish();
    if (std::fclose(f_) != 0 && s) s = fail("close failed");
    f_ = nullptr;
    return s;
  }

 private:
  // A call that cannot be honoured: rejected, nothing written, the file stays valid.
  Status reject(const std::string& what) const { return Error{path_ + ": " + what}; }
  // An I/O or compression failure: sticky, every later call reports it.
  Status fail(const std::string& what) {
    if (error_.empty()) error_ = path_ + ": " + what;
    return Error{path_ + ": " + what};
  }

  ChannelEntry* channel(uint16_t id) {
    const size_t i = size_t{id} - opt_.first_channel_id;
    if (id < opt_.first_channel_id || i >= channels_.size()) return nullptr;
    return &channels_[i];
  }

  // A chunk closes before a message at least chunk_max_log_ns away from its first one
  // (either way: log times need not increase).
  bool closes_chunk(uint64_t log_time_ns) const {
    if (opt_.chunk_max_log_ns <= 0) return true;
    const uint64_t span = log_time_ns >= chunk_first_ns_ ? log_time_ns - chunk_first_ns_ : chunk_first_ns_ - log_time_ns;
    return span >= static_cast<uint64_t>(opt_.chunk_max_log_ns);
  }

  // Appends bytes to the file, keeping the running data section CRC.
  Status emit(const std::vector<uint8_t>& bytes) { return emit(bytes.data(), bytes.size()); }
  Status emit(const uint8_t* p, size_t n) {
    if (!error_.empty()) return Error{error_};
    if (n > 0 && std::fwrite(p, 1, n, f_) != n) return fail("write failed at byte offset " + std::to_string(offset_));
    if (in_data_) data_crc_ = crc32(data_crc_, p, n);
    offset_ += n;
    return {};
  }
  Status flush() {
    if (std::fflush(f_) != 0) return fail("flush failed at byte offset " + std::to_string(offset_));
    return {};
  }

  static void put_schema(CanonicalWriter& out, uint16_t id, const SchemaEntry& s) {
    CanonicalWriter c;
    c.put_u16(id);
    c.put_string(s.name);
    c.put_string(s.encoding);
    c.put_u32(static_cast<uint32_t>(s.data.size()));
    c.put_bytes(reinterpret_cast<const uint8_t*>(s.data.data()), s.data.size());
    put_record(out, Op::kSchema, c);
  }
  static void put_channel(CanonicalWriter& out, uint16_t id, const ChannelEntry& ch) {
    CanonicalWriter c;
    c.put_u16(id);
    c.put_u16(ch.schema_id);
    c.put_string(ch.topic);
    c.put_string(ch.message_encoding);
    put_map(c, ch.metadata);
    put_record(out, Op::kChannel, c);
  }

  Status write_channel(uint16_t id, ChannelEntry& ch) {
    CanonicalWriter out;
    if (ch.schema_id != 0 && !schemas_[ch.schema_id - 1u].written) {
      put_schema(out, ch.schema_id, schemas_[ch.schema_id - 1u]);
      schemas_[ch.schema_id - 1u].written = true;
    }
    put_channel(out, id, ch);
    ch.written = true;
    return emit(out.bytes());
  }

  // Compresses the open chunk into zbuf_ (zstd), or returns it as it is.
  Result<std::pair<const uint8_t*, size_t>> chunk_body() {
    const auto& raw = chunk_.bytes();
    if (opt_.compression.empty()) return std::pair{raw.data(), raw.size()};
    if (cctx_ == nullptr && (cctx_ = ZSTD_createCCtx()) == nullptr) return Error{"cannot create a zstd context"};
    zbuf_.resize(ZSTD_compressBound(raw.size()));
    const size_t z = ZSTD_compressCCtx(cctx_, zbuf_.data(), zbuf_.size(), raw.data(), raw.size(), opt_.zstd_level);
    if (ZSTD_isError(z)) return Error{std::string("zstd: ") + ZSTD_getErrorName(z)};
    return std::pair<const uint8_t*, size_t>{zbuf_.data(), z};
  }

  Status flush_chunk() {
    if (!chunk_open_) return {};
    chunk_open_ = false;
    const auto& raw = chunk_.bytes();
    const uint32_t crc = crc32(0, raw.data(), raw.size());
    auto body = chunk_body();
    if (!body) return fail(body.error().message);
    const auto [data, body_size] = *body;
    ChunkIndexEntry ix;
    ix.start_ns = chunk_start_;
    ix.end_ns = chunk_end_;
    ix.offset = offset_;
    ix.compression = opt_.compression;
    ix.compressed_size = body_size;
    ix.uncompressed_size = raw.size();
    CanonicalWriter head;
    head.put_u8(static_cast<uint8_t>(Op::kChunk));
    const uint64_t content = 8 + 8 + 8 + 4 + 4 + ix.compression.size() + 8 + body_size;
    head.put_u64(content);
    head.put_u64(chunk_start_);
    head.put_u64(chunk_end_);
    head.put_u64(raw.size());
    head.put_u32(crc);
    head.put_string(ix.compression);
    head.put_u64(body_size);
    ix.length = kRecordPrefix + content;
    CanonicalWriter idx;
    const uint64_t idx_start = offset_ + ix.length;
    for (auto& [id, entries] : chunk_index_) {
      if (entries.empty()) continue;
      std::sort(entries.begin(), entries.end());  // by log time, then offset
      ix.index_offsets[id] = idx_start + idx.size();
      CanonicalWriter c;
      c.put_u16(id);
      c.put_u32(static_cast<uint32_t>(entries.size() * 16));
      for (const auto& [t, off] : entries) {
        c.put_u64(t);
        c.put_u64(off);
      }
      put_record(idx, Op::kMessageIndex, c);
    }
    ix.index_length = idx.size();
    if (auto s = emit(head.bytes()); !s) return s;
    if (auto s = emit(data, body_size); !s) return s;
    if (auto s = emit(idx.bytes()); !s) return s;
    chunks_.push_back(std::move(ix));
    chunk_.clear();
    chunk_index_.clear();
    return flush();
  }

  void put_statistics(CanonicalWriter& sum) const {
    CanonicalWriter c;
    c.put_u64(message_count_);
    c.put_u16(static_cast<uint16_t>(std::count_if(schemas_.begin(), schemas_.end(), [](auto& s) { return s.written; })));
    c.put_u32(static_cast<uint32_t>(std::count_if(channels_.begin(), channels_.end(), [](auto& ch) { return ch.written; })));
    c.put_u32(static_cast<uint32_t>(attachments_.size()));
    c.put_u32(static_cast<uint32_t>(metadata_.size()));
    c.put_u32(static_cast<uint32_t>(chunks_.size()));
    c.put_u64(first_ns_);
    c.put_u64(last_ns_);
    c.put_u32(static_cast<uint32_t>(channel_counts_.size() * 10));
    for (const auto& [id, n] : channel_counts_) {
      c.put_u16(id);
      c.put_u64(n);
    }
    put_record(sum, Op::kStatistics, c);
  }

  void put_chunk_indexes(CanonicalWriter& sum) const {
    for (const auto& ix : chunks_) {
      CanonicalWriter c;
      c.put_u64(ix.start_ns);
      c.put_u64(ix.end_ns);
      c.put_u64(ix.offset);
      c.put_u64(ix.length);
      c.put_u32(static_cast<uint32_t>(ix.index_offsets.size() * 10));
      for (const auto& [id, off] : ix.index_offsets) {
        c.put_u16(id);
        c.put_u64(off);
      }
      c.put_u64(ix.index_length);
      c.put_string(ix.compression);
      c.put_u64(ix.compressed_size);
      c.put_u64(ix.uncompressed_size);
      put_record(sum, Op::kChunkIndex, c);
    }
  }

  // Data End, then the summary: one group of records per opcode, each listed by a
  // Summary Offset record, then the Footer (whose CRC covers the summary) and the magic.
  Status finish() {
    if (!error_.empty()) return Error{error_};
    if (auto s = flush_chunk(); !s) return s;
    CanonicalWriter out;
    out.put_u8(static_cast<uint8_t>(Op::kDataEnd));
    out.put_u64(4);
    out.put_u32(data_crc_);
    if (auto s = emit(out.bytes()); !s) return s;
    in_data_ = false;

    const uint64_t summary_start = offset_;
    CanonicalWriter sum;
    struct Group { Op op; uint64_t start, length; };
    std::vector<Group> groups;
    auto group = [&](Op op, const std::function<void()>& fill) {
      const uint64_t at = sum.size();
      fill();
      if (sum.size() > at) groups.push_back({op, summary_start + at, sum.size() - at});
    };
    group(Op::kSchema, [&] {
      for (size_t i = 0; i < schemas_.size(); ++i)
        if (schemas_[i].written) put_schema(sum, static_cast<uint16_t>(i + 1), schemas_[i]);
    });
    group(Op::kChannel, [&] {
      for (size_t i = 0; i < channels_.size(); ++i)
        if (channels_[i].written) put_channel(sum, static_cast<uint16_t>(opt_.first_channel_id + i), channels_[i]);
    });
    group(Op::kStatistics, [&] { put_statistics(sum); });
    group(Op::kMetadataIndex, [&] {
      for (const auto& ix : metadata_) {
        CanonicalWriter c;
        c.put_u64(ix.offset);
        c.put_u64(ix.length);
        c.put_string(ix.name);
        put_record(sum, Op::kMetadataIndex, c);
      }
    });
    group(Op::kAttachmentIndex, [&] {
      for (const auto& ix : attachments_) {
        CanonicalWriter c;
        c.put_u64(ix.offset);
        c.put_u64(ix.length);
        c.put_u64(ix.log_time);
        c.put_u64(ix.create_time);
        c.put_u64(ix.data_size);
        c.put_string(ix.name);
        c.put_string(ix.media_type);
        put_record(sum, Op::kAttachmentIndex, c);
      }
    });
    group(Op::kChunkIndex, [&] { put_chunk_indexes(sum); });
    const uint64_t summary_offset_start = summary_start + sum.size();
    for (const auto& g : groups) {
      CanonicalWriter c;
      c.put_u8(static_cast<uint8_t>(g.op));
      c.put_u64(g.start);
      c.put_u64(g.length);
      put_record(sum, Op::kSummaryOffset, c);
    }
    sum.put_u8(static_cast<uint8_t>(Op::kFooter));
    sum.put_u64(20);
    sum.put_u64(summary_start);
    sum.put_u64(summary_offset_start);
    sum.put_u32(crc32(0, sum.bytes().data(), sum.size()));
    sum.put_bytes(kMagic, kMagicSize);
    if (auto s = emit(sum.bytes()); !s) return s;
    return flush();
  }

  std::FILE* f_;
  std::string path_;
  GenericWriterOptions opt_;
  std::string error_;
  uint64_t offset_ = 0;
  bool in_data_ = true;
  uint32_t data_crc_ = 0;
  std::vector<SchemaEntry> schemas_;    // id = index + 1
  std::vector<ChannelEntry> channels_;  // id = index + first_channel_id
  CanonicalWriter chunk_;
  std::vector<uint8_t> zbuf_;
  ZSTD_CCtx* cctx_ = nullptr;
  bool chunk_open_ = false;
  uint64_t chunk_first_ns_ = 0, chunk_start_ = 0, chunk_end_ = 0;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;  // (log time, offset)
  std::vector<ChunkIndexEntry> chunks_;
  std::vector<IndexEntry> metadata_, attachments_;
  uint64_t message_count_ = 0, first_ns_ = 0, last_ns_ = 0;
  std::map<uint16_t, uint64_t> channel_counts_;
};

}  // namespace

Result<std::unique_ptr<GenericWriter>> GenericWriter::open(const std::string& path, const GenericWriterOptions& options) {
  if (options.compression != "" && options.compression != "zstd")
    return Error{path + ": unsupported chunk compression '" + options.compression + "' (\"zstd\" or \"\")"};
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return Error{path + ": cannot open for writing"};
  auto w = std::make_unique<Writer>(f, path, options);
  if (auto s = w->start(); !s) return s.error();
  return std::unique_ptr<GenericWriter>(std::move(w));
}

}  // namespace orthosonar::replay::mcap
