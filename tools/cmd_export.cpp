// `orthosonar export FIXTURE --to ros1-bag|ros2-mcap -o OUT [--sonar-type oculus|projected]`:
// a fixture in the authors' ROS types or the community's, with a topics.yaml beside it
// that maps it back (docs/IMPORT.md).
#include <iostream>

#include "replay/ros/export.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {

struct ExportArgs {
  std::string fixture, out, to, sonar_type = "oculus", image = "jpeg", compression;
  int jpeg_quality = 80;
  bool no_yaml = false, quiet = false;
};

int run_export(const ExportArgs& a) {
  replay::ros::ExportOptions o;
  o.target = a.to == "ros2-mcap" ? replay::ros::ExportTarget::kRos2Mcap : replay::ros::ExportTarget::kRos1Bag;
  o.sonar = a.sonar_type == "projected" ? replay::ros::SonarType::kProjected : replay::ros::SonarType::kOculus;
  o.jpeg = a.image == "jpeg";
  o.jpeg_quality = a.jpeg_quality;
  o.compression = a.compression;
  o.write_topics_yaml = !a.no_yaml;
  if (o.sonar == replay::ros::SonarType::kProjected && a.image == "jpeg") o.jpeg = false;
  auto r = replay::ros::export_fixture(a.fixture, a.out, o);
  if (!r) {
    std::cerr << "orthosonar export: " << r.error().message << "\n";
    return 2;
  }
  note_input(a.fixture, r->input_recovery);
  if (!a.quiet) {
    std::cerr << "wrote " << a.out << ":\n";
    for (const auto& [topic, n] : r->messages) std::cerr << "  " << topic << ": " << n << "\n";
    if (r->skipped_labels > 0) std::cerr << "  (" << r->skipped_labels << " label messages not exported)\n";
    if (!r->topics_yaml.empty())
      std::cerr << "mapping back: orthosonar import " << a.out << " --map " << r->topics_yaml << " -o OUT.mcap\n";
  }
  std::cout << a.out << "\n";
  return 0;
}

const bool registered_export = register_command(
    {"export", "Export a fixture as a ROS 1 bag or a ROS 2 MCAP recording (authors' or standard types)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<ExportArgs>();
       sub.add_option("fixture", a->fixture, "Fixture (.mcap)")->required();
       sub.add_option("--to", a->to, "ros1-bag or ros2-mcap")->required()->check(CLI::IsMember({"ros1-bag", "ros2-mcap"}));
       sub.add_option("-o,--out", a->out, "Output file")->required();
       sub.add_option("--sonar-type", a->sonar_type, "oculus (sonar_oculus/OculusPing and the authors' navigation types) "
                                                     "or projected (marine_acoustic_msgs/ProjectedSonarImage, standard types)")
           ->check(CLI::IsMember({"oculus", "projected"}))
           ->capture_default_str();
       sub.add_option("--image", a->image, "oculus: jpeg (OculusPing, as the driver publishes) or raw (OculusPingUncompressed)")
           ->check(CLI::IsMember({"jpeg", "raw"}))
           ->capture_default_str();
       sub.add_option("--jpeg-quality", a->jpeg_quality, "JPEG quality")->check(CLI::Range(1, 100))->capture_default_str();
       sub.add_option("--compression", a->compression, "bag: none, bz2, lz4 (default none); MCAP: zstd, none (default zstd)")
           ->check(CLI::IsMember({"none", "bz2", "lz4", "zstd"}));
       sub.add_flag("--no-topics-yaml", a->no_yaml, "Do not write OUT's topics.yaml beside it");
       add_allow_incomplete_flag(sub);
       sub.add_flag("-q,--quiet", a->quiet, "Print only the output path");
       return [a] { return run_export(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
