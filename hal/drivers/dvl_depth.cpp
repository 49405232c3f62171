// Depth lines: "$DEPTH,<metres>*XX" and the A50-style JSON {"type":"depth",...}.
#include "hal/drivers/dvl_protocols.hpp"

#include <string>

#include "hal/drivers/dvl_detail.hpp"

namespace orthosonar::hal::drivers::dvl {

using namespace detail;

Result<DepthLine> parse_depth(std::string_view line) {
  line = trim(line);
  if (!line.empty() && line.front() == '{') {
    const json j = json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return err("depth line is not a JSON object");
    Keys k(j, "depth JSON");
    const auto d = k.number("depth", true);
    if (k.error) return *k.error;
    return DepthLine{*d, true};
  }
  auto body = nmea_body(line);
  if (!body) return body.error();
  const auto f = split(*body, ',');
  if (f.size() != 2 || f[0] != "DEPTH") return err("expected $DEPTH,<metres>");
  const auto d = to_double(f[1]);
  if (!d || *d < -100.0 || *d > 12000.0) return err("$DEPTH value is not a plausible number");
  return DepthLine{*d, false};
}

Result<double> parse_depth_line(std::string_view line) {
  auto d = parse_depth(line);
  if (!d) return d.error();
  return d->depth_m;
}

std::string encode_depth_line(double depth_m) { return with_checksum("DEPTH," + num(depth_m)); }

FieldList describe(const DepthLine& r) {
  return {{"form", r.json ? "json" : "$DEPTH"}, {"depth_m", g9(r.depth_m)}};
}

}  // namespace orthosonar::hal::drivers::dvl
