#pragma once
// MCAP Attachment records: a file carried inside a recording (the fixture writer and the
// generic writer write them; the readers return them CRC-checked).
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace orthosonar::replay {

// A file embedded in a fixture as an MCAP Attachment record (the simulator embeds its
// scene this way, hal/sim/scene.hpp embed_scene). Times are stream times or 0, never the
// wall clock, so the fixture's bytes stay a pure function of the recording.
struct Attachment {
  std::string name;        // e.g. "orthosonar_scene.yaml"
  std::string media_type;  // e.g. "application/yaml"
  std::vector<uint8_t> data;
  uint64_t log_time_ns = 0;
  uint64_t create_time_ns = 0;
  friend bool operator==(const Attachment&, const Attachment&) = default;
};

// The first attachment called `name`, or nullptr.
const Attachment* find_attachment(const std::vector<Attachment>& attachments, std::string_view name);
// name -> data (the first of equal names), the form hal/sim's scene_from_fixture takes.
std::map<std::string, std::vector<uint8_t>> attachment_files(const std::vector<Attachment>& attachments);

}  // namespace orthosonar::replay
