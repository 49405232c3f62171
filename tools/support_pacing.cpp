#include "tools/support_pacing.hpp"

#include <cmath>
#include <sstream>
#include <thread>

namespace orthosonar::cli {

PacedSource::PacedSource(std::unique_ptr<hal::EventSource> inner, double rate)
    : inner_(std::move(inner)), rate_(rate > 0 ? rate : 1.0) {}

hal::Pulled PacedSource::next() {
  hal::Pulled p = inner_->next();
  if (!p.event) return p;
  const Time stamp = p.event->stamp;
  if (!first_stamp_) {
    first_stamp_ = stamp;
    wall_start_ = std::chrono::steady_clock::now();
    return p;
  }
  const double wall_ns = static_cast<double>((stamp - *first_stamp_).ns()) / rate_;
  if (wall_ns > 0) {
    const auto due = wall_start_ + std::chrono::nanoseconds(static_cast<int64_t>(std::llround(wall_ns)));
    std::this_thread::sleep_until(due);
  }
  return p;
}

std::string PacedSource::describe() const {
  std::ostringstream s;
  s << inner_->describe() << " @" << rate_ << "x";
  return s.str();
}

std::unique_ptr<hal::EventSource> paced(std::unique_ptr<hal::EventSource> source, double rate) {
  if (rate <= 0) return source;
  return std::make_unique<PacedSource>(std::move(source), rate);
}

}  // namespace orthosonar::cli
