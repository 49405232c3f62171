#include "replay/fixture_summary.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>

#include "replay/mcap_format.hpp"
#include "replay/mcap_reader.hpp"
#include "replay/ros1_codec.hpp"

namespace orthosonar::replay {

bool has_mcap_magic(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  char head[5] = {};
  f.read(head, 5);
  return f.gcount() == 5 && std::memcmp(head, mcap::kMagic, 5) == 0;
}

Result<FixtureSummary> summarize_fixture(const std::string& path) {
  auto file = mcap::MappedFile::open(path);
  if (!file) return file.error();
  auto layout = mcap::scan(**file);
  if (!layout) return layout.error();
  FixtureSummary s;
  s.path = path;
  s.profile = layout->profile;
  s.library = layout->library;
  s.file_bytes = (*file)->size();
  s.read = layout->read;
  s.chunks = s.read.chunk_count;
  s.compressions = s.read.compressions;
  const auto channels = layout->channels;
  // One scan: the source replays the layout just read (a linear scan is not done twice).
  const auto src = mcap::make_source(std::move(file.value()), std::move(layout.value()));
  s.metadata = src->metadata();
  s.recovery = src->recovery();
  for (const auto& a : src->attachments()) s.attachments.push_back({a.name, a.media_type, a.data.size()});
  std::array<std::vector<Time>, kChannelCount> stamps;
  for (;;) {
    auto p = src->next();
    if (p.error) return *p.error;
    if (p.end_of_stream) break;
    stamps[static_cast<size_t>(p.event->channel)].push_back(p.event->stamp);
    if (s.messages == 0) s.start = p.event->stamp;
    s.end = p.event->stamp;
    ++s.messages;
  }
  for (int c = 0; c < kChannelCount; ++c) {
    const auto ch = static_cast<Channel>(c);
    const auto& t = stamps[static_cast<size_t>(c)];
    bool defined = false;
    for (const auto& [id, ref] : channels) defined = defined || ref.channel == ch;
    if (t.empty() && !defined) continue;
    ChannelSummary cs;
    cs.topic = channel_topic(ch);
    cs.schema = std::string(ros1::schema_for(ch).name);
    cs.count = t.size();
    if (!t.empty()) {
      cs.first = t.front();
      cs.last = t.back();
    }
    if (t.size() >= 2) {
      std::vector<Time> dt;
      for (size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
      std::vector<Time> sorted = dt;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<ptrdiff_t>((sorted.size() - 1) / 2), sorted.end());
      cs.nominal_period = sorted[(sorted.size() - 1) / 2];
      const Time span = cs.last - cs.first;
      if (span.ns() > 0) cs.rate_hz = static_cast<double>(t.size() - 1) / span.seconds();
      for (size_t i = 0; i < dt.size(); ++i)
        if (cs.nominal_period.ns() > 0 && dt[i] > cs.nominal_period * 2) cs.gaps.push_back({t[i], t[i + 1]});
    }
    s.channels.push_back(std::move(cs));
  }
  return s;
}

}  // namespace orthosonar::replay
