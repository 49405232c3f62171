// libFuzzer harness: `orthosonar import` end to end on a whole recording (a ROS 1 bag or a
// ROS 2 / ROS 1 MCAP file, told apart by its magic as the command does): the container
// readers, the file's own message definitions, both decoding passes, every role's converter
// (raw, JPEG/PNG and ProjectedSonarImage pings, IMU, DVL, depth, truth, gyro) and the fixture
// writer. An input may be rejected with an error, never crash. (`import --list` reads the
// same containers without decoding; leaving it out keeps the executions per second up.)
// The topic map is the authors' topics plus the standard types' (what `orthosonar export`
// writes with and without --projected), in one of three variants
// chosen by the input's size modulo 3, so that one corpus reaches every converter branch:
// as is (header stamps), NED/FRD axes with receive stamps, or flipped bearings with the
// sonars' part numbers and a FluidPressure calibration from the map.
// Seeds: testdata/fuzz/ros_import/ (README there says how they were made).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include "hal/fuzz_support.hpp"
#include "replay/ros/import.hpp"

using namespace orthosonar;
using namespace orthosonar::replay::ros;

namespace {

// The fixture import writes (and its ".partial" while writing): one per process, removed
// after every input and at exit.
struct RosImportFuzzOutput {
  std::string path;
  RosImportFuzzOutput() {
    const char* dir = std::getenv("TMPDIR");
    path = std::string(dir && *dir ? dir : "/tmp") + "/orthosonar_fuzz_" + std::to_string(::getpid()) +
           "_import.mcap";
  }
  ~RosImportFuzzOutput() { clear(); }
  void clear() const {
    std::remove(path.c_str());
    std::remove((path + ".partial").c_str());
  }
};

ImportOptions ros_import_fuzz_options(size_t variant) {
  ImportOptions o;
  auto map = parse_topic_map(
      "topics:\n"
      "  /oculus_m750d/sonar_image: horizontal_sonar\n"
      "  /oculus_m1200d/sonar_image: vertical_sonar\n"
      "  /imu/data: imu\n"
      "  /dvl/twist: dvl\n"
      "  /pressure: depth\n",
      "ros_import_fuzz.yaml");
  if (!map.ok()) std::abort();  // a harness failure, not a finding
  o.map = *map;
  o.writer.compress = false;  // the writer is not under test; uncompressed is faster
  for (TopicRule& r : o.map.rules) {
    if (variant == 1) {
      r.convention = Convention::kNedFrd;
      r.stamp = StampSource::kReceive;
    } else if (variant == 2) {
      r.flip_bearings = true;
      r.part_number = r.role == Role::kVerticalSonar ? 0 : 0x1234;
      r.fluid_density_kg_m3 = 997.0;
      r.atmospheric_pressure_pa = 0.0;
    }
  }
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile in(".rec");
  static const RosImportFuzzOutput out;
  static const ImportOptions options[3] = {ros_import_fuzz_options(0), ros_import_fuzz_options(1),
                                           ros_import_fuzz_options(2)};
  const std::string& path = in.write(data, size);
  const ImportOptions& o = options[size % 3];
  auto report = import_recording(path, out.path, o);
  out.clear();
  const uint64_t seen = report.ok() ? report->events + report->input.topics.size() : report.error().message.size();
  (void)seen;
  return 0;
}
