#pragma once
// Live device configuration (devices.yaml, see docs/DRIVERS.md): which devices, where, how
// they are mounted, and the reconnect and queue policies.
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/drivers/dsp1760.hpp"
#include "hal/drivers/live_queue.hpp"
#include "hal/drivers/oculus_protocol.hpp"

namespace orthosonar::hal::drivers {

enum class DeviceKind { kOculus, kVn100, kA50, kPrti01, kDepth, kDsp1760, kRtiEnsemble };
const char* kind_name(DeviceKind k);
Result<DeviceKind> kind_from_name(const std::string& s);

struct DeviceConfig {
  std::string name;
  DeviceKind kind = DeviceKind::kOculus;
  std::string address = "127.0.0.1";  // Oculus: "auto" = discover from the UDP status broadcast
  uint16_t port = 0;
  std::string serial_path;            // VN-100 / PRTI01 / DSP-1760 over a serial port instead of TCP
  int baud = 115200;
  // Oculus.
  SonarMount mount = SonarMount::kHorizontal;
  uint16_t part_number = 0;           // 0: take it from the status message
  int fire_version = 2;               // SimpleFire V1 or V2
  oculus::FireConfig fire;
  bool listen_status = true;           // UDP status listener (part number, discovery)
  uint16_t status_port = oculus::kStatusUdpPort;  // 0 with listen_status: an ephemeral port (tests)
  // IMU / DVL mounting rotation of the sensor frame in V (roll, pitch, yaw in radians).
  Quat q_V_S = Quat::Identity();
  // KVH DSP-1760: what the gyro was configured to send (its readings stay in its frame G).
  dsp1760::Config gyro;
};

struct ReconnectPolicy {
  int64_t initial_backoff_ms = 100;   // doubled after each failed attempt ...
  int64_t max_backoff_ms = 5000;      // ... up to this
  int64_t connect_timeout_ms = 1000;
  int64_t silence_timeout_ms = 5000;  // no bytes for this long on a connected link = dropped
};

struct LiveConfig {
  std::vector<DeviceConfig> devices;
  QueuePolicy queue;
  ReconnectPolicy reconnect;
};

// Parses devices.yaml text (errors name the device and key).
Result<LiveConfig> parse_live_config(const std::string& yaml_text);
Result<LiveConfig> load_live_config(const std::string& path);
// A devices.yaml for the given config (what `orthosonar emulate` prints for its ports).
std::string to_yaml(const LiveConfig& config);

}  // namespace orthosonar::hal::drivers
