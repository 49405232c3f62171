#include "hal/sim/embree_device.hpp"

#include <embree3/rtcore.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

namespace orthosonar::sim {
namespace {

// Runs fn with file descriptor 1 (std::cout and stdout) sent to a temporary file; returns
// what was written there.
template <class Fn>
std::string capture_stdout(Fn&& fn) {
  std::cout.flush();
  std::fflush(stdout);
  std::FILE* tmp = std::tmpfile();
  if (tmp == nullptr) {
    fn();
    return {};
  }
  const int saved = ::dup(1);
  ::dup2(::fileno(tmp), 1);
  fn();
  std::cout.flush();
  std::fflush(stdout);
  ::dup2(saved, 1);
  ::close(saved);
  std::string text;
  std::rewind(tmp);
  char buf[4096];
  size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, tmp)) > 0) text.append(buf, n);
  std::fclose(tmp);
  return text;
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

}  // namespace

EmbreeIsaReport embree_isa_report() {
  EmbreeIsaReport r;
  r.config = kEmbreeDeviceConfig;
  RTCError err = RTC_ERROR_NONE;
  bool created = false;
  const std::string log = capture_stdout([&] {
    const std::string cfg = std::string(kEmbreeDeviceConfig) + ",verbose=2";
    RTCDevice device = rtcNewDevice(cfg.c_str());
    err = rtcGetDeviceError(device);
    if (device == nullptr) return;
    created = true;
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3));
    auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 1));
    const float verts[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i) v[i] = verts[i];
    ix[0] = 0;
    ix[1] = 1;
    ix[2] = 2;
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  });
  if (!created || err != RTC_ERROR_NONE) {
    r.error = "rtcNewDevice(\"" + r.config + "\") failed, error " + std::to_string(static_cast<int>(err));
    return r;
  }
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (r.cpu_targets.empty() && t.rfind("Targets", 0) == 0) {  // the CPU's line comes first
      const auto colon = t.find(':');
      if (colon != std::string::npos) r.cpu_targets = trim(t.substr(colon + 1));
    }
    if (r.intersector.empty() && t.rfind("intersector1", 0) == 0) {
      const auto eq = t.find('=');
      if (eq != std::string::npos) r.intersector = trim(t.substr(eq + 1));
    }
  }
  const auto sep = r.intersector.find("::");
  if (sep != std::string::npos) r.isa = r.intersector.substr(0, sep);
  r.ok = r.isa == kEmbreePinnedIsa;
  if (!r.ok) r.error = r.intersector.empty() ? "Embree reported no intersector" : "Embree selected " + r.intersector;
  return r;
}

}  // namespace orthosonar::sim
