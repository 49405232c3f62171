// Raw Oculus captures (TCP 52100 bytes as a logger saved them) described ping by ping.
#include "hal/drivers/oculus_capture.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <variant>
#include <vector>

#include "hal/drivers/oculus_stream.hpp"

namespace orthosonar::hal::drivers::oculus {

namespace {

nlohmann::json capture_ping_json(const PingResult& p) {
  const double b0 = p.bearings_centideg.empty() ? 0.0 : p.bearings_centideg.front() / 100.0;
  const double b1 = p.bearings_centideg.empty() ? 0.0 : p.bearings_centideg.back() / 100.0;
  return {{"ping_id", p.ping_id},         {"src_device_id", p.header.src_device_id},
          {"msg_id", p.header.msg_id},    {"msg_version", p.header.msg_version},
          {"layout", p.version},          {"mode", p.fire.master_mode},
          {"flags", p.fire.flags},        {"range", p.fire.range},
          {"gain_percent", p.fire.gain_percent}, {"gamma", p.fire.gamma},
          {"frequency_hz", p.frequency_hz}, {"range_resolution_m", p.range_resolution_m},
          {"n_ranges", p.n_ranges},       {"n_beams", p.n_beams},
          {"bits", 8 * p.bytes_per_pixel()}, {"has_gain", p.has_gain()},
          {"bearing_first_deg", b0},      {"bearing_last_deg", b1},
          {"image_offset", p.image_offset}, {"image_size", p.image_size},
          {"message_size", p.message_size}};
}

}  // namespace

int inspect_oculus_capture(const std::string& path, bool json, std::ostream& out, std::ostream& err) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    err << "orthosonar inspect: cannot open '" << path << "'\n";
    return 2;
  }
  StreamParser parser;
  std::vector<char> chunk(1 << 16);
  nlohmann::json pings = nlohmann::json::array();
  uint64_t status_messages = 0, other_messages = 0;
  auto drain = [&] {
    while (auto m = parser.pop()) {
      if (const auto* p = std::get_if<PingResult>(&*m)) {
        if (json) {
          pings.push_back(capture_ping_json(*p));
          continue;
        }
        char line[320];
        std::snprintf(line, sizeof line,
                      "ping %u src %u V%d (msgVersion %u) mode %u flags 0x%02x range %.3f%s gain %.1f%% "
                      "freq %.1f kHz res %.6f m %ux%u %d-bit%s bearings [%.2f, %.2f] deg image @%u +%u of %u",
                      p->ping_id, p->header.src_device_id, p->version, p->header.msg_version, p->fire.master_mode,
                      p->fire.flags, p->fire.range, (p->fire.flags & kFlagRangeAsMeters) ? " m" : " %",
                      p->fire.gain_percent, p->frequency_hz / 1e3, p->range_resolution_m, p->n_ranges, p->n_beams,
                      8 * p->bytes_per_pixel(), p->has_gain() ? " +gain" : "",
                      p->bearings_centideg.empty() ? 0.0 : p->bearings_centideg.front() / 100.0,
                      p->bearings_centideg.empty() ? 0.0 : p->bearings_centideg.back() / 100.0, p->image_offset,
                      p->image_size, p->message_size);
        out << line << "\n";
        pings.push_back(p->ping_id);
      } else if (std::holds_alternative<StatusMessage>(*m)) {
        ++status_messages;
      } else {
        ++other_messages;
      }
    }
  };
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<size_t>(in.gcount());
    if (n == 0) break;
    parser.push(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(chunk.data()), n));
    drain();
  }
  const auto& st = parser.stats();
  const uint64_t trailing = parser.buffered();
  if (json) {
    nlohmann::json doc = {{"file", path},
                          {"format", "oculus-raw"},
                          {"pings", pings},
                          {"status_messages", status_messages},
                          {"other_messages", other_messages},
                          {"malformed", st.malformed},
                          {"garbage_bytes", st.garbage_bytes},
                          {"trailing_bytes", trailing}};
    out << doc.dump(2) << "\n";
  } else {
    out << path << ": " << pings.size() << " ping(s), " << status_messages << " status, " << other_messages
              << " other message(s), " << st.malformed << " malformed, " << st.garbage_bytes << " garbage byte(s), "
              << trailing << " trailing byte(s)\n";
  }
  if (pings.empty()) {
    err << "orthosonar inspect: '" << path << "' holds no Oculus ping (not an MCAP file either)"
              << (st.malformed ? "; last error: " + parser.last_error() : std::string()) << "\n";
    return 2;
  }
  return 0;
}

}  // namespace orthosonar::hal::drivers::oculus
