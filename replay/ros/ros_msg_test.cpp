// ROS message definitions (Schema), MD5 sums, and the ros1 / CDR encodings (Writer and
// decode): the published MD5s of the standard types, round trips of random contents for
// every known type in both encodings, hand-made CDR bytes for alignment and endianness,
// and malformed inputs that must give errors, never crashes.
#include "replay/ros/ros_msg.hpp"

#include <catch2/catch.hpp>
#include <rapidcheck/catch.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <string>

#include "replay/ros/msg_types.hpp"

using namespace orthosonar::replay::rosmsg;

namespace {

Schema parse_ok(std::string_view root, std::string_view text, Dialect d = Dialect::kRos1) {
  auto s = Schema::parse(root, text, d);
  INFO(root << ": " << (s ? std::string() : s.error().message));
  REQUIRE(s.ok());
  return std::move(s).value();
}

std::vector<uint8_t> hex_bytes(std::string_view hex) {
  std::vector<uint8_t> out;
  std::string digits;
  for (char c : hex) {
    if (std::isxdigit(static_cast<unsigned char>(c))) digits.push_back(c);
  }
  for (size_t i = 0; i + 1 < digits.size(); i += 2) {
    out.push_back(static_cast<uint8_t>(std::stoi(digits.substr(i, 2), nullptr, 16)));
  }
  return out;
}

// Writes random contents for a schema's type field by field with the Writer (the way an
// exporter does) and builds the Value the decoder must give back. Contents come from
// rapidcheck, so a failing case shrinks and prints its seed.
class RandomMessage {
 public:
  RandomMessage(const Schema& schema, Writer& w) : schema_(schema), w_(w) {}

  Value message(const MsgSpec& spec) {
    std::vector<std::pair<std::string, Value>> fields;
    if (w_.encoding() == Encoding::kCdr && spec.fields.empty()) w_.u8(0);
    for (const Field& f : spec.fields) fields.emplace_back(f.name, field(f));
    return Value::message(std::move(fields));
  }

 private:
  Value field(const Field& f) {
    if (f.array < 0) return element(f);
    const auto n = f.array > 0 ? static_cast<uint32_t>(f.array)
                               : *rc::gen::inRange<uint32_t>(0, f.prim == Prim::kUint8 ? 40 : 6);
    if (f.array == 0) w_.sequence_length(n);
    if (f.prim == Prim::kUint8 || f.prim == Prim::kInt8) {
      auto& bytes = storage_.emplace_back(*rc::gen::container<std::vector<uint8_t>>(n, rc::gen::arbitrary<uint8_t>()));
      w_.raw(bytes.data(), bytes.size());
      return Value::bytes(bytes, f.prim == Prim::kInt8);
    }
    std::vector<Value> elements;
    for (uint32_t i = 0; i < n; ++i) elements.push_back(element(f));
    return Value::array(std::move(elements));
  }

  template <class T>
  static Value num(T x) {
    if constexpr (std::is_floating_point_v<T>) {
      return Value::number(static_cast<double>(x), 0, false);
    } else {
      return Value::number(static_cast<double>(x), static_cast<int64_t>(x), true);
    }
  }

  Value element(const Field& f) {
    switch (f.prim) {
      case Prim::kBool: { const bool x = *rc::gen::arbitrary<bool>(); w_.boolean(x); return num(x ? 1 : 0); }
      case Prim::kInt8: { const auto x = *rc::gen::arbitrary<int8_t>(); w_.i8(x); return num(x); }
      case Prim::kUint8: { const auto x = *rc::gen::arbitrary<uint8_t>(); w_.u8(x); return num(x); }
      case Prim::kInt16: { const auto x = *rc::gen::arbitrary<int16_t>(); w_.i16(x); return num(x); }
      case Prim::kUint16: { const auto x = *rc::gen::arbitrary<uint16_t>(); w_.u16(x); return num(x); }
      case Prim::kInt32: { const auto x = *rc::gen::arbitrary<int32_t>(); w_.i32(x); return num(x); }
      case Prim::kUint32: { const auto x = *rc::gen::arbitrary<uint32_t>(); w_.u32(x); return num(x); }
      case Prim::kInt64: { const auto x = *rc::gen::arbitrary<int64_t>(); w_.i64(x); return num(x); }
      case Prim::kUint64: { const auto x = *rc::gen::arbitrary<uint64_t>(); w_.u64(x); return num(x); }
      case Prim::kFloat32: { const auto x = *rc::gen::arbitrary<float>(); w_.f32(x); return num(x); }
      case Prim::kFloat64: { const auto x = *rc::gen::arbitrary<double>(); w_.f64(x); return num(x); }
      case Prim::kString: {
        const auto s = *rc::gen::container<std::string>(rc::gen::inRange<char>(32, 127));
        w_.string(s);
        return Value::string(s);
      }
      case Prim::kTime: {
        const int64_t ns = int64_t{*rc::gen::inRange<int32_t>(0, INT32_MAX)} * 1'000'000'000 +
                           *rc::gen::inRange<int32_t>(0, 1'000'000'000);
        w_.time(ns);
        return Value::time(ns);
      }
      case Prim::kDuration: {
        // The Writer has no duration: ros1 int32 sec + int32 nsec, CDR int32 + uint32.
        const int32_t sec = *rc::gen::arbitrary<int32_t>();
        const int32_t nsec = *rc::gen::inRange<int32_t>(0, 1'000'000'000);
        w_.i32(sec);
        if (w_.encoding() == Encoding::kRos1) w_.i32(nsec); else w_.u32(static_cast<uint32_t>(nsec));
        return Value::time(int64_t{sec} * 1'000'000'000 + nsec);
      }
      case Prim::kMessage:
        return message(*schema_.find(f.type));
    }
    return {};
  }

  const Schema& schema_;
  Writer& w_;
  std::deque<std::vector<uint8_t>> storage_;
};

// Structural equality; floats bit for bit (NaN equals NaN).
bool same(const Value& a, const Value& b, std::string& where, const std::string& path = "") {
  if (a.kind() != b.kind()) {
    where = path + ": kind";
    return false;
  }
  switch (a.kind()) {
    case Value::Kind::kNumber: {
      const double x = a.as_double(), y = b.as_double();
      const bool eq = (std::isnan(x) && std::isnan(y)) || std::memcmp(&x, &y, sizeof x) == 0;
      if (!eq || a.is_integer() != b.is_integer() || (a.is_integer() && a.as_int() != b.as_int())) {
        where = path + ": " + std::to_string(x) + " vs " + std::to_string(y);
        return false;
      }
      return true;
    }
    case Value::Kind::kString:
      if (a.as_string() != b.as_string()) where = path + ": string";
      return a.as_string() == b.as_string();
    case Value::Kind::kTime:
      if (a.as_ns() != b.as_ns()) where = path + ": time";
      return a.as_ns() == b.as_ns();
    case Value::Kind::kBytes: {
      const auto x = a.bytes(), y = b.bytes();
      const bool eq = x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin()) && a.as_doubles() == b.as_doubles();
      if (!eq) where = path + ": bytes";
      return eq;
    }
    case Value::Kind::kArray:
      if (a.elements().size() != b.elements().size()) {
        where = path + ": length";
        return false;
      }
      for (size_t i = 0; i < a.elements().size(); ++i) {
        if (!same(a.elements()[i], b.elements()[i], where, path + "[" + std::to_string(i) + "]")) return false;
      }
      return true;
    case Value::Kind::kMessage:
      if (a.fields().size() != b.fields().size()) {
        where = path + ": field count";
        return false;
      }
      for (size_t i = 0; i < a.fields().size(); ++i) {
        if (a.fields()[i].first != b.fields()[i].first) {
          where = path + ": field name";
          return false;
        }
        if (!same(a.fields()[i].second, b.fields()[i].second, where, path + "." + a.fields()[i].first)) return false;
      }
      return true;
  }
  return false;
}

void check_round_trip(const Schema& schema, Encoding enc) {
  Writer w(enc);
  RandomMessage gen(schema, w);
  const Value expected = gen.message(*schema.find(schema.root()));
  const auto bytes = w.bytes();
  auto got = decode(schema, enc, bytes.data(), bytes.size());
  RC_ASSERT(got.ok());
  std::string where;
  const bool eq = same(expected, *got, where);
  if (!eq) RC_LOG() << schema.root() << " differs at " << where << "\n";
  RC_ASSERT(eq);
}

}  // namespace

TEST_CASE("every known type parses in both dialects, with its dependencies", "[ros_msg]") {
  REQUIRE(known_types().size() == 13);
  for (const KnownType& k : known_types()) {
    for (Dialect d : {Dialect::kRos1, Dialect::kRos2}) {
      const Schema s = parse_ok(k.name, d == Dialect::kRos1 ? k.ros1 : k.ros2, d);
      CHECK(s.root() == k.name);
      const MsgSpec* root = s.find(k.name);
      REQUIRE(root != nullptr);
      CHECK(!root->fields.empty());
      // Every message field resolves to a section of the same text.
      for (const auto& [name, spec] : s.types()) {
        for (const Field& f : spec.fields) {
          if (f.prim == Prim::kMessage) CHECK(s.find(f.type) != nullptr);
        }
      }
      const MsgSpec* header = s.find("std_msgs/Header");
      REQUIRE(header != nullptr);
      // ROS 1 Header: seq, stamp, frame_id; ROS 2: stamp (builtin_interfaces/Time), frame_id.
      CHECK(header->fields.size() == (d == Dialect::kRos1 ? 3u : 2u));
      CHECK(header->fields[d == Dialect::kRos1 ? 1 : 0].prim == Prim::kTime);
    }
  }
  CHECK(known_type("sensor_msgs/Imu") != nullptr);
  CHECK(known_type("sensor_msgs/Nope") == nullptr);
  CHECK(definition("sensor_msgs/Nope", Dialect::kRos1).empty());
}

TEST_CASE("the authors' types have the fields the issue describes", "[ros_msg]") {
  const Schema ping = parse_ok("sonar_oculus/OculusPing", definition("sonar_oculus/OculusPing", Dialect::kRos1));
  std::vector<std::string> names;
  for (const Field& f : ping.find("sonar_oculus/OculusPing")->fields) names.push_back(f.name);
  CHECK(names == std::vector<std::string>{"header", "fire_msg", "ping_id", "part_number", "start_time", "bearings",
                                          "range_resolution", "num_ranges", "num_beams", "ping"});
  CHECK(ping.find("sonar_oculus/OculusPing")->fields[1].type == "sonar_oculus/OculusFire");
  CHECK(ping.find("sonar_oculus/OculusPing")->fields[9].type == "sensor_msgs/CompressedImage");
  const auto& fire = ping.find("sonar_oculus/OculusFire")->fields;
  REQUIRE(fire.size() == 8);
  CHECK(fire[0].type == "std_msgs/Header");  // "Header header" resolves to std_msgs/Header
  const Schema psi = parse_ok("marine_acoustic_msgs/ProjectedSonarImage",
                              definition("marine_acoustic_msgs/ProjectedSonarImage", Dialect::kRos2), Dialect::kRos2);
  const MsgSpec* data = psi.find("marine_acoustic_msgs/SonarImageData");
  REQUIRE(data != nullptr);
  REQUIRE(data->constants.size() == 10);
  CHECK(data->constants[9].name == "DTYPE_FLOAT64");
  CHECK(data->constants[9].value == "9");
  CHECK(psi.find("marine_acoustic_msgs/PingInfo")->fields.size() == 4);
}

TEST_CASE("MD5 sums equal the published ones (genmsg's rule)", "[ros_msg]") {
  // Standard types: the values genpy prints for Noetic's common_msgs (_md5sum). The
  // authors' and marine_acoustic_msgs types: genmsg's compute_md5 over the packages'
  // files (the marine_acoustic_msgs values also name the package's own migration rules).
  const std::map<std::string, std::string> expected = {
      {"sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2"},
      {"sensor_msgs/Image", "060021388200f6f0f447d0fcd9c64743"},
      {"sensor_msgs/CompressedImage", "8f7a12909da2c9d3332d540a0977563f"},
      {"sensor_msgs/FluidPressure", "804dc5cea1c5306d6a2eb80b9833befe"},
      {"geometry_msgs/PoseStamped", "d3812c3cbc69362b77dc0b19b345f8f5"},
      {"geometry_msgs/TwistWithCovarianceStamped", "8927a1a12fb2607ceea095b2dc440a96"},
      {"sonar_oculus/OculusPing", "9f6ad8a7bb36e92c4f0225b11da7ca2e"},
      {"sonar_oculus/OculusPingUncompressed", "4339b8338f845749301a38b07bd11f83"},
      {"sonar_oculus/OculusFire", "0ab4b9458f99dac20a81bfd379cffcb5"},
      {"rti_dvl/DVL", "84fe0dd3f2fa07f272dbadf697440637"},
      {"bar30_depth/Depth", "dd07528378d12aab22e9e6b826443a3a"},
      {"kvh_gyro/gyro", "7bf4a7f82fe96d9124091847a68d6212"},
      {"marine_acoustic_msgs/ProjectedSonarImage", "c72fc8e29ab227a547720a36666022fd"},
  };
  for (const KnownType& k : known_types()) {
    INFO(k.name);
    REQUIRE(expected.count(std::string(k.name)) == 1);
    CHECK(md5_of(k.name) == expected.at(std::string(k.name)));
  }
  CHECK(md5_of("nope/Nope").empty());
  // Header alone, and the nested types with constants (SonarImageData) and arrays of messages.
  CHECK(parse_ok("std_msgs/Header", "uint32 seq\ntime stamp\nstring frame_id\n").md5() == "2176decaecbce78abc3b96ef049fabed");
  CHECK(parse_ok("geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z").md5() == "4a842b65f413084dc2b10fb484ea7f17");
  CHECK(parse_ok("marine_acoustic_msgs/SonarImageData",
                 "bool    is_bigendian\n\nuint32  DTYPE_UINT8 = 0\nuint32  DTYPE_INT8 = 1\nuint32  DTYPE_UINT16 = 2\n"
                 "uint32  DTYPE_INT16 = 3\nuint32  DTYPE_UINT32 = 4\nuint32  DTYPE_INT32 = 5\nuint32  DTYPE_UINT64 = 6\n"
                 "uint32  DTYPE_INT64 = 7\nuint32  DTYPE_FLOAT32 = 8\nuint32  DTYPE_FLOAT64 = 9\n\nuint32  dtype\n"
                 "uint32 beam_count\nuint8[] data\n")
            .md5() == "4daa9f67cfdb0ed22d5f2fe52c794da3");
}

TEST_CASE("definition texts: comments, constants, ROS 2 defaults and bounds, names", "[ros_msg]") {
  const std::string text =
      "# leading comment\n"
      "  int32 FOO = 7   # constant with a comment\n"
      "string GREETING=hello # not a comment in a string constant\n"
      "float64 w 1.0\n"                 // ROS 2 default value
      "string<=8 name \"abc\"\n"        // bounded string with default
      "int16[<=4] few\n"                // bounded sequence
      "string<=3[] words\n"             // sequence of bounded strings
      "builtin_interfaces/msg/Time t\n"
      "builtin_interfaces/Duration d\n"
      "Inner inner\n"
      "pkg/msg/Inner[2] two\n"
      "================================================================================\n"
      "MSG: pkg/msg/Inner\n"
      "byte b\n"
      "char c\n";
  const Schema s = parse_ok("pkg/msg/Outer", text, Dialect::kRos2);
  CHECK(s.root() == "pkg/Outer");
  const MsgSpec& o = *s.find("pkg/Outer");
  REQUIRE(o.constants.size() == 2);
  CHECK(o.constants[0].value == "7");
  CHECK(o.constants[1].value == "hello # not a comment in a string constant");
  REQUIRE(o.fields.size() == 8);
  CHECK(o.fields[1].upper_bound == 8);
  CHECK(o.fields[2].array == 0);
  CHECK(o.fields[2].upper_bound == 4);
  CHECK(o.fields[3].upper_bound == 0);
  CHECK(o.fields[4].prim == Prim::kTime);
  CHECK(o.fields[5].prim == Prim::kDuration);
  CHECK(o.fields[6].type == "pkg/Inner");
  CHECK(o.fields[7].array == 2);
  CHECK(s.find("pkg/Inner")->fields[0].prim == Prim::kUint8);  // ROS 2 byte is an octet
  CHECK(parse_ok("pkg/Inner", "byte b\n").find("pkg/Inner")->fields[0].prim == Prim::kInt8);  // ROS 1 byte: int8

  // Unqualified names resolve in the package of the type that uses them (genmsg).
  const Schema pose = parse_ok("geometry_msgs/PoseStamped", definition("geometry_msgs/PoseStamped", Dialect::kRos1));
  CHECK(pose.find("geometry_msgs/Pose")->fields[0].type == "geometry_msgs/Point");
}

TEST_CASE("definition errors name the type and field", "[ros_msg]") {
  auto missing = Schema::parse("a/B", "int32 x\nOther y\n", Dialect::kRos1);
  REQUIRE(!missing.ok());
  CHECK_THAT(missing.error().message, Catch::Contains("field y") && Catch::Contains("a/Other"));
  auto cyc = Schema::parse("a/B", "C c\n===\nMSG: a/C\nB b\n", Dialect::kRos1);
  REQUIRE(!cyc.ok());
  CHECK_THAT(cyc.error().message, Catch::Contains("contains itself"));
  std::string deep = "T0 t\n";
  for (int i = 0; i < 40; ++i) {
    deep += "===\nMSG: a/T" + std::to_string(i) + "\nT" + std::to_string(i + 1) + " t\n";
  }
  deep += "===\nMSG: a/T40\nint32 x\n";
  auto too_deep = Schema::parse("a/B", deep, Dialect::kRos1);
  REQUIRE(!too_deep.ok());
  CHECK_THAT(too_deep.error().message, Catch::Contains("deeper"));
  CHECK(!Schema::parse("a/B", "int32 x\nint32 x\n", Dialect::kRos1).ok());
  CHECK(!Schema::parse("a/B", "int32[0] x\n", Dialect::kRos1).ok());
  CHECK(!Schema::parse("a/B", "int32[x] x\n", Dialect::kRos1).ok());
  CHECK(!Schema::parse("a/B", "int32 9x\n", Dialect::kRos1).ok());
  CHECK(!Schema::parse("a/B", "wstring w\n", Dialect::kRos2).ok());
  CHECK(!Schema::parse("a/B", "int32 x\n===\nIDL: a/C\n", Dialect::kRos2).ok());
  CHECK(!Schema::parse("a/B", "int32 x\n===\nnot a header\n", Dialect::kRos2).ok());
  CHECK(!Schema::parse("nopackage", "int32 x\n", Dialect::kRos1).ok());
  CHECK(Schema::parse("std_msgs/Empty", "", Dialect::kRos1).ok());
}

TEST_CASE("Writer and decode round trip random contents of every known type", "[ros_msg][property][rapidcheck]") {
  for (const KnownType& k : known_types()) {
    for (Encoding enc : {Encoding::kRos1, Encoding::kCdr}) {
      const Dialect d = enc == Encoding::kRos1 ? Dialect::kRos1 : Dialect::kRos2;
      const Schema schema = parse_ok(k.name, d == Dialect::kRos1 ? k.ros1 : k.ros2, d);
      const std::string label = std::string(k.name) + (enc == Encoding::kCdr ? " cdr" : " ros1");
      rc::prop(label, [&schema, enc] { check_round_trip(schema, enc); });
    }
  }
}

TEST_CASE("round trips of every primitive, fixed arrays, bounded and empty types", "[ros_msg][property][rapidcheck]") {
  const std::string text =
      "bool a\nint8 b\nuint8 c\nint16 d\nuint16 e\nint32 f\nuint32 g\nint64 h\nuint64 i\n"
      "float32 j\nfloat64 k\nstring l\ntime m\nduration n\nbyte o\nchar p\n"
      "int8[] q\nuint8[3] r\nfloat64[2] s\nstring[] t\ntime[] u\nbool[] v\nuint64[] w\n"
      "Empty e1\nEmpty[] e2\nInner[] x\nInner[2] y\n"
      "===\nMSG: t/Empty\n"
      "===\nMSG: t/Inner\nuint8 a\nfloat64 b\nstring c\nint16[] d\n";
  for (Encoding enc : {Encoding::kRos1, Encoding::kCdr}) {
    const Schema schema = parse_ok("t/All", text, enc == Encoding::kRos1 ? Dialect::kRos1 : Dialect::kRos2);
    rc::prop(enc == Encoding::kCdr ? "cdr" : "ros1", [&schema, enc] { check_round_trip(schema, enc); });
  }
}

TEST_CASE("CDR alignment counts from the end of the encapsulation header", "[ros_msg]") {
  const Schema s = parse_ok("t/A",
                            "uint8 a\nfloat64 b\nuint16 c\nint32[] d\nstring e\nuint8 f\nfloat64[] g\nuint8 h\nuint32 i\n",
                            Dialect::kRos2);
  Writer w(Encoding::kCdr);
  w.u8(1);
  w.f64(2.0);
  w.u16(3);
  w.sequence_length(1);
  w.i32(-4);
  w.string("hi");
  w.u8(5);
  w.sequence_length(0);  // empty float64 sequence: no alignment to 8
  w.u8(6);
  w.u32(7);
  const auto expected = hex_bytes(
      "00 01 00 00"                // encapsulation: CDR little endian
      "01 00 00 00 00 00 00 00"    // a, pad to 8
      "00 00 00 00 00 00 00 40"    // b = 2.0
      "03 00 00 00"                // c, pad to 4
      "01 00 00 00 fc ff ff ff"    // d = [-4]
      "03 00 00 00 68 69 00"       // e = "hi" + NUL
      "05"                         // f
      "00 00 00 00"                // g = [] (count, already aligned)
      "06 00 00 00"                // h, pad to 4
      "07 00 00 00");              // i
  CHECK(w.bytes() == expected);
  auto v = decode(s, Encoding::kCdr, expected.data(), expected.size());
  REQUIRE(v.ok());
  CHECK(v->find("b")->as_double() == 2.0);
  CHECK(v->find("d")->elements()[0].as_int() == -4);
  CHECK(v->find("e")->as_string() == "hi");
  CHECK(v->find("i")->as_int() == 7);

  // The same message big endian (encapsulation 00 00).
  const auto be = hex_bytes(
      "00 00 00 00"
      "01 00 00 00 00 00 00 00"
      "40 00 00 00 00 00 00 00"
      "00 03 00 00"
      "00 00 00 01 ff ff ff fc"
      "00 00 00 03 68 69 00"
      "05"
      "00 00 00 00"
      "06 00 00 00"
      "00 00 00 07");
  auto vb = decode(s, Encoding::kCdr, be.data(), be.size());
  REQUIRE(vb.ok());
  std::string where;
  CHECK(same(*v, *vb, where));

  // Final padding: up to 3 zero bytes are accepted; more, or non-zero, are not.
  auto padded = expected;
  padded.insert(padded.end(), {0, 0, 0});
  CHECK(decode(s, Encoding::kCdr, padded.data(), padded.size()).ok());
  padded.push_back(0);
  CHECK(!decode(s, Encoding::kCdr, padded.data(), padded.size()).ok());
  auto garbage = expected;
  garbage.push_back(1);
  CHECK(!decode(s, Encoding::kCdr, garbage.data(), garbage.size()).ok());
}

TEST_CASE("Writer::header writes the Header of each encoding", "[ros_msg]") {
  const int64_t stamp = 1'700'000'000'123'456'789;
  Writer a(Encoding::kRos1);
  a.header(42, stamp, "sonar");
  Writer b(Encoding::kRos1);
  b.u32(42);
  b.u32(1'700'000'000);
  b.u32(123'456'789);
  b.u32(5);
  b.raw(reinterpret_cast<const uint8_t*>("sonar"), 5);
  CHECK(a.bytes() == b.bytes());
  const Schema h1 = parse_ok("std_msgs/Header", "uint32 seq\ntime stamp\nstring frame_id\n");
  auto v1 = decode(h1, Encoding::kRos1, a.bytes().data(), a.bytes().size());
  REQUIRE(v1.ok());
  CHECK(v1->find("seq")->as_int() == 42);
  CHECK(v1->find("stamp")->as_ns() == stamp);
  CHECK(v1->find("frame_id")->as_string() == "sonar");

  Writer c(Encoding::kCdr);
  c.header(42, stamp, "sonar");
  CHECK(c.bytes() == hex_bytes("00 01 00 00  00 f1 53 65  15 cd 5b 07  06 00 00 00  73 6f 6e 61 72 00"));
  const Schema h2 = parse_ok("std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n", Dialect::kRos2);
  auto v2 = decode(h2, Encoding::kCdr, c.bytes().data(), c.bytes().size());
  REQUIRE(v2.ok());
  CHECK(v2->find("stamp")->as_ns() == stamp);
}

TEST_CASE("byte arrays are views into the input, not copies", "[ros_msg]") {
  const Schema s = parse_ok("sensor_msgs/CompressedImage", definition("sensor_msgs/CompressedImage", Dialect::kRos1));
  std::vector<uint8_t> image(300'000);
  for (size_t i = 0; i < image.size(); ++i) image[i] = static_cast<uint8_t>(i * 7);
  Writer w(Encoding::kRos1);
  w.header(1, 2, "f");
  w.string("jpeg");
  w.sequence_length(static_cast<uint32_t>(image.size()));
  w.raw(image.data(), image.size());
  const auto bytes = w.take();
  auto v = decode(s, Encoding::kRos1, bytes.data(), bytes.size());
  REQUIRE(v.ok());
  const auto data = v->find("data")->bytes();
  CHECK(data.data() == bytes.data() + (bytes.size() - image.size()));
  CHECK(std::equal(data.begin(), data.end(), image.begin(), image.end()));
  CHECK(v->find("header.stamp")->as_ns() == 2);
  CHECK(v->find("header.nope") == nullptr);
  CHECK(v->find("data")->as_doubles().size() == image.size());
}

TEST_CASE("malformed messages give errors naming the field and offset", "[ros_msg]") {
  for (Encoding enc : {Encoding::kRos1, Encoding::kCdr}) {
    const Dialect d = enc == Encoding::kRos1 ? Dialect::kRos1 : Dialect::kRos2;
    const Schema s = parse_ok("marine_acoustic_msgs/ProjectedSonarImage",
                              definition("marine_acoustic_msgs/ProjectedSonarImage", d), d);
    Writer w(enc);
    w.header(7, 1'000'000'000, "sonar");
    w.f32(1.2e6f);
    w.f32(1500.f);
    w.sequence_length(2);
    w.f32(0.01f);
    w.f32(0.02f);
    w.sequence_length(5);
    for (int i = 0; i < 5; ++i) w.f32(0.1f * static_cast<float>(i));
    const size_t rx_at = w.bytes().size() - 20;  // first rx_beamwidths element
    w.sequence_length(1);
    w.f64(0);
    w.f64(0);
    w.f64(1);
    w.sequence_length(1);
    w.f32(5.f);
    w.boolean(false);
    w.u32(0);
    w.u32(1);
    w.sequence_length(3);
    const uint8_t px[3] = {1, 2, 3};
    w.raw(px, 3);
    const auto full = w.bytes();
    REQUIRE(decode(s, enc, full.data(), full.size()).ok());

    // Cut inside rx_beamwidths[3].
    auto cut = decode(s, enc, full.data(), rx_at + 13);
    REQUIRE(!cut.ok());
    CHECK_THAT(cut.error().message, Catch::Contains("marine_acoustic_msgs/ProjectedSonarImage") &&
                                        Catch::Contains("ping_info.rx_beamwidths[3]") &&
                                        Catch::Contains("byte offset"));
    // Every prefix fails cleanly.
    for (size_t n = 0; n < full.size(); ++n) CHECK(!decode(s, enc, full.data(), n).ok());
    // Trailing bytes.
    auto longer = full;
    longer.insert(longer.end(), {9, 9, 9, 9, 9});
    CHECK(!decode(s, enc, longer.data(), longer.size()).ok());
    // A huge sequence length in every length position does not allocate: it is an error.
    for (size_t at = enc == Encoding::kCdr ? 4 : 0; at + 4 <= full.size(); ++at) {
      auto bad = full;
      bad[at] = bad[at + 1] = bad[at + 2] = bad[at + 3] = 0xff;
      (void)decode(s, enc, bad.data(), bad.size());  // no crash, no huge allocation
    }
    auto huge = full;
    const size_t len_at = rx_at - 4;
    huge[len_at] = huge[len_at + 1] = huge[len_at + 2] = huge[len_at + 3] = 0xff;
    auto e = decode(s, enc, huge.data(), huge.size());
    REQUIRE(!e.ok());
    CHECK_THAT(e.error().message, Catch::Contains("ping_info.rx_beamwidths"));
  }
  const Schema s = parse_ok("t/A", "int32 a\n", Dialect::kRos2);
  for (const char* hdr : {"00 02 00 00 01 00 00 00", "00 07 00 00 01 00 00 00", "01 01 00 00 01 00 00 00", "00 01"}) {
    const auto b = hex_bytes(hdr);
    auto r = decode(s, Encoding::kCdr, b.data(), b.size());
    REQUIRE(!r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("encapsulation"));
  }
  CHECK(!decode(s, Encoding::kCdr, nullptr, 0).ok());
  CHECK(decode(parse_ok("t/E", ""), Encoding::kRos1, nullptr, 0).ok());
}

TEST_CASE("zero-size elements cannot exhaust memory", "[ros_msg]") {
  // ros1 empty messages take no bytes: a huge count of them is bounded by the budget.
  const Schema s = parse_ok("t/A", "E[] e\n===\nMSG: t/E\n", Dialect::kRos1);
  const auto b = hex_bytes("ff ff ff ff");
  auto r = decode(s, Encoding::kRos1, b.data(), b.size());
  REQUIRE(!r.ok());
  CHECK_THAT(r.error().message, Catch::Contains("too many"));
  const Schema fixed = parse_ok("t/A", "E[2000000000] e\n===\nMSG: t/E\nF[2000000000] f\n===\nMSG: t/F\n",
                                Dialect::kRos1);
  CHECK(!decode(fixed, Encoding::kRos1, b.data(), 0).ok());
  // Bounded sequences and strings are enforced.
  const Schema bounded = parse_ok("t/B", "int8[<=2] a\nstring<=2 s\n", Dialect::kRos2);
  Writer w(Encoding::kCdr);
  w.sequence_length(3);
  for (int8_t i = 0; i < 3; ++i) w.i8(i);
  w.string("ab");
  CHECK_THAT(decode(bounded, Encoding::kCdr, w.bytes().data(), w.bytes().size()).error().message, Catch::Contains("bound"));
  Writer w2(Encoding::kCdr);
  w2.sequence_length(2);
  w2.i8(-1);
  w2.i8(2);
  w2.string("abc");
  auto r2 = decode(bounded, Encoding::kCdr, w2.bytes().data(), w2.bytes().size());
  REQUIRE(!r2.ok());
  CHECK_THAT(r2.error().message, Catch::Contains("s (string"));
  Writer w3(Encoding::kCdr);
  w3.sequence_length(2);
  w3.i8(-1);
  w3.i8(2);
  w3.string("ab");
  auto r3 = decode(bounded, Encoding::kCdr, w3.bytes().data(), w3.bytes().size());
  REQUIRE(r3.ok());
  CHECK(r3->find("a")->as_doubles() == std::vector<double>{-1, 2});
}
