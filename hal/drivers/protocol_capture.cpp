#include "hal/drivers/protocol_capture.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "hal/drivers/protocol_decoder.hpp"

namespace orthosonar::hal::drivers {
namespace {


// A field's text as JSON: a number when the whole text is one, true/false, else a string.
nlohmann::ordered_json capture_value_json(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  if (!text.empty()) {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (errno == 0 && end == text.c_str() + text.size() && std::isfinite(v) && text.find_first_of("xX") == std::string::npos) {
      if (text.find_first_of(".eE") == std::string::npos && std::fabs(v) < 9.0e15) return static_cast<int64_t>(v);
      return v;
    }
  }
  return text;
}

std::string capture_csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

int inspect_protocol_capture(const std::string& path, const std::string& protocol, bool json,
                             const std::string& csv_path, std::ostream& out, std::ostream& err) {
  auto p = protocol_from_name(protocol);
  if (!p) {
    err << "orthosonar inspect: --protocol: " << p.error().message << "\n";
    return 2;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    err << "orthosonar inspect: cannot open '" << path << "'\n";
    return 2;
  }
  auto decoder = make_decoder(*p);
  nlohmann::ordered_json messages = nlohmann::ordered_json::array();
  std::vector<DecodedMessage> rows;  // for --csv
  std::map<std::string, uint64_t> types;
  auto drain = [&] {
    while (auto m = decoder->pop()) {
      ++types[m->type];
      if (json) {
        nlohmann::ordered_json f = nlohmann::ordered_json::object();
        for (const auto& [k, v] : m->fields) f[k] = capture_value_json(v);
        messages.push_back({{"offset", m->offset}, {"size", m->size}, {"type", m->type}, {"fields", f}});
      } else {
        out << "@" << m->offset << " " << m->type;
        for (const auto& [k, v] : m->fields) out << " " << k << "=" << v;
        out << "\n";
      }
      if (!csv_path.empty()) rows.push_back(std::move(*m));
    }
  };
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<size_t>(in.gcount());
    if (n == 0) break;
    decoder->push(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(chunk.data()), n));
    drain();
  }
  if (in.bad()) {
    err << "orthosonar inspect: read error in '" << path << "'\n";
    return 2;
  }
  decoder->finish();
  drain();
  const auto c = decoder->counts();

  if (!csv_path.empty()) {
    std::vector<std::string> columns;
    std::map<std::string, size_t> index;
    for (const auto& r : rows)
      for (const auto& [k, v] : r.fields)
        if (index.emplace(k, columns.size()).second) columns.push_back(k);
    std::ofstream csv(csv_path, std::ios::binary | std::ios::trunc);
    csv << "offset,type";
    for (const auto& k : columns) csv << "," << capture_csv_cell(k);
    csv << "\n";
    for (const auto& r : rows) {
      std::vector<std::string> cells(columns.size());
      for (const auto& [k, v] : r.fields) cells[index[k]] = v;
      csv << r.offset << "," << capture_csv_cell(r.type);
      for (const auto& v : cells) csv << "," << capture_csv_cell(v);
      csv << "\n";
    }
    csv.close();
    if (!csv) {
      err << "orthosonar inspect: cannot write '" << csv_path << "'\n";
      return 2;
    }
  }

  if (json) {
    nlohmann::ordered_json doc;
    doc["file"] = path;
    doc["protocol"] = protocol;
    doc["messages"] = messages;
    doc["types"] = types;
    doc["counts"] = {{"good", c.good},           {"bad", c.bad},
                     {"unsupported", c.unsupported}, {"duplicates", c.duplicates},
                     {"other", c.other},         {"skipped_bytes", c.skipped_bytes},
                     {"trailing_bytes", c.trailing_bytes}};
    if (c.sequence_gaps) {
      doc["counts"]["sequence_gaps"] = *c.sequence_gaps;
      doc["counts"]["missing_packets"] = c.missing_packets;
    }
    if (!c.last_error.empty()) doc["last_error"] = c.last_error;
    out << doc.dump(2) << "\n";
  } else {
    out << path << " (" << protocol << "): " << c.good << " good, " << c.bad << " bad, " << c.unsupported
              << " unsupported, " << c.duplicates << " duplicate, " << c.other << " other message(s); "
              << c.skipped_bytes << " skipped byte(s), " << c.trailing_bytes << " trailing byte(s)";
    if (c.sequence_gaps)
      out << "; " << *c.sequence_gaps << " sequence gap(s), " << c.missing_packets << " missing packet(s)";
    out << "\n";
    if (!c.last_error.empty()) out << "last error: " << c.last_error << "\n";
  }
  if (c.good == 0) {
    err << "orthosonar inspect: '" << path << "' holds no " << protocol << " message"
              << (c.last_error.empty() ? std::string() : "; last error: " + c.last_error) << "\n";
    return 2;
  }
  return (c.bad > 0 || c.unsupported > 0) ? 1 : 0;
}

}  // namespace orthosonar::hal::drivers
