#include "replay/ros/msg_encode.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace orthosonar::replay::rosmsg {
namespace {

const Value* field_of(const Value* msg, const std::string& name) {
  if (msg == nullptr || msg->kind() != Value::Kind::kMessage) return nullptr;
  for (const auto& [n, v] : msg->fields())
    if (n == name) return &v;
  return nullptr;
}

bool is_bytes_prim(Prim p) { return p == Prim::kUint8 || p == Prim::kInt8; }

template <class T>
Status checked_int(const Value* v, const std::string& at, T& out) {
  if (v == nullptr) {
    out = 0;
    return {};
  }
  if (v->kind() != Value::Kind::kNumber) return Error{at + ": expected a number"};
  const int64_t i = v->is_integer() ? v->as_int() : static_cast<int64_t>(v->as_double());
  if (!v->is_integer() && static_cast<double>(i) != v->as_double()) return Error{at + ": expected an integer"};
  if constexpr (!std::is_same_v<T, int64_t>) {
    if (i < static_cast<int64_t>(std::numeric_limits<T>::min()) || i > static_cast<int64_t>(std::numeric_limits<T>::max()))
      return Error{at + ": " + std::to_string(i) + " out of range"};
  }
  out = static_cast<T>(i);
  return {};
}

Status encode_message(const Schema& schema, const std::string& type, const Value* msg, Writer& w,
                      const std::string& path, int depth);

Status encode_scalar(const Schema& schema, const Field& f, const Value* v, Writer& w, const std::string& at,
                     int depth) {
  const double d = (v != nullptr && v->kind() == Value::Kind::kNumber) ? v->as_double() : 0.0;
  switch (f.prim) {
    case Prim::kBool: w.boolean(d != 0.0); return {};
    case Prim::kInt8: { int8_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.i8(x); return {}; }
    case Prim::kUint8: { uint8_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.u8(x); return {}; }
    case Prim::kInt16: { int16_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.i16(x); return {}; }
    case Prim::kUint16: { uint16_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.u16(x); return {}; }
    case Prim::kInt32: { int32_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.i32(x); return {}; }
    case Prim::kUint32: { uint32_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.u32(x); return {}; }
    case Prim::kInt64: { int64_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.i64(x); return {}; }
    case Prim::kUint64: { int64_t x = 0; if (auto s = checked_int(v, at, x); !s) return s; w.u64(static_cast<uint64_t>(x)); return {}; }
    case Prim::kFloat32: w.f32(static_cast<float>(d)); return {};
    case Prim::kFloat64: w.f64(d); return {};
    case Prim::kString:
      if (v != nullptr && v->kind() != Value::Kind::kString) return Error{at + ": expected a string"};
      w.string(v != nullptr ? std::string_view(v->as_string()) : std::string_view());
      return {};
    case Prim::kTime:
    case Prim::kDuration: {
      const int64_t ns = v == nullptr ? 0 : v->as_ns();
      if (ns < 0) return Error{at + ": negative time"};
      w.time(ns);
      return {};
    }
    case Prim::kMessage: return encode_message(schema, f.type, v, w, at, depth + 1);
  }
  return {};
}

Status encode_message(const Schema& schema, const std::string& type, const Value* msg, Writer& w,
                      const std::string& path, int depth) {
  if (depth > 32) return Error{path + ": nested too deeply"};
  const MsgSpec* spec = schema.find(type);
  if (spec == nullptr) return Error{path + ": type " + type + " is not in the schema"};
  if (msg != nullptr && msg->kind() != Value::Kind::kMessage) return Error{path + ": expected a message of " + type};
  for (const Field& f : spec->fields) {
    const std::string at = path.empty() ? f.name : path + "." + f.name;
    const Value* v = field_of(msg, f.name);
    if (f.array < 0) {
      if (auto s = encode_scalar(schema, f, v, w, at, depth); !s) return s;
      continue;
    }
    // Arrays: bytes for uint8/int8, else elements.
    if (is_bytes_prim(f.prim) && (v == nullptr || v->kind() == Value::Kind::kBytes)) {
      const auto b = v != nullptr ? v->bytes() : std::span<const uint8_t>();
      if (f.array > 0) {
        if (b.size() != static_cast<size_t>(f.array) && v != nullptr)
          return Error{at + ": " + std::to_string(b.size()) + " bytes for a uint8[" + std::to_string(f.array) + "]"};
        if (v == nullptr) {
          for (int i = 0; i < f.array; ++i) w.u8(0);
          continue;
        }
      } else {
        w.sequence_length(static_cast<uint32_t>(b.size()));
      }
      w.raw(b.data(), b.size());
      continue;
    }
    if (v != nullptr && v->kind() != Value::Kind::kArray) return Error{at + ": expected an array"};
    const size_t n = v != nullptr ? v->elements().size() : (f.array > 0 ? static_cast<size_t>(f.array) : 0);
    if (f.array > 0 && n != static_cast<size_t>(f.array))
      return Error{at + ": " + std::to_string(n) + " elements for a fixed array of " + std::to_string(f.array)};
    if (f.array == 0) {
      if (n > UINT32_MAX) return Error{at + ": too many elements"};
      w.sequence_length(static_cast<uint32_t>(n));
    }
    Field element = f;
    element.array = -1;
    for (size_t i = 0; i < n; ++i) {
      const Value* e = v != nullptr ? &v->elements()[i] : nullptr;
      if (auto s = encode_scalar(schema, element, e, w, at + "[" + std::to_string(i) + "]", depth); !s) return s;
    }
  }
  return {};
}

}  // namespace

Status encode(const Schema& schema, const Value& message, Writer& out) {
  return encode_message(schema, schema.root(), &message, out, "", 0);
}

}  // namespace orthosonar::replay::rosmsg
