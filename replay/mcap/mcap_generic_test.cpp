// GenericWriter -> visit_messages round trips (several schemas, encodings, a channel
// without schema, zstd and uncompressed chunks, metadata and attachments), files as other
// writers make them (lz4 chunks, Schema and Channel records inside chunks, messages outside
// chunks, no summary), truncated and corrupt files, and our fixtures read generically.
#include "replay/mcap/mcap_generic.hpp"

#include <lz4frame.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/canonical.hpp"
#include "replay/mcap/mcap_format.hpp"
#include "replay/fixture/synthetic.hpp"
#include "replay/fixture/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::mcap;
using orthosonar::replay::testing::case_dir;
using orthosonar::replay::testing::read_bytes;
using orthosonar::replay::testing::write_bytes;

namespace {

struct Msg {
  uint16_t channel = 0;
  uint32_t sequence = 0;
  uint64_t log_ns = 0, publish_ns = 0;
  std::string data;
  friend bool operator==(const Msg&, const Msg&) = default;
};

struct Sample {
  std::vector<Msg> messages;                 // in write (= file) order
  std::map<uint16_t, RawChannel> channels;   // those with messages
  std::map<uint16_t, RawSchema> schemas;     // those of these channels
};

// Three schemas (one never used), four channels (one without a schema, one never used),
// 300 messages whose log times step back now and then, sizes 0..49 bytes.
Sample write_sample(const std::string& path, const std::string& compression, uint64_t chunk_max_bytes = 2048) {
  GenericWriterOptions o;
  o.profile = "ros2";
  o.library = "orthosonar test";
  o.compression = compression;
  o.chunk_max_bytes = chunk_max_bytes;
  o.chunk_max_log_ns = 400'000'000;
  auto w = GenericWriter::open(path, o);
  REQUIRE(w.ok());
  GenericWriter& g = **w;
  REQUIRE(g.metadata("run", {{"scene", "harbor"}, {"seed", "7"}}).ok());
  REQUIRE(g.attach({"notes.txt", "text/plain", {'h', 'i'}, 5, 6}).ok());
  Sample s;
  const RawSchema imu{g.add_schema("sensor_msgs/msg/Imu", "ros2msg", "std_msgs/Header header\nfloat64 x\n"),
                      "sensor_msgs/msg/Imu", "ros2msg", "std_msgs/Header header\nfloat64 x\n"};
  const RawSchema status{g.add_schema("Status", "jsonschema", R"({"type":"object"})"), "Status", "jsonschema",
                         R"({"type":"object"})"};
  const uint16_t unused = g.add_schema("Unused", "ros2msg", "int32 x\n");
  const RawChannel channels[] = {
      {g.add_channel(imu.id, "/imu", "cdr", {{"offered_qos_profiles", "- history: 3"}}), imu.id, "/imu", "cdr",
       {{"offered_qos_profiles", "- history: 3"}}},
      {g.add_channel(status.id, "/status", "json"), status.id, "/status", "json", {}},
      {g.add_channel(0, "/raw", "application/octet-stream"), 0, "/raw", "application/octet-stream", {}},
  };
  (void)g.add_channel(unused, "/never", "cdr");
  CHECK(imu.id == 1);
  CHECK(channels[0].id == 1);
  s.schemas = {{imu.id, imu}, {status.id, status}};
  for (const auto& c : channels) s.channels[c.id] = c;
  for (uint32_t i = 0; i < 300; ++i) {
    Msg m;
    m.channel = channels[i % 3].id;
    m.sequence = i / 3;
    m.log_ns = uint64_t{i} * 7'000'000 + (i % 5 == 4 ? 0 : 20'000'000);  // every fifth steps back
    m.publish_ns = m.log_ns + 1;
    for (uint32_t k = 0; k < (i * 13) % 50; ++k) m.data.push_back(static_cast<char>('a' + (i + k) % 26));
    REQUIRE(g.write(m.channel, m.sequence, m.log_ns, m.publish_ns, reinterpret_cast<const uint8_t*>(m.data.data()),
                    m.data.size())
                .ok());
    s.messages.push_back(std::move(m));
  }
  REQUIRE(g.close().ok());
  return s;
}

struct Visited {
  std::vector<RawChannel> channels;  // in the order announced
  std::vector<std::optional<RawSchema>> schemas;
  std::vector<Msg> messages;
  std::vector<std::pair<uint64_t, uint64_t>> where;  // (chunk_offset, offset) per message
  RecoveryReport recovery;
  std::string error;
};

Visited visit(const std::string& path) {
  Visited v;
  const Status s = visit_messages(
      path,
      [&](const RawChannel& c, const RawSchema* schema) -> Status {
        v.channels.push_back(c);
        v.schemas.push_back(schema == nullptr ? std::nullopt : std::optional<RawSchema>(*schema));
        return {};
      },
      [&](const RawMessage& m) -> Status {
        v.messages.push_back({m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns,
                              std::string(reinterpret_cast<const char*>(m.data), m.size)});
        v.where.emplace_back(m.chunk_offset, m.offset);
        return {};
      },
      &v.recovery);
  if (!s) v.error = s.error().message;
  return v;
}

bool same_channel(const RawChannel& a, const RawChannel& b) {
  return a.id == b.id && a.schema_id == b.schema_id && a.topic == b.topic && a.message_encoding == b.message_encoding &&
         a.metadata == b.metadata;
}

void check_channels(const Visited& v, const Sample& s) {
  REQUIRE(v.channels.size() == s.channels.size());
  for (size_t i = 0; i < v.channels.size(); ++i) {
    const auto& c = v.channels[i];
    REQUIRE(s.channels.count(c.id) == 1);
    CHECK(same_channel(c, s.channels.at(c.id)));
    if (c.schema_id == 0) {
      CHECK_FALSE(v.schemas[i].has_value());
    } else {
      REQUIRE(v.schemas[i].has_value());
      const auto& want = s.schemas.at(c.schema_id);
      CHECK(v.schemas[i]->id == want.id);
      CHECK(v.schemas[i]->name == want.name);
      CHECK(v.schemas[i]->encoding == want.encoding);
      CHECK(v.schemas[i]->data == want.data);
    }
  }
}

// The top-level records of a file (after the magic, up to and including the footer).
struct TopRecord {
  Op op;
  size_t pos;
  std::vector<uint8_t> body;
};
std::vector<TopRecord> top_records(const std::vector<uint8_t>& bytes) {
  std::vector<TopRecord> out;
  for (size_t pos = kMagicSize; pos + kRecordPrefix <= bytes.size();) {
    ByteReader r(bytes.data() + pos, bytes.size() - pos);
    const auto op = static_cast<Op>(r.u8());
    const uint64_t len = r.u64();
    const uint8_t* body = r.take(len);
    REQUIRE(body != nullptr);
    out.push_back({op, pos, std::vector<uint8_t>(body, body + len)});
    pos += kRecordPrefix + len;
    if (op == Op::kFooter) break;
  }
  return out;
}

void put(CanonicalWriter& out, Op op, const std::vector<uint8_t>& body) {
  out.put_u8(static_cast<uint8_t>(op));
  out.put_u64(body.size());
  out.put_bytes(body);
}

// What another writer makes of an uncompressed sample: Schema and Channel records moved
// into the next chunk, chunks lz4-compressed (the frame's content size in every other one,
// the CRC left unset in every third), Message Index records and the summary dropped
// (summary_start 0, data CRC unset), and `loose` records written first, outside chunks.
std::vector<uint8_t> as_other_writer(const std::vector<uint8_t>& plain, const std::vector<uint8_t>& loose) {
  CanonicalWriter out;
  out.put_bytes(kMagic, kMagicSize);
  std::vector<uint8_t> pending;
  int chunk = 0;
  for (const auto& rec : top_records(plain)) {
    if (rec.op == Op::kSchema || rec.op == Op::kChannel) {
      CanonicalWriter w;
      put(w, rec.op, rec.body);
      pending.insert(pending.end(), w.bytes().begin(), w.bytes().end());
    } else if (rec.op == Op::kChunk) {
      ByteReader r(rec.body.data(), rec.body.size());
      const uint64_t start = r.u64(), end = r.u64();
      r.u64();
      r.u32();
      REQUIRE(r.str().empty());
      const uint64_t n = r.u64();
      std::vector<uint8_t> records = pending;
      records.insert(records.end(), r.here(), r.here() + n);
      pending.clear();
      LZ4F_preferences_t prefs{};
      prefs.frameInfo.contentSize = chunk % 2 == 0 ? records.size() : 0;
      std::vector<uint8_t> z(LZ4F_compressFrameBound(records.size(), &prefs));
      const size_t zn = LZ4F_compressFrame(z.data(), z.size(), records.data(), records.size(), &prefs);
      REQUIRE_FALSE(LZ4F_isError(zn));
      CanonicalWriter c;
      c.put_u64(start);
      c.put_u64(end);
      c.put_u64(records.size());
      c.put_u32(chunk % 3 == 2 ? 0 : crc32(0, records.data(), records.size()));
      c.put_string("lz4");
      c.put_u64(zn);
      c.put_bytes(z.data(), zn);
      put(out, Op::kChunk, c.bytes());
      ++chunk;
    } else if (rec.op == Op::kDataEnd) {
      put(out, Op::kDataEnd, std::vector<uint8_t>(4, 0));
      break;
    } else if (rec.op != Op::kMessageIndex) {
      put(out, rec.op, rec.body);
      if (rec.op == Op::kHeader) out.put_bytes(loose);
    }
  }
  CanonicalWriter footer;
  footer.put_u64(0);
  footer.put_u64(0);
  footer.put_u32(0);
  put(out, Op::kFooter, footer.bytes());
  out.put_bytes(kMagic, kMagicSize);
  return out.take();
}

size_t first_chunk_offset(const std::vector<uint8_t>& bytes) {
  for (const auto& rec : top_records(bytes))
    if (rec.op == Op::kChunk) return rec.pos;
  FAIL("no chunk");
  return 0;
}

}  // namespace

TEST_CASE("generic MCAP round trip: schemas, encodings, metadata and attachments, zstd and uncompressed", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  for (const std::string compression : {"zstd", ""}) {
    INFO("compression '" << compression << "'");
    const std::string path = (dir / ("sample_" + compression + ".mcap")).string();
    const Sample s = write_sample(path, compression);
    const Visited v = visit(path);
    REQUIRE(v.error.empty());
    CHECK(v.recovery.complete);
    CHECK(v.recovery.detail.empty());
    CHECK(v.recovery.messages_recovered == s.messages.size());
    CHECK(v.recovery.bytes_recovered == v.recovery.bytes_total);
    check_channels(v, s);
    CHECK(v.messages == s.messages);
    for (const auto& [chunk, offset] : v.where) CHECK(chunk > 0);  // our writer chunks every message
    // Bytes are a pure function of the calls.
    const std::string again = (dir / ("again_" + compression + ".mcap")).string();
    write_sample(again, compression);
    CHECK(read_bytes(again) == read_bytes(path));
  }
}

TEST_CASE("visit_messages reads other writers' files: lz4, channels in chunks, loose messages, no summary", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string plain = (dir / "plain.mcap").string();
  Sample s = write_sample(plain, "");
  // A schemaless channel 900 and two messages on it, outside chunks, before any chunk.
  CanonicalWriter loose;
  CanonicalWriter ch;
  ch.put_u16(900);
  ch.put_u16(0);
  ch.put_string("/loose");
  ch.put_string("json");
  ch.put_u32(0);
  put(loose, Op::kChannel, ch.bytes());
  std::vector<size_t> loose_offsets;
  for (uint32_t i = 0; i < 2; ++i) {
    CanonicalWriter m;
    m.put_u16(900);
    m.put_u32(i);
    m.put_u64(5 + i);
    m.put_u64(6 + i);
    m.put_bytes(std::vector<uint8_t>{'{', '}'});
    loose_offsets.push_back(loose.size());
    put(loose, Op::kMessage, m.bytes());
    s.messages.insert(s.messages.begin() + i, Msg{900, i, 5 + i, 6 + i, "{}"});
  }
  s.channels[900] = RawChannel{900, 0, "/loose", "json", {}};
  const std::string other = (dir / "other.mcap").string();
  write_bytes(other, as_other_writer(read_bytes(plain), loose.bytes()));
  const Visited v = visit(other);
  REQUIRE(v.error.empty());
  CHECK(v.recovery.complete);
  check_channels(v, s);
  CHECK(v.channels.front().id == 900);
  CHECK(v.messages == s.messages);
  // The loose messages are located by file offset (after the magic and the Header).
  const size_t header_end = top_records(read_bytes(other)).front().pos + kRecordPrefix +
                            top_records(read_bytes(other)).front().body.size();
  CHECK(v.where[0] == std::pair<uint64_t, uint64_t>{0, header_end + loose_offsets[0]});
  CHECK(v.where[1] == std::pair<uint64_t, uint64_t>{0, header_end + loose_offsets[1]});
  CHECK(v.where[2].first > 0);
}

TEST_CASE("visit_messages reads a truncated file up to its last complete record and says so", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string path = (dir / "full.mcap").string();
  const Sample s = write_sample(path, "zstd", 1024);
  const auto bytes = read_bytes(path);
  const size_t n = bytes.size();
  size_t data_end = 0;
  for (const auto& rec : top_records(bytes))
    if (rec.op == Op::kDataEnd) data_end = rec.pos;
  size_t last = 0;
  for (const size_t cut : {size_t{8}, size_t{20}, n / 5, n / 3, n / 2, 2 * n / 3, data_end, n - 40, n - 10, n - 1}) {
    INFO("cut at " << cut << " of " << n);
    const std::string cut_path = (dir / ("cut_" + std::to_string(cut) + ".mcap")).string();
    write_bytes(cut_path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut)));
    const Visited v = visit(cut_path);
    REQUIRE(v.error.empty());
    CHECK_FALSE(v.recovery.complete);
    CHECK(v.recovery.bytes_total == cut);
    CHECK(v.recovery.bytes_recovered <= cut);
    CHECK(v.recovery.detail.find(cut_path) != std::string::npos);
    CHECK(v.recovery.detail.find("at byte offset") != std::string::npos);
    CHECK(v.recovery.messages_recovered == v.messages.size());
    REQUIRE(v.messages.size() <= s.messages.size());
    CHECK(std::equal(v.messages.begin(), v.messages.end(), s.messages.begin()));
    CHECK(v.messages.size() >= last);
    last = v.messages.size();
    if (cut >= data_end) CHECK(v.messages.size() == s.messages.size());
    if (cut > n / 3 && cut < data_end) CHECK(v.messages.size() < s.messages.size());
  }
  CHECK(last == s.messages.size());
}

TEST_CASE("visit_messages: a corrupt chunk CRC or opcode is an error naming the file and offset", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string path = (dir / "good.mcap").string();
  write_sample(path, "zstd");
  const auto good = read_bytes(path);
  const size_t chunk = first_chunk_offset(good);
  {
    auto bad = good;
    bad[chunk + kRecordPrefix + 24] ^= 0x01;  // the chunk's uncompressed_crc
    const std::string bad_path = (dir / "bad_crc.mcap").string();
    write_bytes(bad_path, bad);
    const Visited v = visit(bad_path);
    CHECK(v.error.find(bad_path) == 0);
    CHECK(v.error.find("chunk CRC mismatch") != std::string::npos);
    CHECK(v.error.find("at byte offset " + std::to_string(chunk)) != std::string::npos);
    CHECK(v.messages.empty());
  }
  {
    auto bad = good;
    bad[chunk] = 0x42;  // no such opcode
    const std::string bad_path = (dir / "bad_opcode.mcap").string();
    write_bytes(bad_path, bad);
    const Visited v = visit(bad_path);
    CHECK(v.error.find("unsupported record opcode 0x42 at byte offset " + std::to_string(chunk)) != std::string::npos);
  }
  {
    const std::string bad_path = (dir / "not_mcap.mcap").string();
    write_bytes(bad_path, std::vector<uint8_t>(good.begin() + 1, good.end()));
    CHECK(visit(bad_path).error.find("bad magic") != std::string::npos);
  }
}

TEST_CASE("GenericWriter rejects what it cannot write and names the path", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string path = (dir / "w.mcap").string();
  GenericWriterOptions o;
  o.compression = "bz2";
  auto bad = GenericWriter::open(path, o);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("bz2") != std::string::npos);
  auto w = GenericWriter::open(path, {});
  REQUIRE(w.ok());
  const uint16_t c = (*w)->add_channel(0, "/a", "json");
  const uint8_t byte = 1;
  const Status unknown = (*w)->write(7, 0, 0, 0, &byte, 1);
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().message.find(path + ": write on unknown channel id 7") == 0);
  CHECK_FALSE((*w)->attach({"", "text/plain", {}, 0, 0}).ok());
  REQUIRE((*w)->write(c, 0, 1, 1, &byte, 1).ok());
  REQUIRE((*w)->close().ok());
  CHECK_FALSE((*w)->write(c, 1, 2, 2, &byte, 1).ok());
  const Visited v = visit(path);
  REQUIRE(v.error.empty());
  CHECK(v.messages.size() == 1);
}

TEST_CASE("visit_messages reads our fixtures: every channel, ros1, in file order", "[unit]") {
  const auto dir = case_dir("mcap_generic", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string path = (dir / "fixture.mcap").string();
  SyntheticOptions so;
  so.duration_ns = 1'500'000'000;
  so.gyro_rate_hz = 100.0;  // every channel
  const auto events = synthetic_events(3, so);
  REQUIRE(testing::write_fixture(path, events, {{"scene", "harbor"}}).ok());
  const Visited v = visit(path);
  REQUIRE(v.error.empty());
  CHECK(v.recovery.complete);
  REQUIRE(v.channels.size() == kChannelCount);
  for (size_t i = 0; i < v.channels.size(); ++i) {
    const auto ch = static_cast<Channel>(v.channels[i].id);
    CHECK(v.channels[i].topic == channel_topic(ch));
    CHECK(v.channels[i].message_encoding == "ros1");
    REQUIRE(v.schemas[i].has_value());
    CHECK(v.schemas[i]->encoding == "ros1msg");
  }
  REQUIRE(v.messages.size() == events.size());
  for (size_t i = 0; i < events.size(); ++i) {
    CHECK(v.messages[i].channel == static_cast<uint16_t>(events[i].channel));
    CHECK(v.messages[i].sequence == events[i].sequence);
    CHECK(v.messages[i].log_ns == static_cast<uint64_t>(events[i].stamp.ns()));
  }
}

// Not run by ctest directly: replay:interop-generic-writer runs it to write the file that
// replay/interop/generic_check.mjs reads with the official TypeScript MCAP readers.
TEST_CASE("write a generic MCAP file for the TypeScript interop check", "[.interop-generic]") {
  const char* out = std::getenv("ORTHOSONAR_GENERIC_MCAP");
  REQUIRE(out != nullptr);
  const Sample s = write_sample(out, "zstd", 1024);
  nlohmann::json messages = nlohmann::json::array();
  for (const auto& m : s.messages)
    messages.push_back({{"topic", s.channels.at(m.channel).topic},
                        {"sequence", m.sequence},
                        {"log_time", std::to_string(m.log_ns)},
                        {"publish_time", std::to_string(m.publish_ns)},
                        {"data", m.data}});
  nlohmann::json channels = nlohmann::json::object();
  for (const auto& [id, c] : s.channels)
    channels[c.topic] = {{"encoding", c.message_encoding},
                         {"schema", c.schema_id == 0 ? "" : s.schemas.at(c.schema_id).name},
                         {"schema_encoding", c.schema_id == 0 ? "" : s.schemas.at(c.schema_id).encoding},
                         {"metadata", c.metadata}};
  const nlohmann::json expected{{"profile", "ros2"},
                                {"channels", channels},
                                {"messages", messages},
                                {"metadata", {{"name", "run"}, {"values", {{"scene", "harbor"}, {"seed", "7"}}}}},
                                {"attachment", {{"name", "notes.txt"}, {"media_type", "text/plain"}, {"text", "hi"}}}};
  std::ofstream(std::string(out) + ".expected.json") << expected.dump(2) << "\n";
}
