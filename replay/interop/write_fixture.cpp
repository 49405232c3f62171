// Writes the interop fixture (every channel, zstd chunks) and prints what a reader must
// find in it as JSON: {"counts": {topic: n}, "chunks": n, "scene": s, "attachments": [...]}.
//   orthosonar_interop_fixture out.mcap > expected.json
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "replay/fixture/fixture.hpp"
#include "replay/fixture/synthetic.hpp"

int main(int argc, char** argv) {
  using namespace orthosonar;
  if (argc != 2) {
    std::cerr << "usage: orthosonar_interop_fixture out.mcap\n";
    return 2;
  }
  replay::SyntheticOptions so;
  so.duration_ns = 3'000'000'000;
  const auto events = replay::synthetic_events(42, so);
  replay::WriterOptions o;
  o.chunk_max_stream_ns = 500'000'000;
  auto w = replay::FixtureWriter::open(argv[1], {{"scene", "interop"}, {"seed", "42"}}, o);
  if (!w) {
    std::cerr << w.error().message << "\n";
    return 2;
  }
  // One attachment (as the simulator embeds its scene): found through the summary's
  // Attachment Index, CRC checked.
  const std::string text = "orthosonar interop attachment\n";
  const replay::Attachment att{"interop.txt", "text/plain", std::vector<uint8_t>(text.begin(), text.end()), 7, 0};
  if (auto s = (*w)->attach(att); !s) {
    std::cerr << s.error().message << "\n";
    return 2;
  }
  std::map<std::string, int> counts;
  Time first = events.front().stamp;
  int chunks = 1;
  for (const auto& e : events) {
    if (auto s = (*w)->write(e); !s) {
      std::cerr << s.error().message << "\n";
      return 2;
    }
    if (e.stamp - first >= Time::from_ns(o.chunk_max_stream_ns)) {  // mirrors the writer's rule
      first = e.stamp;
      ++chunks;
    }
    ++counts[channel_topic(e.channel)];
  }
  if (auto s = (*w)->close(); !s) {
    std::cerr << s.error().message << "\n";
    return 2;
  }
  nlohmann::json j;
  j["counts"] = counts;
  j["chunks"] = chunks;
  j["scene"] = "interop";
  j["attachments"] = nlohmann::json::array(
      {{{"name", att.name}, {"media_type", att.media_type}, {"text", text}, {"log_time", att.log_time_ns}}});
  std::cout << j.dump() << "\n";
  return 0;
}
