// PCD through pcl::io: the one PCD writer and reader. The only translation unit of the
// project that includes PCL (its headers cost ~10 s of compile time each).
//
// What PCL does not do for us: it trusts the header's counts (pcd_header.hpp validates
// them first); it reads a short or non-numeric ascii line as zeros (check_ascii_data);
// and it prints a warning for an empty cloud and then writes HEIGHT 0 (an empty cloud is
// written here as PCL's own header with no data: WIDTH 0, HEIGHT 1, POINTS 0, and read
// back as empty without calling PCL).
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "replay/outputs/map_writers.hpp"
#include "replay/outputs/pcd_header.hpp"

namespace orthosonar::outputs {
namespace {

Status write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{path + ": cannot open for writing"};
  f << text;
  f.flush();
  if (!f) return Error{path + ": write failed"};
  return {};
}

// PCL reports I/O failures by return code or by pcl::IOException.
template <class F>
Status call_pcl(const std::string& path, F&& f) {
  try {
    if (f() != 0) return Error{path + ": PCL could not write the file"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  return {};
}

// PCL reads a short or non-numeric ascii line as zeros without failing, so each data line
// is checked first: POINTS non-empty lines of exactly one number per value.
Status check_ascii_data(const std::string& path, const pcd::Header& h) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  uint64_t values = 0;
  for (const pcd::Field& f : h.fields) values += f.count;
  uint64_t points = 0;
  std::string line;
  for (uint64_t line_no = 1; std::getline(in, line); ++line_no) {
    std::istringstream ls(line);
    uint64_t n = 0;
    for (std::string tok; ls >> tok; ++n) {
      double v = 0;
      const char* first = tok.data() + (tok[0] == '+' ? 1 : 0);
      auto [p, ec] = std::from_chars(first, tok.data() + tok.size(), v);
      if (ec != std::errc() || p != tok.data() + tok.size())
        return Error{path + ": data line " + std::to_string(line_no) + ": '" + tok + "' is not a number"};
    }
    if (n == 0) continue;
    if (n != values)
      return Error{path + ": data line " + std::to_string(line_no) + ": " + std::to_string(n) + " values, FIELDS/COUNT say " +
                   std::to_string(values)};
    if (++points > h.points) break;
  }
  if (points != h.points)
    return Error{path + ": " + (points < h.points ? "truncated: " : "") + std::to_string(points) +
                 " data lines, header says POINTS " + std::to_string(h.points)};
  return {};
}

}  // namespace

Status write_pcd(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) cloud[i] = pcl::PointXYZ(points[i].x(), points[i].y(), points[i].z());
  cloud.width = static_cast<uint32_t>(points.size());
  cloud.height = 1;
  if (points.empty()) return write_text(path, pcl::PCDWriter::generateHeader(cloud, 0) + "DATA binary\n");
  return call_pcl(path, [&] { return pcl::io::savePCDFileBinary(path, cloud); });
}

Status write_pcd_fields(const std::string& path, const std::vector<std::string>& names,
                        const std::vector<float>& values, PcdEncoding encoding) {
  if (names.empty() || values.size() % names.size() != 0)
    return Error{path + ": " + std::to_string(values.size()) + " values for " + std::to_string(names.size()) + " fields"};
  pcl::PCLPointCloud2 blob;
  for (size_t k = 0; k < names.size(); ++k) {
    pcl::PCLPointField f;
    f.name = names[k];
    f.offset = static_cast<uint32_t>(4 * k);
    f.datatype = pcl::PCLPointField::FLOAT32;
    f.count = 1;
    blob.fields.push_back(f);
  }
  const size_t n = values.size() / names.size();
  blob.width = static_cast<uint32_t>(n);
  blob.height = 1;
  blob.point_step = static_cast<uint32_t>(4 * names.size());
  blob.row_step = static_cast<uint32_t>(blob.point_step * n);
  blob.is_dense = true;
  blob.data.resize(values.size() * sizeof(float));
  if (!blob.data.empty()) std::memcpy(blob.data.data(), values.data(), blob.data.size());
  const Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  const Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  pcl::PCDWriter w;
  if (n == 0) {
    const bool ascii = encoding == PcdEncoding::kAscii;
    return write_text(path, (ascii ? w.generateHeaderASCII(blob, origin, orientation)
                                   : w.generateHeaderBinary(blob, origin, orientation)) +
                                (ascii ? "DATA ascii\n" : "DATA binary\n"));
  }
  return call_pcl(path, [&] {
    return encoding == PcdEncoding::kAscii ? w.writeASCII(path, blob, origin, orientation)
                                           : w.writeBinary(path, blob, origin, orientation);
  });
}

Result<std::vector<Eigen::Vector3f>> read_pcd(const std::string& path) {
  auto h = pcd::read_header(path);
  if (!h) return h.error();
  for (const char* axis : {"x", "y", "z"}) {
    const pcd::Field* f = h->field(axis);
    if (!f) return Error{path + ": header: no field " + axis};
    if (f->type != 'F' || f->size != 4 || f->count != 1)
      return Error{path + ": header: field " + axis + " is not one 4-byte float"};
  }
  if (h->points == 0) return std::vector<Eigen::Vector3f>{};
  if (h->data == pcd::Data::kAscii)
    if (Status s = check_ascii_data(path, *h); !s) return s.error();
  pcl::PointCloud<pcl::PointXYZ> cloud;
  try {
    if (pcl::io::loadPCDFile(path, cloud) != 0) return Error{path + ": PCL could not read the point data (truncated or malformed)"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  if (cloud.size() != h->points)
    return Error{path + ": read " + std::to_string(cloud.size()) + " points, header says " + std::to_string(h->points)};
  std::vector<Eigen::Vector3f> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) out.emplace_back(p.x, p.y, p.z);
  return out;
}

}  // namespace orthosonar::outputs
