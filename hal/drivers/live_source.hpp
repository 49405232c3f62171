#pragma once
// The live EventSource: one thread per configured device (DriverDevice) feeding the bounded
// LiveQueue, with reconnects on exponential backoff. Events come out in arrival order with
// stamps from the tool's clock (strictly increasing) and per-channel sequences 0, 1, ...
// Faults are values: link gaps, reconnects, malformed counts and queue drops are in report().
#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "hal/drivers/device_config.hpp"
#include "hal/drivers/driver_device.hpp"
#include "hal/event_source.hpp"

namespace orthosonar::hal::drivers {

struct LinkGap {
  Time from;                 // when the link was lost (clock)
  Time to = Time::max();     // when it came back (Time::max() while still down)
  std::string reason;
};

struct DeviceReport {
  std::string name;
  std::string kind;
  DeviceHealth health;
  uint64_t connect_failures = 0;
  uint16_t part_number = 0;
  std::vector<LinkGap> gaps;
};

struct LiveReport {
  std::vector<DeviceReport> devices;
  QueueStats queue;
  QueuePolicy policy;
  uint64_t events_consumed = 0;
};
// The report as JSON (stamps in ns; "open" gaps have "to_ns": null).
std::string report_json(const LiveReport& r);

class LiveSource final : public EventSource {
 public:
  explicit LiveSource(LiveConfig config, Clock clock = monotonic_clock_from_now());
  ~LiveSource() override;
  // Starts one thread per device. Oculus status listeners are bound before this returns.
  Status start();
  // The next consumed event; end of stream after stop() or once the clock passes the deadline.
  Pulled next() override;
  std::string describe() const override { return "live:" + std::to_string(config_.devices.size()) + " devices"; }
  // Thread-safe and async-signal-safe (sets a flag).
  void stop() { stop_.store(true); }
  void set_deadline(Time t) { deadline_ns_.store(t.ns()); }
  Time now() const { return queue_.now(); }
  LiveReport report() const;
  // The bound UDP status port of a device (tests use ephemeral ports); 0 when none.
  uint16_t status_port(const std::string& device) const;

 private:
  struct Link;
  void run_link(Link& link);
  LiveConfig config_;
  LiveQueue queue_;
  std::vector<std::unique_ptr<Link>> links_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> deadline_ns_{Time::max().ns()};
  uint64_t consumed_ = 0;
  bool ended_ = false;
};

}  // namespace orthosonar::hal::drivers
