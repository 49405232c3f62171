#include "replay/outputs/ping_pair_io.hpp"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "hal/codec/image_codec.hpp"

namespace orthosonar::outputs {
namespace fs = std::filesystem;

namespace {

constexpr const char* kJson = "ping_pair.json";

const char* file_of(SonarMount m) { return m == SonarMount::kHorizontal ? "horizontal.png" : "vertical.png"; }

cv::Mat image_of(const SonarPing& p) {
  if (p.bytes_per_pixel == 1) return cv::Mat(p.rows, p.cols, CV_8UC1, const_cast<uint8_t*>(p.image.data())).clone();
  cv::Mat m(p.rows, p.cols, CV_16UC1);
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c) m.at<uint16_t>(r, c) = p.at(r, c);
  return m;
}

nlohmann::json ping_json(const SonarPing& p) {
  return {{"file", file_of(p.mount)},       {"device_id", p.device_id},
          {"part_number", p.part_number},   {"ping_id", p.ping_id},
          {"stamp_ns", p.stamp.ns()},       {"rows", p.rows},
          {"cols", p.cols},                 {"bytes_per_pixel", p.bytes_per_pixel},
          {"range_resolution_m", p.range_resolution_m}, {"frequency_hz", p.frequency_hz},
          {"bearings_rad", p.bearings_rad}};
}

nlohmann::json detections_json(const std::vector<perception::Detection>& d) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& x : d) j.push_back({x.row, x.col, x.intensity});
  return j;
}

struct Reader {
  std::string file;
  Error fail(const std::string& field, const std::string& what) const {
    return Error{"ping pair '" + file + "': " + field + ": " + what};
  }
};

Result<SonarPing> read_ping(const Reader& rd, const fs::path& dir, const nlohmann::json& j, const std::string& key,
                            SonarMount mount) {
  if (!j.contains(key) || !j[key].is_object()) return rd.fail(key, "missing or not an object");
  const auto& o = j[key];
  SonarPing p;
  p.mount = mount;
  try {
    p.device_id = o.at("device_id").get<uint32_t>();
    p.part_number = o.at("part_number").get<uint16_t>();
    p.ping_id = o.at("ping_id").get<uint32_t>();
    p.stamp = Time::from_ns(o.at("stamp_ns").get<int64_t>());
    p.rows = o.at("rows").get<uint16_t>();
    p.cols = o.at("cols").get<uint16_t>();
    p.bytes_per_pixel = o.at("bytes_per_pixel").get<uint8_t>();
    p.range_resolution_m = o.at("range_resolution_m").get<double>();
    p.frequency_hz = o.at("frequency_hz").get<double>();
    p.bearings_rad = o.at("bearings_rad").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    return rd.fail(key, e.what());
  }
  if (p.rows == 0 || p.cols < 2) return rd.fail(key + ".rows/cols", "an image needs rows and at least two beams");
  if (p.bytes_per_pixel != 1 && p.bytes_per_pixel != 2) return rd.fail(key + ".bytes_per_pixel", "must be 1 or 2");
  if (p.bearings_rad.size() != p.cols)
    return rd.fail(key + ".bearings_rad", std::to_string(p.bearings_rad.size()) + " bearings for " +
                                              std::to_string(p.cols) + " beams");
  if (!(p.range_resolution_m > 0.0)) return rd.fail(key + ".range_resolution_m", "must be positive");
  const std::string png = (dir / file_of(mount)).string();
  auto img = codec::read_image(png, codec::DecodeAs::kGray);
  if (!img) return img.error();
  const int want_depth = p.bytes_per_pixel == 1 ? CV_8U : CV_16U;
  if (img->rows != p.rows || img->cols != p.cols || img->depth() != want_depth)
    return Error{"ping pair '" + png + "': image is " + std::to_string(img->cols) + "x" + std::to_string(img->rows) +
                 ", " + rd.file + " says " + std::to_string(p.cols) + "x" + std::to_string(p.rows) + " at " +
                 std::to_string(8 * p.bytes_per_pixel) + " bits"};
  p.image.resize(static_cast<size_t>(p.rows) * p.cols * p.bytes_per_pixel);
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c) {
      const size_t i = static_cast<size_t>(r) * p.cols + static_cast<size_t>(c);
      if (p.bytes_per_pixel == 1) {
        p.image[i] = img->at<uint8_t>(r, c);
      } else {
        const uint16_t v = img->at<uint16_t>(r, c);
        p.image[2 * i] = static_cast<uint8_t>(v & 0xff);
        p.image[2 * i + 1] = static_cast<uint8_t>(v >> 8);
      }
    }
  return p;
}

Result<std::vector<perception::Detection>> read_detections(const Reader& rd, const nlohmann::json& j,
                                                           const std::string& key, const SonarPing& p) {
  if (!j.contains(key) || !j[key].is_array()) return rd.fail(key, "missing or not an array");
  std::vector<perception::Detection> out;
  for (size_t i = 0; i < j[key].size(); ++i) {
    const auto& d = j[key][i];
    const std::string where = key + "[" + std::to_string(i) + "]";
    if (!d.is_array() || d.size() != 3 || !d[0].is_number_integer() || !d[1].is_number_integer() || !d[2].is_number())
      return rd.fail(where, "expected [row, col, intensity]");
    perception::Detection x{d[0].get<int>(), d[1].get<int>(), d[2].get<float>()};
    if (x.row < 0 || x.row >= p.rows || x.col < 0 || x.col >= p.cols)
      return rd.fail(where, "outside the " + std::to_string(p.cols) + "x" + std::to_string(p.rows) + " image");
    out.push_back(x);
  }
  return out;
}

}  // namespace

Status write_ping_pair(const std::string& dir, const SonarPing& h, const SonarPing& v,
                       const perception::FusionResult& fused, double overlap_deg) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Error{"cannot create '" + dir + "': " + ec.message()};
  for (const SonarPing* p : {&h, &v})
    if (Status s = codec::write_png((fs::path(dir) / file_of(p->mount)).string(), image_of(*p)); !s) return s;
  nlohmann::json points = nlohmann::json::array();
  for (const auto& f : fused.points)
    points.push_back({{"range_m", f.range_m},
                      {"bearing_rad", f.bearing_rad},
                      {"elevation_rad", f.elevation_rad},
                      {"confidence", f.confidence},
                      {"elevation_from", f.elevation_from == perception::FusedPoint::Elevation::sloped_face
                                             ? "sloped_face" : "v_return"},
                      {"elevation_sigma_rad", f.elevation_sigma_rad},
                      {"p_V", {f.p_V.x(), f.p_V.y(), f.p_V.z()}}});
  const nlohmann::json j = {{"horizontal", ping_json(h)},
                            {"vertical", ping_json(v)},
                            {"detections_h", detections_json(fused.detections_h)},
                            {"detections_v", detections_json(fused.detections_v)},
                            {"fused_points", points},
                            {"overlap_deg", overlap_deg}};
  const fs::path path = fs::path(dir) / kJson;
  std::ofstream f(path, std::ios::trunc);
  f << j.dump(1) << "\n";
  if (!f) return Error{"cannot write '" + path.string() + "'"};
  return {};
}

Result<PingPairRecord> read_ping_pair(const std::string& dir) {
  const fs::path path = fs::path(dir) / kJson;
  const Reader rd{path.string()};
  std::ifstream in(path);
  if (!in) return Error{"cannot open '" + path.string() + "'"};
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    return Error{"ping pair '" + path.string() + "': " + e.what()};
  }
  if (!j.is_object()) return rd.fail("(top level)", "not an object");
  PingPairRecord r;
  auto h = read_ping(rd, dir, j, "horizontal", SonarMount::kHorizontal);
  if (!h) return h.error();
  auto v = read_ping(rd, dir, j, "vertical", SonarMount::kVertical);
  if (!v) return v.error();
  r.h = std::move(*h);
  r.v = std::move(*v);
  auto dh = read_detections(rd, j, "detections_h", r.h);
  if (!dh) return dh.error();
  auto dv = read_detections(rd, j, "detections_v", r.v);
  if (!dv) return dv.error();
  r.detections_h = std::move(*dh);
  r.detections_v = std::move(*dv);
  if (j.contains("overlap_deg")) {
    if (!j["overlap_deg"].is_number() || !(j["overlap_deg"].get<double>() > 0.0))
      return rd.fail("overlap_deg", "must be a positive number");
    r.overlap_deg = j["overlap_deg"].get<double>();
  }
  if (!j.contains("fused_points") || !j["fused_points"].is_array()) return rd.fail("fused_points", "missing or not an array");
  for (size_t i = 0; i < j["fused_points"].size(); ++i) {
    const auto& o = j["fused_points"][i];
    perception::FusedPoint f;
    try {
      f.range_m = o.at("range_m").get<float>();
      f.bearing_rad = o.at("bearing_rad").get<float>();
      f.elevation_rad = o.at("elevation_rad").get<float>();
      f.confidence = o.at("confidence").get<float>();
      const auto p = o.at("p_V").get<std::vector<float>>();
      if (p.size() != 3) return rd.fail("fused_points[" + std::to_string(i) + "].p_V", "expected [x, y, z]");
      f.p_V = Eigen::Vector3f(p[0], p[1], p[2]);
      // Written since issue 34's uncertainty; files from before have neither.
      if (o.contains("elevation_sigma_rad")) f.elevation_sigma_rad = o.at("elevation_sigma_rad").get<float>();
      if (o.contains("elevation_from")) {
        const auto from = o.at("elevation_from").get<std::string>();
        if (from == "sloped_face") f.elevation_from = perception::FusedPoint::Elevation::sloped_face;
        else if (from != "v_return")
          return rd.fail("fused_points[" + std::to_string(i) + "].elevation_from",
                         "'" + from + "' is neither v_return nor sloped_face");
      }
    } catch (const nlohmann::json::exception& e) {
      return rd.fail("fused_points[" + std::to_string(i) + "]", e.what());
    }
    r.fused.push_back(f);
  }
  return r;
}

}  // namespace orthosonar::outputs
