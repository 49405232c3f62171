// MCAP files as other writers make them (the official libraries, rosbag2, Foxglove),
// built byte by byte here: Schema and Channel records inside chunks, no summary, no
// chunks, lz4 / zstd / uncompressed chunks, no indexes, a truncated recording. Each must
// replay exactly the events written; bad input must be an error naming file and offset.
// (replay/interop/run_rewrite.sh does the same with the official TypeScript writer.)
#include <lz4frame.h>
#include <sys/resource.h>
#include <zstd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <string>
#include <vector>

#include "core/canonical.hpp"
#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/mcap_reader.hpp"
#include "replay/ros1_codec.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;
using mcap::Op;

namespace {

struct WriterMode {
  bool chunks = true;               // false: every record in the data section itself
  bool channels_in_chunks = true;   // Schema and Channel records inside the chunk of their first use
  bool summary = false;             // Data End, then schemas, channels and statistics; else no summary
  std::string compression = "zstd";
  bool lz4_size_in_even_chunks = true;  // the LZ4 frame's optional content size: in chunks 0, 2, ... (else 1, 3, ...)
  bool zstd_content_size = true;        // false: zstd frames without their (optional) content size
  // Declared uncompressed size minus the real one (a lying chunk header), for error tests.
  int64_t size_lie = 0;
};

// A hand-made MCAP file and, per chunk (or run of loose messages), where it ends in the
// file and how many events the file holds up to there.
struct Built {
  std::vector<uint8_t> bytes;
  std::vector<std::pair<size_t, size_t>> group_ends;
  std::vector<size_t> chunk_offsets;
};

uint16_t channel_id(Channel c) { return static_cast<uint16_t>(100 + 3 * static_cast<int>(c)); }

std::vector<uint8_t> record(Op op, const std::vector<uint8_t>& body) {
  CanonicalWriter w;
  w.put_u8(static_cast<uint8_t>(op));
  w.put_u64(body.size());
  w.put_bytes(body);
  return w.take();
}

void append(std::vector<uint8_t>& out, const std::vector<uint8_t>& more) { out.insert(out.end(), more.begin(), more.end()); }

std::vector<uint8_t> schema_record(Channel c) {
  const auto& s = ros1::schema_for(c);
  CanonicalWriter w;
  w.put_u16(s.id);
  w.put_string(s.name);
  w.put_string(mcap::kSchemaEncoding);
  w.put_string(s.text);
  return record(Op::kSchema, w.take());
}

std::vector<uint8_t> channel_record(Channel c) {
  CanonicalWriter w;
  w.put_u16(channel_id(c));
  w.put_u16(ros1::schema_for(c).id);
  w.put_string(channel_topic(c));
  w.put_string(mcap::kMessageEncoding);
  w.put_u32(0);  // no channel metadata
  return record(Op::kChannel, w.take());
}

std::vector<uint8_t> message_record(const Event& e) {
  CanonicalWriter payload;
  REQUIRE(ros1::encode(e, payload).ok());
  CanonicalWriter w;
  w.put_u16(channel_id(e.channel));
  w.put_u32(static_cast<uint32_t>(e.sequence));
  w.put_u64(static_cast<uint64_t>(e.stamp.ns()));
  w.put_u64(static_cast<uint64_t>(e.stamp.ns()));  // publish time
  w.put_bytes(payload.bytes());
  return record(Op::kMessage, w.take());
}

std::vector<uint8_t> compress(const std::vector<uint8_t>& in, const std::string& how, bool lz4_content_size,
                              bool zstd_content_size = true) {
  if (how.empty()) return in;
  std::vector<uint8_t> out;
  if (how == "zstd" && !zstd_content_size) {
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    REQUIRE(cctx != nullptr);
    REQUIRE_FALSE(ZSTD_isError(ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 0)));
    out.resize(ZSTD_compressBound(in.size()));
    const size_t n = ZSTD_compress2(cctx, out.data(), out.size(), in.data(), in.size());
    ZSTD_freeCCtx(cctx);
    REQUIRE_FALSE(ZSTD_isError(n));
    out.resize(n);
    REQUIRE(ZSTD_getFrameContentSize(out.data(), out.size()) == ZSTD_CONTENTSIZE_UNKNOWN);
  } else if (how == "zstd") {
    out.resize(ZSTD_compressBound(in.size()));
    const size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 1);
    REQUIRE_FALSE(ZSTD_isError(n));
    out.resize(n);
  } else if (how == "lz4") {
    LZ4F_preferences_t prefs{};
    prefs.frameInfo.contentSize = lz4_content_size ? in.size() : 0;  // optional in the frame format
    out.resize(LZ4F_compressFrameBound(in.size(), &prefs));
    const size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), &prefs);
    REQUIRE_FALSE(LZ4F_isError(n));
    out.resize(n);
  } else {
    out = in;  // an unknown compression: bytes as they are
  }
  return out;
}

std::vector<std::vector<Event>> split(const std::vector<Event>& events, int64_t chunk_ns) {
  std::vector<std::vector<Event>> groups;
  for (const auto& e : events) {
    if (groups.empty() || e.stamp - groups.back().front().stamp >= Time::from_ns(chunk_ns)) groups.emplace_back();
    groups.back().push_back(e);
  }
  return groups;
}

Built build(const std::vector<std::vector<Event>>& groups, const WriterMode& m) {
  Built b;
  auto& out = b.bytes;
  out.assign(mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  {
    CanonicalWriter h;
    h.put_string("ros1");
    h.put_string("orthosonar mcap_interop_test (a foreign writer)");
    append(out, record(Op::kHeader, h.take()));
    CanonicalWriter md;
    md.put_string(mcap::kMetadataName);
    CanonicalWriter kv;
    kv.put_string("scene");
    kv.put_string("hand-made");
    md.put_u32(static_cast<uint32_t>(kv.size()));
    md.put_bytes(kv.bytes());
    append(out, record(Op::kMetadata, md.take()));
  }
  std::map<uint16_t, bool> schema_written;
  std::map<Channel, bool> channel_written;
  std::map<Channel, uint64_t> counts;
  size_t events = 0;
  uint64_t lo = UINT64_MAX, hi = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    std::vector<uint8_t> inner;  // the chunk's records
    auto& defs = m.chunks && m.channels_in_chunks ? inner : out;
    uint64_t start = UINT64_MAX, end = 0;
    for (const auto& e : groups[g]) {
      if (!channel_written[e.channel]) {
        if (!schema_written[ros1::schema_for(e.channel).id]) append(defs, schema_record(e.channel));
        schema_written[ros1::schema_for(e.channel).id] = true;
        append(defs, channel_record(e.channel));
        channel_written[e.channel] = true;
      }
      append(m.chunks ? inner : out, message_record(e));
      const auto t = static_cast<uint64_t>(e.stamp.ns());
      start = std::min(start, t);
      end = std::max(end, t);
      ++counts[e.channel];
    }
    lo = std::min(lo, start);
    hi = std::max(hi, end);
    events += groups[g].size();
    if (m.chunks) {
      const auto data = compress(inner, m.compression, (g % 2 == 0) == m.lz4_size_in_even_chunks, m.zstd_content_size);
      CanonicalWriter c;
      c.put_u64(start);
      c.put_u64(end);
      c.put_u64(static_cast<uint64_t>(static_cast<int64_t>(inner.size()) + m.size_lie));
      c.put_u32(mcap::crc32(0, inner.data(), inner.size()));
      c.put_string(m.compression);
      c.put_u64(data.size());
      c.put_bytes(data);
      b.chunk_offsets.push_back(out.size());
      append(out, record(Op::kChunk, c.take()));
    }
    b.group_ends.emplace_back(out.size(), events);
  }
  {
    CanonicalWriter de;
    de.put_u32(mcap::crc32(0, out.data(), out.size()));
    append(out, record(Op::kDataEnd, de.take()));
  }
  uint64_t summary_start = 0;
  if (m.summary) {
    summary_start = out.size();
    for (const auto& [id, written] : schema_written)
      for (int c = 0; c < kChannelCount; ++c)
        if (ros1::schema_for(static_cast<Channel>(c)).id == id && channel_written[static_cast<Channel>(c)]) {
          append(out, schema_record(static_cast<Channel>(c)));
          break;
        }
    for (const auto& [c, written] : channel_written) append(out, channel_record(c));
    CanonicalWriter st;
    st.put_u64(events);
    st.put_u16(static_cast<uint16_t>(schema_written.size()));
    st.put_u32(static_cast<uint32_t>(channel_written.size()));
    st.put_u32(0);  // attachments
    st.put_u32(1);  // metadata
    st.put_u32(m.chunks ? static_cast<uint32_t>(groups.size()) : 0u);
    st.put_u64(lo);
    st.put_u64(hi);
    st.put_u32(static_cast<uint32_t>(counts.size() * 10));
    for (const auto& [c, n] : counts) {
      st.put_u16(channel_id(c));
      st.put_u64(n);
    }
    append(out, record(Op::kStatistics, st.take()));
  }
  const size_t footer = out.size();
  append(out, record(Op::kFooter, [&] {
           CanonicalWriter body;
           body.put_u64(summary_start);
           body.put_u64(0);
           body.put_u32(0);
           return body.take();
         }()));
  if (summary_start != 0) {
    const uint32_t crc = mcap::crc32(0, out.data() + summary_start, footer + 9 + 16 - summary_start);
    for (size_t i = 0; i < 4; ++i) out[footer + 9 + 16 + i] = static_cast<uint8_t>(crc >> (8 * i));
  }
  out.insert(out.end(), mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  return b;
}

std::vector<Event> small_recording(uint64_t seed) {
  SyntheticOptions so;
  so.duration_ns = 2'000'000'000;
  so.ping_rows = 16;
  so.ping_cols = 8;
  return synthetic_events(seed, so);
}

mcap::Layout scan_file(const std::string& path) {
  auto f = mcap::MappedFile::open(path);
  REQUIRE(f.ok());
  auto layout = mcap::scan(**f);
  INFO((layout.ok() ? std::string() : layout.error().message));
  REQUIRE(layout.ok());
  return std::move(layout.value());
}

std::string mode_name(const WriterMode& m) {
  return std::string(m.chunks ? "chunks" : "nochunks") + (m.channels_in_chunks ? "_inner" : "_outer") +
         (m.summary ? "_summary" : "_nosummary") + "_" + (m.compression.empty() ? "none" : m.compression);
}

// Writes `bytes` and expects an error naming the file and "byte offset <at>".
std::string expect_error_at(const std::string& path, const std::vector<uint8_t>& bytes, size_t at) {
  write_bytes(path, bytes);
  const auto back = read_fixture(path);
  INFO("events read: " << back.events.size());
  REQUIRE_FALSE(back.error.empty());
  INFO(back.error);
  CHECK(back.error.find(path + ": ") == 0);
  CHECK(back.error.find("byte offset " + std::to_string(at)) != std::string::npos);
  return back.error;
}

}  // namespace

TEST_CASE("interop: channels inside or outside chunks, with or without a summary, any compression", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(21);
  const auto groups = split(events, 300'000'000);
  for (const std::string compression : {"", "zstd", "lz4"})
    for (const bool summary : {true, false})
      for (const bool inner : {true, false}) {
        WriterMode m;
        m.compression = compression;
        m.summary = summary;
        m.channels_in_chunks = inner;
        const std::string path = dir + "/" + mode_name(m) + ".mcap";
        write_bytes(path, build(groups, m).bytes);
        const auto back = read_fixture(path);
        INFO(path << ": " << back.error);
        REQUIRE(back.error.empty());
        CHECK(back.events == events);
        CHECK(back.recovery.complete);
        CHECK(back.recovery.messages_recovered == events.size());
        CHECK(back.metadata.at("scene") == "hand-made");
        const auto layout = scan_file(path);
        CHECK(layout.read.summary_present == summary);
        CHECK(layout.read.read_by_linear_scan == !summary);
        CHECK(layout.read.summary_note.empty());
        CHECK(layout.read.chunk_count == groups.size());
        CHECK(layout.read.compressions == std::vector<std::string>{compression});
        CHECK_FALSE(layout.read.message_indexes);
        CHECK_FALSE(layout.read.chunk_indexes);
        CHECK(layout.read.truncated_bytes == 0);
        CHECK(layout.message_count == events.size());
      }
}

TEST_CASE("interop: a file without chunks replays every message, with or without a summary", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(22);
  for (const bool summary : {true, false}) {
    WriterMode m;
    m.chunks = false;
    m.summary = summary;
    const std::string path = dir + "/" + mode_name(m) + ".mcap";
    write_bytes(path, build(split(events, 300'000'000), m).bytes);
    const auto back = read_fixture(path);
    INFO(back.error);
    REQUIRE(back.error.empty());
    CHECK(back.events == events);
    CHECK(back.recovery.messages_recovered == events.size());
    const auto layout = scan_file(path);
    CHECK(layout.read.chunk_count == 0);
    CHECK(layout.read.compressions.empty());
    CHECK(layout.read.loose_message_count == events.size());
    CHECK(layout.read.read_by_linear_scan == !summary);
  }
}

TEST_CASE("interop: a channel defined in an earlier chunk may be replayed later", "[unit]") {
  // The chunk that defines the channels holds the later half of the recording: replay
  // (stamp order) reads the other chunk first, whose messages use those channels.
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(23);
  const size_t half = events.size() / 2;
  const std::vector<std::vector<Event>> groups{{events.begin() + static_cast<ptrdiff_t>(half), events.end()},
                                               {events.begin(), events.begin() + static_cast<ptrdiff_t>(half)}};
  WriterMode m;
  m.compression = "lz4";
  const std::string path = dir + "/reversed.mcap";
  write_bytes(path, build(groups, m).bytes);
  const auto back = read_fixture(path);
  INFO(back.error);
  REQUIRE(back.error.empty());
  CHECK(back.events == events);
}

TEST_CASE("interop: a recorder that died leaves a file read up to its last complete record, with a warning",
          "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(24);
  WriterMode m;
  m.compression = "lz4";
  m.summary = true;  // ... that it never wrote
  const auto b = build(split(events, 300'000'000), m);
  REQUIRE(b.group_ends.size() >= 4);
  const size_t third = b.chunk_offsets[2];
  struct Cut {
    size_t at;
    size_t events;  // complete before the cut
  };
  // Inside the third chunk, at the start of the third chunk, and inside the footer.
  for (const Cut cut : {Cut{third + 40, b.group_ends[1].second}, Cut{third, b.group_ends[1].second},
                        Cut{b.bytes.size() - 12, events.size()}}) {
    const std::string path = dir + "/cut" + std::to_string(cut.at) + ".mcap";
    write_bytes(path, std::vector<uint8_t>(b.bytes.begin(), b.bytes.begin() + static_cast<ptrdiff_t>(cut.at)));
    const auto back = read_fixture(path);
    INFO(path << ": " << back.error);
    REQUIRE(back.error.empty());
    CHECK(back.events == std::vector<Event>(events.begin(), events.begin() + static_cast<ptrdiff_t>(cut.events)));
    CHECK_FALSE(back.recovery.complete);
    CHECK(back.recovery.messages_recovered == cut.events);
    CHECK(back.recovery.detail.find(path + ": ") == 0);
    CHECK(back.recovery.detail.find("byte offset") != std::string::npos);
    const auto layout = scan_file(path);
    CHECK_FALSE(layout.read.summary_present);
    CHECK(layout.read.read_by_linear_scan);
    CHECK(layout.read.truncated_bytes == cut.at - back.recovery.bytes_recovered);
    CHECK((layout.read.truncated_bytes == 0) == (cut.at == third));  // a cut between records leaves none
  }
}

TEST_CASE("interop: a chunk whose declared uncompressed size lies is an error naming its offset", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(25);
  const auto groups = split(events, 500'000'000);
  for (const std::string compression : {"", "zstd", "lz4", "lz4-nosize"})
    for (const int64_t lie : {-7, 9})
      for (const bool summary : {true, false}) {
        WriterMode m;
        m.compression = compression == "lz4-nosize" ? "lz4" : compression;
        m.lz4_size_in_even_chunks = compression != "lz4-nosize";
        m.size_lie = lie;
        m.summary = summary;
        const auto b = build(groups, m);
        const std::string path = dir + "/lie_" + compression + "_" + mode_name(m) + std::to_string(lie) + ".mcap";
        const auto e = expect_error_at(path, b.bytes, b.chunk_offsets[0]);
        if (compression.empty()) CHECK(e.find("uncompressed chunk with inconsistent sizes") != std::string::npos);
        if (compression == "zstd") CHECK(e.find("not a zstd frame of the stated size") != std::string::npos);
        if (compression == "lz4") CHECK(e.find("lz4 chunk frame states") != std::string::npos);
        if (compression == "lz4-nosize")
          CHECK(e.find(lie < 0 ? "lz4 chunk decompresses to more than its stated" : "lz4 chunk decompresses to") !=
                std::string::npos);
      }
}

TEST_CASE("interop: an lz4 chunk claiming more than lz4 can expand is rejected before allocating", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  WriterMode m;
  m.compression = "lz4";
  m.size_lie = int64_t{1} << 29;
  const auto b = build(split(small_recording(26), 500'000'000), m);
  const auto e = expect_error_at(dir + "/lz4ratio.mcap", b.bytes, b.chunk_offsets[0]);
  CHECK(e.find("more than lz4 can expand") != std::string::npos);
}

// Peak resident memory of this process so far, in bytes.
size_t interop_test_peak_rss_bytes() {
  struct rusage u {};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<size_t>(u.ru_maxrss) * 1024;
}

// Issue 35: a zstd frame need not state its content size; the reader used to allocate the
// chunk's declared uncompressed size (up to 1 GiB) before decompressing a single byte.
TEST_CASE("interop: a zstd chunk without a content size is read streaming, bounded by its declared size", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(29);
  const auto groups = split(events, 500'000'000);
  WriterMode m;
  m.zstd_content_size = false;
  write_bytes(dir + "/zstd_nosize.mcap", build(groups, m).bytes);
  const auto back = read_fixture(dir + "/zstd_nosize.mcap");
  INFO(back.error);
  REQUIRE(back.error.empty());
  CHECK(back.events == events);
  // A declared size that lies either way is an error naming the chunk.
  for (const int64_t lie : {-7, 9}) {
    m.size_lie = lie;
    const auto b = build(groups, m);
    const auto e = expect_error_at(dir + "/zstd_nosize_lie" + std::to_string(lie) + ".mcap", b.bytes, b.chunk_offsets[0]);
    CHECK(e.find(lie < 0 ? "zstd chunk decompresses to more than its stated" : "zstd chunk decompresses to") !=
          std::string::npos);
  }
  // 1 GiB declared for a chunk of a few kB: rejected before a buffer of that size exists.
  m.size_lie = (int64_t{1} << 30) - 200000;  // the chunk holds far less than 200 kB
  const auto b = build(groups, m);
  const size_t rss_before = interop_test_peak_rss_bytes();
  const auto e = expect_error_at(dir + "/zstd_nosize_1gib.mcap", b.bytes, b.chunk_offsets[0]);
  CHECK(e.find("more than zstd can expand") != std::string::npos);
  CHECK(interop_test_peak_rss_bytes() < rss_before + (size_t{256} << 20));
}

TEST_CASE("interop: an unknown chunk compression is an error naming its offset", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  WriterMode m;
  m.compression = "brotli";
  const auto b = build(split(small_recording(27), 500'000'000), m);
  const auto e = expect_error_at(dir + "/brotli.mcap", b.bytes, b.chunk_offsets[0]);
  CHECK(e.find("unsupported chunk compression 'brotli'") != std::string::npos);
}

TEST_CASE("interop: a record length beyond the file end is an error naming its offset", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  WriterMode m;
  m.summary = true;
  auto b = build(split(small_recording(28), 500'000'000), m);
  // The second chunk's length: a complete file (footer and magic in place) cannot hold it.
  const size_t at = b.chunk_offsets[1];
  for (size_t i = 0; i < 8; ++i) b.bytes[at + 1 + i] = i == 5 ? 0x01 : 0x00;  // 2^40 bytes
  const auto e = expect_error_at(dir + "/length.mcap", b.bytes, at);
  CHECK(e.find("runs past the end of the file") != std::string::npos);
  // Inside a chunk (uncompressed, CRC off so the length is what is checked).
  m.compression = "";
  b = build(split(small_recording(28), 500'000'000), m);
  const size_t chunk = b.chunk_offsets[0];
  const size_t crc_at = chunk + 9 + 24;
  std::fill(b.bytes.begin() + static_cast<ptrdiff_t>(crc_at), b.bytes.begin() + static_cast<ptrdiff_t>(crc_at) + 4,
            uint8_t{0});
  const size_t first_inner = crc_at + 4 + 4 + 8;
  b.bytes[first_inner + 1 + 6] = 0x7f;
  // The data section CRC, recomputed so the scan reaches the chunk.
  size_t de = 8;
  while (b.bytes[de] != static_cast<uint8_t>(Op::kDataEnd)) {
    uint64_t len = 0;
    for (size_t i = 0; i < 8; ++i) len |= static_cast<uint64_t>(b.bytes[de + 1 + i]) << (8 * i);
    de += 9 + static_cast<size_t>(len);
  }
  const uint32_t crc = mcap::crc32(0, b.bytes.data(), de);
  for (size_t i = 0; i < 4; ++i) b.bytes[de + 9 + i] = static_cast<uint8_t>(crc >> (8 * i));
  const auto inner = expect_error_at(dir + "/inner_length.mcap", b.bytes, chunk);
  CHECK(inner.find("record runs past the end of the chunk at offset 0 inside the chunk") != std::string::npos);
}

TEST_CASE("interop: a message on a channel no record defines is an error naming its offset", "[unit]") {
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(29);
  WriterMode m;
  m.compression = "";
  auto b = build(split(events, 500'000'000), m);
  // Rename the first chunk's first Channel record id (CRCs off: chunk CRC zeroed, data CRC 0).
  const size_t chunk = b.chunk_offsets[0];
  const size_t crc_at = chunk + 9 + 24;
  std::fill(b.bytes.begin() + static_cast<ptrdiff_t>(crc_at), b.bytes.begin() + static_cast<ptrdiff_t>(crc_at) + 4,
            uint8_t{0});
  const size_t records = crc_at + 4 + 4 + 8;
  size_t pos = records;
  while (b.bytes[pos] != static_cast<uint8_t>(Op::kChannel)) {
    uint64_t len = 0;
    for (size_t i = 0; i < 8; ++i) len |= static_cast<uint64_t>(b.bytes[pos + 1 + i]) << (8 * i);
    pos += 9 + static_cast<size_t>(len);
  }
  b.bytes[pos + 9] ^= 0x40;  // channel id 100 + 3k -> another id
  size_t de = b.bytes.size() - 8 - 29 - 13;
  REQUIRE(b.bytes[de] == static_cast<uint8_t>(Op::kDataEnd));
  std::fill(b.bytes.begin() + static_cast<ptrdiff_t>(de + 9), b.bytes.begin() + static_cast<ptrdiff_t>(de + 13),
            uint8_t{0});
  const auto e = expect_error_at(dir + "/undefined_channel.mcap", b.bytes, chunk);
  CHECK(e.find("message on undefined channel id") != std::string::npos);
  CHECK(e.find("inside the chunk at byte offset " + std::to_string(chunk)) != std::string::npos);
}

TEST_CASE("interop: damaged foreign files give their events, a recovery or an error, never a crash", "[unit]") {
  // A deterministic sweep (the rapidcheck corruption property covers our own writer's
  // files): one byte flipped, or the file cut, at many places of a file read by linear
  // scan (lz4 chunks with their channels inside, no summary) and of one with a summary.
  const std::string dir = test_dir("mcap_interop");
  const auto events = small_recording(30);
  for (const bool summary : {false, true}) {
    WriterMode m;
    m.compression = "lz4";
    m.summary = summary;
    const auto original = build(split(events, 500'000'000), m).bytes;
    const std::string path = dir + "/damaged" + (summary ? "_summary" : "") + ".mcap";
    const size_t step = original.size() / 150 + 1;
    for (size_t at = 0; at < original.size(); at += step)
      for (const bool cut : {false, true}) {
        auto bytes = original;
        if (cut) bytes.resize(at);
        else bytes[at] ^= static_cast<uint8_t>(0x5a);
        write_bytes(path, bytes);
        const auto back = read_fixture(path);
        INFO((cut ? "cut at " : "flip at ") << at << ": " << back.error);
        if (!back.error.empty()) {
          CHECK(back.error.find(path + ": ") == 0);
          CHECK(back.error.find("offset") != std::string::npos);
        } else if (back.recovery.complete) {
          CHECK(back.events == events);  // the data section and chunk CRCs cover every byte
        } else {
          CHECK(back.events == std::vector<Event>(events.begin(), events.begin() + static_cast<ptrdiff_t>(back.events.size())));
        }
      }
  }
}
