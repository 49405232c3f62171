// Issue 40, part 4: a small simulated fixture (a 2 s reduced-resolution mission, two
// chunks, a 766 KB scene mesh attachment) cut at every 4 KiB boundary of the file (header,
// attachments, chunks, message indexes, summary) and at a few offsets in the header and
// the tail (summary, footer, closing magic), in-process through the functions the CLI
// uses: FixtureSource::open and its recovery (what `inspect` and every reader decide),
// cut_input_warning (the warning `replay` prints), recover_fixture (`recover`) and
// run_fixture (`replay`). At every cut:
//   - nothing throws; a file shorter than the magic is an error naming the file, any
//     longer one opens and is reported cut: recovered bytes between the end of the last
//     complete record before the cut and the cut, the warning naming the file and that
//     byte offset;
//   - the events read are exactly those of the complete chunks before the cut (a
//     subsequence of the whole file's events, of the expected count), and the stream ends
//     cleanly; the attachments are the complete ones before the cut;
//   - recover_fixture writes a whole file with the same events and attachments.
// The pipeline (run_fixture) sees only the recovered events and attachments, so it runs
// once per distinct recovered content (the first cut giving it): it returns a result with the cut warning
// (or an error naming the file), and the recovered file replays whole with the same digest.
// The CLI's exit codes and messages for cut inputs are checked end to end at a few offsets
// by drivers:record-under-faults (hal/drivers/record_faults_test.sh).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "replay/fixture/fixture.hpp"
#include "replay/fixture/mcap_reader.hpp"
#include "replay/fixture/recover.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/run.hpp"
#include "replay/fixture/testing.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using namespace orthosonar::replay::testing;

namespace {

uint64_t le64(const std::vector<uint8_t>& b, uint64_t at) {
  uint64_t v = 0;
  std::memcpy(&v, b.data() + at, sizeof v);  // MCAP is little-endian, as are our targets
  return v;
}

// Everything read from one fixture file, exceptions included (as text).
struct Opened {
  std::string error;  // FixtureSource::open's or next()'s error; empty when read to the end
  replay::RecoveryReport recovery;
  std::vector<Event> events;
  std::vector<replay::Attachment> attachments;
  bool opened = false;
};
Opened open_and_read(const std::string& path) {
  Opened o;
  auto src = replay::FixtureSource::open(path);
  if (!src.ok()) {
    o.error = src.error().message;
    return o;
  }
  o.opened = true;
  o.recovery = (*src)->recovery();
  o.attachments = (*src)->attachments();
  for (;;) {
    auto p = (*src)->next();
    if (p.error) {
      o.error = p.error->message;
      return o;
    }
    if (p.end_of_stream) return o;
    o.events.push_back(std::move(*p.event));
  }
}

bool is_subsequence(const std::vector<Event>& part, const std::vector<Event>& whole) {
  size_t j = 0;
  for (size_t i = 0; i < whole.size() && j < part.size(); ++i)
    if (whole[i] == part[j]) ++j;
  return j == part.size();
}

}  // namespace

TEST_CASE("a small fixture cut at every 4 KiB boundary opens and reports the cut and recovers whole with the same digest",
          "[unit][recover][cut]") {
  const fs::path dir = case_dir("cut_sweep", Catch::getResultCapture().getCurrentTestName(), true);
  const std::string whole_path = (dir / "small.mcap").string();
  run::MissionSpec spec;
  spec.scene = "marina1";
  spec.duration_s = 2.0;
  spec.resolution = sim::Resolution::kReduced;
  spec.seed = 1;
  spec.render_threads = 1;
  REQUIRE(run::ensure_mission_fixture(spec, whole_path).ok());
  const auto bytes = read_bytes(whole_path);
  const uint64_t size = bytes.size();
  REQUIRE(size > 100'000);

  // The whole file: complete, its events, and its layout read independently of the
  // recovery code: the top-level records (opcode, u64 length) and, per chunk, its
  // message count.
  const Opened whole = open_and_read(whole_path);
  REQUIRE(whole.error.empty());
  REQUIRE(whole.recovery.complete);
  REQUIRE_FALSE(replay::cut_input_warning(whole_path, whole.recovery).has_value());
  REQUIRE(whole.attachments.size() >= 2);
  std::vector<uint64_t> record_ends;  // end offset of every top-level record, in order
  std::map<uint64_t, uint64_t> messages_in_chunk_ending_at;
  std::map<uint64_t, size_t> attachments_ending_by;  // record end -> attachments complete by then
  {
    auto file = replay::mcap::MappedFile::open(whole_path);
    REQUIRE(file.ok());
    auto layout = replay::mcap::scan(**file);
    REQUIRE(layout.ok());
    REQUIRE(layout->chunks.size() >= 2);  // a cut between chunks recovers some messages
    std::vector<uint8_t> scratch;
    for (const auto& c : layout->chunks) {
      std::vector<replay::mcap::LocatedEvent> evs;
      REQUIRE(replay::mcap::read_chunk(**file, *layout, c, evs, scratch).ok());
      messages_in_chunk_ending_at[c.offset + 9 + le64(bytes, c.offset + 1)] = evs.size();
    }
    const uint64_t footer = size - 8 - 29;  // Footer record (opcode 0x02, 20 bytes) + magic
    REQUIRE(bytes[footer] == 0x02);
    size_t attachments = 0;
    for (uint64_t pos = 8; pos < size - 8;) {
      const uint64_t end = pos + 9 + le64(bytes, pos + 1);
      REQUIRE(end <= size - 8);
      if (bytes[pos] == 0x09) ++attachments;
      record_ends.push_back(end);
      attachments_ending_by[end] = attachments;
      pos = end;
    }
    REQUIRE(attachments == whole.attachments.size());
  }

  // Every 4 KiB boundary, and a few offsets 4 KiB steps would miss: in the magic, the
  // header and metadata, the data end, the summary, the footer and the closing magic.
  std::set<uint64_t> cuts;
  for (uint64_t off = 0; off < size; off += 4096) cuts.insert(off);
  const uint64_t summary_start = le64(bytes, size - 8 - 29 + 9);
  REQUIRE(summary_start > 0);
  REQUIRE(summary_start < size);
  for (uint64_t off : {uint64_t{5}, uint64_t{8}, uint64_t{20}, uint64_t{300}, summary_start - 1, summary_start,
                       summary_start + 1, summary_start + 200, size - 37, size - 30, size - 8, size - 1})
    cuts.insert(off);
  const uint64_t boundaries = (size + 4095) / 4096;

  const std::string cut_path = (dir / "cut.mcap").string();
  const std::string out_path = (dir / "recovered.mcap").string();
  // (events, attachments) recovered -> digest: what the pipeline sees (the events are
  // checked to be the expected ones, so their count names them).
  std::map<std::pair<size_t, size_t>, std::string> digest_of_prefix;
  size_t opened = 0, with_messages = 0, pipeline_runs = 0;
  for (const uint64_t off : cuts) {
    INFO("the fixture (" << size << " bytes) cut at byte offset " << off);
    write_bytes(cut_path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(off)));
    try {
      const Opened cut = open_and_read(cut_path);
      if (off < 8) {  // not even the magic: an error naming the file
        CHECK_FALSE(cut.opened);
        CHECK(cut.error.find(cut_path) != std::string::npos);
        auto r = replay::recover_fixture(cut_path, out_path);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().message.find(cut_path) != std::string::npos);
        CHECK_FALSE(fs::exists(out_path));
        continue;
      }
      INFO(cut.error);
      REQUIRE(cut.opened);
      CHECK(cut.error.empty());  // the recovered records read to a clean end
      ++opened;
      // What a reader must keep: every record complete before the cut, nothing beyond it.
      uint64_t last_end = 8;
      for (uint64_t e : record_ends)
        if (e <= off) last_end = e;
      uint64_t expect_messages = 0;
      for (const auto& [end, n] : messages_in_chunk_ending_at)
        if (end <= off) expect_messages += n;
      const auto ab = attachments_ending_by.upper_bound(off);
      const size_t expect_attachments = ab == attachments_ending_by.begin() ? 0 : std::prev(ab)->second;
      CHECK_FALSE(cut.recovery.complete);
      CHECK(cut.recovery.bytes_total == off);
      CHECK(cut.recovery.bytes_recovered >= last_end);
      CHECK(cut.recovery.bytes_recovered <= off);
      CHECK(cut.recovery.messages_recovered == expect_messages);
      CHECK(cut.events.size() == expect_messages);
      CHECK(is_subsequence(cut.events, whole.events));
      REQUIRE(cut.attachments.size() == expect_attachments);
      CHECK(std::equal(cut.attachments.begin(), cut.attachments.end(), whole.attachments.begin()));
      if (!cut.events.empty()) ++with_messages;
      const auto warning = replay::cut_input_warning(cut_path, cut.recovery);
      REQUIRE(warning.has_value());
      CHECK(warning->find(cut_path + ": input cut at byte offset " + std::to_string(cut.recovery.bytes_recovered) +
                          " of " + std::to_string(off) + " bytes") == 0);

      // `recover`: a whole file with the same events and attachments.
      auto r = replay::recover_fixture(cut_path, out_path);
      REQUIRE(r.ok());
      CHECK(r->events == cut.events.size());
      CHECK(r->attachments == cut.attachments.size());
      const Opened back = open_and_read(out_path);
      CHECK(back.error.empty());
      CHECK(back.recovery.complete);
      CHECK(back.events == cut.events);
      CHECK(back.attachments == cut.attachments);

      // `replay` (the pipeline), once per distinct recovered content.
      const std::pair<size_t, size_t> content{cut.events.size(), cut.attachments.size()};
      if (digest_of_prefix.count(content) != 0) continue;
      ++pipeline_runs;
      std::string cut_warning;
      auto run_cut = run::run_fixture(cut_path, run::RunOptions{}, {}, &cut_warning);
      if (!run_cut.ok()) {  // an error must name the file
        CHECK(run_cut.error().message.find(cut_path) != std::string::npos);
        digest_of_prefix[content] = "error";
        continue;
      }
      CHECK(cut_warning == *warning);
      CHECK(run_cut->input_recovery.bytes_recovered == cut.recovery.bytes_recovered);
      std::string whole_warning;
      auto run_back = run::run_fixture(out_path, run::RunOptions{}, {}, &whole_warning);
      REQUIRE(run_back.ok());
      CHECK(whole_warning.empty());
      CHECK(run_back->digest.overall_hex == run_cut->digest.overall_hex);
      digest_of_prefix[content] = run_cut->digest.overall_hex;
    } catch (const std::exception& e) {
      FAIL("an exception escaped: " << e.what());
    }
  }
  // The sweep reached every part of the file: cuts recovering no messages (in the header
  // and attachments), some (between chunks) and all (in the indexes and summary).
  CHECK(opened + 2 == cuts.size());  // all but the cuts at 0 and 5 bytes
  CHECK(cuts.size() >= boundaries);
  CHECK(with_messages > 0);
  CHECK(pipeline_runs >= 4);
  std::set<std::string> distinct_digests;
  for (const auto& [prefix, digest] : digest_of_prefix) distinct_digests.insert(digest);
  CHECK(distinct_digests.size() >= 3);
  WARN(cuts.size() << " cuts (" << boundaries << " at 4 KiB boundaries) of a " << size << "-byte fixture, "
                   << pipeline_runs << " pipeline runs");
}
