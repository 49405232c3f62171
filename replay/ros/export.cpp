// `orthosonar export` (export.hpp). Messages are built as Value trees and serialised by
// the very definition text the file carries (msg_encode.hpp), in ros1 for bags and CDR
// for ROS 2 MCAP.
#include "replay/ros/export.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <span>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"
#include "orthosonar/version.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/mcap/mcap_generic.hpp"
#include "replay/ros/msg_encode.hpp"
#include "replay/ros/msg_types.hpp"
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/rosbag.hpp"
#include "replay/ros/topic_map.hpp"

namespace orthosonar::replay::ros {
namespace {

using rosmsg::Value;
using Fields = std::vector<std::pair<std::string, Value>>;

constexpr int64_t kMaxRosNs = (int64_t{1} << 31) * 1'000'000'000;  // int32 seconds (ROS 2) and uint32 (ROS 1)
constexpr double kAtmospherePa = 101325.0, kSeawaterDensity = 1025.0, kGravity = 9.80665;

// The integer view of a float field is only defined inside int64's range; NaN (an invalid
// DVL velocity, say) and infinities get 0 (clang's UBSan: float-cast-overflow).
Value num(double d) {
  const bool fits = std::isfinite(d) && d > -9.2e18 && d < 9.2e18;
  return Value::number(d, fits ? static_cast<int64_t>(d) : 0, false);
}
Value integer(int64_t i) { return Value::number(static_cast<double>(i), i, true); }
Value str(std::string s) { return Value::string(std::move(s)); }
Value msg(Fields f) { return Value::message(std::move(f)); }
Value vec3(const Vec3& v) { return msg({{"x", num(v.x())}, {"y", num(v.y())}, {"z", num(v.z())}}); }
Value quat(const Quat& q) { return msg({{"x", num(q.x())}, {"y", num(q.y())}, {"z", num(q.z())}, {"w", num(q.w())}}); }
Value header(uint64_t seq, int64_t ns, const std::string& frame) {
  return msg({{"seq", integer(static_cast<int64_t>(seq & 0xffffffffu))}, {"stamp", Value::time(ns)}, {"frame_id", str(frame)}});
}
Value numbers(const std::vector<double>& v, bool as_integers) {
  std::vector<Value> e;
  e.reserve(v.size());
  for (double d : v) e.push_back(as_integers ? integer(static_cast<int64_t>(d)) : num(d));
  return Value::array(std::move(e));
}

struct Topic {
  std::string name, type;
  Role role;
  std::optional<rosmsg::Schema> schema;
  uint32_t bag_conn = 0;
  uint16_t mcap_channel = 0;
};

// Oculus fire-message mode (1 low, 2 high frequency) from the ping's frequency.
int oculus_mode(const SonarPing& p) {
  const double high = p.part_number == kPartM1200d ? 2.1e6 : 1.2e6;
  return std::abs(p.frequency_hz - high) < 1.0 ? 2 : 1;
}

// The authors' driver: range_resolution and bearings as the device reports them.
Result<Value> oculus_ping(const Event& e, const SonarPing& p, const ExportOptions& o, const std::string& frame,
                          std::vector<uint8_t>& jpeg) {
  const int64_t ns = e.stamp.ns();
  std::vector<double> centi;
  centi.reserve(p.bearings_rad.size());
  for (double b : p.bearings_rad) {
    const double c = std::round(b / (0.01 * std::numbers::pi / 180.0));
    if (c < -32768 || c > 32767) return Error{"bearing " + std::to_string(b) + " rad is outside int16 centidegrees"};
    centi.push_back(c);
  }
  Value image;
  if (o.jpeg) {
    if (p.bytes_per_pixel != 1)
      return Error{"ping " + std::to_string(p.ping_id) + " has 16-bit pixels, which JPEG cannot hold: export with --image raw"};
    const cv::Mat m(p.rows, p.cols, CV_8U, const_cast<uint8_t*>(p.image.data()));
    auto encoded = codec::encode_jpeg(m, o.jpeg_quality);
    if (!encoded) return Error{"ping " + std::to_string(p.ping_id) + ": " + encoded.error().message};
    jpeg = std::move(*encoded);
    image = msg({{"header", header(e.sequence, ns, frame)}, {"format", str("mono8; jpeg compressed ")},
                 {"data", Value::bytes(std::span<const uint8_t>(jpeg))}});
  } else {
    image = msg({{"header", header(e.sequence, ns, frame)},
                 {"height", integer(p.rows)},
                 {"width", integer(p.cols)},
                 {"encoding", str(p.bytes_per_pixel == 2 ? "mono16" : "mono8")},
                 {"is_bigendian", integer(0)},
                 {"step", integer(static_cast<int64_t>(p.cols) * p.bytes_per_pixel)},
                 {"data", Value::bytes(std::span<const uint8_t>(p.image))}});
  }
  Fields fire = {{"header", header(e.sequence, ns, frame)},
                 {"mode", integer(oculus_mode(p))},
                 {"gamma", integer(0)},
                 {"flags", integer(0)},
                 {"range", num(p.max_range_m())},
                 {"gain", num(p.gain_percent)},
                 {"speed_of_sound", num(1500.0)},
                 {"salinity", num(35.0)}};
  return msg({{"header", header(e.sequence, ns, frame)},
              {"fire_msg", msg(std::move(fire))},
              {"ping_id", integer(p.ping_id)},
              {"part_number", integer(p.part_number)},
              {"start_time", integer(0)},
              {"bearings", numbers(centi, true)},
              {"range_resolution", num(p.range_resolution_m)},
              {"num_ranges", integer(p.rows)},
              {"num_beams", integer(p.cols)},
              {"ping", std::move(image)}});
}

Value projected_ping(const Event& e, const SonarPing& p, const std::string& frame) {
  std::vector<Value> dirs;
  for (double b : p.bearings_rad) dirs.push_back(vec3(Vec3(0.0, -std::sin(b), std::cos(b))));
  std::vector<double> ranges;
  for (int r = 0; r < p.rows; ++r) ranges.push_back(p.range_of_row(r));
  return msg({{"header", header(e.sequence, e.stamp.ns(), frame)},
              {"ping_info", msg({{"frequency", num(p.frequency_hz)}, {"sound_speed", num(1500.0)},
                                 {"tx_beamwidths", Value::array({})}, {"rx_beamwidths", Value::array({})}})},
              {"beam_directions", Value::array(std::move(dirs))},
              {"ranges", numbers(ranges, false)},
              {"image", msg({{"is_bigendian", integer(0)},
                             {"dtype", integer(p.bytes_per_pixel == 2 ? 2 : 0)},
                             {"beam_count", integer(p.cols)},
                             {"data", Value::bytes(std::span<const uint8_t>(p.image))}})}});
}

// `jpeg` holds a compressed image the returned Value points into.
Result<Value> message_for(const Event& e, const ExportOptions& o, std::vector<uint8_t>& jpeg) {
  const std::string frame(e.channel == Channel::kSonarHorizontal ? "sonar_horizontal"
                          : e.channel == Channel::kSonarVertical ? "sonar_vertical"
                          : e.channel == Channel::kTruthPose     ? "world"
                                                                 : "vehicle");
  const int64_t ns = e.stamp.ns();
  const bool std_types = o.sonar == SonarType::kProjected;
  if (const auto* p = std::get_if<SonarPing>(&e.payload))
    return std_types ? Result<Value>(projected_ping(e, *p, frame)) : oculus_ping(e, *p, o, frame, jpeg);
  if (const auto* r = std::get_if<ImuReading>(&e.payload)) {
    std::vector<Value> zeros(9, num(0.0));
    return msg({{"header", header(e.sequence, ns, frame)},
                {"orientation", quat(r->q_W_V)},
                {"orientation_covariance", Value::array(zeros)},
                {"angular_velocity", vec3(r->angular_velocity_V)},
                {"angular_velocity_covariance", Value::array(zeros)},
                {"linear_acceleration", vec3(r->linear_acceleration_V)},
                {"linear_acceleration_covariance", Value::array(zeros)}});
  }
  if (const auto* r = std::get_if<DvlReading>(&e.payload)) {
    // An invalid reading (no bottom lock) is published with NaN velocity.
    const Vec3 v = r->valid ? r->velocity_V_mps : Vec3::Constant(std::nan(""));
    if (!std_types)
      return msg({{"header", header(e.sequence, ns, frame)}, {"velocity", vec3(v)}, {"temperature", num(0.0)},
                  {"altitude", num(r->altitude_m)}, {"time", num(e.stamp.seconds())}});
    std::vector<Value> cov(36, num(0.0));
    if (!r->valid) cov[0] = num(-1.0);
    return msg({{"header", header(e.sequence, ns, frame)},
                {"twist", msg({{"twist", msg({{"linear", vec3(v)}, {"angular", vec3(Vec3::Zero())}})},
                               {"covariance", Value::array(std::move(cov))}})}});
  }
  if (const auto* r = std::get_if<DepthReading>(&e.payload)) {
    const double pa = kAtmospherePa + kSeawaterDensity * kGravity * r->depth_m;
    if (!std_types)
      return msg({{"header", header(e.sequence, ns, frame)}, {"time", num(e.stamp.seconds())},
                  {"pressure_abs", num(pa / 100.0)}, {"pressure_diff", num((pa - kAtmospherePa) / 100.0)},
                  {"temperature", num(0.0)}, {"depth", num(r->depth_m)}});
    return msg({{"header", header(e.sequence, ns, frame)}, {"fluid_pressure", num(pa)}, {"variance", num(0.0)}});
  }
  if (const auto* r = std::get_if<TruthPose>(&e.payload))
    return msg({{"header", header(e.sequence, ns, frame)},
                {"pose", msg({{"position", vec3(r->p_W)}, {"orientation", quat(r->q_W_V)}})}});
  if (const auto* r = std::get_if<GyroReading>(&e.payload)) {
    // kvh_gyro/gyro: delta angles only (GyroDeltas made rates into them); the device's
    // packet counter and temperature have no field.
    if (r->is_rate) return Error{"a gyro rate reached the writer unconverted"};
    return msg({{"header", header(e.sequence, ns, "gyro")},
                {"status", integer(r->valid ? 1 : 0)},
                {"delta", numbers({r->value_G.x(), r->value_G.y(), r->value_G.z()}, false)}});
  }
  return Error{"no ROS type for this event"};
}

struct Plan {
  std::string topic, type;
  Role role;
};

Plan plan_for(Channel c, const ExportOptions& o) {
  const bool std_types = o.sonar == SonarType::kProjected;
  switch (c) {
    case Channel::kSonarHorizontal:
      return std_types ? Plan{"/oculus_m750d/sonar_image", "marine_acoustic_msgs/ProjectedSonarImage", Role::kHorizontalSonar}
                       : Plan{"/sonar_oculus_node/M750d/ping",
                              o.jpeg ? "sonar_oculus/OculusPing" : "sonar_oculus/OculusPingUncompressed",
                              Role::kHorizontalSonar};
    case Channel::kSonarVertical:
      return std_types ? Plan{"/oculus_m1200d/sonar_image", "marine_acoustic_msgs/ProjectedSonarImage", Role::kVerticalSonar}
                       : Plan{"/sonar_oculus_node/M1200d/ping",
                              o.jpeg ? "sonar_oculus/OculusPing" : "sonar_oculus/OculusPingUncompressed",
                              Role::kVerticalSonar};
    case Channel::kImu:
      return std_types ? Plan{"/imu/data", "sensor_msgs/Imu", Role::kImu} : Plan{"/vn100/imu/raw", "sensor_msgs/Imu", Role::kImu};
    case Channel::kDvl:
      return std_types ? Plan{"/dvl/twist", "geometry_msgs/TwistWithCovarianceStamped", Role::kDvl}
                       : Plan{"/rti/body_velocity/raw", "rti_dvl/DVL", Role::kDvl};
    case Channel::kDepth:
      return std_types ? Plan{"/pressure", "sensor_msgs/FluidPressure", Role::kDepth}
                       : Plan{"/bar30/depth/raw", "bar30_depth/Depth", Role::kDepth};
    case Channel::kTruthPose: return Plan{"/orthosonar/truth", "geometry_msgs/PoseStamped", Role::kTruth};
    // The authors' type with either sonar type: no common ROS type carries delta angles.
    case Channel::kGyro: return Plan{"/gyro", "kvh_gyro/gyro", Role::kGyro};
    default: return Plan{"", "", Role::kTruth};
  }
}

// Gyro readings as kvh_gyro/gyro holds them: delta angles. A rate (rad/s: a DSP-1760
// configured for rates) becomes the angle turned over the interval it covers, by dead
// reckoning's rule (core/slam/gyro_heading): the time since the previous gyro reading, or
// one sample period (the shortest interval so far) after a gap of more than 1.5 periods,
// whose lost samples are not in it. The first reading has no previous one: it takes the
// interval to the second and waits for it. Readings come in stamp order; delta angles pass
// unchanged (only their stamps count).
class GyroDeltas {
 public:
  // The readings ready to write after `e` (none while the first, a rate, waits).
  Result<std::vector<Event>> push(const Event& e) {
    std::vector<Event> out;
    if (pending_) {
      const int64_t dt = e.stamp.ns() - pending_->stamp.ns();
      if (dt <= 0) return Error{"gyro readings " + std::to_string(pending_->sequence) + " and " +
                                std::to_string(e.sequence) + " share a stamp: no interval to make a rate an angle"};
      out.push_back(as_delta(*pending_, dt));
      pending_.reset();
    }
    if (last_ns_) {
      const int64_t dt = e.stamp.ns() - *last_ns_;
      if (dt <= 0 && std::get<GyroReading>(e.payload).is_rate)
        return Error{"gyro reading " + std::to_string(e.sequence) + " has the stamp of the one before it: "
                     "no interval to make its rate an angle"};
      if (dt > 0 && (period_ns_ == 0 || dt < period_ns_)) period_ns_ = dt;
      const int64_t covered = dt > period_ns_ + period_ns_ / 2 ? period_ns_ : dt;
      out.push_back(as_delta(e, covered));
    } else if (std::get<GyroReading>(e.payload).is_rate) {
      pending_ = e;
    } else {
      out.push_back(e);
    }
    last_ns_ = e.stamp.ns();
    return out;
  }
  // At the end of the fixture: a lone rate reading has no interval.
  Status finish() const {
    if (pending_) return Error{"gyro reading " + std::to_string(pending_->sequence) +
                               " is a rate and the fixture's only gyro reading: no interval to make it an angle"};
    return {};
  }

 private:
  static Event as_delta(Event e, int64_t covered_ns) {
    auto& g = std::get<GyroReading>(e.payload);
    if (g.is_rate) {
      g.value_G = g.value_G * (static_cast<double>(covered_ns) * 1e-9);
      g.is_rate = false;
    }
    return e;
  }
  std::optional<Event> pending_;
  std::optional<int64_t> last_ns_;
  int64_t period_ns_ = 0;
};

// "pkg/Type" -> "pkg/msg/Type" (rosbag2's schema names).
std::string ros2_name(const std::string& type) {
  const auto slash = type.find('/');
  return slash == std::string::npos ? type : type.substr(0, slash) + "/msg/" + type.substr(slash + 1);
}

}  // namespace

std::string topics_yaml_path(const std::string& out) {
  std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + ".topics.yaml")).string();
}

Result<ExportReport> export_fixture(const std::string& fixture, const std::string& out, const ExportOptions& o) {
  auto src = FixtureSource::open(fixture);
  if (!src) return src.error();
  const bool bag = o.target == ExportTarget::kRos1Bag;
  const std::string compression = o.compression.empty() ? (bag ? "none" : "zstd") : o.compression;
  if (bag && compression != "none" && compression != "bz2" && compression != "lz4")
    return Error{"--compression " + compression + ": a bag's chunks are none, bz2 or lz4"};
  if (!bag && compression != "zstd" && compression != "none")
    return Error{"--compression " + compression + ": MCAP chunks are written zstd or none"};
  if (o.jpeg_quality < 1 || o.jpeg_quality > 100) return Error{"JPEG quality " + std::to_string(o.jpeg_quality) + " (1..100)"};
  const rosmsg::Dialect dialect = bag ? rosmsg::Dialect::kRos1 : rosmsg::Dialect::kRos2;
  const rosmsg::Encoding encoding = bag ? rosmsg::Encoding::kRos1 : rosmsg::Encoding::kCdr;

  // The survey's latitude (the gyro's Earth rate) goes to the companion topics.yaml: checked first.
  std::optional<double> latitude;
  if (const auto& md = (*src)->metadata(); md.count("latitude_deg")) {
    const std::string& text = md.at("latitude_deg");
    char* end = nullptr;
    const double lat = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !(lat >= -90.0 && lat <= 90.0))
      return Error{fixture + ": metadata 'latitude_deg' = '" + text + "' is not a latitude in [-90, 90] degrees"};
    latitude = lat;
  }

  const std::string tmp = out + ".partial";
  std::unique_ptr<rosbag::BagWriter> bw;
  std::unique_ptr<mcap::GenericWriter> mw;
  if (bag) {
    rosbag::BagWriterOptions bo;
    bo.compression = compression;
    bo.chunk_threshold = o.bag_chunk_bytes;
    auto w = rosbag::BagWriter::open(tmp, bo);
    if (!w) return w.error();
    bw = std::move(*w);
  } else {
    mcap::GenericWriterOptions mo;
    mo.profile = "ros2";
    mo.library = std::string("orthosonar ") + kVersion;
    mo.compression = compression == "none" ? "" : "zstd";
    auto w = mcap::GenericWriter::open(tmp, mo);
    if (!w) return w.error();
    mw = std::move(*w);
  }
  auto fail = [&](const Error& e) -> Result<ExportReport> {
    bw.reset();
    mw.reset();
    std::remove(tmp.c_str());
    return e;
  };

  ExportReport report;
  report.input_recovery = (*src)->recovery();
  std::map<Channel, Topic> topics;
  std::vector<uint8_t> jpeg;
  std::map<Channel, uint32_t> device_ids;
  // Writes one event as its topic's message (the topic's connection made on its first).
  auto emit = [&](const Event& e) -> Status {
    auto it = topics.find(e.channel);
    if (it == topics.end()) {
      const Plan plan = plan_for(e.channel, o);
      Topic t{plan.topic, plan.type, plan.role, std::nullopt, 0, 0};
      const std::string text(rosmsg::definition(t.type, dialect));
      auto schema = rosmsg::Schema::parse(t.type, text, dialect);
      if (!schema) return Error{"definition of " + t.type + ": " + schema.error().message};
      t.schema = std::move(*schema);
      if (bag) {
        auto id = bw->add_connection(t.name, t.type, rosmsg::md5_of(t.type), text, "/orthosonar_export", false);
        if (!id) return id.error();
        t.bag_conn = *id;
      } else {
        const uint16_t schema_id = mw->add_schema(ros2_name(t.type), "ros2msg", text);
        t.mcap_channel = mw->add_channel(schema_id, t.name, "cdr", {});
      }
      if (const auto* p = std::get_if<SonarPing>(&e.payload)) device_ids[e.channel] = p->device_id;
      it = topics.emplace(e.channel, std::move(t)).first;
    }
    Topic& t = it->second;
    auto value = message_for(e, o, jpeg);
    if (!value)
      return Error{fixture + ": " + channel_topic(e.channel) + " event " + std::to_string(e.sequence) + ": " +
                   value.error().message};
    rosmsg::Writer w(encoding);
    if (auto s = rosmsg::encode(*t.schema, *value, w); !s)
      return Error{fixture + ": " + t.name + " (" + t.type + ") event " + std::to_string(e.sequence) + ": " +
                   s.error().message};
    const auto& bytes = w.bytes();
    const auto stamp = static_cast<uint64_t>(e.stamp.ns());
    Status s = bag ? bw->write(t.bag_conn, stamp, bytes.data(), bytes.size())
                   : mw->write(t.mcap_channel, static_cast<uint32_t>(e.sequence & 0xffffffffu), stamp, stamp,
                               bytes.data(), bytes.size());
    if (!s) return s.error();
    ++report.messages[t.name];
    return {};
  };
  GyroDeltas gyro;
  for (;;) {
    hal::Pulled pulled = (*src)->next();
    if (pulled.error) return fail(Error{fixture + ": " + pulled.error->message});
    if (pulled.end_of_stream || !pulled.event) break;
    const Event& e = *pulled.event;
    if (e.channel == Channel::kLabelsHorizontal || e.channel == Channel::kLabelsVertical) {
      ++report.skipped_labels;
      continue;
    }
    if (e.stamp.ns() < 0 || e.stamp.ns() >= kMaxRosNs)
      return fail(Error{fixture + ": " + channel_topic(e.channel) + " event " + std::to_string(e.sequence) + ": stamp " +
                        std::to_string(e.stamp.ns()) + " ns is outside the ROS time range"});
    if (e.channel != Channel::kGyro) {
      if (Status s = emit(e); !s) return fail(s.error());
      continue;
    }
    auto ready = gyro.push(e);
    if (!ready) return fail(Error{fixture + ": " + ready.error().message});
    for (const Event& g : *ready)
      if (Status s = emit(g); !s) return fail(s.error());
  }
  if (Status s = gyro.finish(); !s) return fail(Error{fixture + ": " + s.error().message});
  Status s = bag ? bw->close() : mw->close();
  if (!s) return fail(s.error());
  bw.reset();
  mw.reset();
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) return fail(Error{out + ": cannot write (" + ec.message() + ")"});

  if (o.write_topics_yaml) {
    TopicMap map;
    const auto& md = (*src)->metadata();
    if (auto m = md.find("T_V_h"); m != md.end()) map.T_V_h = m->second;
    if (auto m = md.find("T_V_v"); m != md.end()) map.T_V_v = m->second;
    if (auto m = md.find("T_V_gyro"); m != md.end()) map.T_V_gyro = m->second;
    map.latitude_deg = latitude;
    for (const auto& [ch, t] : topics) {
      TopicRule r;
      r.topic = t.name;
      r.role = t.role;
      if (auto d = device_ids.find(ch); d != device_ids.end()) r.device_id = d->second;
      if (t.role == Role::kDepth && o.sonar == SonarType::kProjected) {
        r.fluid_density_kg_m3 = kSeawaterDensity;
        r.atmospheric_pressure_pa = kAtmospherePa;
        r.gravity_m_s2 = kGravity;
      }
      map.rules.push_back(r);
    }
    report.topics_yaml = topics_yaml_path(out);
    std::ofstream y(report.topics_yaml, std::ios::binary);
    y << "# Written by `orthosonar export` for " << std::filesystem::path(out).filename().string()
      << " (from " << std::filesystem::path(fixture).filename().string() << ")\n"
      << topic_map_yaml(map, false);
    if (!y) return Error{report.topics_yaml + ": cannot write"};
  }
  return report;
}

}  // namespace orthosonar::replay::ros
