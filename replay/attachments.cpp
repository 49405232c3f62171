// Attachments of fixtures (replay/fixture.hpp): lookups shared by the run path and tests.
#include "replay/fixture.hpp"

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

const std::vector<Attachment>& FixtureSource::attachments() const {
  static const std::vector<Attachment> kNone;
  return kNone;
}

}  // namespace orthosonar::replay
