// visit_messages: a front-to-back reader of any writer's MCAP file, for any topics and
// encodings (the writer is mcap_writer.cpp).
#include "replay/mcap/mcap_generic.hpp"

#include <functional>
#include <map>
#include <vector>

#include "replay/mcap/mcap_chunks.hpp"
#include "replay/mcap/mcap_format.hpp"
#include "replay/mcap/mapped_file.hpp"

namespace orthosonar::replay::mcap {
namespace {

// visit_messages: one pass over the records, front to back. Schema and Channel records
// are kept (a few per file); a chunk is decompressed into one reused buffer, its messages
// visited, and its file bytes released.
class Visitor {
 public:
  using OnChannel = std::function<Status(const RawChannel&, const RawSchema*)>;
  using OnMessage = std::function<Status(const RawMessage&)>;
  Visitor(const MappedFile& f, const OnChannel& on_channel, const OnMessage& on_message)
      : f_(f), path_(f.path()), on_channel_(on_channel), on_message_(on_message) {}

  Status run(RecoveryReport& report) {
    using namespace detail;
    report = {};
    report.bytes_total = f_.size();
    if (auto s = check_magic(f_); !s) return s;
    report.bytes_recovered = kMagicSize;
    const uint64_t footer_pos = trailing_footer(f_);
    uint64_t pos = kMagicSize;
    bool data_end = false, footer = false;
    while (!footer) {
      auto head = record_head(f_, pos, footer_pos);
      if (!head) return head.error();
      if (!head->cut.empty()) {
        cut(report, pos, head->cut);
        break;
      }
      const auto op = static_cast<Op>(head->op);
      const uint8_t* body = head->body;
      const uint64_t len = head->len, end = pos + kRecordPrefix + len;
      const Loc loc{0, pos};
      if (data_end && (op == Op::kMessage || op == Op::kChunk))
        return at(path_, pos, "Message or Chunk record in the summary section");
      Status s;
      switch (op) {
        case Op::kDataEnd:
          s = progress_.check_data_end(pos, body, len);
          data_end = true;
          break;
        case Op::kFooter: {
          footer = true;
          auto magic_cut = check_trailing_magic(f_, end);
          if (!magic_cut) return magic_cut.error();
          if (!magic_cut->empty()) cut(report, end, *magic_cut);
          break;
        }
        // The summary repeats the data section's schemas and channels: not needed.
        case Op::kSchema:
          if (!data_end) s = schema(loc, body, len);
          break;
        case Op::kChannel:
          if (!data_end) s = channel(loc, body, len);
          break;
        case Op::kMessage: s = message(loc, body, len); break;
        case Op::kChunk: s = chunk(pos, body, len); break;
        default: break;  // Header, Metadata, Attachment, indexes, Statistics, Summary Offsets
      }
      if (!s) return s;
      pos = end;
      report.bytes_recovered = pos;
      progress_.advance(pos, !data_end);
      if (op == Op::kChunk) f_.release(pos - kRecordPrefix - len, kRecordPrefix + len);
    }
    f_.release(0, f_.size());
    if (report.complete) report.bytes_recovered = f_.size();
    report.messages_recovered = messages_;
    return {};
  }

 private:
  void cut(RecoveryReport& report, uint64_t pos, const std::string& why) const {
    report.complete = false;
    report.detail = detail::cut_detail(f_, pos, why);
  }

  Status schema(detail::Loc loc, const uint8_t* body, uint64_t len) {
    RawSchema s;
    if (auto st = detail::parse_schema(path_, loc, body, len, s); !st) return st;
    auto [it, added] = schemas_.try_emplace(s.id, s);
    if (!added && (it->second.name != s.name || it->second.encoding != s.encoding || it->second.data != s.data))
      return detail::at(path_, loc, "schema id " + std::to_string(s.id) + " redefined (" + s.name + ", was " +
                                        it->second.name + ")");
    return {};
  }

  Status channel(detail::Loc loc, const uint8_t* body, uint64_t len) {
    RawChannel c;
    if (auto st = detail::parse_channel(path_, loc, body, len, c); !st) return st;
    if (c.schema_id != 0 && schemas_.find(c.schema_id) == schemas_.end())
      return detail::at(path_, loc, "channel " + c.topic + " uses undefined schema id " + std::to_string(c.schema_id));
    auto [it, added] = channels_.try_emplace(c.id, Known{c, false});
    const RawChannel& old = it->second.channel;
    if (!added && (old.topic != c.topic || old.schema_id != c.schema_id || old.message_encoding != c.message_encoding))
      return detail::at(path_, loc, "channel id " + std::to_string(c.id) + " redefined (topic " + c.topic + ", was " +
                                        old.topic + ")");
    return {};
  }

  // A Message record at `loc` (inside a chunk: loc.chunk is the chunk's file offset).
  Status message(detail::Loc loc, const uint8_t* body, uint64_t len) {
    RawMessage m;
    if (auto st = detail::parse_message(path_, loc, body, len, m); !st) return st;
    m.chunk_offset = loc.chunk;
    m.offset = loc.offset;
    const auto it = channels_.find(m.channel_id);
    if (it == channels_.end())
      return detail::at(path_, loc, "message on undefined channel id " + std::to_string(m.channel_id));
    if (!it->second.announced) {
      const RawChannel& c = it->second.channel;
      const auto s = schemas_.find(c.schema_id);
      if (auto st = on_channel_(c, s == schemas_.end() ? nullptr : &s->second); !st) return st;
      it->second.announced = true;
    }
    ++messages_;
    return on_message_(m);
  }

  Status chunk(uint64_t pos, const uint8_t* body, uint64_t len) {
    ChunkRef c;
    if (auto st = detail::parse_chunk(path_, pos, body, len, c); !st) return st;
    auto records = detail::chunk_records(f_, c, scratch_);
    if (!records) return records.error();
    return detail::for_each_record(path_, c, *records, [&](const detail::InnerRecord& rec, uint64_t at) -> Status {
      const detail::Loc loc{c.offset, at};
      switch (static_cast<Op>(rec.op)) {
        case Op::kSchema: return schema(loc, rec.body, rec.len);
        case Op::kChannel: return channel(loc, rec.body, rec.len);
        case Op::kMessage: return message(loc, rec.body, rec.len);
        default: return detail::at(path_, loc, "unexpected opcode " + detail::hex(rec.op) + " in a chunk");
      }
    });
  }

  struct Known {
    RawChannel channel;
    bool announced = false;  // on_channel called
  };

  const MappedFile& f_;
  const std::string& path_;
  const OnChannel& on_channel_;
  const OnMessage& on_message_;
  detail::Progress progress_{f_};
  std::map<uint16_t, RawSchema> schemas_;
  std::map<uint16_t, Known> channels_;
  std::vector<uint8_t> scratch_;  // one chunk's records
  uint64_t messages_ = 0;
};

}  // namespace
Status visit_messages(const std::string& path,
                      const std::function<Status(const RawChannel&, const RawSchema*)>& on_channel,
                      const std::function<Status(const RawMessage&)>& on_message, RecoveryReport* recovery) {
  auto file = MappedFile::open(path);
  if (!file) return file.error();
  RecoveryReport report;
  Visitor v(**file, on_channel, on_message);
  const Status s = v.run(report);
  if (recovery != nullptr) *recovery = report;
  return s;
}

}  // namespace orthosonar::replay::mcap
