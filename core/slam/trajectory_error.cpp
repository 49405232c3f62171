#include "core/slam/trajectory_error.hpp"

#include <cmath>
#include <string>

namespace orthosonar::slam {

Result<double> ate_rmse(const std::vector<Vec3>& est, const std::vector<Vec3>& truth,
                        AteAlignment alignment) {
  if (est.empty() || est.size() != truth.size())
    return Error{"ate_rmse: estimate has " + std::to_string(est.size()) + " positions, truth " +
                 std::to_string(truth.size()) + " (need the same number, at least one)"};
  const Vec3 offset =
      alignment == AteAlignment::kFirstPosition ? Vec3(truth.front() - est.front()) : Vec3::Zero();
  double sum = 0.0;
  for (size_t i = 0; i < est.size(); ++i) sum += (est[i] + offset - truth[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(est.size()));
}

}  // namespace orthosonar::slam
