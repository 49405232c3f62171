// orthosonar_rosbag_dump: the rosbag reader and writer seen from outside, for the Python
// interop test (rosbag_interop.py) and for making fuzz seeds.
//   orthosonar_rosbag_dump dump BAG
//     prints JSON {info, connections, messages: [{conn, topic, time_ns, size, chunk_offset, sha1}]}
//   orthosonar_rosbag_dump copy IN OUT [--compression none|bz2|lz4] [--chunk-threshold BYTES]
//     reads IN and writes every message again with BagWriter
// Exit status: 0 done, 1 the bag is rejected (message on stderr), 2 usage.
#include <openssl/evp.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "replay/ros/rosbag.hpp"

using namespace orthosonar;
using namespace orthosonar::replay::rosbag;

namespace {

std::string sha1_hex(const uint8_t* data, size_t n) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned len = 0;
  EVP_Digest(data, n, md, &len, EVP_sha1(), nullptr);
  std::string s;
  char hex[3];
  for (unsigned i = 0; i < len; ++i) {
    std::snprintf(hex, sizeof hex, "%02x", md[i]);
    s += hex;
  }
  return s;
}

int fail(const std::string& what) {
  std::cerr << "orthosonar_rosbag_dump: " << what << "\n";
  return 1;
}

int dump(const std::string& path) {
  auto bag = BagReader::open(path);
  if (!bag) return fail(bag.error().message);
  const BagInfo& i = (*bag)->info();
  nlohmann::ordered_json out;
  out["info"] = {{"file_bytes", i.file_bytes}, {"indexed", i.indexed}, {"compressions", i.compressions},
                 {"chunk_count", i.chunk_count}, {"message_count", i.message_count}, {"start_ns", i.start_ns},
                 {"end_ns", i.end_ns}, {"complete", i.complete}, {"bytes_recovered", i.bytes_recovered},
                 {"detail", i.detail}};
  out["connections"] = nlohmann::json::array();
  for (const auto& c : (*bag)->connections())
    out["connections"].push_back({{"id", c.id}, {"topic", c.topic}, {"type", c.type}, {"md5sum", c.md5sum},
                                  {"message_definition", c.message_definition}, {"callerid", c.callerid},
                                  {"latching", c.latching}});
  auto& msgs = out["messages"] = nlohmann::json::array();
  auto s = (*bag)->for_each([&](const Connection& c, const MessageView& m) -> Status {
    msgs.push_back({{"conn", m.conn}, {"topic", c.topic}, {"time_ns", m.time_ns}, {"size", m.size},
                    {"chunk_offset", m.chunk_offset}, {"sha1", sha1_hex(m.data, m.size)}});
    return {};
  });
  if (!s) return fail(s.error().message);
  std::cout << out.dump(1) << "\n";
  return 0;
}

int copy(const std::string& in, const std::string& out, const BagWriterOptions& o) {
  auto bag = BagReader::open(in);
  if (!bag) return fail(bag.error().message);
  auto w = BagWriter::open(out, o);
  if (!w) return fail(w.error().message);
  std::map<uint32_t, uint32_t> ids;  // ours -> the copy's
  for (const auto& c : (*bag)->connections()) {
    auto id = (*w)->add_connection(c.topic, c.type, c.md5sum, c.message_definition, c.callerid, c.latching);
    if (!id) return fail(id.error().message);
    ids[c.id] = *id;
  }
  auto s = (*bag)->for_each([&](const Connection& c, const MessageView& m) -> Status {
    return (*w)->write(ids.at(c.id), m.time_ns, m.data, m.size);
  });
  if (!s) return fail(s.error().message);
  if (auto c = (*w)->close(); !c) return fail(c.error().message);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "usage: orthosonar_rosbag_dump dump BAG | copy IN OUT [--compression none|bz2|lz4] [--chunk-threshold BYTES]";
  if (argc == 3 && std::strcmp(argv[1], "dump") == 0) return dump(argv[2]);
  if (argc >= 4 && std::strcmp(argv[1], "copy") == 0) {
    BagWriterOptions o;
    for (int i = 4; i + 1 < argc; i += 2) {
      if (std::strcmp(argv[i], "--compression") == 0) {
        o.compression = argv[i + 1];
      } else if (std::strcmp(argv[i], "--chunk-threshold") == 0) {
        o.chunk_threshold = std::strtoull(argv[i + 1], nullptr, 10);
      } else {
        std::cerr << usage << "\n";
        return 2;
      }
    }
    if ((argc - 4) % 2 == 0) return copy(argv[2], argv[3], o);
  }
  std::cerr << usage << "\n";
  return 2;
}
