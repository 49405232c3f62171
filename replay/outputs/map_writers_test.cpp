#include "replay/outputs/map_writers.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <utility>

#include <octomap/OcTree.h>

#include "replay/outputs/pcd_header.hpp"

using namespace orthosonar;

namespace {
std::filesystem::path out_dir() {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  auto d = std::filesystem::path(env ? env : std::filesystem::temp_directory_path().string()) / "outputs";
  std::filesystem::create_directories(d);
  return d;
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

bool mentions(const Error& e, const std::string& what) { return e.message.find(what) != std::string::npos; }

const std::string kPcdHeader3 =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
}  // namespace

TEST_CASE("PCD and PLY round trip", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-0.5f, 0.25f, 7}};
  for (const char* name : {"m.pcd", "m.ply"}) {
    const auto path = (out_dir() / name).string();
    const Status s = std::string(name).ends_with(".pcd") ? outputs::write_pcd(path, pts) : outputs::write_ply(path, pts);
    REQUIRE(s.ok());
    const auto back = outputs::read_cloud(path);
    REQUIRE(back.ok());
    CHECK(*back == pts);
  }
  CHECK_FALSE(outputs::write_pcd("/nonexistent-dir/x.pcd", pts).ok());
  CHECK_FALSE(outputs::write_ply("/nonexistent-dir/x.ply", pts).ok());
  CHECK_FALSE(outputs::read_cloud((out_dir() / "m.xyz").string()).ok());
}

TEST_CASE("map.pcd is binary PCD v0.7 with x y z floats, bytes as before PCL wrote it", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-0.5f, 0.25f, 7}};
  REQUIRE(outputs::write_pcd((out_dir() / "bytes.pcd").string(), pts).ok());
  std::string expect = kPcdHeader3 + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n";
  for (const auto& p : pts) expect.append(reinterpret_cast<const char*>(p.data()), 12);
  CHECK(read_bytes(out_dir() / "bytes.pcd") == expect);
}

TEST_CASE("empty clouds round trip as PCD and PLY", "[unit]") {
  for (const char* name : {"empty.pcd", "empty.ply"}) {
    const auto path = (out_dir() / name).string();
    REQUIRE((std::string(name).ends_with(".pcd") ? outputs::write_pcd(path, {}) : outputs::write_ply(path, {})).ok());
    const auto back = outputs::read_cloud(path);
    REQUIRE(back.ok());
    CHECK(back->empty());
  }
  CHECK(read_bytes(out_dir() / "empty.pcd") ==
        kPcdHeader3 + "WIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA binary\n");
}

TEST_CASE("PCD with extra fields, ascii and binary, reads back its x y z", "[unit]") {
  const std::vector<std::string> names = {"x", "y", "z", "intensity", "range"};
  const std::vector<float> values = {1.5f, -2.25f, 3, 0.5f, 10, 4, 5, 6, 0.25f, 12.5f};
  for (auto enc : {outputs::PcdEncoding::kAscii, outputs::PcdEncoding::kBinary}) {
    const auto path = (out_dir() / (enc == outputs::PcdEncoding::kAscii ? "fields_ascii.pcd" : "fields_bin.pcd")).string();
    REQUIRE(outputs::write_pcd_fields(path, names, values, enc).ok());
    auto back = outputs::read_cloud(path);
    REQUIRE(back.ok());
    CHECK(*back == std::vector<Eigen::Vector3f>{{1.5f, -2.25f, 3}, {4, 5, 6}});
    auto h = outputs::pcd::read_header(path);
    REQUIRE(h.ok());
    CHECK(h->fields.size() == 5u);
    CHECK(h->points == 2u);
    REQUIRE(outputs::write_pcd_fields(path, names, {}, enc).ok());
    CHECK(read_bytes(path).ends_with(enc == outputs::PcdEncoding::kAscii ? "POINTS 0\nDATA ascii\n" : "POINTS 0\nDATA binary\n"));
    auto empty = outputs::read_cloud(path);
    REQUIRE(empty.ok());
    CHECK(empty->empty());
  }
  CHECK(read_bytes(out_dir() / "fields_ascii.pcd").find("DATA ascii\n") != std::string::npos);
  CHECK_FALSE(outputs::write_pcd_fields((out_dir() / "bad.pcd").string(), names, {1, 2}, outputs::PcdEncoding::kAscii).ok());
}

TEST_CASE("a PCD header claiming 2^64 points is a clear error, before PCL allocates", "[unit]") {
  const auto path = out_dir() / "huge.pcd";
  const std::string viewpoint = "VIEWPOINT 0 0 0 1 0 0 0\n";
  for (const char* data : {"binary", "ascii"}) {
    INFO(data);
    write_bytes(path, kPcdHeader3 + "WIDTH 18446744073709551615\nHEIGHT 1\n" + viewpoint +
                          "POINTS 18446744073709551615\nDATA " + data + "\n0123456789ab");
    auto r = outputs::read_cloud(path.string());
    REQUIRE_FALSE(r.ok());
    CHECK(mentions(r.error(), "huge.pcd: header: POINTS 18446744073709551615 exceeds what 12 bytes of data can hold"));
  }
  // WIDTH × HEIGHT overflowing 64 bits, without POINTS.
  write_bytes(path, kPcdHeader3 + "WIDTH 4294967296\nHEIGHT 4294967296\n" + viewpoint + "DATA binary\n");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "huge.pcd: header: WIDTH 4294967296 × HEIGHT 4294967296"));
  // 2^64 does not parse.
  write_bytes(path, kPcdHeader3 + "WIDTH 18446744073709551616\nHEIGHT 1\n" + viewpoint + "POINTS 1\nDATA binary\n");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "WIDTH '18446744073709551616' is not an unsigned 64-bit integer"));
  // POINTS that disagrees with WIDTH × HEIGHT.
  write_bytes(path, kPcdHeader3 + "WIDTH 2\nHEIGHT 1\n" + viewpoint + "POINTS 1\nDATA binary\n" + std::string(24, '\0'));
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "WIDTH 2 × HEIGHT 1 is not POINTS 1"));
  // binary_compressed sizes that cannot be true.
  std::string pre(8, '\0');
  const uint32_t compressed = 4, uncompressed = 0xfffffff0u;
  std::memcpy(pre.data(), &compressed, 4);
  std::memcpy(pre.data() + 4, &uncompressed, 4);
  write_bytes(path, kPcdHeader3 + "WIDTH 357913940\nHEIGHT 1\n" + viewpoint + "POINTS 357913940\nDATA binary_compressed\n" + pre + "abcd");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "POINTS 357913940 exceeds what 4 compressed bytes can hold"));
  // COUNT and SIZE are bounded too.
  write_bytes(path, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 18446744073709551615\nWIDTH 1\nHEIGHT 1\nDATA binary\n");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "COUNT '18446744073709551615' of field z is not in 1..2^32"));
  write_bytes(path, "FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA binary\n");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "SIZE '3' of field z"));
  write_bytes(path, "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA binary\n" + std::string(24, '\0'));
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "field x is not one 4-byte float"));
  write_bytes(path, "# no data line\nFIELDS x y z\n");
  CHECK(mentions(outputs::read_cloud(path.string()).error(), "huge.pcd: header: truncated (no DATA line)"));
}

TEST_CASE("every truncation of a binary map.pcd or map.ply is an error naming the file", "[unit]") {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(static_cast<float>(i), 0.5f * static_cast<float>(i), -1.0f);
  for (const char* name : {"full.pcd", "full.ply"}) {
    const auto full = out_dir() / name;
    REQUIRE((std::string(name).ends_with(".pcd") ? outputs::write_pcd(full.string(), pts) : outputs::write_ply(full.string(), pts)).ok());
    const std::string bytes = read_bytes(full);
    const auto cut = out_dir() / (std::string("cut") + full.extension().string());
    size_t rejected = 0;
    for (size_t n = 0; n < bytes.size(); ++n) {
      write_bytes(cut, bytes.substr(0, n));
      auto r = outputs::read_cloud(cut.string());
      if (!r.ok() && mentions(r.error(), cut.filename().string())) ++rejected;
    }
    INFO(name);
    CHECK(rejected == bytes.size());
  }
}

TEST_CASE("a truncated ascii PCD is an error", "[unit]") {
  const auto path = out_dir() / "trunc_ascii.pcd";
  write_bytes(path, kPcdHeader3 + "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 2 3\n4 5 6\n7 8 9 \n");
  auto ok = outputs::read_cloud(path.string());
  REQUIRE(ok.ok());
  CHECK(ok->size() == 3u);
  write_bytes(path, kPcdHeader3 + "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 2 3\n4 5 6\n7\n");
  auto r = outputs::read_cloud(path.string());
  REQUIRE_FALSE(r.ok());
  CHECK(mentions(r.error(), "trunc_ascii.pcd: header: POINTS 3 exceeds what 14 bytes"));
  // Enough bytes for the header's count, but lines that PCL alone would read as zeros.
  const std::string head = kPcdHeader3 + "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n";
  const std::pair<const char*, const char*> cases[] = {
      {"1.0 2.0 3.0\n4.0 5.0 6.0\n", "truncated: 2 data lines, header says POINTS 3"},
      {"1.0 2.0 3.0\n4.0 5.0 6.0\n7.0 8.0\n", "data line 3: 2 values, FIELDS/COUNT say 3"},
      {"1.0 2.0 3.0\n4.0 5.0 6.0\n7.0 8.0 abc\n", "data line 3: 'abc' is not a number"},
      {"1 2 3\n4 5 6\n7 8 9\n1 1 1\n", "4 data lines, header says POINTS 3"}};
  for (const auto& [data, what] : cases) {
    write_bytes(path, head + data);
    auto bad = outputs::read_cloud(path.string());
    REQUIRE_FALSE(bad.ok());
    CHECK(mentions(bad.error(), std::string("trunc_ascii.pcd: ") + what));
  }
}

TEST_CASE("OctoMap file marks the points occupied", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1.05f, 2.05f, -3.05f}, {4, 4, 4}};
  const auto path = (out_dir() / "m.bt").string();
  REQUIRE(outputs::write_octomap(path, pts, 0.1).ok());
  octomap::OcTree tree(path);
  CHECK(tree.getResolution() == Approx(0.1));
  auto* n = tree.search(1.05, 2.05, -3.05);
  REQUIRE(n != nullptr);
  CHECK(tree.isNodeOccupied(n));
  CHECK(tree.search(-7.0, -7.0, -7.0) == nullptr);
  CHECK(tree.getNumLeafNodes() == 2);
}

// Issue 35: OctoMap's 16-bit keys hold +-32768 x resolution; a point beyond (a DR start of
// 1e7 m is a valid dr.initial_xy_m) was dropped by updateNode without a word. The writer
// now counts what it could not insert, and the run reports it in summary.json.
TEST_CASE("OctoMap points outside its key range are counted, not dropped silently", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{1.05f, 2.05f, -3.05f}, {1e7f, 0.0f, -3.0f}, {3300.0f, 0.0f, 0.0f},
                                            {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f},
                                            {0.0f, -1e30f, 0.0f},  // beyond int when scaled: OctoMap's cast would be UB
                                            {0.0f, 0.0f, std::numeric_limits<float>::infinity()}};
  const auto path = (out_dir() / "outside.bt").string();
  size_t outside = 99;
  REQUIRE(outputs::write_octomap(path, pts, 0.1, &outside).ok());
  CHECK(outside == 5);  // 1e7 m and 3300 m lie beyond +-3276.8 m at 0.1 m; NaN, 1e30 and inf have no key
  octomap::OcTree tree(path);
  CHECK(tree.getNumLeafNodes() == 1);
  // At 1 m the tree holds +-32768 m: 3300 m fits.
  REQUIRE(outputs::write_octomap(path, pts, 1.0, &outside).ok());
  CHECK(outside == 4);
}
