// The files of a plan folder (see files.hpp).
#include "replay/batch/files.hpp"

#include <unistd.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <sstream>

namespace orthosonar::batch {

namespace fs = std::filesystem;
using nlohmann::json;

Result<std::string> read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{"cannot open '" + path + "'"};
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Status write_text(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::trunc | std::ios::binary);
  if (!f) return Error{"cannot open '" + path.string() + "' for writing"};
  f << text;
  f.close();
  return f ? Status{} : Status{Error{"write failed for '" + path.string() + "'"}};
}

Result<json> read_json_file(const std::string& path) {
  auto text = read_text(path);
  if (!text.ok()) return text.error();
  try {
    return json::parse(*text);
  } catch (const std::exception& e) {
    return Error{path + ": not valid JSON: " + e.what()};
  }
}

std::string absolute_path(const std::string& p) {
  std::error_code ec;
  const auto a = fs::absolute(p, ec);
  return (ec ? fs::path(p) : a).lexically_normal().string();
}

std::string utc_now() {
  const auto t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char buf[32];
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string host_name() {
  char buf[256] = {};
  ::gethostname(buf, sizeof buf - 1);
  return buf;
}

}  // namespace orthosonar::batch
