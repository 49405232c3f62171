#include "replay/ros/rosbag.hpp"

#include <catch2/catch.hpp>
#include <rapidcheck/catch.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <string_view>

#include "replay/fixture/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay::rosbag;
using orthosonar::replay::testing::case_dir;
using orthosonar::replay::testing::read_bytes;
using orthosonar::replay::testing::write_bytes;

namespace {

struct Msg {
  uint32_t conn = 0;
  uint64_t time_ns = 0;
  std::vector<uint8_t> data;
  uint64_t chunk_offset = 0;
  bool operator==(const Msg& o) const { return conn == o.conn && time_ns == o.time_ns && data == o.data; }
};
struct ReadBack {
  std::unique_ptr<BagReader> bag;
  std::vector<Msg> msgs;
  std::string error;  // of open or for_each
};
ReadBack read_bag(const std::string& path) {
  ReadBack rb;
  auto r = BagReader::open(path);
  if (!r) {
    rb.error = r.error().message;
    return rb;
  }
  rb.bag = std::move(r.value());
  auto s = rb.bag->for_each([&](const Connection& c, const MessageView& m) -> Status {
    if (c.id != m.conn) return Error{"connection passed does not match the message"};
    rb.msgs.push_back({m.conn, m.time_ns, std::vector<uint8_t>(m.data, m.data + m.size), m.chunk_offset});
    return {};
  });
  if (!s) rb.error = s.error().message;
  return rb;
}

struct Conn {
  std::string topic, type, md5sum, definition, callerid;
  bool latching = false;
};
Status write_bag(const std::string& path, const std::vector<Conn>& conns, const std::vector<Msg>& msgs,
                 const BagWriterOptions& o) {
  auto w = BagWriter::open(path, o);
  if (!w) return w.error();
  for (const auto& c : conns)
    if (auto id = (*w)->add_connection(c.topic, c.type, c.md5sum, c.definition, c.callerid, c.latching); !id) return id.error();
  for (const auto& m : msgs)
    if (auto s = (*w)->write(m.conn, m.time_ns, m.data.data(), m.data.size()); !s) return s;
  return (*w)->close();
}

uint32_t get32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v = 0;
  for (size_t i = 4; i-- > 0;) v = v << 8 | b.at(at + i);
  return v;
}
void put32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (size_t i = 0; i < 4; ++i) b.at(at + i) = static_cast<uint8_t>(v >> (8 * i));
}
// The offset of `field=` inside the header of the record at `rec`.
size_t field_at(const std::vector<uint8_t>& b, size_t rec, std::string_view field) {
  const auto begin = b.begin() + static_cast<long>(rec) + 4;
  const auto it = std::search(begin, begin + get32(b, rec), field.begin(), field.end());
  REQUIRE(it != begin + get32(b, rec));
  return static_cast<size_t>(it - b.begin()) + field.size();
}
constexpr size_t kBagHeaderAt = 13;  // after "#ROSBAG V2.0\n"
uint64_t index_pos(const std::vector<uint8_t>& b) {
  const size_t at = field_at(b, kBagHeaderAt, "index_pos=");
  return get32(b, at) | uint64_t{get32(b, at + 4)} << 32;
}
std::vector<uint64_t> chunk_offsets(const std::vector<Msg>& msgs) {
  std::vector<uint64_t> out;
  for (const auto& m : msgs)
    if (out.empty() || out.back() != m.chunk_offset) out.push_back(m.chunk_offset);
  return out;
}

// A hand-made bag: records from header fields and data.
using Fields = std::vector<std::pair<std::string, std::string>>;
std::string le32(uint32_t v) { return {static_cast<char>(v), static_cast<char>(v >> 8), static_cast<char>(v >> 16), static_cast<char>(v >> 24)}; }
std::string block(const Fields& f) {
  std::string s;
  for (const auto& [k, v] : f) s += le32(static_cast<uint32_t>(k.size() + 1 + v.size())) + k + "=" + v;
  return s;
}
std::string rec(const Fields& f, const std::string& data) {
  const std::string h = block(f);
  return le32(static_cast<uint32_t>(h.size())) + h + le32(static_cast<uint32_t>(data.size())) + data;
}
std::string unindexed_start() {
  return "#ROSBAG V2.0\n" + rec({{"index_pos", std::string(8, '\0')}, {"conn_count", le32(0)}, {"chunk_count", le32(0)},
                                 {"op", "\x03"}}, std::string(100, ' '));
}
std::string conn_rec(uint32_t id) {
  return rec({{"op", "\x07"}, {"conn", le32(id)}, {"topic", "/a"}},
             block({{"topic", "/a"}, {"type", "std_msgs/String"}, {"md5sum", "992ce8a1687cec8c8bd883ec73ca41d1"},
                    {"message_definition", "string data\n"}}));
}
void write_text(const std::string& path, const std::string& s) { write_bytes(path, std::vector<uint8_t>(s.begin(), s.end())); }

const std::vector<std::string> kCompressions = {"none", "bz2", "lz4"};

// Three connections and `n` messages of a few hundred bytes, in chunks of ~2 KB.
std::vector<Conn> some_conns() {
  return {{"/imu", "sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2", "Header header\n=\nline", "/recorder", true},
          {"/ping", "orthosonar_msgs/Ping", std::string(32, 'a'), "uint8[] data\nstring note\n", "", false},
          {"/odd", "x/Y", std::string(32, 'b'), "", "", true}};
}
std::vector<Msg> some_msgs(size_t n) {
  std::vector<Msg> msgs;
  for (size_t i = 0; i < n; ++i) {
    Msg m{static_cast<uint32_t>(i % 3), 1'700'000'000'000'000'000ull + i * 10'000'000ull, {}, 0};
    m.data.resize(100 + (i * 37) % 300);
    for (size_t j = 0; j < m.data.size(); ++j) m.data[j] = static_cast<uint8_t>(i * 7 + j / 16);
    msgs.push_back(std::move(m));
  }
  return msgs;
}

}  // namespace

TEST_CASE("rosbag: random messages round trip through writer and reader, indexed and by scan", "[unit][rapidcheck]") {
  const auto dir = case_dir("rosbag", "round_trip", true);
  rc::prop("write, read by index, by scan (index_pos 0) and with the index cut off", [&] {
    const std::string compression = *rc::gen::elementOf(kCompressions);
    const auto nconn = *rc::gen::inRange<size_t>(1, 5);
    std::vector<Conn> conns;
    auto text = rc::gen::container<std::string>(rc::gen::elementOf(std::string("ab=\n #/_9")));
    for (size_t i = 0; i < nconn; ++i)
      conns.push_back({"/topic" + std::to_string(i), "pkg/T" + std::to_string(i), std::string(32, static_cast<char>('0' + i)),
                       *text, *rc::gen::oneOf(rc::gen::just(std::string()), text), *rc::gen::arbitrary<bool>()});
    const auto n = *rc::gen::inRange<size_t>(0, 60);
    std::vector<Msg> msgs;
    for (size_t i = 0; i < n; ++i) {
      Msg m;
      m.conn = static_cast<uint32_t>(*rc::gen::inRange<size_t>(0, nconn));
      m.time_ns = *rc::gen::inRange<uint64_t>(0, 4'294'967'296'000'000'000ull);
      m.data = *rc::gen::resize(600, rc::gen::container<std::vector<uint8_t>>(rc::gen::inRange<uint8_t>(0, 4)));
      msgs.push_back(std::move(m));
    }
    BagWriterOptions o;
    o.compression = compression;
    o.chunk_threshold = *rc::gen::inRange<uint64_t>(0, 3000);
    const std::string path = (dir / "bag.bag").string();
    RC_ASSERT(write_bag(path, conns, msgs, o).ok());

    auto rb = read_bag(path);
    RC_ASSERT(rb.error.empty());
    const BagInfo& info = rb.bag->info();
    RC_ASSERT(info.indexed);
    RC_ASSERT(info.complete);
    RC_ASSERT(info.message_count == n);
    RC_ASSERT(rb.msgs == msgs);
    RC_ASSERT(info.chunk_count == chunk_offsets(rb.msgs).size());
    RC_ASSERT(info.compressions == (n == 0 ? std::vector<std::string>{} : std::vector<std::string>{compression}));
    if (n > 0) {
      auto [lo, hi] = std::minmax_element(msgs.begin(), msgs.end(), [](auto& a, auto& b) { return a.time_ns < b.time_ns; });
      RC_ASSERT(info.start_ns == lo->time_ns);
      RC_ASSERT(info.end_ns == hi->time_ns);
    }
    const auto& got = rb.bag->connections();
    RC_ASSERT(got.size() == nconn);
    for (size_t i = 0; i < nconn; ++i) {
      RC_ASSERT(got[i].id == i);
      RC_ASSERT(got[i].topic == conns[i].topic);
      RC_ASSERT(got[i].type == conns[i].type);
      RC_ASSERT(got[i].md5sum == conns[i].md5sum);
      RC_ASSERT(got[i].message_definition == conns[i].definition);
      RC_ASSERT(got[i].callerid == conns[i].callerid);
      RC_ASSERT(got[i].latching == conns[i].latching);
    }

    // As a recorder killed before closing leaves it: index_pos 0, the index still there.
    auto bytes = read_bytes(path);
    const uint64_t ipos = index_pos(bytes);
    put32(bytes, field_at(bytes, kBagHeaderAt, "index_pos="), 0);
    put32(bytes, field_at(bytes, kBagHeaderAt, "index_pos=") + 4, 0);
    write_bytes(path, bytes);
    auto scanned = read_bag(path);
    RC_ASSERT(scanned.error.empty());
    RC_ASSERT(!scanned.bag->info().indexed);
    RC_ASSERT(scanned.bag->info().complete);
    RC_ASSERT(scanned.bag->info().message_count == n);
    RC_ASSERT(scanned.msgs == msgs);
    // The index section's connection records are still there, read as records after the chunks.
    RC_ASSERT(scanned.bag->connections().size() == nconn);

    // A copy that stopped at the index section: the header points past the end.
    auto cut = read_bytes(path);
    cut.resize(ipos);
    put32(cut, field_at(cut, kBagHeaderAt, "index_pos="), static_cast<uint32_t>(ipos));
    write_bytes(path, cut);
    auto no_index = read_bag(path);
    RC_ASSERT(no_index.error.empty());
    RC_ASSERT(!no_index.bag->info().indexed);
    RC_ASSERT(no_index.msgs == msgs);
    RC_ASSERT(no_index.bag->info().detail.find("unusable") != std::string::npos);
    std::set<uint32_t> used;  // now only the connections found inside chunks
    for (const auto& m : msgs) used.insert(m.conn);
    RC_ASSERT(no_index.bag->connections().size() == used.size());
    for (const auto& c : no_index.bag->connections()) RC_ASSERT(c.md5sum == conns[c.id].md5sum);
  });
}

TEST_CASE("rosbag: the writer's bytes are a pure function of its calls, and laid out as rosbag's", "[unit]") {
  const auto dir = case_dir("rosbag", "deterministic", true);
  for (const auto& c : kCompressions) {
    BagWriterOptions o{c, 2048};
    REQUIRE(write_bag((dir / "a.bag").string(), some_conns(), some_msgs(50), o).ok());
    REQUIRE(write_bag((dir / "b.bag").string(), some_conns(), some_msgs(50), o).ok());
    const auto a = read_bytes((dir / "a.bag").string());
    CHECK(a == read_bytes((dir / "b.bag").string()));
    // Version line, a bag header record of 4 + 4096 + 4 bytes, then the first chunk.
    CHECK(std::string(a.begin(), a.begin() + 13) == "#ROSBAG V2.0\n");
    CHECK(get32(a, 13) + get32(a, 17 + get32(a, 13)) == 4096);
    auto rb = read_bag((dir / "a.bag").string());
    REQUIRE(rb.error.empty());
    CHECK(chunk_offsets(rb.msgs).front() == 13 + 4104);
    CHECK(rb.bag->info().chunk_count > 3);
  }
}

TEST_CASE("rosbag: a bag cut inside a chunk keeps the chunks before it", "[unit]") {
  const auto dir = case_dir("rosbag", "truncated", true);
  for (const auto& c : kCompressions) {
    const std::string path = (dir / ("full_" + c + ".bag")).string();
    const auto msgs = some_msgs(60);
    REQUIRE(write_bag(path, some_conns(), msgs, {c, 2048}).ok());
    const auto full = read_bag(path);
    REQUIRE(full.error.empty());
    const auto chunks = chunk_offsets(full.msgs);
    REQUIRE(chunks.size() > 3);
    auto bytes = read_bytes(path);
    bytes.resize(chunks[2] + 40);
    const std::string cut = (dir / ("cut_" + c + ".bag")).string();
    write_bytes(cut, bytes);
    const auto rb = read_bag(cut);
    REQUIRE(rb.error.empty());
    const BagInfo& info = rb.bag->info();
    CHECK_FALSE(info.complete);
    CHECK_FALSE(info.indexed);
    CHECK(info.bytes_recovered == chunks[2]);
    CHECK(info.detail.find("byte offset " + std::to_string(chunks[2])) != std::string::npos);
    CHECK(info.chunk_count == 2);
    size_t kept = 0;
    while (kept < full.msgs.size() && full.msgs[kept].chunk_offset < chunks[2]) ++kept;
    CHECK(info.message_count == kept);
    CHECK(rb.msgs == std::vector<Msg>(msgs.begin(), msgs.begin() + static_cast<long>(kept)));
  }
}

TEST_CASE("rosbag: a recorder killed inside a chunk leaves its sizes at 0", "[unit]") {
  const auto dir = case_dir("rosbag", "unterminated", true);
  for (const auto& c : kCompressions) {
    const std::string path = (dir / ("full_" + c + ".bag")).string();
    const auto msgs = some_msgs(60);
    REQUIRE(write_bag(path, some_conns(), msgs, {c, 2048}).ok());
    const auto full = read_bag(path);
    const auto chunks = chunk_offsets(full.msgs);
    auto bytes = read_bytes(path);
    // The header as rosbag wrote it when opening the third chunk, and the file cut in it.
    for (size_t i = 0; i < 8; ++i) bytes[field_at(bytes, kBagHeaderAt, "index_pos=") + i] = 0;
    put32(bytes, field_at(bytes, chunks[2], "size="), 0);
    put32(bytes, chunks[2] + 4 + get32(bytes, chunks[2]), 0);
    bytes.resize(chunks[3] - 100);
    const std::string cut = (dir / ("killed_" + c + ".bag")).string();
    write_bytes(cut, bytes);
    const auto rb = read_bag(cut);
    REQUIRE(rb.error.empty());
    CHECK_FALSE(rb.bag->info().complete);
    size_t kept = 0;
    while (kept < full.msgs.size() && full.msgs[kept].chunk_offset < chunks[2]) ++kept;
    if (c == "none") {
      // The open chunk's records follow its header and are read as records outside chunks.
      REQUIRE(rb.msgs.size() > kept);
      CHECK(rb.msgs.back().chunk_offset == 0);
      CHECK(rb.bag->info().detail.find("unterminated uncompressed chunk at byte offset " + std::to_string(chunks[2])) !=
            std::string::npos);
    } else {
      CHECK(rb.bag->info().detail.find("unterminated " + c + " chunk at byte offset " + std::to_string(chunks[2])) !=
            std::string::npos);
      REQUIRE(rb.msgs.size() == kept);
    }
    CHECK(std::equal(rb.msgs.begin(), rb.msgs.end(), msgs.begin()));
  }
}

TEST_CASE("rosbag: corrupt chunks are errors naming the file and the chunk's offset", "[unit]") {
  const auto dir = case_dir("rosbag", "corrupt", true);
  for (const auto& c : kCompressions) {
    const std::string path = (dir / ("full_" + c + ".bag")).string();
    REQUIRE(write_bag(path, some_conns(), some_msgs(60), {c, 2048}).ok());
    const auto chunks = chunk_offsets(read_bag(path).msgs);
    const auto good = read_bytes(path);
    const std::string where = "byte offset " + std::to_string(chunks[1]);
    auto expect_error = [&](const std::vector<uint8_t>& bytes, const std::string& what) {
      INFO(c << ": " << what);
      const std::string bad = (dir / ("bad_" + c + ".bag")).string();
      write_bytes(bad, bytes);
      const auto rb = read_bag(bad);  // indexed: open works, the visit fails at the chunk
      CHECK_THAT(rb.error, Catch::Contains(bad) && Catch::Contains(where) && Catch::Contains(what));
      auto scan = bytes;  // by a scan: open itself fails
      for (size_t i = 0; i < 8; ++i) scan[field_at(scan, kBagHeaderAt, "index_pos=") + i] = 0;
      write_bytes(bad, scan);
      const auto r = BagReader::open(bad);
      REQUIRE_FALSE(r.ok());
      CHECK_THAT(r.error().message, Catch::Contains(where) && Catch::Contains(what));
    };
    const size_t data_at = chunks[1] + 8 + get32(good, chunks[1]);
    auto bytes = good;
    if (c == "none") {
      put32(bytes, data_at, 0x7fffffff);  // the header length of the chunk's first record
      expect_error(bytes, "runs past the end of its chunk");
    } else {
      for (size_t i = 40; i < 60; ++i) bytes[data_at + i] ^= 0x5a;
      expect_error(bytes, c + " chunk");
    }
    bytes = good;  // the stated uncompressed size
    put32(bytes, field_at(bytes, chunks[1], "size="), get32(bytes, field_at(bytes, chunks[1], "size=")) + 1);
    expect_error(bytes, c == "none" ? "states" : "bytes");
    bytes = good;
    put32(bytes, field_at(bytes, chunks[1], "size="), 0x7fffffff);
    expect_error(bytes, "more than 1 GiB");
  }
}

TEST_CASE("rosbag: a message for a connection never defined is an error", "[unit]") {
  const auto dir = case_dir("rosbag", "undefined_conn", true);
  const std::string path = (dir / "bag.bag").string();
  REQUIRE(write_bag(path, some_conns(), some_msgs(10), {"none", 1 << 20}).ok());
  auto bytes = read_bytes(path);
  // The last message record's "conn" field (fields conn, op, time).
  const std::string pattern = std::string("\x04\0\0\0op=\x02", 8);
  const auto it = std::find_end(bytes.begin(), bytes.end(), pattern.begin(), pattern.end());
  REQUIRE(it != bytes.end());
  put32(bytes, static_cast<size_t>(it - bytes.begin()) - 4, 99);
  write_bytes(path, bytes);
  const auto rb = read_bag(path);
  CHECK_THAT(rb.error, Catch::Contains("message for connection 99") && Catch::Contains("inside the chunk at byte offset 4117"));
}

TEST_CASE("rosbag: hand-made bags: messages outside chunks, bad fields, not a bag", "[unit]") {
  const auto dir = case_dir("rosbag", "hand_made", true);
  const std::string path = (dir / "bag.bag").string();
  const std::string msg = rec({{"op", "\x02"}, {"conn", le32(5)}, {"time", le32(7) + le32(9)}}, std::string("\x02\0\0\0hi", 6));

  write_text(path, unindexed_start() + conn_rec(5) + msg + msg);
  auto rb = read_bag(path);
  REQUIRE(rb.error.empty());
  REQUIRE(rb.msgs.size() == 2);
  CHECK(rb.msgs[0].time_ns == 7'000'000'009);
  CHECK(rb.msgs[0].chunk_offset == 0);
  CHECK(rb.bag->info().complete);
  CHECK(rb.bag->info().message_count == 2);
  REQUIRE(rb.bag->connections().size() == 1);
  CHECK(rb.bag->connections()[0].type == "std_msgs/String");
  CHECK(rb.bag->connections()[0].message_definition == "string data\n");

  const size_t bad_at = unindexed_start().size() + conn_rec(5).size();
  write_text(path, unindexed_start() + conn_rec(5) + rec({{"op", "\x02"}, {"conn", "abc"}, {"time", std::string(8, '\0')}}, ""));
  rb = read_bag(path);
  CHECK_THAT(rb.error, Catch::Contains("field 'conn' has 3 bytes, not 4") &&
                           Catch::Contains("at byte offset " + std::to_string(bad_at)));

  write_text(path, unindexed_start() + msg);
  CHECK_THAT(read_bag(path).error, Catch::Contains("no connection record before it"));

  write_text(path, unindexed_start() + conn_rec(5) + msg + msg.substr(0, 20));  // cut inside a record
  rb = read_bag(path);
  REQUIRE(rb.error.empty());
  CHECK(rb.msgs.size() == 1);
  CHECK_FALSE(rb.bag->info().complete);
  CHECK(rb.bag->info().bytes_recovered == bad_at + msg.size());

  write_text(path, "");
  CHECK_THAT(read_bag(path).error, Catch::Contains("not a ROS bag"));
  write_text(path, "#ROSBAG V1.2\n" + std::string(100, 'x'));
  CHECK_THAT(read_bag(path).error, Catch::Contains("unsupported bag version"));
  write_text(path, "#ROSBAG V2.0\n\xff\xff\xff\x7f garbage");
  CHECK_THAT(read_bag(path).error, Catch::Contains("bag header record runs past the end"));
  write_text(path, unindexed_start() + rec({{"op", "\x01"}}, ""));
  CHECK_THAT(read_bag(path).error, Catch::Contains("unexpected record with op 1"));
  write_text(path, "#ROSBAG V2.0\n" + rec({{"op", "\x05"}}, ""));
  CHECK_THAT(read_bag(path).error, Catch::Contains("not a bag header"));
  CHECK_THAT(read_bag((dir / "missing.bag").string()).error, Catch::Contains("missing.bag"));
}

TEST_CASE("rosbag: connection fields survive both index and scan", "[unit]") {
  const auto dir = case_dir("rosbag", "connections", true);
  const std::string path = (dir / "bag.bag").string();
  const auto conns = some_conns();
  REQUIRE(write_bag(path, conns, some_msgs(3), {"lz4", 768 * 1024}).ok());
  for (int pass = 0; pass < 2; ++pass) {
    const auto rb = read_bag(path);
    REQUIRE(rb.error.empty());
    CHECK(rb.bag->info().indexed == (pass == 0));
    REQUIRE(rb.bag->connections().size() == 3);
    for (size_t i = 0; i < 3; ++i) {
      const Connection& k = rb.bag->connections()[i];
      CHECK(k.topic == conns[i].topic);
      CHECK(k.type == conns[i].type);
      CHECK(k.md5sum == conns[i].md5sum);
      CHECK(k.message_definition == conns[i].definition);
      CHECK(k.callerid == conns[i].callerid);
      CHECK(k.latching == conns[i].latching);
    }
    auto bytes = read_bytes(path);
    for (size_t i = 0; i < 8; ++i) bytes[field_at(bytes, kBagHeaderAt, "index_pos=") + i] = 0;
    write_bytes(path, bytes);
  }
}

TEST_CASE("rosbag: writer rejects what a bag cannot hold", "[unit]") {
  const auto dir = case_dir("rosbag", "writer_errors", true);
  CHECK_FALSE(BagWriter::open((dir / "x.bag").string(), {"zstd", 1}).ok());
  CHECK_FALSE(BagWriter::open((dir / "no/such/dir.bag").string()).ok());
  auto w = BagWriter::open((dir / "x.bag").string());
  REQUIRE(w.ok());
  const uint8_t b = 0;
  CHECK_FALSE((*w)->write(0, 0, &b, 1).ok());  // no such connection
  REQUIRE((*w)->add_connection("/a", "a/A", std::string(32, '0'), "").ok());
  CHECK_FALSE((*w)->write(0, 5'000'000'000'000'000'000ull, &b, 1).ok());  // past ROS time (uint32 seconds)
  CHECK((*w)->write(0, 1, &b, 1).ok());
  CHECK((*w)->close().ok());
  CHECK_FALSE((*w)->write(0, 1, &b, 1).ok());
}
