// `orthosonar import` (import.hpp), the driver: channels resolved against the topic map (roles), then two passes.
//
// Both passes go over the recording in file order: the first reads each mapped message's
// stamp (the header's, without decoding the rest) and numbers the messages of each channel
// in stamp order; the second decodes, converts and writes them. Memory holds one chunk and
// 12 bytes per message, never the recording.
#include "replay/ros/import.hpp"
#include "replay/ros/import_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>

#include "orthosonar/version.hpp"
#include "replay/ros/ros_msg.hpp"

namespace orthosonar::replay::ros {
using namespace detail;
namespace {

// ---- Channel state shared by both passes ------------------------------------------------

struct ChannelState {
  SrcChannel src;
  const TopicRule* rule = nullptr;  // nullptr: not imported
  const TypeEntry* entry = nullptr;
  std::optional<rosmsg::Schema> schema;
  bool header_first = false;        // the root's first field is a std_msgs/Header
  uint64_t index = 0;               // messages seen on this channel (this pass)
};

// Whether the file's own std_msgs/Header is laid out as fast_header_stamp reads it: ros1
// `uint32 seq` then `time stamp`; CDR `builtin_interfaces/Time stamp` first. Another
// layout (a ROS 2 Header in a ros1-encoded file, a definition of its own) is decoded.
bool import_standard_header(const rosmsg::Schema& schema, rosmsg::Encoding encoding) {
  const rosmsg::MsgSpec* h = schema.find("std_msgs/Header");
  if (h == nullptr) return false;
  const auto& f = h->fields;
  auto is_stamp = [](const rosmsg::Field& x) { return x.prim == rosmsg::Prim::kTime && x.array < 0; };
  if (encoding == rosmsg::Encoding::kRos1)
    return f.size() >= 2 && f[0].array < 0 && (f[0].prim == rosmsg::Prim::kUint32 || f[0].prim == rosmsg::Prim::kInt32) &&
           is_stamp(f[1]) && f[1].name == "stamp";
  return !f.empty() && is_stamp(f[0]) && f[0].name == "stamp";
}

// The header stamp read straight from the bytes when the root starts with a Header.
std::optional<int64_t> fast_header_stamp(const ChannelState& c, const SrcMessage& m) {
  if (!c.header_first) return std::nullopt;
  auto u32 = [&](size_t at, bool big) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<uint32_t>(m.data[at + static_cast<size_t>(i)]) << (big ? 8 * (3 - i) : 8 * i);
    return v;
  };
  if (c.src.encoding == rosmsg::Encoding::kRos1) {
    if (m.size < 12) return std::nullopt;
    return static_cast<int64_t>(u32(4, false)) * kNsPerS + u32(8, false);
  }
  if (m.size < 12 || m.data[0] != 0 || (m.data[1] != 0 && m.data[1] != 1)) return std::nullopt;
  const bool big = m.data[1] == 0;
  const auto sec = static_cast<int32_t>(u32(4, big));
  return static_cast<int64_t>(sec) * kNsPerS + u32(8, big);
}

}  // namespace

double TopicInfo::rate_hz() const {
  if (count < 2 || last_ns <= first_ns) return 0.0;
  return static_cast<double>(count - 1) / (static_cast<double>(last_ns - first_ns) * 1e-9);
}

std::string normalise_type(const std::string& type) {
  const auto a = type.find("/msg/");
  if (a != std::string::npos) return type.substr(0, a) + "/" + type.substr(a + 5);
  return type;
}

namespace {

// Resolves channels against the map (both commands).
struct Resolver {
  const TopicMap& map;
  std::map<uint32_t, ChannelState> channels;
  std::map<Role, std::string> role_topic;
  std::vector<std::string> skipped;  // default topics of optional roles left out, and why
  Status add(uint32_t id, const SrcChannel& s, const std::string& path, bool strict) {
    ChannelState c;
    c.src = s;
    c.rule = map.find(s.topic);
    if (c.rule != nullptr) {
      std::string why = s.unusable;
      if (why.empty()) why = check_type(c.rule->role, s.type);
      if (why.empty()) {
        c.entry = type_entry(s.type);
        auto schema = rosmsg::Schema::parse(s.type, s.definition, s.dialect);
        if (!schema) why = "its definition does not parse: " + schema.error().message;
        else c.schema = std::move(*schema);
      }
      // A default topic of an optional role (a /gyro of some other type, say) is not the
      // user's choice: it is left out with a warning rather than failing the import.
      const bool optional = c.rule->from_defaults && std::find(std::begin(kRequiredRoles), std::end(kRequiredRoles),
                                                                c.rule->role) == std::end(kRequiredRoles);
      if (!why.empty()) {
        if (strict && !optional)
          return Error{path + ": topic " + s.topic + " (" + std::string(role_name(c.rule->role)) + "): " + why};
        c.src.unusable = why;
        if (strict) {  // its messages are not read
          std::string w = path + ": topic " + s.topic + " not imported as the " + std::string(role_name(c.rule->role)) +
                          " (a default topic): " + why;
          if (std::find(skipped.begin(), skipped.end(), w) == skipped.end()) skipped.push_back(std::move(w));
          c.rule = nullptr;
        }
      } else {
        const auto [it, fresh] = role_topic.emplace(c.rule->role, s.topic);
        if (!fresh && it->second != s.topic) {
          if (strict)
            return Error{path + ": two topics for the " + std::string(role_name(c.rule->role)) + ": " + it->second +
                         " and " + s.topic + " (map one of them to another role, or drop it from topics.yaml)"};
          c.src.unusable = "another topic (" + it->second + ") already feeds this role";
        }
        const auto& fields = c.schema->find(c.schema->root())->fields;
        c.header_first = !fields.empty() && fields.front().prim == rosmsg::Prim::kMessage &&
                         fields.front().array < 0 && fields.front().type == "std_msgs/Header" &&
                         import_standard_header(*c.schema, s.encoding);
      }
    }
    channels[id] = std::move(c);
    return {};
  }
};

}  // namespace

namespace {

void count(std::map<std::string, TopicInfo>& topics, const std::string& topic, const SrcMessage& m) {
  TopicInfo& t = topics[topic];
  if (t.count == 0) t.first_ns = t.last_ns = m.receive_ns;
  ++t.count;
  t.first_ns = std::min(t.first_ns, m.receive_ns);
  t.last_ns = std::max(t.last_ns, m.receive_ns);
}

InputSummary summarise(const std::string& path, const Recording* rec, const Resolver& res,
                       std::map<std::string, TopicInfo> topics) {
  InputSummary out;
  out.path = path;
  out.format = rec->format;
  out.bytes = rec->bytes;
  out.complete = rec->complete;
  out.recovery = rec->recovery;
  for (const auto& [id, c] : res.channels) {
    TopicInfo& t = topics[c.src.topic];
    t.topic = c.src.topic;
    if (t.type.empty()) t.type = c.src.type;
    t.encoding = c.src.encoding_name;
    if (c.rule != nullptr) t.role = c.rule->role;
    if (!c.src.unusable.empty()) t.note = c.src.unusable;
  }
  for (auto& [name, t] : topics) out.topics.push_back(t);
  return out;
}

}  // namespace

Result<InputSummary> list_input(const std::string& path, const TopicMap& map) {
  auto rec = open_recording(path);
  if (!rec) return rec.error();
  Resolver res{map, {}, {}, {}};
  std::map<std::string, TopicInfo> topics;
  Status s = rec->visit([&](uint32_t id, const SrcChannel& c) { return res.add(id, c, path, false); },
                        [&](const SrcMessage& m) -> Status {
                          const auto it = res.channels.find(m.channel);
                          if (it == res.channels.end())
                            return Error{path + ": message on undefined connection " + std::to_string(m.channel)};
                          count(topics, it->second.src.topic, m);
                          return {};
                        });
  if (!s) return s.error();
  return summarise(path, &*rec, res, std::move(topics));
}

Result<ImportReport> import_recording(const std::string& in, const std::string& out, const ImportOptions& options) {
  auto rec = open_recording(in);
  if (!rec) return rec.error();
  ImportReport report;

  // Pass 1: channels, stamps, per-channel order.
  Resolver res{options.map, {}, {}, {}};
  struct Stamp {
    int64_t ns;
    uint32_t k;  // the message's index among imported messages, file order
  };
  std::map<Channel, std::vector<Stamp>> stamps;
  uint32_t k = 0;
  std::map<std::string, TopicInfo> topics;
  Status s = rec->visit([&](uint32_t id, const SrcChannel& c) { return res.add(id, c, in, true); },
                        [&](const SrcMessage& m) -> Status {
                          const auto it = res.channels.find(m.channel);
                          if (it == res.channels.end())
                            return Error{in + ": message on undefined connection " + std::to_string(m.channel)};
                          ChannelState& c = it->second;
                          count(topics, c.src.topic, m);
                          const uint64_t index = c.index++;
                          if (c.rule == nullptr) return {};
                          int64_t ns = static_cast<int64_t>(m.receive_ns);
                          if (c.rule->stamp == StampSource::kHeader) {
                            auto fast = fast_header_stamp(c, m);
                            if (!fast) {
                              auto v = rosmsg::decode(*c.schema, c.src.encoding, m.data, m.size);
                              if (!v) return Error{where(*rec, c.src, index, m) + ": " + v.error().message};
                              const Value* h = v->find("header.stamp");
                              if (h == nullptr)
                                return Error{where(*rec, c.src, index, m) +
                                             ": no header.stamp (set `stamp: receive` for this topic in topics.yaml)"};
                              if (h->kind() != Value::Kind::kTime)
                                return Error{where(*rec, c.src, index, m) + ": field 'header.stamp' is not a time"};
                              fast = h->as_ns();
                            }
                            ns = *fast;
                          }
                          if (ns < 0 || ns >= (int64_t{1} << 32) * kNsPerS)
                            return Error{where(*rec, c.src, index, m) + ": stamp " + std::to_string(ns) +
                                         " ns is outside the ROS time range"};
                          if (k == UINT32_MAX) return Error{in + ": more than 4294967295 messages"};
                          stamps[channel_for(c.rule->role)].push_back({ns, k++});
                          return {};
                        });
  if (!s) return s.error();
  std::string missing;
  for (Role r : kRequiredRoles)
    if (!stamps.count(channel_for(r))) missing += (missing.empty() ? "" : ", ") + std::string(role_name(r));
  if (!missing.empty()) {
    std::string mapped;
    for (const auto& [role, topic] : res.role_topic) mapped += "\n  " + topic + " -> " + std::string(role_name(role));
    return Error{in + ": no messages for " + missing + " (mapped topics:" + (mapped.empty() ? " none" : mapped) +
                 "); map a topic to each role in topics.yaml (--map), see `orthosonar import --list " + in + "`" +
                 (rec->complete ? "" : "; " + in + " is truncated: " + rec->recovery)};
  }
  std::vector<uint64_t> sequence(k);
  for (auto& [ch, v] : stamps) {
    std::stable_sort(v.begin(), v.end(), [](const Stamp& a, const Stamp& b) { return a.ns < b.ns; });
    for (size_t i = 0; i < v.size(); ++i) sequence[v[i].k] = i;
  }
  int64_t first = INT64_MAX, last = INT64_MIN;
  for (const auto& [ch, v] : stamps) {
    first = std::min(first, v.front().ns);
    last = std::max(last, v.back().ns);
  }

  // Pass 2: decode, convert, write (to a temporary name, renamed when complete).
  FixtureMetadata md;
  md["imported_from"] = std::filesystem::path(in).filename().string();
  md["import_format"] = rec->format;
  md["software_version"] = kVersion;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(last - first) * 1e-9);
  md["duration_s"] = buf;
  if (!options.map.T_V_h.empty()) md["T_V_h"] = options.map.T_V_h;
  if (!options.map.T_V_v.empty()) md["T_V_v"] = options.map.T_V_v;
  if (!options.map.T_V_gyro.empty()) md["T_V_gyro"] = options.map.T_V_gyro;
  if (options.map.latitude_deg) {
    std::snprintf(buf, sizeof buf, "%.17g", *options.map.latitude_deg);
    md["latitude_deg"] = buf;
  }
  for (const auto& [role, topic] : res.role_topic) md["topic." + std::string(role_name(role))] = topic;
  const std::string tmp = out + ".partial";
  auto writer = FixtureWriter::open(tmp, md, options.writer);
  if (!writer) return writer.error();
  for (auto& [id, c] : res.channels) c.index = 0;
  k = 0;
  s = rec->visit([&](uint32_t, const SrcChannel&) { return Status{}; },
                 [&](const SrcMessage& m) -> Status {
                   ChannelState& c = res.channels.at(m.channel);
                   const uint64_t index = c.index++;
                   if (c.rule == nullptr) return {};
                   const uint32_t kk = k++;
                   auto v = rosmsg::decode(*c.schema, c.src.encoding, m.data, m.size);
                   if (!v) return Error{where(*rec, c.src, index, m) + ": " + v.error().message};
                   int64_t ns = static_cast<int64_t>(m.receive_ns);
                   if (c.rule->stamp == StampSource::kHeader) {
                     const Value* h = v->find("header.stamp");
                     if (h == nullptr) return Error{where(*rec, c.src, index, m) + ": no header.stamp"};
                     if (h->kind() != Value::Kind::kTime)
                       return Error{where(*rec, c.src, index, m) + ": field 'header.stamp' is not a time"};
                     ns = h->as_ns();
                   }
                   // Pass 1 checked the stamp it read; the decoded one is the same (see
                   // header_first), checked again so that no path writes one out of range.
                   if (ns < 0 || ns >= (int64_t{1} << 32) * kNsPerS)
                     return Error{where(*rec, c.src, index, m) + ": stamp " + std::to_string(ns) +
                                  " ns is outside the ROS time range"};
                   auto payload = convert(c.entry->kind, *v, *c.rule, ns, where(*rec, c.src, index, m));
                   if (!payload) return payload.error();
                   Event e;
                   e.stamp = Time::from_ns(ns);
                   e.channel = channel_for(c.rule->role);
                   e.sequence = sequence[kk];
                   if (auto* ping = std::get_if<SonarPing>(&*payload); ping && c.entry->kind == Kind::kProjected)
                     ping->ping_id = static_cast<uint32_t>(e.sequence);
                   e.payload = std::move(*payload);
                   ++report.messages[c.rule->role];
                   ++report.events;
                   return (*writer)->write(e);
                 });
  if (s) s = (*writer)->close();
  writer->reset();
  if (!s) {
    std::remove(tmp.c_str());
    return s.error();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) {
    std::remove(tmp.c_str());
    return Error{out + ": cannot write (" + ec.message() + ")"};
  }
  report.input = summarise(in, &*rec, res, std::move(topics));
  report.first_ns = first;
  report.last_ns = last;
  report.warnings = res.skipped;
  if (!rec->complete) report.warnings.push_back(in + " is truncated: " + rec->recovery);
  return report;
}

}  // namespace orthosonar::replay::ros
