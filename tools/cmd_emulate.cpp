// `orthosonar emulate f.mcap`: serves a fixture's sensor data over the real device protocols
// on loopback at the recorded rate (Oculus TCP pings + UDP status, VN-100 binary, A50 JSON or
// $PRTI01, $DEPTH lines, DSP-1760 gyro packets) and writes the devices.yaml that `orthosonar
// run` connects with.
#include <atomic>
#include <csignal>
#include <fstream>
#include <iostream>
#include <thread>

#include "hal/drivers/emulator.hpp"
#include "replay/fixture/fixture.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {
namespace {

std::atomic<bool> g_emulate_stop{false};
extern "C" void emulate_on_signal(int) { g_emulate_stop.store(true); }

struct EmulateArgs {
  std::string fixture;
  double rate = 1.0;
  uint16_t base_port = 0;
  std::string address = "127.0.0.1";
  int oculus_version = 2;
  bool prti01 = false;
  bool rti_ensemble = false;
  int status_port = hal::drivers::oculus::kStatusUdpPort;
  std::string devices_out;
  double linger_s = 2.0;
  bool no_wait = false;
  std::vector<std::string> outages;
};

int run_emulate(const EmulateArgs& a) {
  using namespace hal::drivers;
  auto src = replay::FixtureSource::open(a.fixture);
  if (!src) {
    std::cerr << "orthosonar emulate: " << src.error().message << "\n";
    return 2;
  }
  std::vector<Event> events;
  for (auto p = (*src)->next(); !p.end_of_stream; p = (*src)->next()) {
    if (p.error) {
      std::cerr << "orthosonar emulate: " << p.error->message << "\n";
      return 2;
    }
    if (p.event) events.push_back(std::move(*p.event));
  }
  if (!(a.rate > 0)) {
    std::cerr << "orthosonar emulate: --rate must be positive\n";
    return 2;
  }
  EmulatorOptions o;
  o.address = a.address;
  o.base_port = a.base_port;
  o.rate = a.rate;
  o.oculus_version = a.oculus_version;
  o.dvl_prti01 = a.prti01;
  o.dvl_rti_ensemble = a.rti_ensemble;
  o.status_port = static_cast<uint16_t>(a.status_port);
  o.wait_for_clients = !a.no_wait;
  for (const auto& spec : a.outages) {  // device:at_s:duration_s
    const auto c1 = spec.find(':');
    const auto c2 = spec.rfind(':');
    if (c1 == std::string::npos || c2 == c1) {
      std::cerr << "orthosonar emulate: --outage wants device:at_s:duration_s, got '" << spec << "'\n";
      return 2;
    }
    try {
      o.outages.push_back({spec.substr(0, c1), Time::from_seconds(std::stod(spec.substr(c1 + 1, c2 - c1 - 1))),
                           Time::from_seconds(std::stod(spec.substr(c2 + 1)))});
    } catch (...) {
      std::cerr << "orthosonar emulate: bad --outage '" << spec << "'\n";
      return 2;
    }
  }
  MissionEmulator emu(std::move(events), o);
  if (Status s = emu.start(); !s.ok()) {
    std::cerr << "orthosonar emulate: " << s.error().message << "\n";
    return 2;
  }
  LiveConfig lc = emu.live_config();
  for (auto& d : lc.devices) {
    d.listen_status = a.status_port != 0;
    d.status_port = static_cast<uint16_t>(a.status_port);
  }
  const std::string yaml = to_yaml(lc);
  if (!a.devices_out.empty()) {
    const std::string tmp = a.devices_out + ".tmp";
    std::ofstream(tmp) << yaml;
    std::rename(tmp.c_str(), a.devices_out.c_str());  // appears complete or not at all
  }
  std::cout << yaml << std::flush;
  std::cerr << "emulating " << a.fixture << " (" << emu.duration().seconds() << " s at " << a.rate
            << "x); Ctrl-C to stop\n";
  std::signal(SIGINT, emulate_on_signal);
  std::signal(SIGTERM, emulate_on_signal);
  while (!g_emulate_stop.load() && !emu.finished()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto linger_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int64_t>(a.linger_s * 1000));
  while (!g_emulate_stop.load() && std::chrono::steady_clock::now() < linger_until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  emu.stop();
  for (const auto& s : emu.stats())
    std::cerr << s.name << " port " << s.port << ": sent " << s.sent << " of " << s.frames << " (" << s.unsent
              << " with no client), clients " << s.clients << ", fire messages " << s.fire_messages << "\n";
  return 0;
}

const bool registered_emulate = register_command(
    {"emulate", "Serve a fixture's data over the real device protocols on loopback (device emulators)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<EmulateArgs>();
       sub.add_option("fixture", a->fixture, "Fixture (.mcap) to serve")->required();
       sub.add_option("--rate", a->rate, "Playback speed factor (1 = recorded rate)")->capture_default_str();
       sub.add_option("--base-port", a->base_port,
                      "First TCP port: sonar_h, sonar_v, imu, dvl, depth, gyro = P..P+5 (0: ephemeral ports)")
           ->capture_default_str();
       sub.add_option("--address", a->address, "Address to listen on")->capture_default_str();
       sub.add_option("--oculus-version", a->oculus_version, "SimplePingResult version 1 or 2")
           ->check(CLI::IsMember({1, 2}))->capture_default_str();
       sub.add_flag("--prti01", a->prti01, "Serve the DVL as Rowe $PRTI01 instead of Water Linked A50 JSON");
       sub.add_flag("--rti-ensemble", a->rti_ensemble,
                    "Serve the DVL as Rowe RTI binary ensembles (bottom track) instead of A50 JSON")
           ->excludes("--prti01");
       sub.add_option("--status-port", a->status_port, "UDP port for Oculus status datagrams (0: none)")
           ->check(CLI::Range(0, 65535))->capture_default_str();
       sub.add_option("--devices-out", a->devices_out, "Write the devices.yaml for `orthosonar run` here");
       sub.add_option("--linger", a->linger_s, "Seconds to keep connections open after the last frame")->capture_default_str();
       sub.add_flag("--no-wait", a->no_wait, "Start the stream clock at once instead of when every device has a client");
       sub.add_option("--outage", a->outages, "Simulate a device restart: device:at_s:duration_s (stream time)");
       return [a] { return run_emulate(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
