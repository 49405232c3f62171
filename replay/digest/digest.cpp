#include "replay/digest/digest.hpp"

#include <openssl/evp.h>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "core/canonical.hpp"

namespace orthosonar::replay {
namespace {

// Incremental SHA-256. A failure inside OpenSSL (a programmer-level fault: OpenSSL itself
// is broken) makes ok() false and finish() empty.
class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    ok_ = ctx_ && EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) == 1;
  }
  void update(const void* data, size_t size) { ok_ = ok_ && EVP_DigestUpdate(ctx_.get(), data, size) == 1; }
  std::vector<uint8_t> finish() {
    std::vector<uint8_t> md(EVP_MAX_MD_SIZE);
    unsigned int len = 0;
    ok_ = ok_ && EVP_DigestFinal_ex(ctx_.get(), md.data(), &len) == 1;
    md.resize(ok_ ? len : 0);
    return md;
  }
  bool ok() const { return ok_; }

 private:
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx_;
  bool ok_ = false;
};

std::vector<uint8_t> sha256(const uint8_t* data, size_t size) {
  Sha256 h;
  h.update(data, size);
  return h.finish();
}

std::string to_hex(const std::vector<uint8_t>& b) {
  static const char* kDigits = "0123456789abcdef";
  std::string s;
  for (uint8_t v : b) {
    s.push_back(kDigits[v >> 4]);
    s.push_back(kDigits[v & 15]);
  }
  return s;
}

bool is_hex64(const std::string& s) {
  if (s.size() != 64) return false;
  for (char c : s)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

}  // namespace

void DigestBuilder::add(const std::string& name, const std::vector<uint8_t>& bytes) {
  add(name, bytes.data(), bytes.size());
}

void DigestBuilder::add(const std::string& name, const uint8_t* data, size_t size) {
  auto& part = parts_[name];
  part.insert(part.end(), data, data + size);
}

DigestResult DigestBuilder::finish() const {
  DigestResult r;
  CanonicalWriter all;
  for (const auto& [name, bytes] : parts_) {
    const auto md = sha256(bytes.data(), bytes.size());
    r.outputs[name] = to_hex(md);
    all.put_string(name);
    all.put_bytes(md);
  }
  r.overall_hex = to_hex(sha256(all.bytes().data(), all.size()));
  return r;
}

std::string sha256_hex(const uint8_t* data, size_t size) { return to_hex(sha256(data, size)); }

Result<std::string> sha256_file_hex(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{"cannot open '" + path + "'"};
  Sha256 h;
  std::vector<char> buf(1 << 20);
  while (f) {
    f.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    if (const auto n = f.gcount(); n > 0) h.update(buf.data(), static_cast<size_t>(n));
  }
  if (f.bad()) return Error{"read error in '" + path + "'"};
  const auto md = h.finish();
  if (!h.ok()) return Error{"sha256 of '" + path + "': OpenSSL failed"};
  return to_hex(md);
}

Status write_digest_json(const std::string& path, const DigestResult& d) {
  nlohmann::ordered_json j;
  j["overall"] = d.overall_hex;
  j["outputs"] = nlohmann::ordered_json::object();
  for (const auto& [k, v] : d.outputs) j["outputs"][k] = v;
  std::ofstream f(path, std::ios::trunc);
  if (!f) return Error{path + ": cannot open for writing"};
  f << j.dump(2) << "\n";
  if (!f.good()) return Error{path + ": write failed"};
  return {};
}

Result<DigestResult> read_digest_json(const std::string& path) {
  std::ifstream f(path);
  if (!f) return Error{path + ": cannot open"};
  const auto j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return Error{path + ": not a JSON object"};
  DigestResult d;
  const auto overall = j.find("overall");
  if (overall == j.end() || !overall->is_string() || !is_hex64(overall->get<std::string>()))
    return Error{path + ": \"overall\" is missing or not a 64-digit lowercase hex SHA-256"};
  d.overall_hex = overall->get<std::string>();
  const auto outputs = j.find("outputs");
  if (outputs == j.end() || !outputs->is_object()) return Error{path + ": \"outputs\" is missing or not an object"};
  for (const auto& [k, v] : outputs->items()) {
    if (!v.is_string() || !is_hex64(v.get<std::string>()))
      return Error{path + ": outputs." + k + " is not a 64-digit lowercase hex SHA-256"};
    d.outputs[k] = v.get<std::string>();
  }
  return d;
}

std::vector<std::string> differing_outputs(const DigestResult& expected, const DigestResult& actual) {
  std::set<std::string> names;
  for (const auto& [k, v] : expected.outputs) names.insert(k);
  for (const auto& [k, v] : actual.outputs) names.insert(k);
  std::vector<std::string> out;
  for (const auto& n : names) {
    const auto a = expected.outputs.find(n);
    const auto b = actual.outputs.find(n);
    if (a == expected.outputs.end() || b == actual.outputs.end() || a->second != b->second) out.push_back(n);
  }
  return out;
}

}  // namespace orthosonar::replay
