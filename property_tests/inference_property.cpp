// Inference stage properties (SPEC §8): DBSCAN with grid neighbour search equals the
// brute-force reference and DBSCAN computed from its definition (border points included);
// the Bayes height update concentrates at the measured height.
// Seeds are printed by rapidcheck; replay with RC_PARAMS="seed=...".
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "core/inference/dbscan.hpp"
#include "core/inference/height_model.hpp"

using namespace orthosonar::inference;

namespace {
// Pixels in a small window, so that clusters, borders and noise all occur.
std::vector<PixelRC> any_pixels() {
  const int n = *rc::gen::inRange(0, 300);
  const int side = *rc::gen::inRange(5, 120);
  std::vector<PixelRC> v;
  for (int i = 0; i < n; ++i) v.push_back({*rc::gen::inRange(-side, side), *rc::gen::inRange(0, side)});
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}
}  // namespace

TEST_CASE("dbscan grid search equals brute force", "[property]") {
  rc::prop("labels identical for any pixels, eps and min_samples", [] {
    const auto pts = any_pixels();
    DbscanConfig cfg;
    cfg.eps_px = static_cast<double>(*rc::gen::inRange(10, 80)) / 10.0;
    cfg.min_samples = *rc::gen::inRange(1, 6);
    RC_ASSERT(dbscan_labels(pts, cfg) == dbscan_labels_brute_force(pts, cfg));
  });
}

TEST_CASE("dbscan cluster ids follow the first member in row-major order", "[property]") {
  rc::prop("first occurrences of labels are 0, 1, 2, ...", [] {
    const auto labels = dbscan_labels(any_pixels(), {});
    int next = 0;
    for (int l : labels) {
      if (l < 0) continue;
      RC_ASSERT(l <= next);
      if (l == next) ++next;
    }
  });
}

namespace {

// DBSCAN from its definition (Ester et al. 1996), written independently of dbscan.cpp's
// breadth-first growth: core points have >= min_samples points in their closed eps disc
// (themselves included); clusters are the connected components of the core points (union-find
// over every pair within eps); a non-core point with a core neighbour is a border point and
// joins, of its neighbours' clusters, the one whose seed (first core point in row-major
// order) comes first, since that cluster is grown first; everything else is noise. Ids are
// renumbered by each cluster's first member in row-major order (dbscan.hpp's contract).
struct DbscanDefinitionResult {
  std::vector<int> labels;
  size_t border_points = 0;  // non-core points in a cluster
};

DbscanDefinitionResult dbscan_by_definition(const std::vector<PixelRC>& pts, const DbscanConfig& cfg) {
  const size_t n = pts.size();
  const auto within = [&](size_t i, size_t j) {
    const double dr = pts[i].row - pts[j].row, dc = pts[i].col - pts[j].col;
    return dr * dr + dc * dc <= cfg.eps_px * cfg.eps_px;
  };
  std::vector<bool> core(n, false);
  for (size_t i = 0; i < n; ++i) {
    int k = 0;
    for (size_t j = 0; j < n; ++j) k += within(i, j) ? 1 : 0;
    core[i] = k >= cfg.min_samples;
  }
  std::vector<size_t> parent(n);
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  const auto find = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (core[i] && core[j] && within(i, j)) {
        const size_t a = find(i), b = find(j);
        parent[std::max(a, b)] = std::min(a, b);  // the root is the component's first core point
      }
  DbscanDefinitionResult r;
  std::vector<long> seed(n, -1);  // the seed of the point's cluster, -1 for noise
  for (size_t i = 0; i < n; ++i) {
    if (core[i]) {
      seed[i] = static_cast<long>(find(i));
      continue;
    }
    for (size_t j = 0; j < n; ++j)
      if (core[j] && within(i, j) && (seed[i] < 0 || static_cast<long>(find(j)) < seed[i]))
        seed[i] = static_cast<long>(find(j));
    if (seed[i] >= 0) ++r.border_points;
  }
  std::map<long, int> id;
  r.labels.assign(n, kNoise);
  for (size_t i = 0; i < n; ++i) {
    if (seed[i] < 0) continue;
    const auto it = id.emplace(seed[i], static_cast<int>(id.size())).first;
    r.labels[i] = it->second;
  }
  return r;
}

}  // namespace

// min_samples from 2 to 7: with 2 every point that has a neighbour is core, so border points
// (and the order in which clusters claim them) only exist from 3 on. The counter checks
// that the draws do produce border points.
TEST_CASE("dbscan labels equal DBSCAN computed from its definition, border points included", "[property]") {
  size_t borders_seen = 0, runs_with_borders = 0;
  rc::prop("labels identical to the definition's for any pixels, eps and min_samples", [&] {
    const auto pts = any_pixels();
    DbscanConfig cfg;
    cfg.eps_px = static_cast<double>(*rc::gen::inRange(10, 60)) / 10.0;
    cfg.min_samples = *rc::gen::inRange(2, 8);
    const auto reference = dbscan_by_definition(pts, cfg);
    borders_seen += reference.border_points;
    runs_with_borders += reference.border_points > 0 ? 1 : 0;
    RC_ASSERT(dbscan_labels(pts, cfg) == reference.labels);
  });
  INFO("border points seen " << borders_seen << " in " << runs_with_borders << " draws");
  CHECK(runs_with_borders >= 10);
}

TEST_CASE("Bayes height updates concentrate at the measured height", "[property]") {
  rc::prop("MAP bin within half a bin of a repeated measurement", [] {
    const double z = static_cast<double>(*rc::gen::inRange(-5900, 1900)) / 1000.0;
    const int n = *rc::gen::inRange(3, 40);
    HeightModel m;
    for (int i = 0; i < n; ++i) RC_ASSERT(m.update(0.0, 0.0, z));
    const auto est = m.map_estimate(0.0, 0.0);
    const auto& side = z <= 0.0 ? est.below : est.above;
    // The bin containing 0 is on the z <= 0 side; a z just above 0 may map into it.
    if (std::abs(z) > 0.05) {
      RC_ASSERT(side.has_value());
      RC_ASSERT(std::abs(side->z_m - z) <= 0.025 + 1e-9);
      RC_ASSERT(side->probability > 0.3);  // passes the default MAP threshold
    }
  });
}
