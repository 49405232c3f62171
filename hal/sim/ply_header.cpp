#include "hal/sim/ply_header.hpp"

#include "hal/file_head.hpp"

#include <algorithm>
#include <charconv>
#include <sstream>

namespace orthosonar::sim::ply {
namespace {

bool parse_type(const std::string& s, Type& t) {
  if (s == "char" || s == "int8") t = Type::kI8;
  else if (s == "uchar" || s == "uint8") t = Type::kU8;
  else if (s == "short" || s == "int16") t = Type::kI16;
  else if (s == "ushort" || s == "uint16") t = Type::kU16;
  else if (s == "int" || s == "int32") t = Type::kI32;
  else if (s == "uint" || s == "uint32") t = Type::kU32;
  else if (s == "float" || s == "float32") t = Type::kF32;
  else if (s == "double" || s == "float64") t = Type::kF64;
  else return false;
  return true;
}

bool parse_u64(const std::string& s, uint64_t& v) {
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, v);
  return ec == std::errc() && p == end && !s.empty();
}

// Smallest number of body bytes one item of `e` can occupy.
uint64_t min_item_bytes(const Element& e, Format f) {
  uint64_t n = 0;
  for (const Property& p : e.properties) {
    if (f == Format::kAscii) n += 2;  // one digit and one separator, value or list count
    else n += type_size(p.is_list ? p.count_type : p.type);
  }
  return n;
}

}  // namespace

size_t type_size(Type t) {
  switch (t) {
    case Type::kI8: case Type::kU8: return 1;
    case Type::kI16: case Type::kU16: return 2;
    case Type::kI32: case Type::kU32: case Type::kF32: return 4;
    case Type::kF64: return 8;
  }
  return 1;
}

int Element::scalar_index(std::string_view n) const {
  for (size_t k = 0; k < properties.size(); ++k)
    if (!properties[k].is_list && properties[k].name == n) return static_cast<int>(k);
  return -1;
}

Result<Header> parse_header(std::string_view head, uint64_t file_size, const std::string& path) {
  auto fail = [&path](const std::string& what) { return Error{path + ": " + what}; };
  if (head.size() > kMaxHeaderBytes) head = head.substr(0, kMaxHeaderBytes);
  Header h;
  bool have_format = false;
  bool have_end = false;
  size_t pos = 0;
  int line_no = 0;
  while (pos < head.size()) {
    const size_t nl = head.find('\n', pos);
    if (nl == std::string_view::npos) break;
    std::string line(head.substr(pos, nl - pos));
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = "header line " + std::to_string(line_no) + ": ";
    if (line_no == 1) {
      if (line != "ply") return fail("not a PLY file (no 'ply' magic)");
      continue;
    }
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "end_header") {
      have_end = true;
      break;
    }
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    if (kw == "format") {
      std::string f, version;
      ls >> f >> version;
      if (f == "ascii") h.format = Format::kAscii;
      else if (f == "binary_little_endian") h.format = Format::kBinaryLittleEndian;
      else if (f == "binary_big_endian") h.format = Format::kBinaryBigEndian;
      else return fail(where + "unknown format '" + f + "'");
      have_format = true;
    } else if (kw == "element") {
      Element e;
      std::string count;
      ls >> e.name >> count;
      if (e.name.empty()) return fail(where + "element without a name");
      if (!parse_u64(count, e.count))
        return fail(where + "element " + e.name + " count '" + count + "' is not an unsigned 64-bit integer");
      h.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (h.elements.empty()) return fail(where + "property before any element");
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        if (!parse_type(ct, p.count_type) || !parse_type(it, p.type))
          return fail(where + "unknown list type in '" + line + "'");
        if (p.count_type == Type::kF32 || p.count_type == Type::kF64)
          return fail(where + "list count type must be an integer in '" + line + "'");
      } else {
        ls >> p.name;
        if (!parse_type(t, p.type)) return fail(where + "unknown property type '" + t + "'");
      }
      if (p.name.empty()) return fail(where + "property without a name");
      h.elements.back().properties.push_back(std::move(p));
    } else {
      return fail(where + "unexpected keyword '" + kw + "'");
    }
  }
  if (!have_end) {
    if (head.size() >= kMaxHeaderBytes)
      return fail("header: no end_header in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
    return fail("header: truncated (no end_header)");
  }
  if (!have_format) return fail("header: no format line");
  h.body_offset = pos;
  h.body_bytes = file_size >= pos ? file_size - pos : 0;

  // Every count against the bytes that are left (see the header comment).
  const uint64_t slack = h.format == Format::kAscii ? 1 : 0;  // the last value needs no separator
  uint64_t left = h.body_bytes + slack;
  for (const Element& e : h.elements) {
    if (e.count == 0) continue;
    const uint64_t item = min_item_bytes(e, h.format);
    if (item == 0)
      return fail("header: element " + e.name + " count " + std::to_string(e.count) + " has no properties to read");
    if (e.count > left / item)
      return fail("header: element " + e.name + " count " + std::to_string(e.count) + " exceeds what " +
                  std::to_string(h.body_bytes) + " bytes of data can hold");
    left -= e.count * item;
  }
  return h;
}

Result<Header> read_header(const std::string& path) {
  auto head = hal::read_file_head(path, kMaxHeaderBytes);
  if (!head) return head.error();
  return parse_header(head->bytes, head->size, path);
}

}  // namespace orthosonar::sim::ply
