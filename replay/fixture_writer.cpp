// FixtureWriter: an append-only MCAP writer (mcap.dev/spec). Layout:
//   magic, Header, Metadata "orthosonar", Attachments (when attach() is called, e.g. the
//   simulator's scene), then per first use of a channel its Schema and Channel records,
//   then Chunks each followed by its Message Index records, then Data End (data section
//   CRC), the summary (schemas, channels, statistics, metadata index, attachment indexes,
//   chunk indexes), Summary Offsets, Footer (summary CRC), magic.
// Every chunk is written and flushed as soon as it closes, so a process killed mid-write
// leaves a file readable up to its last complete chunk.
#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <zstd.h>

#include "core/canonical.hpp"
#include "orthosonar/version.hpp"
#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/ros1_codec.hpp"

namespace orthosonar::replay {
namespace {

using mcap::Op;

void put_record(CanonicalWriter& out, Op op, const CanonicalWriter& content) {
  out.put_u8(static_cast<uint8_t>(op));
  out.put_u64(content.size());
  out.put_bytes(content.bytes());
}

struct AttachmentIndexEntry {
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

class McapWriter final : public FixtureWriter {
 public:
  McapWriter(std::FILE* f, std::string path, WriterOptions o) : f_(f), path_(std::move(path)), opt_(o) {}
  ~McapWriter() override {
    if (f_ != nullptr) (void)close();
  }

  Status start(const FixtureMetadata& metadata) {
    CanonicalWriter out, c;
    out.put_bytes(mcap::kMagic, mcap::kMagicSize);
    c.put_string(mcap::kProfile);
    c.put_string(std::string("orthosonar ") + kVersion);
    put_record(out, Op::kHeader, c);
    c.clear();
    c.put_string(mcap::kMetadataName);
    put_map(c, metadata);
    metadata_offset_ = offset_ + out.size();
    metadata_length_ = mcap::kRecordPrefix + c.size();
    put_record(out, Op::kMetadata, c);
    if (auto s = emit(out.bytes()); !s) return s;
    return flush();
  }

  Status write(const Event& e) override {
    if (f_ == nullptr) return reject("write after close");
    if (!error_.empty()) return Error{error_};
    if (e.stamp.ns() < 0) return reject("negative event stamp " + std::to_string(e.stamp.ns()) + " ns");
    if (e.sequence > UINT32_MAX) return reject("sequence " + std::to_string(e.sequence) + " exceeds uint32");
    const auto ch = static_cast<size_t>(e.channel);
    if (ch >= kChannelCount) return reject("unknown channel " + std::to_string(ch));
    msg_.clear();
    if (auto s = ros1::encode(e, msg_); !s)
      return reject(std::string("cannot encode event on ") + channel_topic(e.channel) + " (sequence " +
                  std::to_string(e.sequence) + "): " + s.error().message);
    if (!channel_written_[ch]) {
      if (auto s = write_channel(e.channel); !s) return s;
    }
    const auto stamp = static_cast<uint64_t>(e.stamp.ns());
    if (chunk_open_) {
      const int64_t span = e.stamp.ns() - chunk_first_ns_;
      if (span >= opt_.chunk_max_stream_ns || -span >= opt_.chunk_max_stream_ns) {
        if (auto s = flush_chunk(); !s) return s;
      }
    }
    if (!chunk_open_) {
      chunk_open_ = true;
      chunk_first_ns_ = e.stamp.ns();
      chunk_start_ = chunk_end_ = stamp;
    }
    chunk_start_ = std::min(chunk_start_, stamp);
    chunk_end_ = std::max(chunk_end_, stamp);
    const auto id = static_cast<uint16_t>(ch);
    chunk_index_[id].push_back({stamp, chunk_.size()});
    CanonicalWriter& c = chunk_;
    c.put_u8(static_cast<uint8_t>(Op::kMessage));
    c.put_u64(2 + 4 + 8 + 8 + msg_.size());
    c.put_u16(id);
    c.put_u32(static_cast<uint32_t>(e.sequence));
    c.put_u64(stamp);
    c.put_u64(stamp);
    c.put_bytes(msg_.bytes());
    ++message_count_;
    ++channel_counts_[id];
    if (message_count_ == 1) {
      first_ns_ = last_ns_ = stamp;
    }
    first_ns_ = std::min(first_ns_, stamp);
    last_ns_ = std::max(last_ns_, stamp);
    if (chunk_.size() >= opt_.chunk_max_bytes) return flush_chunk();
    return {};
  }

  Status attach(const Attachment& a) override {
    if (f_ == nullptr) return reject("attach after close");
    if (!error_.empty()) return Error{error_};
    if (a.name.empty()) return reject("attachment without a name");
    if (a.data.size() > mcap::kMaxAttachmentBytes)
      return reject("attachment '" + a.name + "' has " + std::to_string(a.data.size()) + " bytes (at most " +
                    std::to_string(mcap::kMaxAttachmentBytes) + ")");
    CanonicalWriter c;
    c.put_u64(a.log_time_ns);
    c.put_u64(a.create_time_ns);
    c.put_string(a.name);
    c.put_string(a.media_type);
    c.put_u64(a.data.size());
    c.put_bytes(a.data.data(), a.data.size());
    c.put_u32(mcap::crc32(0, c.bytes().data(), c.size()));  // CRC of every preceding field
    CanonicalWriter out;
    put_record(out, Op::kAttachment, c);
    AttachmentIndexEntry ix{offset_, out.size(), a.log_time_ns, a.create_time_ns, a.data.size(), a.name, a.media_type};
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
  // An event that cannot be stored: rejected, nothing written, the file stays valid.
  Status reject(const std::string& what) const { return Error{path_ + ": " + what}; }
  // An I/O or compression failure: sticky, every later call reports it.
  Status fail(const std::string& what) {
    if (error_.empty()) error_ = path_ + ": " + what;
    return Error{path_ + ": " + what};
  }

  static void put_map(CanonicalWriter& c, const std::map<std::string, std::string>& m) {
    CanonicalWriter body;
    for (const auto& [k, v] : m) {
      body.put_string(k);
      body.put_string(v);
    }
    c.put_u32(static_cast<uint32_t>(body.size()));
    c.put_bytes(body.bytes());
  }

  // Appends bytes to the file, keeping the running data section CRC.
  Status emit(const std::vector<uint8_t>& bytes) { return emit(bytes.data(), bytes.size()); }
  Status emit(const uint8_t* p, size_t n) {
    if (!error_.empty()) return Error{error_};
    if (n > 0 && std::fwrite(p, 1, n, f_) != n) return fail("write failed at byte offset " + std::to_string(offset_));
    if (in_data_) data_crc_ = mcap::crc32(data_crc_, p, n);
    offset_ += n;
    return {};
  }
  Status flush() {
    if (std::fflush(f_) != 0) return fail("flush failed at byte offset " + std::to_string(offset_));
    return {};
  }

  void put_schema(CanonicalWriter& out, const ros1::SchemaDef& s) {
    CanonicalWriter c;
    c.put_u16(s.id);
    c.put_string(s.name);
    c.put_string(mcap::kSchemaEncoding);
    c.put_u32(static_cast<uint32_t>(s.text.size()));
    c.put_bytes(reinterpret_cast<const uint8_t*>(s.text.data()), s.text.size());
    put_record(out, Op::kSchema, c);
  }
  void put_channel(CanonicalWriter& out, Channel ch) {
    CanonicalWriter c;
    c.put_u16(static_cast<uint16_t>(ch));
    c.put_u16(ros1::schema_for(ch).id);
    c.put_string(channel_topic(ch));
    c.put_string(mcap::kMessageEncoding);
    put_map(c, {});
    put_record(out, Op::kChannel, c);
  }

  // Schema and Channel records go in the data section (outside chunks) on first use, so
  // a truncated file still defines every channel its complete chunks use.
  Status write_channel(Channel ch) {
    CanonicalWriter out;
    const auto& s = ros1::schema_for(ch);
    if (!schema_written_[s.id]) {
      put_schema(out, s);
      schema_written_[s.id] = true;
    }
    put_channel(out, ch);
    channel_written_[static_cast<size_t>(ch)] = true;
    return emit(out.bytes());
  }

  Status flush_chunk() {
    if (!chunk_open_) return {};
    chunk_open_ = false;
    const auto& raw = chunk_.bytes();
    const uint32_t crc = mcap::crc32(0, raw.data(), raw.size());
    const uint8_t* body = raw.data();
    size_t body_size = raw.size();
    if (opt_.compress) {
      zbuf_.resize(ZSTD_compressBound(raw.size()));
      const size_t z = ZSTD_compress(zbuf_.data(), zbuf_.size(), raw.data(), raw.size(), opt_.zstd_level);
      if (ZSTD_isError(z)) return fail(std::string("zstd: ") + ZSTD_getErrorName(z));
      body = zbuf_.data();
      body_size = z;
    }
    const std::string compression = opt_.compress ? "zstd" : "";
    ChunkIndexEntry ix;
    ix.start_ns = chunk_start_;
    ix.end_ns = chunk_end_;
    ix.offset = offset_;
    ix.compression = compression;
    ix.compressed_size = body_size;
    ix.uncompressed_size = raw.size();
    CanonicalWriter head;
    head.put_u8(static_cast<uint8_t>(Op::kChunk));
    const uint64_t content = 8 + 8 + 8 + 4 + 4 + compression.size() + 8 + body_size;
    head.put_u64(content);
    head.put_u64(chunk_start_);
    head.put_u64(chunk_end_);
    head.put_u64(raw.size());
    head.put_u32(crc);
    head.put_string(compression);
    head.put_u64(body_size);
    ix.length = mcap::kRecordPrefix + content;
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
    if (auto s = emit(body, body_size); !s) return s;
    if (auto s = emit(idx.bytes()); !s) return s;
    chunks_.push_back(std::move(ix));
    chunk_.clear();
    chunk_index_.clear();
    return flush();
  }

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
      for (int c = 0; c < kChannelCount; ++c) {
        const auto& s = ros1::schema_for(static_cast<Channel>(c));
        if (channel_written_[static_cast<size_t>(c)] && !schema_put_[s.id]) {
          put_schema(sum, s);
          schema_put_[s.id] = true;
        }
      }
    });
    group(Op::kChannel, [&] {
      for (int c = 0; c < kChannelCount; ++c)
        if (channel_written_[static_cast<size_t>(c)]) put_channel(sum, static_cast<Channel>(c));
    });
    group(Op::kStatistics, [&] {
      CanonicalWriter c;
      c.put_u64(message_count_);
      uint16_t schemas = 0;
      for (bool b : schema_written_) schemas = static_cast<uint16_t>(schemas + (b ? 1 : 0));
      uint32_t channels = 0;
      for (bool b : channel_written_) channels += b ? 1u : 0u;
      c.put_u16(schemas);
      c.put_u32(channels);
      c.put_u32(static_cast<uint32_t>(attachments_.size()));
      c.put_u32(1);  // metadata
      c.put_u32(static_cast<uint32_t>(chunks_.size()));
      c.put_u64(first_ns_);
      c.put_u64(last_ns_);
      c.put_u32(static_cast<uint32_t>(channel_counts_.size() * 10));
      for (const auto& [id, n] : channel_counts_) {
        c.put_u16(id);
        c.put_u64(n);
      }
      put_record(sum, Op::kStatistics, c);
    });
    group(Op::kMetadataIndex, [&] {
      CanonicalWriter c;
      c.put_u64(metadata_offset_);
      c.put_u64(metadata_length_);
      c.put_string(mcap::kMetadataName);
      put_record(sum, Op::kMetadataIndex, c);
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
    group(Op::kChunkIndex, [&] {
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
    });
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
    sum.put_u32(mcap::crc32(0, sum.bytes().data(), sum.size()));
    sum.put_bytes(mcap::kMagic, mcap::kMagicSize);
    if (auto s = emit(sum.bytes()); !s) return s;
    return flush();
  }

  std::FILE* f_;
  std::string path_;
  WriterOptions opt_;
  std::string error_;
  uint64_t offset_ = 0;
  bool in_data_ = true;
  uint32_t data_crc_ = 0;
  uint64_t metadata_offset_ = 0, metadata_length_ = 0;
  std::array<bool, kChannelCount> channel_written_{};
  std::array<bool, 8> schema_written_{};
  std::array<bool, 8> schema_put_{};
  CanonicalWriter msg_, chunk_;
  std::vector<uint8_t> zbuf_;
  bool chunk_open_ = false;
  int64_t chunk_first_ns_ = 0;
  uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  std::vector<ChunkIndexEntry> chunks_;
  std::vector<AttachmentIndexEntry> attachments_;
  uint64_t message_count_ = 0, first_ns_ = 0, last_ns_ = 0;
  std::map<uint16_t, uint64_t> channel_counts_;
};

}  // namespace

Result<std::unique_ptr<FixtureWriter>> FixtureWriter::open(const std::string& path,
                                                           const FixtureMetadata& metadata,
                                                           const WriterOptions& options) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return Error{path + ": cannot open for writing"};
  auto w = std::make_unique<McapWriter>(f, path, options);
  if (auto s = w->start(metadata); !s) return s.error();
  return std::unique_ptr<FixtureWriter>(std::move(w));
}

}  // namespace orthosonar::replay
