#include "hal/drivers/decoders.hpp"

#include "hal/drivers/dsp1760.hpp"
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/vn100.hpp"

namespace orthosonar::hal::drivers {
namespace {

class OculusDecoder final : public Decoder {
 public:
  explicit OculusDecoder(const DeviceConfig& c) : c_(c), part_(c.part_number) {}
  void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) override {
    parser_.push(bytes);
    while (auto m = parser_.pop()) {
      const auto* p = std::get_if<oculus::PingResult>(&*m);
      if (!p) continue;  // status echoes, acknowledgements: not events
      auto s = oculus::to_sonar_ping(*p, c_.mount, part_, Time());
      if (!s) {
        ++rejected_;
        last_error_ = s.error().message;
        continue;
      }
      ++pings_;
      out.emplace_back(std::move(*s));
    }
  }
  uint64_t messages() const override { return pings_; }
  uint64_t malformed() const override { return parser_.stats().malformed + rejected_; }
  std::string last_error() const override { return last_error_.empty() ? parser_.last_error() : last_error_; }
  Bytes greeting() const override { return oculus::encode_fire(c_.fire, c_.fire_version, 0, 0); }
  bool on_status(std::span<const uint8_t> d) override {
    auto s = oculus::parse_status(d);
    if (!s) return false;
    if (c_.part_number == 0) part_ = s->part_number;
    return true;
  }
  uint16_t part_number() const override { return part_; }

 private:
  DeviceConfig c_;
  uint16_t part_;
  oculus::StreamParser parser_;
  uint64_t pings_ = 0, rejected_ = 0;
  std::string last_error_;
};

class Vn100Decoder final : public Decoder {
 public:
  explicit Vn100Decoder(const DeviceConfig& c) : q_V_S_(c.q_V_S) {}
  void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) override {
    parser_.push(bytes);
    while (auto m = parser_.pop()) {
      auto r = vn100::to_imu_reading(*m, q_V_S_, Time());
      if (!r) {
        ++rejected_;
        last_error_ = r.error().message;
        continue;
      }
      ++ok_;
      out.emplace_back(*r);
    }
  }
  uint64_t messages() const override { return ok_; }
  uint64_t malformed() const override { return parser_.malformed() + rejected_; }
  std::string last_error() const override { return last_error_.empty() ? parser_.last_error() : last_error_; }

 private:
  Quat q_V_S_;
  vn100::StreamParser parser_;
  uint64_t ok_ = 0, rejected_ = 0;
  std::string last_error_;
};

// KVH DSP-1760: every packet with a good CRC is a GyroReading (invalid ones included, marked).
class Dsp1760Decoder final : public Decoder {
 public:
  explicit Dsp1760Decoder(const DeviceConfig& c) : config_(c.gyro) {}
  void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) override {
    parser_.push(bytes);
    while (auto p = parser_.pop()) out.emplace_back(dsp1760::to_gyro_reading(*p, config_, Time()));
  }
  uint64_t messages() const override { return parser_.messages(); }
  uint64_t malformed() const override { return parser_.malformed(); }
  uint64_t sequence_gaps() const override { return parser_.stats().sequence_gaps; }
  std::string last_error() const override { return parser_.last_error(); }

 private:
  dsp1760::Config config_;
  dsp1760::StreamParser parser_;
};

// Rowe RTI binary ensembles: an ensemble with a bottom-track data set is a DvlReading (invalid
// velocities included, marked); ensembles without one are not events.
class RtiEnsembleDecoder final : public Decoder {
 public:
  explicit RtiEnsembleDecoder(const DeviceConfig& c) : q_V_S_(c.q_V_S) {}
  void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) override {
    parser_.push(bytes);
    while (auto e = parser_.pop()) {
      if (auto r = rti::to_dvl_reading(*e, q_V_S_, Time())) {
        ++ok_;
        out.emplace_back(*r);
      }
    }
  }
  uint64_t messages() const override { return ok_; }
  uint64_t malformed() const override {
    const auto& s = parser_.stats();
    return s.bad_checksum + s.partial + s.malformed;
  }
  std::string last_error() const override { return parser_.last_error(); }

 private:
  Quat q_V_S_;
  rti::StreamParser parser_;
  uint64_t ok_ = 0;
};

// Line protocols: A50 JSON, PRTI01, depth.
class LineDecoder final : public Decoder {
 public:
  explicit LineDecoder(const DeviceConfig& c) : kind_(c.kind), q_V_S_(c.q_V_S) {}
  void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) override {
    framer_.push(bytes);
    while (auto line = framer_.pop()) {
      if (line->empty()) continue;
      if (kind_ == DeviceKind::kDepth) {
        auto d = dvl::parse_depth_line(*line);
        if (!d) { fail(d.error()); continue; }
        ++ok_;
        out.emplace_back(DepthReading{Time(), *d});
      } else if (kind_ == DeviceKind::kA50) {
        auto r = a50_.parse(*line);
        if (!r) { fail(r.error()); continue; }
        // Dead reckoning, water tracking, responses and duplicate reports are not events.
        const auto* v = r->has_value() ? std::get_if<dvl::A50Velocity>(&**r) : nullptr;
        if (!v || !v->bottom_tracked()) continue;
        ++ok_;
        out.emplace_back(dvl::to_dvl_reading(v->velocity, q_V_S_, Time()));
      } else {
        auto v = dvl::parse_prti01(*line);
        if (!v) { fail(v.error()); continue; }
        ++ok_;
        out.emplace_back(dvl::to_dvl_reading(*v, q_V_S_, Time()));
      }
    }
  }
  uint64_t messages() const override { return ok_; }
  uint64_t malformed() const override { return bad_ + framer_.overlong(); }
  std::string last_error() const override { return last_error_; }

 private:
  void fail(const Error& e) {
    ++bad_;
    last_error_ = e.message;
  }
  DeviceKind kind_;
  Quat q_V_S_;
  LineFramer framer_;
  dvl::A50Parser a50_;  // drops repeated reports (dvl_protocols.hpp)
  uint64_t ok_ = 0, bad_ = 0;
  std::string last_error_;
};

}  // namespace

std::unique_ptr<Decoder> make_decoder(const DeviceConfig& c) {
  switch (c.kind) {
    case DeviceKind::kOculus: return std::make_unique<OculusDecoder>(c);
    case DeviceKind::kVn100: return std::make_unique<Vn100Decoder>(c);
    case DeviceKind::kA50:
    case DeviceKind::kPrti01:
    case DeviceKind::kDepth: return std::make_unique<LineDecoder>(c);
    case DeviceKind::kRtiEnsemble: return std::make_unique<RtiEnsembleDecoder>(c);
    case DeviceKind::kDsp1760: return std::make_unique<Dsp1760Decoder>(c);
  }
  return nullptr;
}

}  // namespace orthosonar::hal::drivers
