// `orthosonar fuse f.mcap -o out/ [--config run.yaml]`: pairs the fixture's h and v pings
// and fuses every pair (SPEC §4). Writes one PCD per pair (vehicle frame) under
// out/pairs/ and out/fuse_summary.json (pairs, unpaired, detections, matches, culled).
// Extrinsics come from the fixture metadata (T_V_h, T_V_v) when present; a --config file
// (the run YAML, its `fusion:` section) overrides anything it names.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/perception/fusion.hpp"
#include "core/perception/pairing.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/outputs/map_writers.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

namespace fs = std::filesystem;
using perception::FusedPoint;
using perception::FusionConfig;
using perception::FusionResult;

struct FuseArgs {
  std::string fixture;
  std::string out_dir = "out/fuse";
  std::string config_path;
};

// ASCII PCD (outputs::write_pcd_fields, through pcl::io): fixed field order and
// formatting, so bytes are deterministic. Vehicle frame V; metres and radians.
Status write_pcd(const fs::path& path, const std::vector<FusedPoint>& pts) {
  std::vector<float> values;
  values.reserve(pts.size() * 10);
  for (const FusedPoint& p : pts)
    values.insert(values.end(), {p.p_V.x(), p.p_V.y(), p.p_V.z(), p.intensity_h, p.intensity_v, p.confidence,
                                 p.range_m, p.bearing_rad, p.elevation_rad, p.elevation_sigma_rad});
  return outputs::write_pcd_fields(path.string(),
                                   {"x", "y", "z", "intensity_h", "intensity_v", "confidence", "range", "bearing",
                                    "elevation", "elevation_sigma"},
                                   values, outputs::PcdEncoding::kAscii);
}

int run_fuse(const FuseArgs& a) {
  auto src = replay::FixtureSource::open(a.fixture);
  if (!src.ok()) {
    std::cerr << "orthosonar fuse: " << src.error().message << "\n";
    return 2;
  }
  note_input(a.fixture, (*src)->recovery());
  // The run API's precedence: defaults < the fixture's extrinsics < --config.
  RunOptions options;
  if (!a.config_path.empty()) {
    auto text = read_config_text(a.config_path);
    if (!text.ok()) {
      std::cerr << "orthosonar fuse: " << text.error().message << "\n";
      return 2;
    }
    options.config_yaml = *text;
    options.config_origin = a.config_path;
  }
  auto resolved = effective_config((*src)->metadata(), options);
  if (!resolved.ok()) {
    std::cerr << "orthosonar fuse: " << a.fixture << ": " << resolved.error().message << "\n";
    return 2;
  }
  const RunConfig run = *resolved;
  const FusionConfig& cfg = run.pipeline.fusion;
  std::error_code ec;
  const fs::path out(a.out_dir), pairs_dir = out / "pairs";
  fs::create_directories(pairs_dir, ec);
  if (ec) {
    std::cerr << "orthosonar fuse: cannot create '" << pairs_dir.string() << "': " << ec.message() << "\n";
    return 2;
  }

  perception::PingPairer pairer(Time::from_seconds(cfg.max_pair_dt_s));
  nlohmann::json per_pair = nlohmann::json::array();
  size_t det_h = 0, det_v = 0, cand_h = 0, cand_v = 0, subproblems = 0, matches = 0, culled = 0, points = 0;
  Status write_status;
  auto fuse_ready = [&] {
    while (auto pr = pairer.pop()) {
      const SonarPing& h = pr->first;
      const SonarPing& v = pr->second;
      const FusionResult r = perception::fuse_pair(h, v, cfg);
      char name[64];
      std::snprintf(name, sizeof name, "pair_%06zu.pcd", per_pair.size());
      if (Status s = write_pcd(pairs_dir / name, r.points); !s.ok() && write_status.ok()) write_status = s;
      det_h += r.detections_h.size();
      det_v += r.detections_v.size();
      cand_h += r.candidates_h;
      cand_v += r.candidates_v;
      subproblems += r.subproblems;
      matches += r.matches;
      culled += r.culled_low_confidence;
      points += r.points.size();
      per_pair.push_back({{"file", std::string("pairs/") + name}, {"stamp_h_ns", h.stamp.ns()},
                          {"stamp_v_ns", v.stamp.ns()}, {"ping_id_h", h.ping_id}, {"ping_id_v", v.ping_id},
                          {"detections_h", r.detections_h.size()}, {"detections_v", r.detections_v.size()},
                          {"candidates_h", r.candidates_h}, {"candidates_v", r.candidates_v},
                          {"subproblems", r.subproblems}, {"matches", r.matches},
                          {"culled_low_confidence", r.culled_low_confidence}, {"points", r.points.size()}});
    }
  };
  for (;;) {
    hal::Pulled p = (*src)->next();
    if (p.error) {
      std::cerr << "orthosonar fuse: " << p.error->message << "\n";
      return 2;
    }
    if (p.end_of_stream || !p.event) break;
    if (auto* ping = std::get_if<SonarPing>(&p.event->payload)) {
      pairer.push(*ping);
      fuse_ready();
    }
  }
  pairer.flush();
  fuse_ready();
  if (!write_status.ok()) {
    std::cerr << "orthosonar fuse: " << write_status.error().message << "\n";
    return 2;
  }
  const size_t n = per_pair.size();
  auto mean = [n](size_t total) { return n ? static_cast<double>(total) / static_cast<double>(n) : 0.0; };
  nlohmann::json summary = {
      {"fixture", a.fixture},
      {"input_complete", (*src)->recovery().complete},
      {"pairs", n},
      {"unpaired", {{"h", pairer.unpaired_h()}, {"v", pairer.unpaired_v()}}},
      {"detections", {{"h", det_h}, {"v", det_v}, {"h_per_image", mean(det_h)}, {"v_per_image", mean(det_v)}}},
      {"candidates", {{"h", cand_h}, {"v", cand_v}}},
      {"subproblems", subproblems},
      {"matches", matches},
      {"culled_low_confidence", culled},
      {"points", points},
      {"config", config_to_json(run)["fusion"]},
      {"per_pair", per_pair}};
  std::ofstream f(out / "fuse_summary.json");
  f << summary.dump(2) << "\n";
  if (!f) {
    std::cerr << "orthosonar fuse: cannot write " << (out / "fuse_summary.json").string() << "\n";
    return 2;
  }
  std::cerr << "fused " << n << " pairs (unpaired h " << pairer.unpaired_h() << ", v " << pairer.unpaired_v()
            << "): " << points << " points, " << matches << " matches, " << culled << " culled; outputs in "
            << a.out_dir << "\n";
  return 0;
}

const bool registered_fuse = register_command(
    {"fuse", "Fuse every h/v ping pair of a fixture into 3D points (PCD per pair, vehicle frame)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<FuseArgs>();
       sub.add_option("fixture", a->fixture, "Fixture (.mcap)")->required();
       sub.add_option("-o,--out", a->out_dir, "Output directory")->capture_default_str();
       sub.add_option("--config", a->config_path, "Run configuration YAML (its fusion: section applies)");
       add_allow_incomplete_flag(sub);
       return [a] { return run_fuse(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
