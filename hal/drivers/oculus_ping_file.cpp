#include "hal/drivers/oculus_ping_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace orthosonar::hal::drivers::oculus {

Result<OculusPingFile> read_oculus_ping_file(const std::string& path, const std::string& option) {
  const std::string where = option + " '" + path + "'";
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{where + ": cannot open: " + std::strerror(errno)};
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return Error{where + ": cannot read"};
  auto r = parse_ping_result(bytes);
  if (!r) return Error{where + ": not an Oculus ping result: " + r.error().message};
  auto s = to_sonar_ping(*r, SonarMount::kVertical, 0, Time{});
  if (!s) return Error{where + ": " + s.error().message};
  return OculusPingFile{std::move(*r), std::move(*s)};
}

}  // namespace orthosonar::hal::drivers::oculus
