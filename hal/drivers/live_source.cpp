#include "hal/drivers/live_source.hpp"

#include <algorithm>
#include <condition_variable>
#include <nlohmann/json.hpp>

namespace orthosonar::hal::drivers {

struct LiveSource::Link {
  explicit Link(const DeviceConfig& c, const ReconnectPolicy& p) : device(c, p) {}
  DriverDevice device;
  std::thread thread;
  mutable std::mutex mu;  // guards report and device health snapshots
  DeviceReport report;
  DeviceHealth health;
  uint16_t status_port = 0;
};

LiveSource::LiveSource(LiveConfig config, Clock clock) : config_(std::move(config)), queue_(std::move(clock), config_.queue) {}

LiveSource::~LiveSource() {
  stop_.store(true);
  queue_.close();
  for (auto& l : links_)
    if (l->thread.joinable()) l->thread.join();
}

Status LiveSource::start() {
  if (config_.devices.empty()) return Error{"live: no devices configured"};
  for (const auto& d : config_.devices) {
    auto link = std::make_unique<Link>(d, config_.reconnect);
    link->report.name = d.name;
    link->report.kind = kind_name(d.kind);
    links_.push_back(std::move(link));
  }
  for (auto& l : links_) {
    // Bind the status listener now so emulators/tests can learn the port before data flows.
    if (auto s = l->device.listen_status(); !s.ok()) l->health.last_error = s.error().message;
    l->status_port = l->device.status_port();
    Link* raw = l.get();
    l->thread = std::thread([this, raw] { run_link(*raw); });
  }
  return Status::Ok();
}

void LiveSource::run_link(Link& link) {
  const ReconnectPolicy& p = config_.reconnect;
  int64_t backoff_ms = p.initial_backoff_ms;
  bool ever_connected = false;
  auto sleep_interruptible = [&](int64_t ms) {
    const Time until = queue_.now() + Time::from_ms(ms);
    while (!stop_.load() && queue_.now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(std::min<int64_t>(ms, 20)));
  };
  auto snapshot = [&] {
    std::lock_guard lock(link.mu);
    link.health = link.device.health();
    link.report.part_number = link.device.part_number();
  };
  while (!stop_.load()) {
    Status s = link.device.connect();
    snapshot();
    if (!s.ok()) {
      {
        std::lock_guard lock(link.mu);
        ++link.report.connect_failures;
        link.health.last_error = s.error().message;
      }
      sleep_interruptible(backoff_ms);
      backoff_ms = std::min(backoff_ms * 2, p.max_backoff_ms);
      continue;
    }
    backoff_ms = p.initial_backoff_ms;
    {
      std::lock_guard lock(link.mu);
      if (ever_connected) {
        ++link.report.health.reconnects;
        if (!link.report.gaps.empty() && link.report.gaps.back().to == Time::max()) link.report.gaps.back().to = queue_.now();
      }
    }
    ever_connected = true;
    Time last_data = queue_.now();
    std::string reason;
    while (!stop_.load()) {
      link.device.wait(std::chrono::milliseconds(20));
      auto r = link.device.read();
      if (!r) {
        reason = r.error().message;
        break;
      }
      if (!r->empty()) last_data = queue_.now();
      for (auto& payload : *r) queue_.push(std::move(payload));
      if (queue_.now() - last_data > Time::from_ms(p.silence_timeout_ms)) {
        reason = "no data for " + std::to_string(p.silence_timeout_ms) + " ms";
        link.device.disconnect();
        break;
      }
      snapshot();
    }
    snapshot();
    if (stop_.load()) break;
    {
      std::lock_guard lock(link.mu);
      link.report.gaps.push_back(LinkGap{queue_.now(), Time::max(), reason});
      link.health.last_error = reason;
    }
  }
  link.device.disconnect();
  snapshot();
}

Pulled LiveSource::next() {
  if (ended_) return Pulled::end();
  for (;;) {
    if (stop_.load() || queue_.now().ns() >= deadline_ns_.load()) {
      ended_ = true;
      queue_.close();
      return Pulled::end();
    }
    auto e = queue_.pop(std::chrono::milliseconds(20));
    if (e) {
      if (e->stamp.ns() >= deadline_ns_.load()) continue;  // arrived after the deadline: not consumed
      ++consumed_;
      return Pulled::of(std::move(*e));
    }
  }
}

LiveReport LiveSource::report() const {
  LiveReport r;
  for (const auto& l : links_) {
    std::lock_guard lock(l->mu);
    DeviceReport d = l->report;
    const uint64_t reconnects = d.health.reconnects;
    d.health = l->health;
    d.health.reconnects = reconnects;
    r.devices.push_back(std::move(d));
  }
  r.queue = queue_.stats();
  r.policy = config_.queue;
  r.events_consumed = consumed_;
  return r;
}

uint16_t LiveSource::status_port(const std::string& device) const {
  for (const auto& l : links_) {
    std::lock_guard lock(l->mu);
    if (l->report.name == device) return l->status_port;
  }
  return 0;
}

std::string report_json(const LiveReport& r) {
  nlohmann::json j;
  j["events_consumed"] = r.events_consumed;
  j["queue"] = {{"policy", {{"sonar_capacity", r.policy.sonar_capacity}, {"nav_capacity", r.policy.nav_capacity},
                            {"overflow", "drop oldest sonar ping; navigation never dropped for sonar"}}},
                {"max_depth", r.queue.max_depth}};
  for (int c = 0; c < kChannelCount; ++c) {
    const auto i = static_cast<size_t>(c);
    if (r.queue.pushed[i] == 0 && r.queue.dropped[i] == 0) continue;
    j["queue"]["channels"][channel_topic(static_cast<Channel>(c))] = {{"received", r.queue.pushed[i]}, {"dropped", r.queue.dropped[i]}};
  }
  j["devices"] = nlohmann::json::array();
  for (const auto& d : r.devices) {
    nlohmann::json gaps = nlohmann::json::array();
    for (const auto& g : d.gaps)
      gaps.push_back({{"from_ns", g.from.ns()}, {"to_ns", g.to == Time::max() ? nlohmann::json() : nlohmann::json(g.to.ns())}, {"reason", g.reason}});
    j["devices"].push_back({{"name", d.name}, {"kind", d.kind}, {"connected", d.health.connected},
                            {"messages_ok", d.health.messages_ok}, {"messages_malformed", d.health.messages_malformed},
                            {"sequence_gaps", d.health.sequence_gaps},
                            {"reconnects", d.health.reconnects}, {"connect_failures", d.connect_failures},
                            {"part_number", d.part_number}, {"last_error", d.health.last_error}, {"gaps", gaps}});
  }
  return j.dump(2);
}

}  // namespace orthosonar::hal::drivers
