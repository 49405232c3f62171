#include "replay/run/trajectory.hpp"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <optional>

#include "core/mapping/metrics.hpp"

namespace orthosonar::run {
namespace {

std::string stamp_seconds(Time t) {
  const int64_t ns = t.ns();
  const bool neg = ns < 0;
  const uint64_t a = neg ? static_cast<uint64_t>(-(ns + 1)) + 1u : static_cast<uint64_t>(ns);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s%" PRIu64 ".%09" PRIu64, neg ? "-" : "", a / 1000000000u,
                a % 1000000000u);
  return buf;
}

void append_pose(std::string& out, const SE3& T) {
  const Vec3 p = T.translation();
  const Vec3 rpy = rpy_from_rotation(T.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.9f,%.9f,%.9f", p.x(), p.y(), p.z(), rpy.x(),
                rpy.y(), rpy.z());
  out += buf;
}

Status write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  f << text;
  f.close();
  if (!f) return Error{"cannot write '" + path + "'"};
  return Status::Ok();
}

}  // namespace

std::string tum_line(Time stamp, const SE3& T_W_V) {
  Quat q(T_W_V.rotation());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vec3 p = T_W_V.translation();
  char buf[256];
  std::snprintf(buf, sizeof buf, " %.9f %.9f %.9f %.9f %.9f %.9f %.9f", p.x(), p.y(), p.z(), q.x(),
                q.y(), q.z(), q.w());
  return stamp_seconds(stamp) + buf;
}

std::string tum_text(const std::vector<StampedPose>& poses) {
  std::string out;
  for (const auto& p : poses) out += tum_line(p.stamp, p.T_W_V) + "\n";
  return out;
}

Status write_tum(const std::string& path, const std::vector<StampedPose>& poses) {
  return write_text(path, tum_text(poses));
}

Status write_tum(const std::string& path, const std::vector<TruthPose>& truth) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  for (const auto& t : truth) {
    // Through the rotation matrix, as every TUM file is written (same digits).
    f << tum_line(t.stamp, mapping::truth_pose(t)) << '\n';
  }
  f.close();
  if (!f) return Error{"cannot write '" + path + "'"};
  return Status::Ok();
}

Status write_tum(const std::string& path, const TruthSpill& truth) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error{"cannot open '" + path + "' for writing"};
  if (Status s = truth.for_each([&](const TruthPose& t) { f << tum_line(t.stamp, mapping::truth_pose(t)) << '\n'; });
      !s.ok())
    return Error{path + ": " + s.error().message};
  f.close();
  if (!f) return Error{"cannot write '" + path + "'"};
  return Status::Ok();
}

std::vector<StampedPose> keyframe_poses_dr(const slam::KeyframeSlam& slam) {
  std::vector<StampedPose> out;
  for (const auto& k : slam.keyframes()) out.push_back({k.stamp, k.T_W_V_dr});
  return out;
}

std::vector<StampedPose> keyframe_poses_slam(const slam::KeyframeSlam& slam) {
  std::vector<StampedPose> out;
  for (const auto& k : slam.keyframes()) out.push_back({k.stamp, k.T_W_V_slam});
  return out;
}

std::string keyframe_table_csv(const slam::KeyframeSlam& slam) {
  std::string out =
      "id,stamp_ns,dr_x,dr_y,dr_z,dr_roll,dr_pitch,dr_yaw,slam_x,slam_y,slam_z,slam_roll,"
      "slam_pitch,slam_yaw,factors\n";
  std::vector<std::string> factors(slam.keyframes().size());
  for (const auto& f : slam.factors()) {
    if (f.to < 0 || static_cast<size_t>(f.to) >= factors.size()) continue;
    std::string& s = factors[static_cast<size_t>(f.to)];
    if (!s.empty()) s += ';';
    s += std::string(slam::factor_kind_name(f.kind)) + ":" + std::to_string(f.from) + ">" +
         std::to_string(f.to) + ":" + (f.accepted ? "1" : "0");
    if (f.weakened > 0) s += ":w" + std::to_string(f.weakened);  // weakly observed directions
  }
  for (const auto& k : slam.keyframes()) {
    out += std::to_string(k.id) + "," + std::to_string(k.stamp.ns());
    append_pose(out, k.T_W_V_dr);
    append_pose(out, k.T_W_V_slam);
    out += "," + factors[static_cast<size_t>(k.id)] + "\n";
  }
  return out;
}

Status write_keyframe_table(const std::string& path, const slam::KeyframeSlam& slam) {
  return write_text(path, keyframe_table_csv(slam));
}

std::string factor_table_csv(const slam::KeyframeSlam& slam, const std::vector<TruthPose>& truth) {
  std::string out =
      "kind,from,to,x,y,theta,sigma_x,sigma_y,sigma_theta,weakened,accepted,robust_weight,reason,true_x,true_y,"
      "true_theta,err_x,err_y,err_theta\n";
  const auto& kfs = slam.keyframes();
  std::vector<std::optional<SE2>> T_true(kfs.size());
  for (size_t k = 0; k < kfs.size(); ++k)
    if (const auto T = mapping::truth_pose_at(truth, kfs[k].stamp)) T_true[k] = se2_from_se3(*T);
  auto known = [&](int id) { return id >= 0 && static_cast<size_t>(id) < T_true.size() && T_true[id].has_value(); };
  char buf[512];
  for (const auto& f : slam.factors()) {
    std::string reason = f.reason;
    for (char& c : reason)
      if (c == ',' || c == '\n' || c == '"') c = ';';  // one CSV field, no quoting needed
    std::snprintf(buf, sizeof buf, "%s,%d,%d,%.6f,%.6f,%.9f,%.6g,%.6g,%.6g,%d,%d,%.6f,", slam::factor_kind_name(f.kind),
                  f.from, f.to, f.T_from_to.x, f.T_from_to.y, f.T_from_to.theta, f.sigma.x(), f.sigma.y(), f.sigma.z(),
                  f.weakened, f.accepted ? 1 : 0, f.robust_weight);
    out += buf + reason;
    if (f.kind != slam::FactorKind::kPrior && known(f.from) && known(f.to)) {
      const SE2 z = T_true[static_cast<size_t>(f.from)]->inverse() * *T_true[static_cast<size_t>(f.to)];
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.9f,%.6f,%.6f,%.9f\n", z.x, z.y, z.theta, f.T_from_to.x - z.x,
                    f.T_from_to.y - z.y, wrap_angle(f.T_from_to.theta - z.theta));
      out += buf;
    } else {
      out += ",,,,,,\n";
    }
  }
  return out;
}

Status write_factor_table(const std::string& path, const slam::KeyframeSlam& slam,
                          const std::vector<TruthPose>& truth) {
  return write_text(path, factor_table_csv(slam, truth));
}

}  // namespace orthosonar::run
