#pragma once
// Helpers shared by the drivers' tests (header-only; included from *_test.cpp only).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/events.hpp"
#include "hal/fake_source.hpp"

namespace orthosonar::hal::drivers::testing {

// The repository's own test data (testdata/ at the top of the source tree, with the
// licence and provenance of each capture). The test main sets ORTHOSONAR_SOURCE; a missing
// file is an error that fails the test, never a silent skip.
inline std::string testdata(const std::string& relative) {
  const char* s = std::getenv("ORTHOSONAR_SOURCE");
  if (s == nullptr || *s == '\0') throw std::runtime_error("ORTHOSONAR_SOURCE is not set: cannot find testdata/");
  const std::filesystem::path p = std::filesystem::path(s) / "testdata" / relative;
  if (!std::filesystem::is_regular_file(p)) throw std::runtime_error("missing test data file " + p.string());
  return p.string();
}

inline std::filesystem::path test_out(const std::string& name) {
  const char* s = std::getenv("ORTHOSONAR_TEST_OUT");
  std::filesystem::path dir = s ? std::filesystem::path(s) : std::filesystem::temp_directory_path() / "orthosonar_test_out";
  dir /= "drivers";
  std::filesystem::create_directories(dir);
  return dir / name;
}

inline std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A small sonar ping with a deterministic image (reduced resolution).
inline SonarPing small_ping(SonarMount mount, uint32_t id, Time stamp, uint16_t rows = 40, uint16_t cols = 32,
                            uint8_t bpp = 1) {
  SonarPing p;
  p.device_id = mount == SonarMount::kHorizontal ? 11 : 12;
  p.part_number = mount == SonarMount::kHorizontal ? kPartM750d : kPartM1200d;
  p.mount = mount;
  p.stamp = stamp;
  p.ping_id = id;
  p.range_resolution_m = 0.05;
  p.frequency_hz = 1.2e6;
  p.gain_percent = 50.0;
  p.rows = rows;
  p.cols = cols;
  p.bytes_per_pixel = bpp;
  for (uint16_t c = 0; c < cols; ++c) {
    // Bearings exactly representable in 1/100 degree so round trips are exact in value.
    const double centideg = -6500.0 + 13000.0 * c / (cols - 1);
    p.bearings_rad.push_back(static_cast<double>(static_cast<int>(centideg)) / 100.0 * 3.14159265358979323846 / 180.0);
  }
  p.image.resize(static_cast<size_t>(rows) * cols * bpp);
  for (size_t i = 0; i < p.image.size(); ++i) p.image[i] = static_cast<uint8_t>((i * 37 + id * 11) & 0xFF);
  return p;
}

// A short synthetic mission: both sonars at 5 Hz (the vertical 3 ms after the horizontal),
// IMU at 50 Hz, DVL and depth at 5 Hz, a slow yawing turn. Reduced-resolution images.
inline std::vector<Event> synthetic_mission(int64_t duration_ms, uint16_t rows = 40, uint16_t cols = 32) {
  std::vector<Payload> p;
  for (int64_t t = 0; t <= duration_ms; t += 20) {
    ImuReading r;
    r.stamp = Time::from_ms(t);
    r.q_W_V = Quat(Eigen::AngleAxisd(0.0005 * static_cast<double>(t), Vec3::UnitZ()));
    r.angular_velocity_V = Vec3(0.0, 0.0, 0.5);
    r.linear_acceleration_V = Vec3(0.0, 0.0, 9.81);
    p.emplace_back(r);
    if (t % 200 == 0) {
      const auto id = static_cast<uint32_t>(t / 200);
      p.emplace_back(small_ping(SonarMount::kHorizontal, id, Time::from_ms(t), rows, cols));
      p.emplace_back(small_ping(SonarMount::kVertical, id, Time::from_ms(t + 3), rows, cols));
      DvlReading d;
      d.stamp = Time::from_ms(t + 1);
      d.velocity_V_mps = Vec3(0.4, 0.01 * static_cast<double>(id % 3), 0.0);
      d.valid = id % 7 != 6;
      d.altitude_m = 5.0;
      p.emplace_back(d);
      p.emplace_back(DepthReading{Time::from_ms(t + 2), 3.0 + 0.001 * static_cast<double>(id)});
    }
  }
  return make_events(p);
}

inline size_t count_channel(const std::vector<Event>& events, Channel c) {
  size_t n = 0;
  for (const auto& e : events) n += e.channel == c;
  return n;
}

}  // namespace orthosonar::hal::drivers::testing
