#include "hal/drivers/emulator.hpp"

#include <algorithm>
#include <array>
#include <mutex>
#include <thread>

#include "hal/drivers/dsp1760.hpp"
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/socket.hpp"
#include "hal/drivers/vn100.hpp"

namespace orthosonar::hal::drivers {
namespace {

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Frame {
  Time offset;  // stream time since the first event
  Bytes bytes;
};

}  // namespace

struct MissionEmulator::Server {
  DeviceConfig config;
  uint16_t device_id = 0;
  std::vector<Frame> frames;
  Fd listener;
  Fd client;
  bool armed = false;  // Oculus: a SimpleFire was received on this connection
  uint16_t status_port = 0;
  std::thread thread;
  std::atomic<bool> done{false};
  std::atomic<bool> has_client{false};  // connected (and, for an Oculus, fired)
  mutable std::mutex mu;
  EmulatedDeviceStats stats;
  oculus::StreamParser fire_parser;
};

MissionEmulator::MissionEmulator(std::vector<Event> events, EmulatorOptions options) : options_(std::move(options)) {
  std::stable_sort(events.begin(), events.end(), event_before);
  t0_stream_ = events.empty() ? Time() : events.front().stamp;
  duration_ = events.empty() ? Time() : events.back().stamp - t0_stream_;
  const char* names[] = {"sonar_h", "sonar_v", "imu", "dvl", "depth", "gyro"};
  std::map<int, Server*> by_slot;
  auto server_for = [&](int slot) -> Server& {
    auto it = by_slot.find(slot);
    if (it != by_slot.end()) return *it->second;
    auto s = std::make_unique<Server>();
    s->config.name = names[slot];
    s->config.address = options_.address;
    s->config.port = options_.base_port ? static_cast<uint16_t>(options_.base_port + slot) : 0;
    s->config.kind = slot < 2 ? DeviceKind::kOculus
                     : slot == 2 ? DeviceKind::kVn100
                     : slot == 3 ? (options_.dvl_rti_ensemble ? DeviceKind::kRtiEnsemble
                                 : options_.dvl_prti01 ? DeviceKind::kPrti01
                                                       : DeviceKind::kA50)
                     : slot == 4 ? DeviceKind::kDepth
                                 : DeviceKind::kDsp1760;
    s->config.mount = slot == 1 ? SonarMount::kVertical : SonarMount::kHorizontal;
    s->config.q_V_S = slot == 2 ? options_.q_V_imu : slot == 3 ? options_.q_V_dvl : Quat::Identity();
    s->config.fire_version = options_.oculus_version;
    s->status_port = options_.status_port;
    s->stats.name = s->config.name;
    by_slot[slot] = s.get();
    servers_.push_back(std::move(s));
    return *servers_.back();
  };
  uint32_t dvl_sample = 0;
  for (const Event& e : events) {
    const Time off = e.stamp - t0_stream_;
    if (const auto* p = std::get_if<SonarPing>(&e.payload)) {
      Server& s = server_for(p->mount == SonarMount::kVertical ? 1 : 0);
      s.config.part_number = p->part_number;
      s.device_id = static_cast<uint16_t>(p->device_id);
      s.frames.push_back({off, oculus::encode_ping_result(oculus::ping_result_from(*p, options_.oculus_version, s.device_id))});
    } else if (const auto* r = std::get_if<ImuReading>(&e.payload)) {
      server_for(2).frames.push_back({off, vn100::encode_packet(vn100::message_from(*r, options_.q_V_imu))});
    } else if (const auto* d = std::get_if<DvlReading>(&e.payload)) {
      if (options_.dvl_rti_ensemble) {  // ensemble numbers from 1
        const rti::Ensemble ens = rti::ensemble_from(*d, options_.q_V_dvl, ++dvl_sample, off);
        server_for(3).frames.push_back({off, rti::encode_ensemble(ens)});
        continue;
      }
      const dvl::DvlVelocity v = dvl::velocity_from(*d, options_.q_V_dvl);
      const std::string line = options_.dvl_prti01
                                   ? dvl::encode_prti01(v, dvl_sample++, static_cast<uint32_t>(off.ns() / 10000000))
                                   : dvl::encode_a50_velocity(v, 200.0, off.ns() / 1000);  // json_v3.1, tov = stamp
      server_for(3).frames.push_back({off, Bytes(line.begin(), line.end())});
    } else if (const auto* z = std::get_if<DepthReading>(&e.payload)) {
      const std::string line = dvl::encode_depth_line(z->depth_m);
      server_for(4).frames.push_back({off, Bytes(line.begin(), line.end())});
    } else if (const auto* g = std::get_if<GyroReading>(&e.payload)) {
      // Configured as the fixture's gyro was (delta or rate), temperature in 1/100 degree C.
      Server& s = server_for(5);
      s.config.gyro.output = g->is_rate ? dsp1760::Output::kRate : dsp1760::Output::kDeltaAngle;
      s.config.gyro.temperature_unit = dsp1760::TemperatureUnit::kCentiCelsius;
      s.frames.push_back({off, dsp1760::encode_packet(dsp1760::packet_from(*g, s.config.gyro))});
    }
  }
  for (auto& s : servers_) s->stats.frames = s->frames.size();
}

MissionEmulator::~MissionEmulator() { stop(); }

Status MissionEmulator::start() {
  for (auto& s : servers_) {
    auto l = tcp_listen(options_.address, s->config.port);
    if (!l) return Error{"emulator " + s->config.name + ": " + l.error().message};
    s->listener = std::move(*l);
    s->config.port = local_port(s->listener);
    s->stats.port = s->config.port;
  }
  started_ns_ = steady_ns();
  if (!options_.wait_for_clients) start_wall_ns_.store(started_ns_);
  for (auto& s : servers_) {
    Server* raw = s.get();
    s->thread = std::thread([this, raw] { run_server(*raw); });
  }
  return Status::Ok();
}

void MissionEmulator::stop() {
  stop_.store(true);
  for (auto& s : servers_)
    if (s->thread.joinable()) s->thread.join();
}

void MissionEmulator::set_status_port(const std::string& device, uint16_t port) {
  for (auto& s : servers_)
    if (s->config.name == device) {
      std::lock_guard lock(s->mu);
      s->status_port = port;
    }
}

bool MissionEmulator::finished() const {
  return std::all_of(servers_.begin(), servers_.end(), [](const auto& s) { return s->done.load(); });
}

bool MissionEmulator::wait_finished(std::chrono::milliseconds timeout) const {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!finished()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

LiveConfig MissionEmulator::live_config() const {
  LiveConfig c;
  for (const auto& s : servers_) {
    DeviceConfig d = s->config;
    d.listen_status = true;
    d.status_port = 0;  // ephemeral status ports, wired by the caller (set_status_port)
    c.devices.push_back(d);
  }
  return c;
}

std::vector<EmulatedDeviceStats> MissionEmulator::stats() const {
  std::vector<EmulatedDeviceStats> out;
  for (const auto& s : servers_) {
    std::lock_guard lock(s->mu);
    out.push_back(s->stats);
  }
  return out;
}

void MissionEmulator::run_server(Server& s) {
  auto udp = udp_socket();
  int64_t next_status_ns = 0;
  size_t next = 0;
  bool down = false;
  std::array<uint8_t, 4096> buf;
  const bool is_oculus = s.config.kind == DeviceKind::kOculus;
  auto ready = [&] { return s.client.valid() && (!is_oculus || s.armed); };
  auto stream_now = [&]() -> Time {
    const int64_t w0 = start_wall_ns_.load();
    if (w0 < 0) return Time::min();
    return Time::from_ns(static_cast<int64_t>(static_cast<double>(steady_ns() - w0) * options_.rate));
  };
  while (!stop_.load()) {
    const Time now = stream_now();
    // Outages (device restarts).
    bool in_outage = false;
    for (const auto& o : options_.outages)
      if (o.device == s.config.name && now >= o.at && now < o.at + o.duration) in_outage = true;
    if (in_outage && !down) {
      s.client.reset();
      s.listener.reset();
      down = true;
    } else if (!in_outage && down) {
      auto l = tcp_listen(options_.address, s.config.port);
      if (l) {
        s.listener = std::move(*l);
        down = false;
      }
    }
    // Accept a (new) client.
    if (!down && !s.client.valid() && s.listener.valid()) {
      auto c = tcp_accept(s.listener, std::chrono::milliseconds(0));
      if (c && c->valid()) {
        s.client = std::move(*c);
        s.armed = false;
        s.fire_parser = oculus::StreamParser();
        std::lock_guard lock(s.mu);
        ++s.stats.clients;
      }
    }
    // Read what the client sends (Oculus fire messages); detect a closed client.
    if (s.client.valid() && wait_readable(s.client, std::chrono::milliseconds(0))) {
      auto n = read_some(s.client, buf);
      if (!n || *n == 0) {
        s.client.reset();
      } else if (is_oculus) {
        s.fire_parser.push(std::span<const uint8_t>(buf.data(), *n));
        while (auto m = s.fire_parser.pop()) {
          if (const auto* f = std::get_if<oculus::FireMessage>(&*m)) {
            s.armed = true;
            std::lock_guard lock(s.mu);
            ++s.stats.fire_messages;
            s.stats.last_fire_version = f->header.msg_version == 2 ? 2 : 1;
          }
        }
      }
    }
    // Status broadcast.
    if (is_oculus && udp && !down && steady_ns() >= next_status_ns) {
      oculus::StatusMessage st;
      st.header.src_device_id = s.device_id;
      st.device_id = s.device_id;
      st.part_number = s.config.part_number;
      st.ip_addr = 0x0100007F;
      uint16_t port;
      {
        std::lock_guard lock(s.mu);
        port = s.status_port;
      }
      if (port != 0) (void)udp_send_to(*udp, options_.address, port, oculus::encode_status(st));
      next_status_ns = steady_ns() + options_.status_period_ms * 1000000;
    }
    s.has_client.store(ready());
    if (now == Time::min()) {
      const bool all = std::all_of(servers_.begin(), servers_.end(), [](const auto& x) { return x->has_client.load(); });
      if (all || steady_ns() - started_ns_ > options_.client_wait_ms * 1000000) {
        int64_t expected = -1;
        start_wall_ns_.compare_exchange_strong(expected, steady_ns());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    // Send every frame that is due.
    while (next < s.frames.size() && s.frames[next].offset <= now) {
      bool sent = false;
      if (ready()) {
        sent = write_all(s.client, s.frames[next].bytes, std::chrono::milliseconds(2000)).ok();
        if (!sent) s.client.reset();
      }
      std::lock_guard lock(s.mu);
      ++(sent ? s.stats.sent : s.stats.unsent);
      ++next;
    }
    if (next >= s.frames.size()) s.done.store(true);
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  s.done.store(true);
}

}  // namespace orthosonar::hal::drivers
