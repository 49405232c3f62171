#include "hal/drivers/protocol_decoder.hpp"

#include <cstdio>
#include <deque>
#include <variant>

#include "hal/drivers/dsp1760.hpp"
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/vn100.hpp"

namespace orthosonar::hal::drivers {
namespace {

using FieldList = std::vector<std::pair<std::string, std::string>>;

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}
std::string num(uint32_t v) { return std::to_string(v); }
std::string num(uint16_t v) { return std::to_string(v); }
std::string num(int v) { return std::to_string(v); }

// ---- Oculus ----------------------------------------------------------------------------------

FieldList header_fields(const oculus::Header& h) {
  return {{"src_device_id", num(h.src_device_id)}, {"dst_device_id", num(h.dst_device_id)},
          {"msg_id", num(h.msg_id)}, {"msg_version", num(h.msg_version)}, {"payload_size", num(h.payload_size)}};
}

DecodedMessage describe_oculus(const oculus::Message& m) {
  DecodedMessage d;
  const auto& h = std::visit([](const auto& x) -> const oculus::Header& { return x.header; }, m);
  d.size = h.message_bytes();
  d.fields = header_fields(h);
  auto add = [&d](std::string k, std::string v) { d.fields.emplace_back(std::move(k), std::move(v)); };
  if (const auto* p = std::get_if<oculus::PingResult>(&m)) {
    d.type = "ping";
    add("layout", "V" + num(p->version));
    add("ping_id", num(p->ping_id));
    add("mode", num(p->fire.master_mode));
    add("flags", num(p->fire.flags));
    add("range", num(p->fire.range));
    add("range_as_metres", (p->fire.flags & oculus::kFlagRangeAsMeters) ? "true" : "false");
    add("gain_percent", num(p->fire.gain_percent));
    add("gamma", num(p->fire.gamma));
    add("frequency_hz", num(p->frequency_hz));
    add("range_resolution_m", num(p->range_resolution_m));
    add("n_ranges", num(p->n_ranges));
    add("n_beams", num(p->n_beams));
    add("bits", num(8 * p->bytes_per_pixel()));
    add("has_gain", p->has_gain() ? "true" : "false");
    if (!p->bearings_centideg.empty()) {
      add("bearing_first_deg", num(p->bearings_centideg.front() / 100.0));
      add("bearing_last_deg", num(p->bearings_centideg.back() / 100.0));
    }
    add("image_offset", num(p->image_offset));
    add("image_size", num(p->image_size));
  } else if (const auto* s = std::get_if<oculus::StatusMessage>(&m)) {
    d.type = "status";
    add("device_id", num(s->device_id));
    add("device_type", num(s->device_type));
    add("part_number", num(s->part_number));
    add("status", num(s->status));
    char ip[20];
    std::snprintf(ip, sizeof ip, "%u.%u.%u.%u", s->ip_addr & 0xffu, (s->ip_addr >> 8) & 0xffu,
                  (s->ip_addr >> 16) & 0xffu, s->ip_addr >> 24);
    add("ip_addr", ip);
    add("temperature0_c", num(s->temperature0_c));
    add("pressure_bar", num(s->pressure_bar));
  } else if (const auto* f = std::get_if<oculus::FireMessage>(&m)) {
    d.type = "fire";
    add("mode", num(f->config.master_mode));
    add("range", num(f->config.range));
    add("gain_percent", num(f->config.gain_percent));
  } else {
    d.type = "other";
  }
  return d;
}

// A byte-stream parser with push()/pop()/buffered(): a message's offset is where the bytes
// consumed so far end, less its size.
template <class Parser>
class BinaryDecoder : public ProtocolDecoder {
 public:
  void push(std::span<const uint8_t> bytes) override {
    parser_.push(bytes);
    pushed_ += bytes.size();
  }
  void finish() override { finished_ = true; }

 protected:
  uint64_t start_of(uint64_t size) const {
    const uint64_t end = pushed_ - parser_.buffered();
    return end >= size ? end - size : 0;
  }
  uint64_t trailing() const { return finished_ ? parser_.buffered() : 0; }
  Parser parser_;

 private:
  uint64_t pushed_ = 0;
  bool finished_ = false;
};

class OculusProtocolDecoder final : public BinaryDecoder<oculus::StreamParser> {
 public:
  std::optional<DecodedMessage> pop() override {
    auto m = parser_.pop();
    if (!m) return std::nullopt;
    DecodedMessage d = describe_oculus(*m);
    d.offset = start_of(d.size);
    return d;
  }
  DecodeCounts counts() const override {
    DecodeCounts c;
    c.good = parser_.stats().messages;
    c.bad = parser_.stats().malformed;
    c.skipped_bytes = parser_.stats().garbage_bytes;
    c.trailing_bytes = trailing();
    c.last_error = parser_.last_error();
    return c;
  }
};

// ---- VN-100 ----------------------------------------------------------------------------------

class Vn100ProtocolDecoder final : public BinaryDecoder<vn100::StreamParser> {
 public:
  std::optional<DecodedMessage> pop() override {
    auto m = parser_.pop();
    if (!m) return std::nullopt;
    DecodedMessage d;
    d.type = "binary";
    d.size = parser_.last_packet_bytes();
    d.offset = start_of(d.size);
    char groups[8];
    std::snprintf(groups, sizeof groups, "0x%02X", vn100::groups_of(*m));
    d.fields.emplace_back("groups", groups);
    for (auto& f : vn100::describe(*m)) d.fields.push_back(std::move(f));
    return d;
  }
  DecodeCounts counts() const override {
    const auto& s = parser_.stats();
    DecodeCounts c;
    c.good = s.accepted;
    c.bad = s.bad_crc;
    c.unsupported = s.unsupported;
    c.skipped_bytes = s.skipped_bytes + s.dropped_bytes;
    c.trailing_bytes = trailing();
    c.last_error = parser_.last_error();
    return c;
  }
};

// ---- KVH DSP-1760 ----------------------------------------------------------------------------

class Dsp1760ProtocolDecoder final : public BinaryDecoder<dsp1760::StreamParser> {
 public:
  std::optional<DecodedMessage> pop() override {
    auto p = parser_.pop();
    if (!p) return std::nullopt;
    DecodedMessage d;
    d.type = "packet";
    d.size = dsp1760::kPacketBytes;
    d.offset = start_of(d.size);
    d.fields = dsp1760::describe(*p);
    if (parser_.last_missing() > 0) d.fields.emplace_back("missing_before", std::to_string(parser_.last_missing()));
    return d;
  }
  DecodeCounts counts() const override {
    const auto& s = parser_.stats();
    DecodeCounts c;
    c.good = s.accepted;
    c.bad = s.bad_crc + s.bad_field;
    c.skipped_bytes = s.skipped_bytes + s.dropped_bytes;
    c.trailing_bytes = trailing();
    c.sequence_gaps = s.sequence_gaps;
    c.missing_packets = s.missing_packets;
    c.last_error = parser_.last_error();
    return c;
  }
};

// ---- Rowe RTI binary ensembles ---------------------------------------------------------------

class RtiEnsembleProtocolDecoder final : public BinaryDecoder<rti::StreamParser> {
 public:
  std::optional<DecodedMessage> pop() override {
    auto e = parser_.pop();
    if (!e) return std::nullopt;
    DecodedMessage d;
    d.type = "ensemble";
    d.size = parser_.last_ensemble_bytes();
    d.offset = start_of(d.size);
    d.fields = rti::describe(*e);
    return d;
  }
  void finish() override {
    BinaryDecoder::finish();
    parser_.finish();
  }
  DecodeCounts counts() const override {
    const auto& s = parser_.stats();
    DecodeCounts c;
    c.good = s.ensembles;
    // An ensemble the capture ends inside is trailing bytes, not a bad message.
    c.bad = s.bad_checksum + s.malformed + s.partial - (parser_.ended_inside() ? 1 : 0);
    c.skipped_bytes = s.skipped_bytes + s.dropped_bytes;
    c.trailing_bytes = trailing();
    c.last_error = parser_.last_error();
    return c;
  }
};

// ---- Line protocols --------------------------------------------------------------------------

// Splits lines ('\n', optional '\r') with their offsets; lines longer than kMaxLine are
// rejected as bad (their bytes skipped) rather than buffered without bound.
class LineDecoderBase : public ProtocolDecoder {
 public:
  static constexpr size_t kMaxLine = DecoderLimits::kMaxLine;

  void push(std::span<const uint8_t> bytes) override {
    for (uint8_t b : bytes) {
      if (b == '\n') {
        end_line();
      } else if (overlong_) {
        ++counts_.skipped_bytes;
      } else {
        cur_.push_back(static_cast<char>(b));
        if (cur_.size() > kMaxLine) {
          overlong_ = true;
          ++counts_.bad;
          counts_.skipped_bytes += cur_.size();
          counts_.last_error = "line at byte " + std::to_string(line_start_) + " is longer than " +
                               std::to_string(kMaxLine) + " bytes";
          cur_.clear();
        }
      }
      ++pos_;
    }
  }
  std::optional<DecodedMessage> pop() override {
    if (ready_.empty()) return std::nullopt;
    DecodedMessage d = std::move(ready_.front());
    ready_.pop_front();
    return d;
  }
  void finish() override {
    if (!cur_.empty() || overlong_) end_line();
  }
  DecodeCounts counts() const override { return counts_; }

 protected:
  // Decodes one line (no line end); returns a message, or nothing after counting the line
  // (bad, other, duplicate) in counts_.
  virtual std::optional<DecodedMessage> decode(std::string_view line, uint64_t offset) = 0;
  void reject(uint64_t offset, const std::string& why) {
    ++counts_.bad;
    counts_.last_error = "byte " + std::to_string(offset) + ": " + why;
  }
  DecodeCounts counts_;

 private:
  void end_line() {
    if (overlong_) {
      overlong_ = false;
    } else {
      std::string_view line = cur_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.find_first_not_of(" \t\r") == std::string_view::npos) {
        counts_.skipped_bytes += cur_.size();
      } else if (auto d = decode(line, line_start_)) {
        d->offset = line_start_;
        d->size = line.size();
        ready_.push_back(std::move(*d));
      }
    }
    cur_.clear();
    line_start_ = pos_ + 1;
  }
  std::string cur_;
  bool overlong_ = false;
  uint64_t pos_ = 0, line_start_ = 0;
  std::deque<DecodedMessage> ready_;
};

class A50Decoder final : public LineDecoderBase {
 protected:
  std::optional<DecodedMessage> decode(std::string_view line, uint64_t offset) override {
    const auto before = parser_.counters();
    auto r = parser_.parse(line);
    if (!r) {
      reject(offset, r.error().message);
      return std::nullopt;
    }
    const auto& after = parser_.counters();
    DecodedMessage d;
    if (*r) {
      ++counts_.good;
      d.type = std::holds_alternative<dvl::A50Velocity>(**r)
                   ? (std::get<dvl::A50Velocity>(**r).type.empty() ? "velocity" : std::get<dvl::A50Velocity>(**r).type)
                   : "position_local";
      d.fields = dvl::describe(**r);
      return d;
    }
    if (after.duplicates > before.duplicates) {
      ++counts_.duplicates;
      return std::nullopt;
    }
    ++counts_.other;
    auto decoded = dvl::decode_a50(line);
    d.type = "other";
    if (decoded) d.fields = dvl::describe(*decoded);
    return d;
  }

 private:
  dvl::A50Parser parser_;
};

class PrtiDecoder final : public LineDecoderBase {
 protected:
  std::optional<DecodedMessage> decode(std::string_view line, uint64_t offset) override {
    const size_t start = line.find('$');
    if (start == std::string_view::npos || line.substr(start, 5) != "$PRTI") {
      ++counts_.other;  // another sentence on the same port ($GPGGA, ...), or text
      return std::nullopt;
    }
    if (start > 0) {
      counts_.skipped_bytes += start;
      line.remove_prefix(start);
    }
    const std::string_view id = line.substr(0, 7);
    if (id != "$PRTI01" && id != "$PRTI02") {
      ++counts_.unsupported;
      counts_.last_error = "byte " + std::to_string(offset) + ": " + std::string(id) + " is not decoded (PRTI01, PRTI02)";
      return std::nullopt;
    }
    auto r = dvl::parse_prti(line);
    if (!r) {
      reject(offset, r.error().message);
      return std::nullopt;
    }
    ++counts_.good;
    DecodedMessage d;
    d.type = r->sentence == 2 ? "PRTI02" : "PRTI01";
    d.fields = dvl::describe(*r);
    return d;
  }
};

class DepthDecoder final : public LineDecoderBase {
 protected:
  std::optional<DecodedMessage> decode(std::string_view line, uint64_t offset) override {
    auto r = dvl::parse_depth(line);
    if (!r) {
      reject(offset, r.error().message);
      return std::nullopt;
    }
    ++counts_.good;
    DecodedMessage d;
    d.type = r->json ? "depth_json" : "DEPTH";
    d.fields = dvl::describe(*r);
    return d;
  }
};

}  // namespace

Result<Protocol> protocol_from_name(std::string_view name) {
  if (name == "oculus") return Protocol::kOculus;
  if (name == "vn100") return Protocol::kVn100;
  if (name == "a50") return Protocol::kA50;
  if (name == "prti") return Protocol::kPrti;
  if (name == "depth") return Protocol::kDepth;
  if (name == "rti-ensemble") return Protocol::kRtiEnsemble;
  if (name == "dsp1760") return Protocol::kDsp1760;
  return Error{"unknown protocol '" + std::string(name) + "' (oculus, vn100, a50, prti, depth, dsp1760, rti-ensemble)"};
}

const char* protocol_name(Protocol p) {
  switch (p) {
    case Protocol::kOculus: return "oculus";
    case Protocol::kVn100: return "vn100";
    case Protocol::kA50: return "a50";
    case Protocol::kPrti: return "prti";
    case Protocol::kDepth: return "depth";
    case Protocol::kRtiEnsemble: return "rti-ensemble";
    case Protocol::kDsp1760: return "dsp1760";
  }
  return "?";
}

std::unique_ptr<ProtocolDecoder> make_decoder(Protocol p) {
  switch (p) {
    case Protocol::kOculus: return std::make_unique<OculusProtocolDecoder>();
    case Protocol::kVn100: return std::make_unique<Vn100ProtocolDecoder>();
    case Protocol::kA50: return std::make_unique<A50Decoder>();
    case Protocol::kPrti: return std::make_unique<PrtiDecoder>();
    case Protocol::kDepth: return std::make_unique<DepthDecoder>();
    case Protocol::kRtiEnsemble: return std::make_unique<RtiEnsembleProtocolDecoder>();
    case Protocol::kDsp1760: return std::make_unique<Dsp1760ProtocolDecoder>();
  }
  return nullptr;
}

}  // namespace orthosonar::hal::drivers
