// ROS message definitions and the ros1 / CDR encodings (ros_msg.hpp).
//
// Definition text: genmsg's .msg grammar (wiki.ros.org/msg) and the ROS 2 additions
// (design.ros2.org "Interface definition": default values, bounded strings and sequences).
// ros1: little endian, no alignment, uint32 length prefixes (wiki.ros.org/msg
// "Serialization"). CDR: OMG CDR (XCDR1) as rmw writes it, after a 4-byte encapsulation
// header; each primitive aligned to its size counted from the end of that header.
#include "replay/ros/ros_msg.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cctype>
#include <cstring>
#include <limits>
#include <optional>
#include <set>

namespace orthosonar::replay::rosmsg {
namespace {

// Nesting of message types (definition) and of decoded values: real types nest < 10 deep.
constexpr int kMaxDepth = 32;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::string_view strip_comment(std::string_view s) {
  const size_t hash = s.find('#');
  return hash == std::string_view::npos ? s : s.substr(0, hash);
}

bool is_identifier(std::string_view s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

bool is_type_name(std::string_view s) {
  if (s.empty() || s.front() == '/' || s.back() == '/') return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/';
  });
}

std::optional<uint64_t> parse_uint(std::string_view s) {
  s = trim(s);
  if (s.empty() || s.size() > 18) return std::nullopt;
  uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  return v;
}

std::string_view package_of(std::string_view full) {
  const size_t slash = full.find('/');
  return slash == std::string_view::npos ? std::string_view{} : full.substr(0, slash);
}

// "pkg/msg/Type" -> "pkg/Type" (ROS 2 names carry the interface kind).
std::string normalize_type_name(std::string_view name) {
  name = trim(name);
  const size_t first = name.find('/');
  const size_t last = name.rfind('/');
  if (first != std::string_view::npos && last != first) {
    return std::string(name.substr(0, first)) + std::string(name.substr(last));
  }
  return std::string(name);
}

struct Builtin {
  std::string_view name;
  Prim prim;
};

std::optional<Prim> builtin(std::string_view base, Dialect dialect) {
  static constexpr Builtin kBuiltins[] = {
      {"bool", Prim::kBool},       {"int8", Prim::kInt8},       {"uint8", Prim::kUint8},
      {"int16", Prim::kInt16},     {"uint16", Prim::kUint16},   {"int32", Prim::kInt32},
      {"uint32", Prim::kUint32},   {"int64", Prim::kInt64},     {"uint64", Prim::kUint64},
      {"float32", Prim::kFloat32}, {"float64", Prim::kFloat64}, {"string", Prim::kString},
      {"time", Prim::kTime},       {"duration", Prim::kDuration}, {"char", Prim::kUint8},
  };
  // ROS 1's deprecated byte is int8; ROS 2's byte is an octet.
  if (base == "byte") return dialect == Dialect::kRos1 ? Prim::kInt8 : Prim::kUint8;
  for (const auto& b : kBuiltins) {
    if (b.name == base) return b.prim;
  }
  return std::nullopt;
}

size_t prim_size(Prim p) {
  switch (p) {
    case Prim::kBool: case Prim::kInt8: case Prim::kUint8: return 1;
    case Prim::kInt16: case Prim::kUint16: return 2;
    case Prim::kInt32: case Prim::kUint32: case Prim::kFloat32: return 4;
    case Prim::kInt64: case Prim::kUint64: case Prim::kFloat64: return 8;
    default: return 0;
  }
}

// One field line before type resolution: the type as written (message types unresolved).
struct RawSection {
  std::string name;  // normalised "pkg/Type"
  std::vector<std::pair<size_t, std::string_view>> lines;  // (line number, text)
};

Error parse_error(std::string_view type, size_t line, const std::string& what) {
  return Error{"message definition of " + std::string(type) + ", line " + std::to_string(line) + ": " + what};
}

// Parses one declaration line into a field or a constant of `spec`.
std::optional<Error> parse_line(std::string_view type_name, size_t line_no, std::string_view line,
                                Dialect dialect, MsgSpec& spec) {
  const std::string_view t = trim(line);
  size_t sp = 0;
  while (sp < t.size() && !is_space(t[sp])) ++sp;
  std::string_view type_tok = t.substr(0, sp);
  const std::string_view rest = trim(t.substr(sp));
  // A type token with a trailing comment glued on ("float64#x") is not valid .msg.
  if (type_tok.find('#') != std::string_view::npos) return parse_error(type_name, line_no, "bad type");

  // Constant: "TYPE NAME=VALUE" (the part before '=' is one identifier).
  const size_t eq = rest.find('=');
  if (eq != std::string_view::npos) {
    const std::string_view cname = trim(rest.substr(0, eq));
    if (is_identifier(cname) && strip_comment(rest.substr(0, eq)).size() == rest.substr(0, eq).size()) {
      if (!builtin(type_tok, dialect) || type_tok == "time" || type_tok == "duration") {
        return parse_error(type_name, line_no, "constant " + std::string(cname) + " of non-primitive type " + std::string(type_tok));
      }
      std::string_view value = rest.substr(eq + 1);
      // String constants take the rest of the line verbatim (genmsg: no comments there).
      value = type_tok == "string" ? trim(value) : trim(strip_comment(value));
      spec.constants.push_back(Constant{std::string(type_tok), std::string(cname), std::string(value)});
      return std::nullopt;
    }
  }

  const std::string_view decl = trim(strip_comment(rest));
  size_t nsp = 0;
  while (nsp < decl.size() && !is_space(decl[nsp])) ++nsp;
  const std::string_view name = decl.substr(0, nsp);
  // Anything after the name is a ROS 2 default value: not part of the wire format.
  if (!is_identifier(name)) {
    return parse_error(type_name, line_no, "bad field name '" + std::string(name) + "'");
  }

  Field f;
  f.name = std::string(name);
  // Array suffix: [] / [N] / [<=N].
  if (!type_tok.empty() && type_tok.back() == ']') {
    const size_t open = type_tok.rfind('[');
    if (open == std::string_view::npos) return parse_error(type_name, line_no, "bad array type " + std::string(type_tok));
    std::string_view inside = type_tok.substr(open + 1, type_tok.size() - open - 2);
    type_tok = type_tok.substr(0, open);
    if (inside.empty()) {
      f.array = 0;
    } else if (inside.substr(0, 2) == "<=") {
      const auto n = parse_uint(inside.substr(2));
      if (!n || *n > std::numeric_limits<uint32_t>::max()) return parse_error(type_name, line_no, "bad sequence bound");
      f.array = 0;
      f.upper_bound = static_cast<uint32_t>(*n);
    } else {
      const auto n = parse_uint(inside);
      if (!n || *n == 0 || *n > static_cast<uint64_t>(std::numeric_limits<int>::max())) {
        return parse_error(type_name, line_no, "bad array length " + std::string(inside));
      }
      f.array = static_cast<int>(*n);
    }
  }
  // Bounded string: string<=N. Field::type keeps the bound ("string<=N") for the elements
  // of a sequence; upper_bound holds it for a single string.
  const std::string_view written = type_tok;
  if (type_tok.substr(0, 8) == "string<=") {
    const auto n = parse_uint(type_tok.substr(8));
    if (!n || *n > std::numeric_limits<uint32_t>::max()) return parse_error(type_name, line_no, "bad string bound");
    if (f.array < 0) f.upper_bound = static_cast<uint32_t>(*n);
    type_tok = "string";
  }
  if (type_tok == "wstring" || type_tok == "wchar") {
    return parse_error(type_name, line_no, "field " + f.name + ": " + std::string(type_tok) + " is not supported");
  }
  if (!is_type_name(type_tok)) return parse_error(type_name, line_no, "bad type '" + std::string(type_tok) + "'");
  if (const auto p = builtin(type_tok, dialect)) {
    f.prim = *p;
    f.type = std::string(written);
  } else {
    f.prim = Prim::kMessage;
    f.type = std::string(type_tok);  // resolved once every section is known
  }
  for (const Field& other : spec.fields) {
    if (other.name == f.name) return parse_error(type_name, line_no, "field " + f.name + " declared twice");
  }
  spec.fields.push_back(std::move(f));
  return std::nullopt;
}

bool is_separator(std::string_view line) {
  line = trim(line);
  return line.size() >= 3 && std::all_of(line.begin(), line.end(), [](char c) { return c == '='; });
}

std::string hex(const unsigned char* d, size_t n) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  s.reserve(2 * n);
  for (size_t i = 0; i < n; ++i) {
    s.push_back(kHex[d[i] >> 4]);
    s.push_back(kHex[d[i] & 15]);
  }
  return s;
}

std::string md5_hex(std::string_view text) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  // Only fails when OpenSSL itself is broken (no MD5 provider): a programmer-level fault.
  const int ok = EVP_Digest(text.data(), text.size(), md, &len, EVP_md5(), nullptr);
  assert(ok == 1);
  (void)ok;
  return hex(md, len);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Schema

Result<Schema> Schema::parse(std::string_view root_type, std::string_view text, Dialect dialect) {
  Schema s;
  s.dialect_ = dialect;
  s.root_ = normalize_type_name(root_type);
  if (!is_type_name(s.root_) || s.root_.find('/') == std::string::npos) {
    return Error{"message definition: bad root type name '" + std::string(root_type) + "'"};
  }

  // Split into sections: the root's lines, then "====\nMSG: pkg/Type" blocks.
  std::vector<RawSection> sections(1);
  sections[0].name = s.root_;
  bool expect_msg_line = false;
  size_t line_no = 0;
  size_t at = 0;
  while (at <= text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(at, end - at);
    ++line_no;
    at = end + 1;
    if (is_separator(line)) {
      expect_msg_line = true;
      continue;
    }
    const std::string_view t = trim(line);
    if (expect_msg_line) {
      if (t.empty()) continue;
      if (t.substr(0, 4) == "IDL:") return parse_error(s.root_, line_no, "IDL sections (ros2idl) are not supported");
      if (t.substr(0, 4) != "MSG:") return parse_error(s.root_, line_no, "expected 'MSG: pkg/Type' after the separator");
      std::string name = normalize_type_name(t.substr(4));
      if (!is_type_name(name) || name.find('/') == std::string::npos) {
        return parse_error(s.root_, line_no, "bad section type name '" + std::string(trim(t.substr(4))) + "'");
      }
      sections.push_back(RawSection{std::move(name), {}});
      expect_msg_line = false;
      continue;
    }
    if (t.empty() || t.front() == '#') continue;
    sections.back().lines.emplace_back(line_no, line);
  }

  for (const RawSection& sec : sections) {
    // A type defined twice (some writers repeat a dependency): the first one stands.
    if (s.types_.count(sec.name) != 0) continue;
    MsgSpec spec;
    spec.name = sec.name;
    for (const auto& [no, line] : sec.lines) {
      if (auto err = parse_line(sec.name, no, line, dialect, spec)) return *err;
    }
    s.types_.emplace(sec.name, std::move(spec));
  }

  // Resolve message field types.
  const std::string root_pkg(package_of(s.root_));
  for (auto& [tname, spec] : s.types_) {
    const std::string pkg(package_of(tname));
    for (Field& f : spec.fields) {
      if (f.prim != Prim::kMessage) continue;
      const std::string raw = normalize_type_name(f.type);
      if (raw == "builtin_interfaces/Time" || raw == "builtin_interfaces/Duration") {
        f.prim = raw.back() == 'e' ? Prim::kTime : Prim::kDuration;
        f.type = f.prim == Prim::kTime ? "time" : "duration";
        continue;
      }
      std::string resolved;
      if (raw == "Header") {
        resolved = "std_msgs/Header";
      } else if (raw.find('/') != std::string::npos) {
        resolved = raw;
      } else {
        // Unqualified: the containing type's package (genmsg), else the root's.
        for (const std::string& cand : {pkg + "/" + raw, root_pkg + "/" + raw}) {
          if (s.types_.count(cand) != 0) {
            resolved = cand;
            break;
          }
        }
        if (resolved.empty()) resolved = pkg + "/" + raw;
      }
      if (s.types_.count(resolved) == 0) {
        return Error{"message definition of " + s.root_ + ": type " + tname + ", field " + f.name +
                     ": no definition of " + resolved};
      }
      f.type = std::move(resolved);
    }
  }

  // No cycles, bounded nesting: decoding recurses along these edges.
  std::map<std::string, int, std::less<>> depth_of;  // -1 while on the stack
  struct Frame {
    const MsgSpec* spec;
    size_t next;
  };
  std::vector<Frame> stack{{&s.types_.at(s.root_), 0}};
  depth_of[s.root_] = -1;
  while (!stack.empty()) {
    Frame& fr = stack.back();
    if (static_cast<int>(stack.size()) > kMaxDepth) {
      return Error{"message definition of " + s.root_ + ": types nest deeper than " + std::to_string(kMaxDepth)};
    }
    if (fr.next == fr.spec->fields.size()) {
      depth_of[fr.spec->name] = 0;
      stack.pop_back();
      continue;
    }
    const Field& f = fr.spec->fields[fr.next++];
    if (f.prim != Prim::kMessage) continue;
    const auto it = depth_of.find(f.type);
    if (it != depth_of.end()) {
      if (it->second == -1) {
        return Error{"message definition of " + s.root_ + ": type " + f.type + " contains itself (field " +
                     fr.spec->name + "." + f.name + ")"};
      }
      continue;  // already checked
    }
    depth_of[f.type] = -1;
    stack.push_back({&s.types_.at(f.type), 0});
  }
  return s;
}

const MsgSpec* Schema::find(std::string_view type) const {
  const auto it = types_.find(type);
  return it == types_.end() ? nullptr : &it->second;
}

std::string Schema::md5() const {
  // genmsg's compute_md5_text: constants "type name=value", then fields, builtins as
  // written ("float64[9] x"), message types (arrays too) as "<md5 of type> name".
  std::map<std::string, std::string, std::less<>> memo;
  auto rec = [&](auto&& self, const MsgSpec& spec) -> std::string {
    if (const auto it = memo.find(spec.name); it != memo.end()) return it->second;
    std::string text;
    for (const Constant& c : spec.constants) {
      text += c.type + " " + c.name + "=" + c.value + "\n";
    }
    for (const Field& f : spec.fields) {
      if (f.prim == Prim::kMessage) {
        text += self(self, types_.at(f.type)) + " " + f.name + "\n";
      } else {
        text += f.prim == Prim::kString ? std::string("string") : f.type;
        if (f.array == 0) text += "[]";
        if (f.array > 0) text += "[" + std::to_string(f.array) + "]";
        text += " " + f.name + "\n";
      }
    }
    if (!text.empty()) text.pop_back();
    std::string sum = md5_hex(text);
    memo.emplace(spec.name, sum);
    return sum;
  };
  const MsgSpec* root = find(root_);
  return root == nullptr ? std::string{} : rec(rec, *root);
}

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
