#include "replay/outputs/pcd_header.hpp"

#include "hal/file_head.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <sstream>

namespace orthosonar::outputs::pcd {
namespace {

bool parse_u64(const std::string& s, uint64_t& v) {
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, v);
  return !s.empty() && ec == std::errc() && p == end;
}

std::vector<std::string> words(std::istringstream& ls) {
  std::vector<std::string> out;
  for (std::string w; ls >> w;) out.push_back(w);
  return out;
}

}  // namespace

const Field* Header::field(std::string_view name) const {
  for (const Field& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

Result<Header> parse_header(std::string_view head, uint64_t file_size, const std::string& path) {
  auto fail = [&path](const std::string& what) { return Error{path + ": header: " + what}; };
  if (head.size() > kMaxHeaderBytes) head = head.substr(0, kMaxHeaderBytes);
  Header h;
  std::vector<std::string> names, sizes, types, counts;
  bool have_width = false, have_height = false, have_points = false, have_data = false;
  size_t pos = 0;
  int line_no = 0;
  while (pos < head.size() && !have_data) {
    const size_t nl = head.find('\n', pos);
    if (nl == std::string_view::npos) break;
    std::string line(head.substr(pos, nl - pos));
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key.empty() || key[0] == '#') continue;
    const std::string where = "line " + std::to_string(line_no) + ": ";
    auto number = [&](const char* what, uint64_t& v) -> Status {
      std::string s;
      ls >> s;
      if (!parse_u64(s, v)) return fail(where + what + " '" + s + "' is not an unsigned 64-bit integer");
      return Status::Ok();
    };
    if (key == "VERSION" || key == "VIEWPOINT") continue;
    if (key == "FIELDS" || key == "COLUMNS") names = words(ls);
    else if (key == "SIZE") sizes = words(ls);
    else if (key == "TYPE") types = words(ls);
    else if (key == "COUNT") counts = words(ls);
    else if (key == "WIDTH") {
      if (Status s = number("WIDTH", h.width); !s) return s.error();
      have_width = true;
    } else if (key == "HEIGHT") {
      if (Status s = number("HEIGHT", h.height); !s) return s.error();
      have_height = true;
    } else if (key == "POINTS") {
      if (Status s = number("POINTS", h.points); !s) return s.error();
      have_points = true;
    } else if (key == "DATA") {
      std::string d;
      ls >> d;
      if (d == "ascii") h.data = Data::kAscii;
      else if (d == "binary") h.data = Data::kBinary;
      else if (d == "binary_compressed") h.data = Data::kBinaryCompressed;
      else return fail(where + "unknown DATA '" + d + "'");
      have_data = true;
    } else {
      return fail(where + "unexpected key '" + key + "'");
    }
  }
  if (!have_data) {
    if (head.size() >= kMaxHeaderBytes) return fail("no DATA line in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
    return fail("truncated (no DATA line)");
  }
  if (names.empty()) return fail("no FIELDS");
  if (sizes.size() != names.size() || types.size() != names.size() || (!counts.empty() && counts.size() != names.size()))
    return fail("FIELDS, SIZE, TYPE and COUNT list different numbers of fields");
  if (!have_width || !have_height) return fail("no WIDTH or HEIGHT");
  for (size_t i = 0; i < names.size(); ++i) {
    Field f;
    f.name = names[i];
    uint64_t size = 0;
    if (!parse_u64(sizes[i], size) || (size != 1 && size != 2 && size != 4 && size != 8))
      return fail("SIZE '" + sizes[i] + "' of field " + f.name + " is not 1, 2, 4 or 8");
    f.size = static_cast<uint32_t>(size);
    if (types[i].size() != 1 || std::string_view("IUF").find(types[i][0]) == std::string_view::npos ||
        (types[i][0] == 'F' && size < 4))
      return fail("TYPE '" + types[i] + "' of field " + f.name + " is not I, U or F (4 or 8 bytes)");
    f.type = types[i][0];
    if (!counts.empty() && (!parse_u64(counts[i], f.count) || f.count == 0 || f.count > (uint64_t{1} << 32)))
      return fail("COUNT '" + counts[i] + "' of field " + f.name + " is not in 1..2^32");
    h.point_bytes += f.count * f.size;  // <= 2^32 × 8 per field; the header bounds the number of fields
    h.fields.push_back(f);
  }

  // WIDTH × HEIGHT without overflow, then POINTS against it.
  uint64_t wh = 0;
  if (__builtin_mul_overflow(h.width, h.height, &wh))
    return fail("WIDTH " + std::to_string(h.width) + " × HEIGHT " + std::to_string(h.height) + " overflows 64 bits");
  const uint64_t claimed = have_points ? h.points : wh;
  const std::string what = have_points ? "POINTS " + std::to_string(h.points)
                                       : "WIDTH " + std::to_string(h.width) + " × HEIGHT " + std::to_string(h.height);
  h.data_offset = pos;
  h.data_bytes = file_size >= pos ? file_size - pos : 0;

  // The count against the bytes after the DATA line.
  if (h.data == Data::kBinary) {
    if (claimed > h.data_bytes / h.point_bytes)
      return fail(what + " exceeds what " + std::to_string(h.data_bytes) + " bytes of data can hold");
  } else if (h.data == Data::kAscii) {
    uint64_t values = 0;
    for (const Field& f : h.fields) values += f.count;
    if (claimed > (h.data_bytes + 1) / (2 * values))
      return fail(what + " exceeds what " + std::to_string(h.data_bytes) + " bytes of data can hold");
  } else {
    if (h.data_bytes < 8 || head.size() < pos + 8)
      return fail("binary_compressed data shorter than its 8-byte size preamble");
    uint32_t compressed = 0, uncompressed = 0;
    std::memcpy(&compressed, head.data() + pos, 4);
    std::memcpy(&uncompressed, head.data() + pos + 4, 4);
    if (compressed > h.data_bytes - 8)
      return fail("binary_compressed size " + std::to_string(compressed) + " exceeds the " +
                  std::to_string(h.data_bytes - 8) + " bytes that follow");
    if (claimed > (100 * uint64_t{compressed} + 64) / h.point_bytes)
      return fail(what + " exceeds what " + std::to_string(compressed) + " compressed bytes can hold");
    if (uint64_t{uncompressed} != claimed * h.point_bytes)
      return fail("binary_compressed uncompressed size " + std::to_string(uncompressed) + " is not " + what +
                  " × " + std::to_string(h.point_bytes) + " bytes");
  }
  if (wh != claimed)
    return fail("WIDTH " + std::to_string(h.width) + " × HEIGHT " + std::to_string(h.height) + " is not " + what);
  h.points = claimed;
  if (h.width > UINT32_MAX || h.height > UINT32_MAX) return fail("WIDTH or HEIGHT exceeds PCL's 32-bit limit");
  return h;
}

Result<Header> read_header(const std::string& path) {
  auto head = hal::read_file_head(path, kMaxHeaderBytes);
  if (!head) return head.error();
  return parse_header(head->bytes, head->size, path);
}

}  // namespace orthosonar::outputs::pcd
