// FixtureSource: replays a fixture in (stamp, channel, sequence) order (SPEC §9),
// whatever order the events were recorded in. Chunks are decoded lazily: a chunk is
// opened once the earliest pending event is not before the chunk's start time, so only
// the chunks overlapping the current stream time are held in memory; runs of messages
// outside chunks are read the same way, and a chunk's file bytes are released from the
// process once it is decoded. Memory is bounded by the chunks in use, not the file.
#include <algorithm>
#include <array>
#include <numeric>

#include "replay/fixture.hpp"
#include "replay/mcap_reader.hpp"

namespace orthosonar::replay {
namespace {

using mcap::LocatedEvent;

// Heap order: the earliest event on top; identical keys (a malformed file) by position.
bool later(const LocatedEvent& a, const LocatedEvent& b) {
  if (event_before(b.event, a.event)) return true;
  if (event_before(a.event, b.event)) return false;
  if (a.chunk_offset != b.chunk_offset) return a.chunk_offset > b.chunk_offset;
  return a.offset > b.offset;
}

class McapSource final : public FixtureSource {
 public:
  McapSource(std::unique_ptr<mcap::MappedFile> file, mcap::Layout layout)
      : file_(std::move(file)), layout_(std::move(layout)) {
    // Chunks and runs of loose messages alike are read when the stream reaches them.
    for (const auto& c : layout_.chunks) order_.push_back(&c);
    for (const auto& c : layout_.loose_runs) order_.push_back(&c);
    std::stable_sort(order_.begin(), order_.end(), [](const mcap::ChunkRef* a, const mcap::ChunkRef* b) {
      return a->start_ns < b->start_ns;
    });
  }

  const FixtureMetadata& metadata() const override { return layout_.metadata; }
  const RecoveryReport& recovery() const override { return layout_.recovery; }
  const std::vector<Attachment>& attachments() const override { return layout_.attachments; }
  std::string describe() const override { return "fixture:" + file_->path(); }
  Holding holding() const override { return holding_; }

  hal::Pulled next() override {
    if (error_) return hal::Pulled::fail(*error_);
    while (next_chunk_ < order_.size()) {
      const auto& c = *order_[next_chunk_];
      if (!heap_.empty() && static_cast<uint64_t>(heap_.front().event.stamp.ns()) < c.start_ns) break;
      const size_t before = heap_.size();
      if (auto s = mcap::read_chunk(*file_, layout_, c, heap_, scratch_); !s) return fail(s.error());
      for (size_t i = before; i < heap_.size(); ++i) std::push_heap(heap_.begin(), heap_.begin() + static_cast<ptrdiff_t>(i) + 1, later);
      ++next_chunk_;
      ++holding_.chunks_read;
      holding_.peak_events = std::max(holding_.peak_events, heap_.size());
    }
    if (heap_.empty()) return hal::Pulled::end();
    std::pop_heap(heap_.begin(), heap_.end(), later);
    LocatedEvent e = std::move(heap_.back());
    heap_.pop_back();
    holding_.events = heap_.size();
    // Within a channel, yielding in stamp order must also be sequence order; otherwise
    // the recording has stamps going backwards while sequences go forwards.
    auto& last = last_[static_cast<size_t>(e.event.channel)];
    if (last && last->event.sequence >= e.event.sequence) {
      return fail(Error{file_->path() + ": out-of-order stamps on " + channel_topic(e.event.channel) +
                        ": sequence " + std::to_string(e.event.sequence) + " (stamp " +
                        std::to_string(e.event.stamp.ns()) + " ns, " + mcap::describe_location(e) +
                        ") is not after sequence " + std::to_string(last->event.sequence) + " (stamp " +
                        std::to_string(last->event.stamp.ns()) + " ns, " + mcap::describe_location(*last) + ")"});
    }
    last = LocatedEvent{Event{e.event.stamp, e.event.channel, e.event.sequence, {}}, e.chunk_offset, e.offset};
    return hal::Pulled::of(std::move(e.event));
  }

 private:
  hal::Pulled fail(Error e) {
    error_ = e;
    heap_.clear();
    holding_.events = 0;
    return hal::Pulled::fail(std::move(e));
  }

  std::unique_ptr<mcap::MappedFile> file_;
  mcap::Layout layout_;
  std::vector<const mcap::ChunkRef*> order_;  // chunks and loose runs by start time
  size_t next_chunk_ = 0;
  Holding holding_;
  std::vector<LocatedEvent> heap_;
  std::vector<uint8_t> scratch_;
  std::array<std::optional<LocatedEvent>, kChannelCount> last_{};
  std::optional<Error> error_;
};

}  // namespace

Result<std::unique_ptr<FixtureSource>> FixtureSource::open(const std::string& path) {
  auto file = mcap::MappedFile::open(path);
  if (!file) return file.error();
  auto layout = mcap::scan(**file);
  if (!layout) return layout.error();
  return mcap::make_source(std::move(file.value()), std::move(layout.value()));
}

namespace mcap {

std::unique_ptr<FixtureSource> make_source(std::unique_ptr<MappedFile> file, Layout layout) {
  return std::make_unique<McapSource>(std::move(file), std::move(layout));
}

}  // namespace mcap
}  // namespace orthosonar::replay
