#pragma once
// Device emulators: serve a recorded or simulated event stream over the real protocols on
// loopback, at the recorded rate — the bytes a real device would send. One TCP server per
// device: Oculus SimplePingResult (after the client's SimpleFire, as the sonar does) plus UDP
// status datagrams, VN-100 binary, A50 JSON, $PRTI01 or RTI ensembles, $DEPTH lines, KVH DSP-1760 packets
// (gyro). Used in-process by the tests (ephemeral ports) and by `orthosonar emulate`.
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hal/drivers/device_config.hpp"

namespace orthosonar::hal::drivers {

// A device restart: at stream offset `at` the device closes its connection and listener and
// comes back `duration` later (stream time).
struct Outage {
  std::string device;
  Time at;
  Time duration;
};

struct EmulatorOptions {
  std::string address = "127.0.0.1";
  uint16_t base_port = 0;        // 0: ephemeral ports; else sonar_h, sonar_v, imu, dvl, depth, gyro = base+0..5
  double rate = 1.0;             // playback speed (2 = twice as fast as recorded)
  int oculus_version = 2;        // SimplePingResult V1 or V2
  bool dvl_prti01 = false;       // serve the DVL as Rowe $PRTI01 instead of A50 JSON
  bool dvl_rti_ensemble = false; // serve the DVL as Rowe RTI binary ensembles (over dvl_prti01)
  uint16_t status_port = oculus::kStatusUdpPort;  // Oculus status datagrams go to address:status_port
  int64_t status_period_ms = 1000;
  bool wait_for_clients = true;  // start the stream clock once every device has its client ...
  int64_t client_wait_ms = 10000;  // ... or after this long
  Quat q_V_imu = Quat::Identity();
  Quat q_V_dvl = Quat(0.0, 1.0, 0.0, 0.0);  // A50 frame (FRD) in V
  std::vector<Outage> outages;
};

struct EmulatedDeviceStats {
  std::string name;
  uint16_t port = 0;
  uint64_t frames = 0;       // frames in the schedule
  uint64_t sent = 0;         // frames written to a client
  uint64_t unsent = 0;       // no client connected (or device down) at the frame's time
  uint64_t clients = 0;      // connections accepted
  uint64_t fire_messages = 0;  // Oculus SimpleFire messages received
  int last_fire_version = 0;
};

class MissionEmulator {
 public:
  MissionEmulator(std::vector<Event> events, EmulatorOptions options);
  ~MissionEmulator();
  // Opens every listener (ports known after this) and starts serving.
  Status start();
  void stop();
  // True once every scheduled frame has been sent or skipped.
  bool finished() const;
  bool wait_finished(std::chrono::milliseconds timeout) const;
  // A devices.yaml-equivalent configuration pointing at this emulator's ports.
  LiveConfig live_config() const;
  // Where a sonar's status datagrams go (default options.status_port).
  void set_status_port(const std::string& device, uint16_t port);
  std::vector<EmulatedDeviceStats> stats() const;
  // The stream duration (last stamp - first stamp).
  Time duration() const { return duration_; }

 private:
  struct Server;
  void run_server(Server& s);
  EmulatorOptions options_;
  std::vector<std::unique_ptr<Server>> servers_;
  Time t0_stream_;
  Time duration_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> start_wall_ns_{-1};
  int64_t started_ns_ = 0;  // steady clock ns when the stream clock starts
};

}  // namespace orthosonar::hal::drivers
