// Whether an input fixture is whole (replay/fixture.hpp cut_input_warning, issue 40).
#include <cstdio>

#include "replay/fixture.hpp"

namespace orthosonar::replay {

std::optional<std::string> cut_input_warning(const std::string& path, const RecoveryReport& r) {
  if (r.complete) return std::nullopt;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.3f", r.sensor_seconds());
  std::string w = path + ": input cut at byte offset " + std::to_string(r.bytes_recovered) + " of " +
                  std::to_string(r.bytes_total) + " bytes; recovered " + seconds + " s of sensor time, " +
                  std::to_string(r.messages_recovered) + " messages";
  if (!r.detail.empty()) w += " (" + r.detail + ")";
  return w;
}

}  // namespace orthosonar::replay
