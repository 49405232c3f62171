#include "core/inference/height_model.hpp"

#include <algorithm>
#include <cmath>

namespace orthosonar::inference {

HeightModel::HeightModel(const HeightModelConfig& config) : config_(config) {
  bins_ = std::max(1, static_cast<int>(std::lround((config.z_max_m - config.z_min_m) / config.bin_m)));
}

double HeightModel::bin_center(int i) const { return config_.z_min_m + (i + 0.5) * config_.bin_m; }

CellKey HeightModel::cell_of(double x_m, double y_m) const {
  return {static_cast<int>(std::floor(x_m / config_.cell_m)),
          static_cast<int>(std::floor(y_m / config_.cell_m))};
}

bool HeightModel::update(double x_m, double y_m, double z_m) {
  if (!std::isfinite(z_m) || z_m < config_.z_min_m || z_m >= config_.z_max_m) return false;
  auto [it, inserted] = cells_.try_emplace(cell_of(x_m, y_m), static_cast<size_t>(bins_), 0.0);
  std::vector<double>& logp = it->second;  // uniform start: all zeros
  const double inv_two_var = 1.0 / (2.0 * config_.sigma_m * config_.sigma_m);
  double best = -INFINITY;
  for (int i = 0; i < bins_; ++i) {
    const double d = bin_center(i) - z_m;
    logp[static_cast<size_t>(i)] -= d * d * inv_two_var;  // prior x likelihood (Eq. 8)
    best = std::max(best, logp[static_cast<size_t>(i)]);
  }
  for (double& v : logp) v -= best;  // the evidence term: keep the maximum at 0
  ++updates_;
  return true;
}

std::vector<double> HeightModel::posterior(double x_m, double y_m) const {
  std::vector<double> p(static_cast<size_t>(bins_), 1.0 / bins_);
  const auto it = cells_.find(cell_of(x_m, y_m));
  if (it == cells_.end()) return p;
  double sum = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    p[i] = std::exp(it->second[i]);
    sum += p[i];
  }
  for (double& v : p) v /= sum;
  return p;
}

bool HeightModel::visited(double x_m, double y_m) const {
  return cells_.count(cell_of(x_m, y_m)) > 0;
}

TwoSidedMap HeightModel::map_estimate(double x_m, double y_m) const {
  TwoSidedMap out;
  if (!visited(x_m, y_m)) return out;  // uniform: nothing passes a meaningful threshold
  const std::vector<double> p = posterior(x_m, y_m);
  int best_lo = -1, best_hi = -1;
  for (int i = 0; i < bins_; ++i) {
    const size_t k = static_cast<size_t>(i);
    if (bin_center(i) <= 0.0) {
      if (best_lo < 0 || p[k] > p[static_cast<size_t>(best_lo)]) best_lo = i;
    } else if (best_hi < 0 || p[k] > p[static_cast<size_t>(best_hi)]) {
      best_hi = i;
    }
  }
  const auto accept = [&](int i) -> std::optional<HeightEstimate> {
    if (i < 0) return std::nullopt;
    const double prob = p[static_cast<size_t>(i)];
    if (prob < config_.min_map_probability) return std::nullopt;
    return HeightEstimate{bin_center(i), prob};
  };
  out.below = accept(best_lo);  // Eq. 9
  out.above = accept(best_hi);  // Eq. 10
  return out;
}

}  // namespace orthosonar::inference
