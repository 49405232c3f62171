#pragma once
// Per-class height distributions P(z | R, θ) (SPEC §8, paper §VI-B/C, Eqs. 8-10).
//
// A class's reference frame (see object_registry.hpp) is planar; in it, an object pixel's
// position (x, y) stands for its (R, θ) seen from the class's first sighting. Cells of
// `cell_m` on that plane each hold a discrete distribution over the height z of the
// return in the horizontal-sonar frame h (z up, metres, i.e. relative to the vehicle's
// working depth). Bins of `bin_m` over [z_min_m, z_max_m): SPEC's "−2..6 m" is depth
// (positive down) relative to the working depth, i.e. z from −6 m (below) to +2 m (above).
// An unvisited cell is uniform. Each fused 3D point multiplies its cell's distribution by a
// Gaussian likelihood N(z_bin; z_measured, σ) and renormalises (Bayes' rule, Eq. 8).
// Kept as log-probabilities so thousands of updates never underflow. Not thread-safe.
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

namespace orthosonar::inference {

struct HeightModelConfig {
  double z_min_m = -6.0;
  double z_max_m = 2.0;
  double bin_m = 0.05;
  double sigma_m = 0.08;         // Gaussian measurement likelihood
  double cell_m = 0.10;          // planar cell of the reference frame
  double min_map_probability = 0.3;  // a side's MAP bin must reach this (Eqs. 9-10)
};

struct HeightEstimate {
  double z_m = 0.0;
  double probability = 0.0;  // posterior mass of the MAP bin
};

// The two-sided MAP of one cell (Eqs. 9 and 10): the best bin with z <= 0 and the best
// with z > 0, each present only when its probability passes the threshold.
struct TwoSidedMap {
  std::optional<HeightEstimate> below;  // z <= 0
  std::optional<HeightEstimate> above;  // z > 0
};

using CellKey = std::pair<int, int>;

class HeightModel {
 public:
  explicit HeightModel(const HeightModelConfig& config = {});
  int bins() const { return bins_; }
  double bin_center(int i) const;
  CellKey cell_of(double x_m, double y_m) const;
  // Bayes update of the cell at (x, y) with one measured height (Eq. 8). Heights outside
  // the bin range are ignored (returns false).
  bool update(double x_m, double y_m, double z_m);
  // Normalised posterior of a cell (uniform when never updated).
  std::vector<double> posterior(double x_m, double y_m) const;
  bool visited(double x_m, double y_m) const;
  TwoSidedMap map_estimate(double x_m, double y_m) const;  // Eqs. 9-10
  size_t updates() const { return updates_; }
  size_t visited_cells() const { return cells_.size(); }
  const HeightModelConfig& config() const { return config_; }

 private:
  HeightModelConfig config_;
  int bins_ = 0;
  size_t updates_ = 0;
  std::map<CellKey, std::vector<double>> cells_;  // log-posterior, max-normalised to 0
};

}  // namespace orthosonar::inference
