// ROS message definitions: the .msg text (ROS 1 and ROS 2 dialects) parsed into a Schema, and its MD5.
//
// Definition text: genmsg's .msg grammar (wiki.ros.org/msg) and the ROS 2 additions
// (design.ros2.org "Interface definition": default values, bounded strings and sequences).
// The ros1 / CDR encodings of the values are in ros_msg_wire.cpp.
#include "replay/ros/ros_msg.hpp"
#include "replay/ros/ros_msg_detail.hpp"

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
using namespace detail;
namespace {

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

}  // namespace orthosonar::replay::rosmsg
