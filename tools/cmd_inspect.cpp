// `orthosonar inspect f.mcap [--json]`: what a fixture holds. Files that are not MCAP
// (no MCAP magic) are handed to the raw Oculus capture inspector; `--protocol P` decodes a
// raw capture of any device protocol (hal/drivers/protocol_capture.hpp).
// Exit codes: 0 a complete fixture, 1 a truncated fixture (readable prefix reported),
// 2 unreadable or malformed input.
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hal/drivers/oculus_capture.hpp"
#include "hal/drivers/protocol_capture.hpp"
#include "replay/fixture/fixture_summary.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {
namespace {

struct InspectOptions {
  std::string path;
  bool json = false;
  size_t max_gaps = 10;  // per channel, in the text output
  std::string protocol;  // a raw device capture: oculus, vn100, a50, prti, depth, rti-ensemble, dsp1760
  std::string csv;       // --protocol: decoded fields as CSV
};

std::string secs(Time t) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << t.seconds();
  return s.str();
}

nlohmann::ordered_json to_json(const replay::FixtureSummary& s) {
  nlohmann::ordered_json j;
  j["path"] = s.path;
  j["format"] = "mcap";
  j["profile"] = s.profile;
  j["library"] = s.library;
  j["file_bytes"] = s.file_bytes;
  j["start_ns"] = s.start.ns();
  j["end_ns"] = s.end.ns();
  j["duration_s"] = s.duration().seconds();
  j["messages"] = s.messages;
  j["chunks"] = s.chunks;
  j["compression"] = s.compressions;
  j["summary"] = {{"present", s.read.summary_present},
                  {"read_by_linear_scan", s.read.read_by_linear_scan},
                  {"note", s.read.summary_note},
                  {"loose_messages", s.read.loose_message_count},
                  {"message_indexes", s.read.message_indexes},
                  {"chunk_indexes", s.read.chunk_indexes},
                  {"truncated_bytes", s.read.truncated_bytes}};
  j["channels"] = nlohmann::ordered_json::array();
  for (const auto& c : s.channels) {
    nlohmann::ordered_json cj;
    cj["topic"] = c.topic;
    cj["schema"] = c.schema;
    cj["count"] = c.count;
    cj["rate_hz"] = c.rate_hz;
    cj["nominal_period_s"] = c.nominal_period.seconds();
    cj["first_ns"] = c.first.ns();
    cj["last_ns"] = c.last.ns();
    cj["gaps"] = nlohmann::ordered_json::array();
    for (const auto& g : c.gaps)
      cj["gaps"].push_back({{"from_ns", g.from.ns()}, {"to_ns", g.to.ns()}, {"length_s", (g.to - g.from).seconds()}});
    j["channels"].push_back(cj);
  }
  j["metadata"] = s.metadata;
  j["attachments"] = nlohmann::ordered_json::array();
  for (const auto& a : s.attachments)
    j["attachments"].push_back({{"name", a.name}, {"media_type", a.media_type}, {"bytes", a.bytes}});
  j["recovery"] = {{"complete", s.recovery.complete},
                   {"bytes_total", s.recovery.bytes_total},
                   {"bytes_recovered", s.recovery.bytes_recovered},
                   {"messages_recovered", s.recovery.messages_recovered},
                   {"detail", s.recovery.detail}};
  return j;
}

void print_text(const replay::FixtureSummary& s, const InspectOptions& o) {
  std::cout << s.path << ": MCAP (" << s.profile << ", " << s.library << "), " << s.file_bytes << " bytes, "
            << s.chunks << " chunks";
  for (const auto& c : s.compressions) std::cout << " [" << (c.empty() ? "uncompressed" : c) << "]";
  std::cout << "\n";
  std::cout << "summary: " << (s.read.summary_present ? "present" : "missing")
            << (s.read.read_by_linear_scan ? ", read by linear scan" : "")
            << (s.read.summary_note.empty() ? "" : " (" + s.read.summary_note + ")") << "; compression: ";
  for (size_t i = 0; i < s.compressions.size(); ++i)
    std::cout << (i ? ", " : "") << (s.compressions[i].empty() ? "none" : s.compressions[i]);
  if (s.compressions.empty()) std::cout << "none (no chunks)";
  if (s.read.loose_message_count > 0) std::cout << "; " << s.read.loose_message_count << " messages outside chunks";
  std::cout << "\n";
  std::cout << "duration: " << secs(s.duration()) << " s (" << secs(s.start) << " .. " << secs(s.end) << "), "
            << s.messages << " messages\n";
  std::cout << "channels:\n";
  for (const auto& c : s.channels) {
    std::printf("  %-26s %-28s %8llu msgs %9.3f Hz  %zu gaps\n", c.topic.c_str(), c.schema.c_str(),
                static_cast<unsigned long long>(c.count), c.rate_hz, c.gaps.size());
    for (size_t i = 0; i < c.gaps.size() && i < o.max_gaps; ++i)
      std::cout << "    gap " << secs(c.gaps[i].to - c.gaps[i].from) << " s at " << secs(c.gaps[i].from)
                << " s (nominal " << secs(c.nominal_period) << " s)\n";
    if (c.gaps.size() > o.max_gaps) std::cout << "    ... " << c.gaps.size() - o.max_gaps << " more\n";
  }
  std::cout << "metadata:\n";
  for (const auto& [k, v] : s.metadata) std::cout << "  " << k << ": " << v << "\n";
  std::cout << "attachments:" << (s.attachments.empty() ? " none (no embedded scene)" : "") << "\n";
  for (const auto& a : s.attachments) std::cout << "  " << a.name << " (" << a.media_type << ", " << a.bytes << " bytes)\n";
  if (s.recovery.complete) {
    std::cout << "recovery: complete file\n";
  } else {
    std::cout << "recovery: INCOMPLETE, recovered " << s.recovery.bytes_recovered << " of " << s.recovery.bytes_total
              << " bytes, " << s.recovery.messages_recovered << " messages\n  " << s.recovery.detail << "\n";
  }
}

int run_inspect(const InspectOptions& o) {
  if (!o.protocol.empty()) return hal::drivers::inspect_protocol_capture(o.path, o.protocol, o.json, o.csv, std::cout, std::cerr);
  if (!o.csv.empty()) {
    std::cerr << "orthosonar inspect: --csv needs --protocol\n";
    return 2;
  }
  if (!replay::has_mcap_magic(o.path)) return hal::drivers::oculus::inspect_oculus_capture(o.path, o.json, std::cout, std::cerr);
  auto s = replay::summarize_fixture(o.path);
  if (!s) {
    std::cerr << "orthosonar inspect: " << s.error().message << "\n";
    return 2;
  }
  if (o.json) {
    std::cout << to_json(*s).dump(2) << "\n";
  } else {
    print_text(*s, o);
  }
  return s->recovery.complete ? 0 : 1;
}

const bool registered_inspect = register_command(
    {"inspect", "Describe a fixture (.mcap) or a raw device capture (--protocol): channels, rates, gaps, metadata; decoded messages",
     [](CLI::App& sub) -> std::function<int()> {
       auto o = std::make_shared<InspectOptions>();
       sub.add_option("file", o->path, "Fixture (.mcap) or raw Oculus capture")->required();
       sub.add_flag("--json", o->json, "Machine-readable output");
       sub.add_option("--max-gaps", o->max_gaps, "Gaps listed per channel in the text output")->capture_default_str();
       sub.add_option("--protocol", o->protocol,
                      "Decode a raw device capture (serial/TCP bytes): oculus, vn100, a50, prti, depth, rti-ensemble, dsp1760")
           ->check(CLI::IsMember({"oculus", "vn100", "a50", "prti", "depth", "rti-ensemble", "dsp1760"}));
       sub.add_option("--csv", o->csv, "With --protocol: write the decoded fields as CSV here");
       return [o] { return run_inspect(*o); };
     }});

}  // namespace
}  // namespace orthosonar::cli
