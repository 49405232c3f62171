// `orthosonar import IN.bag|IN.mcap -o OUT.mcap [--map topics.yaml]`: a ROS 1 bag or a ROS 2
// MCAP recording to a fixture; `import --list IN` shows its topics and the mapping that
// applies (docs/IMPORT.md).
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "replay/ros/import.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {

struct ImportArgs {
  std::string in, out, map_path;
  bool list = false, json = false, quiet = false;
};

std::string seconds(uint64_t ns) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", static_cast<double>(ns) * 1e-9);
  return b;
}

void print_list(const replay::ros::InputSummary& s, const replay::ros::TopicMap& map) {
  std::cout << s.path << ": " << s.format << ", " << s.bytes << " bytes\n";
  std::cout << "mapping: " << (map.source.empty() ? "built in (the authors' topics)" : map.source) << "\n";
  size_t w = 5;
  for (const auto& t : s.topics) w = std::max(w, t.topic.size());
  for (const auto& t : s.topics) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%8.2f Hz", t.rate_hz());
    std::string role = t.role ? "-> " + std::string(replay::ros::role_name(*t.role)) : "ignored";
    if (!t.note.empty()) role += " (NOT importable: " + t.note + ")";
    std::cout << "  " << t.topic << std::string(w - t.topic.size() + 2, ' ') << t.type << " [" << t.encoding << "]  "
              << t.count << " msgs  " << rate << "  " << role << "\n";
  }
  for (replay::ros::Role r : replay::ros::kRequiredRoles) {
    bool found = false;
    for (const auto& t : s.topics) found = found || (t.role == r && t.note.empty() && t.count > 0);
    if (!found) std::cout << "missing: no topic feeds the " << replay::ros::role_name(r) << "\n";
  }
  if (!s.complete) std::cout << "recovery: INCOMPLETE: " << s.recovery << "\n";
}

nlohmann::json list_json(const replay::ros::InputSummary& s, const replay::ros::TopicMap& map) {
  nlohmann::json j{{"path", s.path}, {"format", s.format}, {"bytes", s.bytes}, {"complete", s.complete},
                   {"mapping", map.source.empty() ? "built-in" : map.source}};
  if (!s.complete) j["recovery"] = s.recovery;
  j["topics"] = nlohmann::json::array();
  for (const auto& t : s.topics) {
    nlohmann::json e{{"topic", t.topic}, {"type", t.type}, {"encoding", t.encoding}, {"count", t.count},
                     {"rate_hz", t.rate_hz()}, {"first_s", seconds(t.first_ns)}, {"last_s", seconds(t.last_ns)}};
    e["role"] = t.role ? nlohmann::json(std::string(replay::ros::role_name(*t.role))) : nlohmann::json(nullptr);
    if (!t.note.empty()) e["note"] = t.note;
    j["topics"].push_back(e);
  }
  return j;
}

int run_import(const ImportArgs& a) {
  replay::ros::ImportOptions options;
  if (!a.map_path.empty()) {
    auto map = replay::ros::load_topic_map(a.map_path);
    if (!map) {
      std::cerr << "orthosonar import: " << map.error().message << "\n";
      return 2;
    }
    options.map = std::move(*map);
  }
  if (a.list) {
    auto s = replay::ros::list_input(a.in, options.map);
    if (!s) {
      std::cerr << "orthosonar import: " << s.error().message << "\n";
      return 2;
    }
    if (a.json) std::cout << list_json(*s, options.map).dump(2) << "\n";
    else print_list(*s, options.map);
    return s->complete ? 0 : 1;
  }
  if (a.out.empty()) {
    std::cerr << "orthosonar import: -o OUT.mcap is required (or --list)\n";
    return 2;
  }
  auto r = replay::ros::import_recording(a.in, a.out, options);
  if (!r) {
    std::cerr << "orthosonar import: " << r.error().message << "\n";
    return 2;
  }
  // A cut bag or recording: the fixture holds what was recovered, and the exit code says
  // so (tools/support_cut_inputs.hpp).
  const std::string cut_warning = a.in + " is truncated: " + r->input.recovery;
  for (const auto& w : r->warnings)
    if (r->input.complete || w != cut_warning) std::cerr << "warning: " << w << "\n";
  if (!r->input.complete)
    note_cut_input_warning(a.in + ": input cut, " + r->input.recovery + "; recovered " +
                           seconds(static_cast<uint64_t>(r->last_ns - r->first_ns)) + " s of sensor time, " +
                           std::to_string(r->events) + " messages");
  if (!a.quiet) {
    std::cerr << "imported " << r->events << " messages (" << seconds(static_cast<uint64_t>(r->last_ns - r->first_ns))
              << " s) from " << a.in << " (" << r->input.format << ") into " << a.out << ":\n";
    for (const auto& [role, n] : r->messages) std::cerr << "  " << replay::ros::role_name(role) << ": " << n << "\n";
    for (const auto& t : r->input.topics)
      if (!t.role) std::cerr << "  ignored: " << t.topic << " (" << t.type << ", " << t.count << ")\n";
  }
  std::cout << a.out << "\n";
  return 0;
}

const bool registered_import = register_command(
    {"import", "Import a ROS 1 bag or a ROS 2 MCAP recording as a fixture (--list: show topics and mapping)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<ImportArgs>();
       sub.add_option("input", a->in, "ROS 1 bag (.bag) or MCAP recording (.mcap)")->required();
       sub.add_option("-o,--out", a->out, "Fixture to write (.mcap)");
       sub.add_option("--map", a->map_path, "topics.yaml: topic -> role, mounts (docs/IMPORT.md)");
       sub.add_flag("--list", a->list, "List topics, types, counts, rates and the mapping; write nothing");
       sub.add_flag("--json", a->json, "With --list: JSON");
       sub.add_flag("-q,--quiet", a->quiet, "Print only the output path");
       add_allow_incomplete_flag(sub);
       return [a] { return run_import(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
