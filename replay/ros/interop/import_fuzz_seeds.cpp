// Writes the seed corpus of fuzz_ros_import (replay/ros/ros_import_fuzz.cpp): a quarter of a
// second of every channel with tiny pings (16 x 8), exported as ROS 1 bags and ROS 2 MCAP
// files in each sonar type (JPEG and raw OculusPing, ProjectedSonarImage), compression and
// pixel depth `orthosonar export` offers, each checked to import again with the topics.yaml
// export writes; two of them with the fibre-optic gyro's kvh_gyro/gyro too (100 Hz, one
// reading invalid). Deterministic (a fixed synthetic seed, no clock).
//   orthosonar_import_fuzz_seeds OUTDIR      e.g. testdata/fuzz/ros_import
#include <filesystem>
#include <iostream>
#include <string>

#include "replay/fixture/fixture.hpp"
#include "replay/ros/export.hpp"
#include "replay/ros/import.hpp"
#include "replay/ros/topic_map.hpp"
#include "replay/fixture/synthetic.hpp"

using namespace orthosonar;
namespace fs = std::filesystem;

namespace {

bool write_source_fixture(const std::string& path, uint8_t bytes_per_pixel, double gyro_rate_hz = 0.0) {
  replay::SyntheticOptions so;
  so.duration_ns = 250'000'000;
  so.ping_rows = 16;
  so.ping_cols = 8;
  so.bytes_per_pixel = bytes_per_pixel;
  so.imu_rate_hz = 20.0;
  so.labels = false;
  so.gyro_rate_hz = gyro_rate_hz;
  auto w = replay::FixtureWriter::open(path, {});
  if (!w) {
    std::cerr << w.error().message << "\n";
    return false;
  }
  for (const Event& e : replay::synthetic_events(11, so)) {
    if (auto s = (*w)->write(e); !s) {
      std::cerr << s.error().message << "\n";
      return false;
    }
  }
  if (auto s = (*w)->close(); !s) {
    std::cerr << s.error().message << "\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: orthosonar_import_fuzz_seeds OUTDIR\n";
    return 2;
  }
  const fs::path out = argv[1];
  fs::create_directories(out);
  const fs::path tmp = fs::temp_directory_path() / "orthosonar_import_fuzz_seeds";
  fs::create_directories(tmp);
  const std::string src8 = (tmp / "src8.mcap").string(), src16 = (tmp / "src16.mcap").string();
  const std::string gyro = (tmp / "gyro.mcap").string();
  if (!write_source_fixture(src8, 1) || !write_source_fixture(src16, 2) || !write_source_fixture(gyro, 1, 100.0))
    return 2;

  using replay::ros::ExportTarget;
  using replay::ros::SonarType;
  struct Seed {
    const char* name;
    const std::string* source;
    ExportTarget target;
    SonarType sonar;
    bool jpeg;
    const char* compression;
  };
  const Seed seeds[] = {
      {"ros1_jpeg.bag", &src8, ExportTarget::kRos1Bag, SonarType::kOculus, true, ""},
      {"ros1_raw16_lz4.bag", &src16, ExportTarget::kRos1Bag, SonarType::kOculus, false, "lz4"},
      {"ros1_projected_bz2.bag", &src8, ExportTarget::kRos1Bag, SonarType::kProjected, false, "bz2"},
      {"ros2_raw.mcap", &src8, ExportTarget::kRos2Mcap, SonarType::kOculus, false, "none"},
      {"ros2_jpeg_zstd.mcap", &src8, ExportTarget::kRos2Mcap, SonarType::kOculus, true, "zstd"},
      {"ros2_projected16.mcap", &src16, ExportTarget::kRos2Mcap, SonarType::kProjected, false, "none"},
      {"ros1_raw_gyro.bag", &gyro, ExportTarget::kRos1Bag, SonarType::kOculus, false, ""},
      {"ros2_raw_gyro.mcap", &gyro, ExportTarget::kRos2Mcap, SonarType::kOculus, false, "none"},
  };
  for (const Seed& s : seeds) {
    replay::ros::ExportOptions o;
    o.target = s.target;
    o.sonar = s.sonar;
    o.jpeg = s.jpeg;
    o.compression = s.compression;
    o.bag_chunk_bytes = 4096;  // several chunks
    const std::string rec = (tmp / s.name).string();
    auto r = replay::ros::export_fixture(*s.source, rec, o);
    if (!r) {
      std::cerr << s.name << ": " << r.error().message << "\n";
      return 2;
    }
    auto map = replay::ros::load_topic_map(r->topics_yaml);
    if (!map) {
      std::cerr << map.error().message << "\n";
      return 2;
    }
    replay::ros::ImportOptions io;
    io.map = *map;
    auto back = replay::ros::import_recording(rec, (tmp / "back.mcap").string(), io);
    if (!back) {
      std::cerr << s.name << " does not import: " << back.error().message << "\n";
      return 2;
    }
    std::cout << s.name << ": " << fs::file_size(rec) << " bytes, " << back->events << " events\n";
    fs::copy_file(rec, out / s.name, fs::copy_options::overwrite_existing);
  }
  fs::remove_all(tmp);
  std::cout << "orthosonar_import_fuzz_seeds: wrote " << std::size(seeds) << " recordings to " << out.string() << "\n";
  return 0;
}
