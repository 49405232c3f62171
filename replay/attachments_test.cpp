// MCAP attachments (fixtures embed their scene this way): written with CRCs and an
// Attachment Index, read back exactly, corruption reported with the file and byte offset.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;

namespace {

std::vector<Event> events() {
  SyntheticOptions so;
  so.duration_ns = 500'000'000;
  return synthetic_events(9, so);
}

std::vector<Attachment> sample_attachments() {
  std::vector<uint8_t> big(200'000);
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<uint8_t>((i * 2654435761u) >> 24);
  const std::string yaml = "name: \"x\"\nroute:\n  - [1, 2]\n";
  return {{"orthosonar_scene.yaml", "application/yaml", std::vector<uint8_t>(yaml.begin(), yaml.end()), 0, 0},
          {"orthosonar_scene.ply", "application/x-ply", big, 5, 0},
          {"empty.bin", "application/octet-stream", {}, 0, 0}};
}

Status write_with_attachments(const std::string& path, const std::vector<Attachment>& atts) {
  WriterOptions o;
  o.chunk_max_stream_ns = 100'000'000;
  auto w = FixtureWriter::open(path, {{"scene", "x"}}, o);
  if (!w) return w.error();
  for (const auto& a : atts)
    if (auto s = (*w)->attach(a); !s) return s;
  for (const auto& e : events())
    if (auto s = (*w)->write(e); !s) return s;
  return (*w)->close();
}

// File offset of the Attachment record whose name is `name` (searched for in the bytes).
size_t attachment_offset(const std::vector<uint8_t>& b, const std::string& name) {
  const auto it = std::search(b.begin(), b.end(), name.begin(), name.end());
  REQUIRE(it != b.end());
  // opcode (1) + length (8) + log_time (8) + create_time (8) + name length (4)
  return static_cast<size_t>(it - b.begin()) - 29;
}

uint64_t le64(const std::vector<uint8_t>& b, size_t at) {
  uint64_t v = 0;
  for (size_t i = 0; i < 8; ++i) v |= static_cast<uint64_t>(b[at + i]) << (8 * i);
  return v;
}

// The footer's summary_start.
size_t summary_start(const std::vector<uint8_t>& b) { return static_cast<size_t>(le64(b, b.size() - 8 - 29 + 9)); }

// The group opcodes the Summary Offset records list.
std::vector<uint8_t> summary_groups(const std::vector<uint8_t>& b) {
  const size_t footer = b.size() - 8 - 29;
  std::vector<uint8_t> ops;
  for (size_t at = static_cast<size_t>(le64(b, footer + 17)); at + 26 <= footer; at += 26) {
    REQUIRE(b[at] == static_cast<uint8_t>(mcap::Op::kSummaryOffset));
    ops.push_back(b[at + 9]);
  }
  return ops;
}

}  // namespace

TEST_CASE("attachments: written, indexed and read back exactly", "[replay][attachments]") {
  const auto dir = test_dir("attachments_roundtrip");
  const auto path = dir + "/a.mcap";
  const auto atts = sample_attachments();
  REQUIRE(write_with_attachments(path, atts).ok());
  auto src = FixtureSource::open(path);
  REQUIRE(src.ok());
  CHECK((*src)->attachments() == atts);
  CHECK((*src)->metadata().at("scene") == "x");
  REQUIRE(find_attachment((*src)->attachments(), "orthosonar_scene.ply") != nullptr);
  CHECK(find_attachment((*src)->attachments(), "orthosonar_scene.ply")->log_time_ns == 5);
  CHECK(find_attachment((*src)->attachments(), "nope") == nullptr);
  const auto files = attachment_files((*src)->attachments());
  CHECK(files.size() == 3);
  CHECK(files.at("orthosonar_scene.ply") == atts[1].data);
  // The events are unaffected.
  const auto back = read_fixture(path);
  CHECK(back.error.empty());
  CHECK(back.events.size() == events().size());

  const auto bytes = read_bytes(path);
  // Each Attachment record: the layout of the MCAP spec, CRC over every preceding field.
  const size_t at = attachment_offset(bytes, "orthosonar_scene.ply");
  CHECK(bytes[at] == static_cast<uint8_t>(mcap::Op::kAttachment));
  // The summary lists them (an Attachment Index group).
  const auto groups = summary_groups(bytes);
  CHECK(std::count(groups.begin(), groups.end(), static_cast<uint8_t>(mcap::Op::kAttachmentIndex)) == 1);

  // Deterministic bytes: the same input gives the same file.
  const auto path2 = dir + "/b.mcap";
  REQUIRE(write_with_attachments(path2, atts).ok());
  CHECK(read_bytes(path2) == bytes);
}

TEST_CASE("attachments: a fixture without them reads as before", "[replay][attachments]") {
  const auto dir = test_dir("attachments_none");
  const auto path = dir + "/old.mcap";
  REQUIRE(write_fixture(path, events(), {{"scene", "x"}}).ok());
  auto src = FixtureSource::open(path);
  REQUIRE(src.ok());
  CHECK((*src)->attachments().empty());
  // No Attachment Index group in the summary of such a file (its bytes are as before).
  const auto groups = summary_groups(read_bytes(path));
  CHECK(!groups.empty());
  CHECK(std::count(groups.begin(), groups.end(), static_cast<uint8_t>(mcap::Op::kAttachmentIndex)) == 0);
}

TEST_CASE("attachments: corruption is named with the file and byte offset", "[replay][attachments]") {
  const auto dir = test_dir("attachments_corrupt");
  const auto path = dir + "/good.mcap";
  REQUIRE(write_with_attachments(path, sample_attachments()).ok());
  const auto good = read_bytes(path);
  const size_t at = attachment_offset(good, "orthosonar_scene.ply");

  SECTION("a flipped data byte fails the attachment CRC") {
    auto bad = good;
    bad[at + 29 + std::strlen("orthosonar_scene.ply") + 4 + std::strlen("application/x-ply") + 8 + 1000] ^= 0x40;
    const auto p = dir + "/flipped.mcap";
    write_bytes(p, bad);
    auto src = FixtureSource::open(p);
    REQUIRE_FALSE(src.ok());
    const auto& msg = src.error().message;
    CHECK(msg.find(p) != std::string::npos);
    CHECK(msg.find("attachment 'orthosonar_scene.ply' CRC mismatch") != std::string::npos);
    CHECK(msg.find("at byte offset " + std::to_string(at)) != std::string::npos);
  }
  SECTION("a data length beyond the record is refused before anything is allocated") {
    auto bad = good;
    const size_t len_at = at + 29 + std::strlen("orthosonar_scene.ply") + 4 + std::strlen("application/x-ply");
    for (int i = 0; i < 8; ++i) bad[len_at + static_cast<size_t>(i)] = i == 5 ? 0x01 : 0x00;  // 2^40 bytes
    const auto p = dir + "/huge.mcap";
    write_bytes(p, bad);
    auto src = FixtureSource::open(p);
    REQUIRE_FALSE(src.ok());
    CHECK(src.error().message.find("attachment 'orthosonar_scene.ply' claims") != std::string::npos);
    CHECK(src.error().message.find("at byte offset " + std::to_string(at)) != std::string::npos);
  }
  SECTION("a zero CRC means unchecked (MCAP spec)") {
    auto bad = good;
    const size_t rec_len = static_cast<size_t>(good[at + 1]) | static_cast<size_t>(good[at + 2]) << 8 |
                           static_cast<size_t>(good[at + 3]) << 16;
    const size_t crc_at = at + 9 + rec_len - 4;
    for (size_t i = 0; i < 4; ++i) bad[crc_at + i] = 0;
    // The data section CRC covers the record too: clear it (0 = not available).
    const size_t data_end_crc = summary_start(bad) - 4;
    for (size_t i = 0; i < 4; ++i) bad[data_end_crc + i] = 0;
    const auto p = dir + "/nocrc.mcap";
    write_bytes(p, bad);
    auto src = FixtureSource::open(p);
    REQUIRE(src.ok());
    CHECK((*src)->attachments().size() == 3);
  }
  SECTION("a truncated recording keeps the attachments written before the cut") {
    auto cut = good;
    cut.resize(summary_start(good) - 13 - 40);  // inside the last chunk's message index
    const auto p = dir + "/cut.mcap";
    write_bytes(p, cut);
    auto src = FixtureSource::open(p);
    REQUIRE(src.ok());
    CHECK_FALSE((*src)->recovery().complete);
    CHECK((*src)->attachments() == sample_attachments());
  }
}

TEST_CASE("attachments: the writer refuses what it cannot store", "[replay][attachments]") {
  const auto dir = test_dir("attachments_reject");
  auto w = FixtureWriter::open(dir + "/r.mcap", {});
  REQUIRE(w.ok());
  auto s = (*w)->attach({"", "text/plain", {1, 2}, 0, 0});
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find(dir + "/r.mcap") != std::string::npos);
  REQUIRE((*w)->close().ok());
  CHECK_FALSE((*w)->attach({"late", "text/plain", {}, 0, 0}).ok());
}
