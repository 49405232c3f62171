// orthosonar_msg_dump: our ROS message definitions and codecs seen from outside, for the
// interop tests with genpy (msg_interop.py) and Foxglove's CDR serialiser (cdr_check.mjs).
//   orthosonar_msg_dump types                          JSON: name, ros1, ros2, md5 per known type
//   orthosonar_msg_dump decode TYPE ros1|cdr FILE      the decoded message as JSON
//   orthosonar_msg_dump encode-sample TYPE ros1|cdr OUT  a deterministic sample message
// JSON values: messages are objects, arrays (byte arrays too) lists, times
// {"sec": s, "nsec": n} with 0 <= n < 1e9, NaN null. ros1 uses the ROS 1 definition text,
// cdr the ROS 2 one.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "replay/ros/msg_types.hpp"
#include "replay/ros/ros_msg.hpp"

using namespace orthosonar::replay::rosmsg;
using json = nlohmann::ordered_json;

namespace {

json to_json(const Value& v) {
  switch (v.kind()) {
    case Value::Kind::kNumber:
      if (v.is_integer()) return v.as_int();
      return v.as_double();  // nlohmann writes NaN and infinities as null
    case Value::Kind::kString:
      return v.as_string();
    case Value::Kind::kTime: {
      int64_t sec = v.as_ns() / 1'000'000'000;
      int64_t nsec = v.as_ns() % 1'000'000'000;
      if (nsec < 0) {
        nsec += 1'000'000'000;
        --sec;
      }
      return json{{"sec", sec}, {"nsec", nsec}};
    }
    case Value::Kind::kBytes: {
      json a = json::array();
      for (double d : v.as_doubles()) a.push_back(static_cast<int64_t>(d));
      return a;
    }
    case Value::Kind::kArray: {
      json a = json::array();
      for (const Value& e : v.elements()) a.push_back(to_json(e));
      return a;
    }
    case Value::Kind::kMessage: {
      json o = json::object();
      for (const auto& [name, f] : v.fields()) o[name] = to_json(f);
      return o;
    }
  }
  return nullptr;
}

// Deterministic contents (splitmix64), varied enough to move CDR alignment about.
class Sample {
 public:
  Sample(const Schema& schema, Writer& w, uint64_t seed) : schema_(schema), w_(w), state_(seed) {}

  void message(const MsgSpec& spec) {
    if (w_.encoding() == Encoding::kCdr && spec.fields.empty()) w_.u8(0);
    for (const Field& f : spec.fields) field(f);
  }

 private:
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // A finite value exact in float32: k / 64 with |k| <= 2^20.
  double real() { return static_cast<double>(static_cast<int64_t>(next() % 2'097'153) - 1'048'576) / 64.0; }

  void field(const Field& f) {
    if (f.array < 0) return element(f);
    uint32_t n = f.array > 0 ? static_cast<uint32_t>(f.array)
                             : static_cast<uint32_t>(next() % (f.prim == Prim::kUint8 || f.prim == Prim::kInt8 ? 41 : 6));
    if (f.upper_bound != 0 && f.array == 0) n = std::min(n, f.upper_bound);
    if (f.array == 0) w_.sequence_length(n);
    for (uint32_t i = 0; i < n; ++i) element(f);
  }

  void element(const Field& f) {
    switch (f.prim) {
      case Prim::kBool: return w_.boolean(next() % 2 == 1);
      case Prim::kInt8: return w_.i8(static_cast<int8_t>(next()));
      case Prim::kUint8: return w_.u8(static_cast<uint8_t>(next()));
      case Prim::kInt16: return w_.i16(static_cast<int16_t>(next()));
      case Prim::kUint16: return w_.u16(static_cast<uint16_t>(next()));
      case Prim::kInt32: return w_.i32(static_cast<int32_t>(next()));
      case Prim::kUint32: return w_.u32(static_cast<uint32_t>(next()));
      // Within 2^53, so every JSON reader keeps them exact.
      case Prim::kInt64: return w_.i64(static_cast<int64_t>(next() % (1ULL << 53)) - (1LL << 52));
      case Prim::kUint64: return w_.u64(next() % (1ULL << 53));
      case Prim::kFloat32: return w_.f32(static_cast<float>(real()));
      case Prim::kFloat64: return w_.f64(real() / 3.0);
      case Prim::kString: {
        std::string s(next() % 10, 'a');
        for (char& c : s) c = static_cast<char>('a' + next() % 26);
        return w_.string(s);
      }
      case Prim::kTime:
        return w_.time(static_cast<int64_t>(next() % (1ULL << 31)) * 1'000'000'000 +
                       static_cast<int64_t>(next() % 1'000'000'000));
      case Prim::kDuration: {
        const auto sec = static_cast<int32_t>(next() % 100'000) - 50'000;
        const auto nsec = static_cast<uint32_t>(next() % 1'000'000'000);
        w_.i32(sec);
        return w_.encoding() == Encoding::kRos1 ? w_.i32(static_cast<int32_t>(nsec)) : w_.u32(nsec);
      }
      case Prim::kMessage:
        return message(*schema_.find(f.type));
    }
  }

  const Schema& schema_;
  Writer& w_;
  uint64_t state_;
};

int usage() {
  std::cerr << "usage: orthosonar_msg_dump types\n"
               "       orthosonar_msg_dump decode TYPE ros1|cdr FILE\n"
               "       orthosonar_msg_dump encode-sample TYPE ros1|cdr OUT\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string mode = argv[1];
  if (mode == "types") {
    json out = json::array();
    for (const KnownType& k : known_types()) {
      out.push_back({{"name", k.name}, {"ros1", k.ros1}, {"ros2", k.ros2}, {"md5", md5_of(k.name)}});
    }
    std::cout << out.dump(1) << "\n";
    return 0;
  }
  if (argc != 5 || (mode != "decode" && mode != "encode-sample")) return usage();
  const std::string type = argv[2], enc_name = argv[3], path = argv[4];
  if (enc_name != "ros1" && enc_name != "cdr") return usage();
  const Encoding enc = enc_name == "ros1" ? Encoding::kRos1 : Encoding::kCdr;
  const Dialect dialect = enc == Encoding::kRos1 ? Dialect::kRos1 : Dialect::kRos2;
  const std::string_view text = definition(type, dialect);
  if (text.empty()) {
    std::cerr << "unknown type " << type << "\n";
    return 2;
  }
  auto schema = Schema::parse(type, text, dialect);
  if (!schema) {
    std::cerr << schema.error().message << "\n";
    return 1;
  }
  if (mode == "decode") {
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) {
      std::cerr << "cannot read " << path << "\n";
      return 1;
    }
    auto v = decode(*schema, enc, bytes.data(), bytes.size());
    if (!v) {
      std::cerr << path << ": " << v.error().message << "\n";
      return 1;
    }
    std::cout << to_json(*v).dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
    return 0;
  }
  Writer w(enc);
  uint64_t seed = 1469598103934665603ULL;  // FNV-1a of the type name: each type its own sample
  for (char c : type) seed = (seed ^ static_cast<uint8_t>(c)) * 1099511628211ULL;
  Sample(*schema, w, seed).message(*schema->find(schema->root()));
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(w.bytes().data()), static_cast<std::streamsize>(w.bytes().size()));
  if (!out) {
    std::cerr << "cannot write " << path << "\n";
    return 1;
  }
  return 0;
}
