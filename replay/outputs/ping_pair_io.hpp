#pragma once
// The output directory's ping_pair/ (docs/OUTPUTS.md): one ping pair as perception saw it,
// for the report's "what the sonars saw" figure. horizontal.png and vertical.png are the
// raw polar images as recorded (rows = range bins, columns = beams; 8- or 16-bit gray);
// ping_pair.json holds each ping's geometry (stamp, range resolution, bearing table), the
// CFAR detections of both images and the fused points.
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/perception/fusion.hpp"
#include "core/result.hpp"

namespace orthosonar::outputs {

struct PingPairRecord {
  SonarPing h, v;
  std::vector<perception::Detection> detections_h, detections_v;
  std::vector<perception::FusedPoint> fused;
  double overlap_deg = 10.0;  // the fusion's shared aperture, ±this about both centre lines
};

// Writes dir/horizontal.png, dir/vertical.png and dir/ping_pair.json (dir is created).
Status write_ping_pair(const std::string& dir, const SonarPing& h, const SonarPing& v,
                       const perception::FusionResult& fused, double overlap_deg);

// Reads them back; errors name the file and the field at fault (a detection outside its
// image, a bearing table that does not match the image, an image of another size).
Result<PingPairRecord> read_ping_pair(const std::string& dir);

}  // namespace orthosonar::outputs
