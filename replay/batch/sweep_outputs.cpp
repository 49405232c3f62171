// A sweep's reference-cell outputs and HTML report (see sweep_outputs.hpp).
#include "replay/batch/sweep_outputs.hpp"

#include <filesystem>
#include <iostream>

#include "reports/report.hpp"

namespace orthosonar::batch {

Status write_reference_outputs(const std::string& fixture, const run::RunOptions& options, int threads,
                               const std::string& out_dir) {
  run::RunOptions ref = options;
  ref.threads_override = threads;
  ref.adjust = [](run::RunConfig& c) {
    c.pipeline.slam.kf_distance_m = kReferenceCell.distance_m;
    c.pipeline.slam.kf_rotation_deg = kReferenceCell.rotation_deg;
  };
  auto out = run::run_fixture(fixture, ref);
  if (!out.ok()) return out.error();
  return run::write_run_outputs(*out, ref, out_dir);
}

Status write_sweep_report(const std::string& sweep_dir, const std::string& title) {
  const std::string report_dir = (std::filesystem::path(sweep_dir) / "report").string();
  reports::ReportOptions ropt;
  ropt.title = title;
  Status rs = reports::write_report(sweep_dir, report_dir, ropt);
  if (!rs.ok()) {
    std::cerr << "sweep: report: " << rs.error().message << "; writing it without 3D renders\n";
    ropt.require_renders = false;
    rs = reports::write_report(sweep_dir, report_dir, ropt);
  }
  if (!rs.ok()) return Error{"report: " + rs.error().message};
  std::cerr << "sweep: report " << (std::filesystem::path(report_dir) / "report.html").string() << "\n";
  return {};
}

}  // namespace orthosonar::batch
