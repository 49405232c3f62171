#include "tools/support_memory_report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace orthosonar::cli {
namespace {

double mb(int64_t bytes) { return bytes < 0 ? -1.0 : static_cast<double>(bytes) / (1024.0 * 1024.0); }

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

ResidentBytes resident_bytes() {
  ResidentBytes r;
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line)) {
    long long kb = 0;
    if (std::sscanf(line.c_str(), "VmRSS: %lld kB", &kb) == 1) r.now = kb * 1024;
    if (std::sscanf(line.c_str(), "VmHWM: %lld kB", &kb) == 1) r.peak = kb * 1024;
  }
  return r;
}

void MemoryReport::sample(const run::RunControl::MemoryView& view) {
  if (!have_first_) {
    first_ = view.stamp;
    have_first_ = true;
  }
  Row row;
  row.sensor_s = (view.stamp - first_).seconds();
  row.phase = view.phase;
  row.rss = resident_bytes();
  row.parts.emplace_back("decoder_buffers", view.source ? view.source->buffered_bytes() : 0);
  for (auto& p : view.pipeline.memory()) {
    if (p.first == "truth") p.second += view.truth_spill_bytes;  // the poses kept in memory, wherever
    row.parts.push_back(std::move(p));
  }
  rows_.push_back(std::move(row));
}

void MemoryReport::sample_outputs(const mapping::Pipeline& pipeline, int64_t truth_spill_bytes) {
  sample({have_first_ ? first_ : Time(), "outputs written", pipeline, nullptr, truth_spill_bytes});
  if (rows_.size() > 1) rows_.back().sensor_s = rows_[rows_.size() - 2].sensor_s;  // the stream's end
}

Status MemoryReport::write_csv(const std::string& path) const {
  std::ofstream f(path);
  if (!f) return Error{path + ": cannot be written"};
  f << "sensor_s,phase,rss_mb,peak_rss_mb";
  if (!rows_.empty())
    for (const auto& [name, bytes] : rows_.front().parts) f << "," << name << "_mb";
  f << ",parts_mb\n";
  for (const Row& r : rows_) {
    int64_t total = 0;
    f << fmt("%.3f", r.sensor_s) << "," << r.phase << "," << fmt("%.2f", mb(r.rss.now)) << ","
      << fmt("%.2f", mb(r.rss.peak));
    for (const auto& [name, bytes] : r.parts) {
      f << "," << fmt("%.3f", mb(bytes));
      total += bytes;
    }
    f << "," << fmt("%.3f", mb(total)) << "\n";
  }
  f.flush();
  if (!f) return Error{path + ": write failed"};
  return {};
}

std::string MemoryReport::budget() const {
  if (rows_.empty()) return "";
  // The end of the stream (pairs flushed): what the run holds for its maps and metrics.
  const auto end = std::find_if(rows_.begin(), rows_.end(), [](const Row& r) { return r.phase == "end of stream"; });
  const Row& at_end = end != rows_.end() ? *end : rows_.back();
  // Growth: least-squares slope of each part over the samples taken during the stream.
  std::vector<const Row*> stream;
  for (const Row& r : rows_)
    if (r.phase == "stream" || r.phase == "end of stream") stream.push_back(&r);
  const auto slope_per_hour = [&](size_t part) {
    if (stream.size() < 3) return 0.0;
    double st = 0, sv = 0, stt = 0, stv = 0;
    for (const Row* r : stream) {
      const double t = r->sensor_s / 3600.0, v = mb(r->parts[part].second);
      st += t, sv += v, stt += t * t, stv += t * v;
    }
    const double n = static_cast<double>(stream.size()), den = n * stt - st * st;
    return den > 0 ? (n * stv - st * sv) / den : 0.0;
  };
  std::ostringstream md;
  md << "| part | end of stream (MB) | largest sample (MB) | growth (MB per hour of mission) |\n|---|---|---|---|\n";
  int64_t total_end = 0;
  for (size_t i = 0; i < at_end.parts.size(); ++i) {
    int64_t largest = 0;
    for (const Row& r : rows_) largest = std::max(largest, i < r.parts.size() ? r.parts[i].second : 0);
    total_end += at_end.parts[i].second;
    md << "| " << at_end.parts[i].first << " | " << fmt("%.2f", mb(at_end.parts[i].second)) << " | "
       << fmt("%.2f", mb(largest)) << " | " << fmt("%+.2f", slope_per_hour(i)) << " |\n";
  }
  md << "| **parts, total** | " << fmt("%.2f", mb(total_end)) << " | | |\n";
  md << "| resident (VmRSS) | " << fmt("%.1f", mb(at_end.rss.now)) << " | | |\n";
  // Where the process's peak was reached: the first sample whose VmHWM is the final one.
  const int64_t peak = rows_.back().rss.peak;
  const auto at_peak = std::find_if(rows_.begin(), rows_.end(), [&](const Row& r) { return r.rss.peak == peak; });
  md << "| **peak resident (VmHWM)** | " << fmt("%.1f", mb(peak)) << " | reached by: " << at_peak->phase << " at "
     << fmt("%.0f", at_peak->sensor_s) << " s | |\n";
  return md.str();
}

}  // namespace orthosonar::cli
