#include "hal/drivers/oculus_protocol.hpp"

#include <string>

namespace orthosonar::hal::drivers::oculus {
namespace {

std::string hex16(uint32_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s = "0x";
  for (int shift = 12; shift >= 0; shift -= 4) s += digits[(v >> shift) & 0xF];
  return s;
}

Header read_header(ByteReader& r) {
  Header h;
  h.oculus_id = r.u16();
  h.src_device_id = r.u16();
  h.dst_device_id = r.u16();
  h.msg_id = r.u16();
  h.msg_version = r.u16();
  h.payload_size = r.u32();
  h.spare = r.u16();
  return h;
}

void write_header(ByteWriter& w, const Header& h) {
  w.u16(h.oculus_id);
  w.u16(h.src_device_id);
  w.u16(h.dst_device_id);
  w.u16(h.msg_id);
  w.u16(h.msg_version);
  w.u32(h.payload_size);
  w.u16(h.spare);
}

FireConfig read_fire(ByteReader& r, int version) {
  FireConfig f;
  f.master_mode = r.u8();
  f.ping_rate = r.u8();
  f.network_speed = r.u8();
  f.gamma = r.u8();
  f.flags = r.u8();
  f.range = r.f64();
  f.gain_percent = r.f64();
  f.speed_of_sound_mps = r.f64();
  f.salinity_ppt = r.f64();
  if (version == 2) {
    f.ext_flags = r.u32();
    r.skip(8 * 4);
  }
  return f;
}

void write_fire(ByteWriter& w, const FireConfig& f, int version) {
  w.u8(f.master_mode);
  w.u8(f.ping_rate);
  w.u8(f.network_speed);
  w.u8(f.gamma);
  w.u8(f.flags);
  w.f64(f.range);
  w.f64(f.gain_percent);
  w.f64(f.speed_of_sound_mps);
  w.f64(f.salinity_ppt);
  if (version == 2) {
    w.u32(f.ext_flags);
    for (int i = 0; i < 8; ++i) w.u32(0);
  }
}

Error err(const std::string& what) { return Error{"oculus: " + what}; }

}  // namespace

Result<Header> parse_header(std::span<const uint8_t> data) {
  if (data.size() < kHeaderSize)
    return err("header needs 16 bytes, have " + std::to_string(data.size()));
  ByteReader r(data);
  const Header h = read_header(r);
  if (h.oculus_id != kOculusId) return err("bad oculusId " + hex16(h.oculus_id) + " (want 0x4f53)");
  if (h.payload_size > kMaxPayload)
    return err("payloadSize " + std::to_string(h.payload_size) + " exceeds " + std::to_string(kMaxPayload));
  return h;
}

Result<PingResult> parse_ping_result(std::span<const uint8_t> data) {
  auto hr = parse_header(data);
  if (!hr) return hr.error();
  const Header h = *hr;
  if (h.msg_id != kMsgSimplePingResult) return err("msgId " + hex16(h.msg_id) + " is not a SimplePingResult");
  if (data.size() < h.message_bytes())
    return err("message truncated: " + std::to_string(data.size()) + " of " + std::to_string(h.message_bytes()) + " bytes");
  const auto msg = data.first(h.message_bytes());
  PingResult p;
  p.header = h;
  p.version = h.msg_version == 2 ? 2 : 1;
  const size_t fixed = p.version == 2 ? kPingV2Size : kPingV1Size;
  if (msg.size() < fixed)
    return err("SimplePingResult V" + std::to_string(p.version) + " needs " + std::to_string(fixed) + " bytes, message has " + std::to_string(msg.size()));
  ByteReader r(msg, kHeaderSize);
  p.fire = read_fire(r, p.version);
  p.ping_id = r.u32();
  p.status = r.u32();
  p.frequency_hz = r.f64();
  p.temperature_c = r.f64();
  p.pressure_bar = r.f64();
  if (p.version == 2) {
    p.heading_deg = r.f64();
    p.pitch_deg = r.f64();
    p.roll_deg = r.f64();
  }
  p.speed_of_sound_used_mps = r.f64();
  p.ping_start_time = p.version == 2 ? r.f64() : static_cast<double>(r.u32());
  p.data_size = r.u8();
  p.range_resolution_m = r.f64();
  p.n_ranges = r.u16();
  p.n_beams = r.u16();
  if (p.version == 2) r.skip(4 * 4);
  p.image_offset = r.u32();
  p.image_size = r.u32();
  p.message_size = r.u32();
  if (r.failed() || r.position() != fixed) return err("SimplePingResult fixed part misread");

  if (p.data_size > 3) return err("dataSize " + std::to_string(p.data_size) + " out of range 0..3");
  if (p.n_beams == 0 || p.n_ranges == 0) return err("empty image: nRanges " + std::to_string(p.n_ranges) + ", nBeams " + std::to_string(p.n_beams));
  if (p.message_size != msg.size())
    return err("messageSize " + std::to_string(p.message_size) + " != header size + payloadSize " + std::to_string(msg.size()));
  const size_t bearings_end = fixed + 2u * p.n_beams;
  if (p.image_offset < bearings_end)
    return err("imageOffset " + std::to_string(p.image_offset) + " overlaps the bearing table ending at " + std::to_string(bearings_end));
  if (static_cast<uint64_t>(p.image_offset) + p.image_size > msg.size())
    return err("image [" + std::to_string(p.image_offset) + ", +" + std::to_string(p.image_size) + ") beyond message end " + std::to_string(msg.size()));
  const size_t row_pixels = static_cast<size_t>(p.n_beams) * static_cast<size_t>(p.bytes_per_pixel());
  const size_t row_bytes = row_pixels + (p.has_gain() ? 4u : 0u);
  if (static_cast<size_t>(p.n_ranges) * row_bytes != p.image_size)
    return err("imageSize " + std::to_string(p.image_size) + " != nRanges " + std::to_string(p.n_ranges) + " x " + std::to_string(row_bytes) + " bytes per row");

  p.bearings_centideg.resize(p.n_beams);
  for (auto& b : p.bearings_centideg) b = r.i16();
  p.image.reserve(static_cast<size_t>(p.n_ranges) * row_pixels);
  if (p.has_gain()) p.row_gains.reserve(p.n_ranges);
  ByteReader img(msg, p.image_offset);
  for (uint16_t row = 0; row < p.n_ranges; ++row) {
    if (p.has_gain()) p.row_gains.push_back(img.u32());
    const size_t at = img.position();
    img.skip(row_pixels);
    if (img.failed()) return err("image row " + std::to_string(row) + " truncated");
    p.image.insert(p.image.end(), msg.begin() + static_cast<std::ptrdiff_t>(at),
                   msg.begin() + static_cast<std::ptrdiff_t>(at + row_pixels));
  }
  if (r.failed()) return err("bearing table truncated");
  return p;
}

Result<StatusMessage> parse_status(std::span<const uint8_t> data) {
  auto hr = parse_header(data);
  if (!hr) return hr.error();
  if (data.size() < hr->message_bytes() || hr->message_bytes() < kStatusSize)
    return err("status message needs " + std::to_string(kStatusSize) + " bytes, have " + std::to_string(data.size()));
  ByteReader r(data, kHeaderSize);
  StatusMessage s;
  s.header = *hr;
  s.device_id = r.u32();
  s.device_type = r.u16();
  s.part_number = r.u16();
  s.status = r.u32();
  r.skip(6 * 4);  // firmware versions and dates
  s.ip_addr = r.u32();
  s.ip_mask = r.u32();
  s.connected_ip_addr = r.u32();
  r.skip(6);  // MAC address
  s.temperature0_c = r.f64();
  r.skip(7 * 8);
  s.pressure_bar = r.f64();
  if (r.failed()) return err("status message truncated");
  return s;
}

Result<Message> parse_message(std::span<const uint8_t> data) {
  auto hr = parse_header(data);
  if (!hr) return hr.error();
  if (data.size() < hr->message_bytes())
    return err("message truncated: " + std::to_string(data.size()) + " of " + std::to_string(hr->message_bytes()) + " bytes");
  switch (hr->msg_id) {
    case kMsgSimplePingResult: {
      auto p = parse_ping_result(data);
      if (!p) return p.error();
      return Message{std::move(*p)};
    }
    case kMsgStatus: {
      auto s = parse_status(data);
      if (!s) return s.error();
      return Message{std::move(*s)};
    }
    case kMsgSimpleFire: {
      const int version = hr->msg_version == 2 ? 2 : 1;
      const size_t need = version == 2 ? kFireV2Size : kFireV1Size;
      if (hr->message_bytes() < need) return err("SimpleFire needs " + std::to_string(need) + " bytes");
      ByteReader r(data, kHeaderSize);
      FireMessage f{*hr, read_fire(r, version)};
      if (r.failed()) return err("SimpleFire truncated");
      return Message{f};
    }
    default:
      return Message{OtherMessage{*hr}};
  }
}

Bytes encode_fire(const FireConfig& config, int version, uint16_t src_device_id, uint16_t dst_device_id) {
  Bytes out;
  ByteWriter w(out);
  Header h;
  h.src_device_id = src_device_id;
  h.dst_device_id = dst_device_id;
  h.msg_id = kMsgSimpleFire;
  h.msg_version = static_cast<uint16_t>(version == 2 ? 2 : 1);
  h.payload_size = static_cast<uint32_t>((version == 2 ? kFireV2Size : kFireV1Size) - kHeaderSize);
  write_header(w, h);
  write_fire(w, config, version == 2 ? 2 : 1);
  return out;
}

Bytes encode_ping_result(const PingResult& p) {
  const int version = p.version == 2 ? 2 : 1;
  const size_t fixed = version == 2 ? kPingV2Size : kPingV1Size;
  const size_t row_pixels = static_cast<size_t>(p.n_beams) * static_cast<size_t>(p.bytes_per_pixel());
  const size_t row_bytes = row_pixels + (p.has_gain() ? 4u : 0u);
  const uint32_t image_offset = static_cast<uint32_t>(fixed + 2u * p.n_beams);
  const uint32_t image_size = static_cast<uint32_t>(static_cast<size_t>(p.n_ranges) * row_bytes);
  const uint32_t total = image_offset + image_size;
  Bytes out;
  out.reserve(total);
  ByteWriter w(out);
  Header h = p.header;
  h.oculus_id = kOculusId;
  h.msg_id = kMsgSimplePingResult;
  h.msg_version = static_cast<uint16_t>(version);
  h.payload_size = static_cast<uint32_t>(total - kHeaderSize);
  write_header(w, h);
  write_fire(w, p.fire, version);
  w.u32(p.ping_id);
  w.u32(p.status);
  w.f64(p.frequency_hz);
  w.f64(p.temperature_c);
  w.f64(p.pressure_bar);
  if (version == 2) {
    w.f64(p.heading_deg);
    w.f64(p.pitch_deg);
    w.f64(p.roll_deg);
  }
  w.f64(p.speed_of_sound_used_mps);
  if (version == 2) {
    w.f64(p.ping_start_time);
  } else {
    w.u32(static_cast<uint32_t>(p.ping_start_time));
  }
  w.u8(p.data_size);
  w.f64(p.range_resolution_m);
  w.u16(p.n_ranges);
  w.u16(p.n_beams);
  if (version == 2)
    for (int i = 0; i < 4; ++i) w.u32(0);
  w.u32(image_offset);
  w.u32(image_size);
  w.u32(total);
  for (uint16_t b = 0; b < p.n_beams; ++b) w.i16(b < p.bearings_centideg.size() ? p.bearings_centideg[b] : int16_t{0});
  for (uint16_t row = 0; row < p.n_ranges; ++row) {
    if (p.has_gain()) w.u32(row < p.row_gains.size() ? p.row_gains[row] : 0u);
    const size_t at = static_cast<size_t>(row) * row_pixels;
    for (size_t i = 0; i < row_pixels; ++i) w.u8(at + i < p.image.size() ? p.image[at + i] : uint8_t{0});
  }
  return out;
}

Bytes encode_status(const StatusMessage& s) {
  Bytes out;
  ByteWriter w(out);
  Header h = s.header;
  h.oculus_id = kOculusId;
  h.msg_id = kMsgStatus;
  h.payload_size = static_cast<uint32_t>(kStatusSize - kHeaderSize);
  write_header(w, h);
  w.u32(s.device_id);
  w.u16(s.device_type);
  w.u16(s.part_number);
  w.u32(s.status);
  for (int i = 0; i < 6; ++i) w.u32(0);
  w.u32(s.ip_addr);
  w.u32(s.ip_mask);
  w.u32(s.connected_ip_addr);
  for (int i = 0; i < 6; ++i) w.u8(0);
  w.f64(s.temperature0_c);
  for (int i = 0; i < 7; ++i) w.f64(0.0);
  w.f64(s.pressure_bar);
  return out;
}

}  // namespace orthosonar::hal::drivers::oculus
