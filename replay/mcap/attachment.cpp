// Lookups in a recording's attachments (replay/mcap/attachment.hpp), shared by the run
// path and tests.
#include "replay/mcap/attachment.hpp"

namespace orthosonar::replay {

const Attachment* find_attachment(const std::vector<Attachment>& attachments, std::string_view name) {
  for (const auto& a : attachments)
    if (a.name == name) return &a;
  return nullptr;
}

std::map<std::string, std::vector<uint8_t>> attachment_files(const std::vector<Attachment>& attachments) {
  std::map<std::string, std::vector<uint8_t>> out;
  for (const auto& a : attachments) out.emplace(a.name, a.data);  // emplace keeps the first
  return out;
}

}  // namespace orthosonar::replay
