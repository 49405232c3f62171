// ROS message values and their two wire encodings: Value, the definition-driven ros1 / CDR decoder, the Writer.
//
// ros1: little endian, no alignment, uint32 length prefixes (wiki.ros.org/msg
// "Serialization"). CDR: OMG CDR (XCDR1) as rmw writes it, after a 4-byte encapsulation
// header; each primitive aligned to its size counted from the end of that header.
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/ros_msg_detail.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <optional>

namespace orthosonar::replay::rosmsg {
using namespace detail;

// ---------------------------------------------------------------------------------------
// Value

const Value* Value::find(std::string_view path) const {
  const Value* v = this;
  while (!path.empty()) {
    const size_t dot = path.find('.');
    std::string_view seg = path.substr(0, dot);
    path = dot == std::string_view::npos ? std::string_view{} : path.substr(dot + 1);
    // Optional element index: "beam_directions[3]".
    std::optional<size_t> index;
    if (const size_t open = seg.find('['); open != std::string_view::npos) {
      if (seg.back() != ']') return nullptr;
      const auto n = parse_uint(seg.substr(open + 1, seg.size() - open - 2));
      if (!n) return nullptr;
      index = static_cast<size_t>(*n);
      seg = seg.substr(0, open);
    }
    if (v->kind_ != Kind::kMessage) return nullptr;
    const auto it = std::find_if(v->fields_.begin(), v->fields_.end(), [&](const auto& p) { return p.first == seg; });
    if (it == v->fields_.end()) return nullptr;
    v = &it->second;
    if (index) {
      if (v->kind_ != Kind::kArray || *index >= v->elements_.size()) return nullptr;
      v = &v->elements_[*index];
    }
  }
  return v;
}

std::vector<double> Value::as_doubles() const {
  std::vector<double> out;
  if (kind_ == Kind::kBytes) {
    out.reserve(bytes_.size());
    const bool is_signed = integer_ != 0;
    for (uint8_t b : bytes_) out.push_back(is_signed ? static_cast<double>(static_cast<int8_t>(b)) : static_cast<double>(b));
  } else if (kind_ == Kind::kArray) {
    out.reserve(elements_.size());
    for (const Value& e : elements_) out.push_back(e.number_);
  }
  return out;
}

Value Value::number(double d, int64_t i, bool integer) {
  Value v;
  v.kind_ = Kind::kNumber;
  v.number_ = d;
  v.integer_ = i;
  v.is_integer_ = integer;
  return v;
}

Value Value::string(std::string s) {
  Value v;
  v.kind_ = Kind::kString;
  v.string_ = std::move(s);
  return v;
}

Value Value::time(int64_t ns) {
  Value v;
  v.kind_ = Kind::kTime;
  v.integer_ = ns;
  v.number_ = static_cast<double>(ns);
  v.is_integer_ = true;
  return v;
}

Value Value::message(std::vector<std::pair<std::string, Value>> fields) {
  Value v;
  v.kind_ = Kind::kMessage;
  v.fields_ = std::move(fields);
  return v;
}

Value Value::array(std::vector<Value> elements) {
  Value v;
  v.kind_ = Kind::kArray;
  v.elements_ = std::move(elements);
  return v;
}

Value Value::bytes(std::span<const uint8_t> b, bool signed_elements) {
  Value v;
  v.kind_ = Kind::kBytes;
  v.bytes_ = b;
  v.integer_ = signed_elements ? 1 : 0;  // kBytes keeps its signedness here
  return v;
}

// ---------------------------------------------------------------------------------------
// Decoding

namespace {

// Where the decoder is, for error messages; built into a string only on error.
struct Path {
  const Path* parent = nullptr;
  std::string_view field;  // empty for an element node
  int64_t index = -1;
};

void render(const Path* p, std::string& out) {
  if (p == nullptr) return;
  render(p->parent, out);
  if (p->field.empty()) {
    out += "[" + std::to_string(p->index) + "]";
  } else {
    if (!out.empty()) out += '.';
    out += p->field;
  }
}

template <class T>
T byteswap(T v) {
  if constexpr (sizeof(T) == 1) {
    return v;
  } else {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
}

class Decoder {
 public:
  Decoder(const Schema& schema, Encoding enc, const uint8_t* data, size_t size)
      : schema_(schema), enc_(enc), data_(data), size_(size),
        // Values not backed by input bytes (elements of empty message types) are bounded
        // by this budget, so a definition like Empty[1000000][...] cannot exhaust memory.
        budget_(8 * size + 4096) {}

  Result<Value> run() {
    if (enc_ == Encoding::kCdr) {
      if (size_ < 4) return Error{schema_.root() + ": CDR message of " + std::to_string(size_) +
                                  " bytes has no encapsulation header"};
      if (data_[0] != 0 || data_[1] > 1) {
        return Error{schema_.root() + ": unsupported CDR encapsulation " + hex(data_, 2) +
                     " (only plain CDR: 0000 big endian, 0001 little endian)"};
      }
      swap_ = (data_[1] == 0) != (std::endian::native == std::endian::big);
      origin_ = pos_ = 4;
    } else {
      swap_ = std::endian::native == std::endian::big;
    }
    const MsgSpec* root = schema_.find(schema_.root());
    if (root == nullptr) return Error{schema_.root() + ": no definition of the root type"};
    Value v;
    if (!message(*root, nullptr, 0, v)) return std::move(*error_);
    if (pos_ != size_) {
      const size_t extra = size_ - pos_;
      const bool padding = enc_ == Encoding::kCdr && extra <= 3 &&
                           std::all_of(data_ + pos_, data_ + size_, [](uint8_t b) { return b == 0; });
      if (!padding) {
        return Error{schema_.root() + ": " + std::to_string(extra) + " trailing bytes after the message at byte offset " +
                     std::to_string(pos_)};
      }
    }
    return v;
  }

 private:
  bool fail(const Path* p, std::string_view type, const std::string& what) {
    std::string path;
    render(p, path);
    error_ = Error{schema_.root() + ": " + (path.empty() ? std::string("(message)") : path) + " (" +
                   std::string(type) + "): " + what + " at byte offset " + std::to_string(pos_)};
    return false;
  }

  size_t remaining() const { return size_ - pos_; }

  // CDR aligns each primitive to its size, counted from the end of the encapsulation header.
  bool align(size_t n, const Path* p, std::string_view type) {
    if (enc_ != Encoding::kCdr || n <= 1) return true;
    const size_t mis = (pos_ - origin_) % n;
    if (mis == 0) return true;
    if (remaining() < n - mis) return fail(p, type, "truncated (alignment padding)");
    pos_ += n - mis;
    return true;
  }

  template <class T>
  bool read(T& out, const Path* p, std::string_view type) {
    if (!align(sizeof(T), p, type)) return false;
    if (remaining() < sizeof(T)) {
      return fail(p, type, "truncated: needs " + std::to_string(sizeof(T)) + " bytes, " +
                               std::to_string(remaining()) + " remain");
    }
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    out = swap_ ? byteswap(v) : v;
    pos_ += sizeof(T);
    return true;
  }

  bool length(uint32_t& n, const Path* p, std::string_view type) { return read(n, p, type); }

  bool spend(size_t n, const Path* p, std::string_view type) {
    if (n > budget_) return fail(p, type, "too many elements for the message size");
    budget_ -= n;
    return true;
  }

  // One primitive value at the current (aligned) position; `p` names it.
  bool primitive(Prim prim, const Path* p, std::string_view type, uint32_t bound, Value& out) {
    switch (prim) {
      case Prim::kBool: {
        uint8_t b = 0;
        if (!read(b, p, type)) return false;
        out = Value::number(b != 0 ? 1.0 : 0.0, b != 0 ? 1 : 0, true);
        return true;
      }
#define ORTHOSONAR_INT_CASE(P, T)                                         \
  case P: {                                                               \
    T x{};                                                                \
    if (!read(x, p, type)) return false;                                  \
    out = Value::number(static_cast<double>(x), static_cast<int64_t>(x), true); \
    return true;                                                          \
  }
      ORTHOSONAR_INT_CASE(Prim::kInt8, int8_t)
      ORTHOSONAR_INT_CASE(Prim::kUint8, uint8_t)
      ORTHOSONAR_INT_CASE(Prim::kInt16, int16_t)
      ORTHOSONAR_INT_CASE(Prim::kUint16, uint16_t)
      ORTHOSONAR_INT_CASE(Prim::kInt32, int32_t)
      ORTHOSONAR_INT_CASE(Prim::kUint32, uint32_t)
      ORTHOSONAR_INT_CASE(Prim::kInt64, int64_t)
      ORTHOSONAR_INT_CASE(Prim::kUint64, uint64_t)
#undef ORTHOSONAR_INT_CASE
      case Prim::kFloat32: {
        float x = 0;
        if (!read(x, p, type)) return false;
        out = float_value(x);
        return true;
      }
      case Prim::kFloat64: {
        double x = 0;
        if (!read(x, p, type)) return false;
        out = float_value(x);
        return true;
      }
      case Prim::kString: {
        uint32_t n = 0;
        if (!length(n, p, type)) return false;
        if (n > remaining()) {
          return fail(p, type, "string length " + std::to_string(n) + " exceeds the " +
                                   std::to_string(remaining()) + " bytes remaining");
        }
        // CDR counts the terminating NUL; ros1 does not.
        const size_t len = enc_ == Encoding::kCdr && n > 0 ? n - 1 : n;
        if (bound != 0 && len > bound) {
          return fail(p, type, "string of " + std::to_string(len) + " bytes exceeds its bound " + std::to_string(bound));
        }
        out = Value::string(std::string(reinterpret_cast<const char*>(data_ + pos_), len));
        pos_ += n;
        return true;
      }
      case Prim::kTime:
      case Prim::kDuration: {
        int64_t sec = 0, nsec = 0;
        if (enc_ == Encoding::kRos1 && prim == Prim::kTime) {
          uint32_t s = 0, ns = 0;
          if (!read(s, p, type) || !read(ns, p, type)) return false;
          sec = s;
          nsec = ns;
        } else if (enc_ == Encoding::kRos1) {
          int32_t s = 0, ns = 0;
          if (!read(s, p, type) || !read(ns, p, type)) return false;
          sec = s;
          nsec = ns;
        } else {
          // builtin_interfaces/Time and Duration: int32 sec, uint32 nanosec.
          int32_t s = 0;
          uint32_t ns = 0;
          if (!read(s, p, type) || !read(ns, p, type)) return false;
          sec = s;
          nsec = ns;
        }
        out = Value::time(sec * 1'000'000'000 + nsec);
        return true;
      }
      case Prim::kMessage:
        break;
    }
    return fail(p, type, "internal: not a primitive");
  }

  template <class F>
  static Value float_value(F x) {
    const double d = static_cast<double>(x);
    // as_int of a float: truncated when representable, else 0 (no UB on NaN or huge values).
    const bool fits = d > -9.2e18 && d < 9.2e18;
    return Value::number(d, fits ? static_cast<int64_t>(d) : 0, false);
  }

  bool field(const Field& f, const Path* parent, int depth, Value& out) {
    const Path here{parent, f.name, -1};
    const std::string_view type = f.type;
    if (f.array < 0) {
      if (f.prim == Prim::kMessage) {
        const MsgSpec* spec = schema_.find(f.type);
        if (spec == nullptr) return fail(&here, type, "no definition");
        return message(*spec, &here, depth + 1, out);
      }
      return primitive(f.prim, &here, type, f.upper_bound, out);
    }

    uint32_t n = 0;
    if (f.array > 0) {
      n = static_cast<uint32_t>(f.array);
    } else if (!length(n, &here, type)) {
      return false;
    }
    if (f.array == 0 && f.upper_bound != 0 && n > f.upper_bound) {
      return fail(&here, type, "sequence of " + std::to_string(n) + " exceeds its bound " + std::to_string(f.upper_bound));
    }

    // Byte arrays: a view into the input, never copied.
    if (f.prim == Prim::kUint8 || f.prim == Prim::kInt8) {
      if (n > remaining()) {
        return fail(&here, type, "array of " + std::to_string(n) + " bytes exceeds the " +
                                     std::to_string(remaining()) + " bytes remaining");
      }
      out = Value::bytes({data_ + pos_, n}, f.prim == Prim::kInt8);
      pos_ += n;
      return true;
    }

    const size_t elem = prim_size(f.prim);
    std::vector<Value> elements;
    if (elem > 0) {
      // Fixed-size numbers: one bounds check (after the first element's alignment; the rest
      // are then aligned too, their size being a multiple of the alignment).
      if (n > 0 && !align(elem, &here, type)) return false;
      if (static_cast<uint64_t>(n) * elem > remaining()) {
        // Name the first element that does not fit.
        const Path at{&here, {}, static_cast<int64_t>(remaining() / elem)};
        return fail(&at, type, "truncated: array of " + std::to_string(n) + " elements needs " +
                                   std::to_string(uint64_t{n} * elem) + " bytes, " + std::to_string(remaining()) +
                                   " remain");
      }
      elements.reserve(n);
      for (uint32_t i = 0; i < n; ++i) {
        Value v;
        const Path at{&here, {}, i};
        if (!primitive(f.prim, &at, type, 0, v)) return false;
        elements.push_back(std::move(v));
      }
      out = Value::array(std::move(elements));
      return true;
    }

    // Strings, times, messages: each element takes at least one byte, except elements of
    // empty message types, which are charged to the budget.
    if (n > remaining() && !spend(n, &here, type)) return false;
    elements.reserve(std::min<size_t>(n, remaining() + 1));
    const MsgSpec* spec = nullptr;
    uint32_t string_bound = 0;
    if (f.prim == Prim::kString && f.type.size() > 8) {
      string_bound = static_cast<uint32_t>(parse_uint(std::string_view(f.type).substr(8)).value_or(0));
    }
    if (f.prim == Prim::kMessage) {
      spec = schema_.find(f.type);
      if (spec == nullptr) return fail(&here, type, "no definition");
    }
    for (uint32_t i = 0; i < n; ++i) {
      Value v;
      const Path at{&here, {}, i};
      const bool ok = spec != nullptr ? message(*spec, &at, depth + 1, v)
                                      : primitive(f.prim, &at, type, string_bound, v);
      if (!ok) return false;
      elements.push_back(std::move(v));
    }
    out = Value::array(std::move(elements));
    return true;
  }

  bool message(const MsgSpec& spec, const Path* p, int depth, Value& out) {
    if (depth > kMaxDepth) return fail(p, spec.name, "nesting deeper than " + std::to_string(kMaxDepth));
    if (!spend(1, p, spec.name)) return false;
    if (enc_ == Encoding::kCdr && spec.fields.empty()) {
      // ROS 2 gives an empty type one uint8 (structure_needs_at_least_one_member): IDL
      // structs cannot be empty.
      uint8_t placeholder = 0;
      if (!read(placeholder, p, spec.name)) return false;
    }
    std::vector<std::pair<std::string, Value>> fields;
    fields.reserve(spec.fields.size());
    for (const Field& f : spec.fields) {
      Value v;
      if (!field(f, p, depth, v)) return false;
      fields.emplace_back(f.name, std::move(v));
    }
    out = Value::message(std::move(fields));
    return true;
  }

  const Schema& schema_;
  Encoding enc_;
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  size_t origin_ = 0;
  bool swap_ = false;
  size_t budget_;
  std::optional<Error> error_;
};

}  // namespace

Result<Value> decode(const Schema& schema, Encoding encoding, const uint8_t* data, size_t size) {
  if (data == nullptr && size > 0) return Error{schema.root() + ": no data"};
  static const uint8_t kEmpty = 0;
  return Decoder(schema, encoding, data == nullptr ? &kEmpty : data, size).run();
}

// ---------------------------------------------------------------------------------------
// Writer

namespace {
template <class T>
void put(std::vector<uint8_t>& buf, T v) {
  if constexpr (std::endian::native == std::endian::big) v = byteswap(v);
  const size_t at = buf.size();
  buf.resize(at + sizeof(T));
  std::memcpy(buf.data() + at, &v, sizeof(T));
}
}  // namespace

Writer::Writer(Encoding encoding) : encoding_(encoding) {
  // CDR little endian, options 0 (rmw's encapsulation header).
  if (encoding_ == Encoding::kCdr) buf_ = {0x00, 0x01, 0x00, 0x00};
}

void Writer::align(size_t n) {
  if (encoding_ != Encoding::kCdr) return;
  while ((buf_.size() - 4) % n != 0) buf_.push_back(0);
}

void Writer::boolean(bool v) { buf_.push_back(v ? 1 : 0); }
void Writer::i8(int8_t v) { buf_.push_back(static_cast<uint8_t>(v)); }
void Writer::u8(uint8_t v) { buf_.push_back(v); }
void Writer::i16(int16_t v) { align(2); put(buf_, v); }
void Writer::u16(uint16_t v) { align(2); put(buf_, v); }
void Writer::i32(int32_t v) { align(4); put(buf_, v); }
void Writer::u32(uint32_t v) { align(4); put(buf_, v); }
void Writer::i64(int64_t v) { align(8); put(buf_, v); }
void Writer::u64(uint64_t v) { align(8); put(buf_, v); }
void Writer::f32(float v) { align(4); put(buf_, v); }
void Writer::f64(double v) { align(8); put(buf_, v); }

void Writer::string(std::string_view s) {
  const bool cdr = encoding_ == Encoding::kCdr;
  u32(static_cast<uint32_t>(s.size() + (cdr ? 1 : 0)));
  buf_.insert(buf_.end(), s.begin(), s.end());
  if (cdr) buf_.push_back(0);
}

void Writer::time(int64_t ns) {
  const auto sec = ns / 1'000'000'000;
  const auto nsec = static_cast<uint32_t>(ns % 1'000'000'000);
  if (encoding_ == Encoding::kRos1) {
    u32(static_cast<uint32_t>(sec));
  } else {
    i32(static_cast<int32_t>(sec));
  }
  u32(nsec);
}

void Writer::sequence_length(uint32_t n) { u32(n); }

void Writer::raw(const uint8_t* data, size_t n) {
  if (n > 0) buf_.insert(buf_.end(), data, data + n);
}

void Writer::header(uint32_t seq, int64_t stamp_ns, std::string_view frame_id) {
  if (encoding_ == Encoding::kRos1) u32(seq);
  time(stamp_ns);
  string(frame_id);
}

}  // namespace orthosonar::replay::rosmsg
