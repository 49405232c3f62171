#include "core/inference/dbscan.hpp"

#include <algorithm>
#include <cmath>

namespace orthosonar::inference {
namespace {

bool within(const PixelRC& a, const PixelRC& b, double eps) {
  const double dr = a.row - b.row;
  const double dc = a.col - b.col;
  return dr * dr + dc * dc <= eps * eps;
}

// Exact lattice index: pixels are integer points, so a dense array over their bounding
// box maps (row, col) to a point index, and a query visits the precomputed offsets of the
// disc in row-major order, which yields neighbour indices already ascending.
class Grid {
 public:
  Grid(const std::vector<PixelRC>& pts, double eps) : pts_(pts) {
    if (pts.empty()) return;
    r0_ = pts.front().row;
    const int r1 = pts.back().row;
    c0_ = pts.front().col;
    int c1 = c0_;
    for (const PixelRC& p : pts) {
      c0_ = std::min(c0_, p.col);
      c1 = std::max(c1, p.col);
    }
    h_ = r1 - r0_ + 1;
    w_ = c1 - c0_ + 1;
    index_.assign(static_cast<size_t>(h_) * static_cast<size_t>(w_), -1);
    for (size_t i = 0; i < pts.size(); ++i) index_[cell(pts[i].row, pts[i].col)] = static_cast<long>(i);
    const int e = static_cast<int>(std::floor(eps));
    for (int dr = -e; dr <= e; ++dr) {
      for (int dc = -e; dc <= e; ++dc) {
        if (within({0, 0}, {dr, dc}, eps)) offsets_.push_back({dr, dc});
      }
    }
  }
  void neighbours(size_t i, std::vector<size_t>& out) const {
    out.clear();
    const PixelRC& p = pts_[i];
    for (const PixelRC& o : offsets_) {
      const int r = p.row + o.row, c = p.col + o.col;
      if (r < r0_ || r >= r0_ + h_ || c < c0_ || c >= c0_ + w_) continue;
      const long j = index_[cell(r, c)];
      if (j >= 0) out.push_back(static_cast<size_t>(j));
    }
  }

 private:
  size_t cell(int r, int c) const {
    return static_cast<size_t>(r - r0_) * static_cast<size_t>(w_) + static_cast<size_t>(c - c0_);
  }
  const std::vector<PixelRC>& pts_;
  int r0_ = 0, c0_ = 0, h_ = 0, w_ = 0;
  std::vector<long> index_;
  std::vector<PixelRC> offsets_;
};

class BruteForce {
 public:
  BruteForce(const std::vector<PixelRC>& pts, double eps) : pts_(pts), eps_(eps) {}
  void neighbours(size_t i, std::vector<size_t>& out) const {
    out.clear();
    for (size_t j = 0; j < pts_.size(); ++j) {
      if (within(pts_[i], pts_[j], eps_)) out.push_back(j);
    }
  }

 private:
  const std::vector<PixelRC>& pts_;
  double eps_;
};

constexpr int kUnvisited = -2;

template <class Index>
std::vector<int> run(const std::vector<PixelRC>& pts, const DbscanConfig& cfg, const Index& index) {
  const size_t n = pts.size();
  std::vector<int> label(n, kUnvisited);
  std::vector<size_t> nb, nb2, queue;
  const size_t min_samples = static_cast<size_t>(std::max(1, cfg.min_samples));
  int next_id = 0;
  for (size_t i = 0; i < n; ++i) {
    if (label[i] != kUnvisited) continue;
    index.neighbours(i, nb);
    if (nb.size() < min_samples) {
      label[i] = kNoise;  // may become a border point later
      continue;
    }
    const int id = next_id++;
    label[i] = id;
    queue.assign(nb.begin(), nb.end());
    for (size_t q = 0; q < queue.size(); ++q) {  // breadth-first, in discovery order
      const size_t j = queue[q];
      if (label[j] == kNoise) label[j] = id;     // border point
      if (label[j] != kUnvisited) continue;
      label[j] = id;
      index.neighbours(j, nb2);
      if (nb2.size() >= min_samples) queue.insert(queue.end(), nb2.begin(), nb2.end());
    }
  }
  // Renumber clusters by their first member in row-major order.
  std::vector<int> remap(static_cast<size_t>(next_id), -1);
  int renumbered = 0;
  for (size_t i = 0; i < n; ++i) {
    if (label[i] < 0) continue;
    int& r = remap[static_cast<size_t>(label[i])];
    if (r < 0) r = renumbered++;
    label[i] = r;
  }
  return label;
}

}  // namespace

std::vector<int> dbscan_labels(const std::vector<PixelRC>& sorted_pixels, const DbscanConfig& config) {
  return run(sorted_pixels, config, Grid(sorted_pixels, config.eps_px));
}

std::vector<int> dbscan_labels_brute_force(const std::vector<PixelRC>& sorted_pixels,
                                           const DbscanConfig& config) {
  return run(sorted_pixels, config, BruteForce(sorted_pixels, config.eps_px));
}

std::vector<Cluster> dbscan_clusters(std::vector<PixelRC> pixels, const DbscanConfig& config) {
  std::sort(pixels.begin(), pixels.end());
  pixels.erase(std::unique(pixels.begin(), pixels.end()), pixels.end());
  const std::vector<int> label = dbscan_labels(pixels, config);
  std::vector<Cluster> all;
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (label[i] < 0) continue;
    const size_t id = static_cast<size_t>(label[i]);
    if (id >= all.size()) all.resize(id + 1);
    all[id].pixels.push_back(pixels[i]);
  }
  std::vector<Cluster> kept;
  for (Cluster& c : all) {
    if (static_cast<int>(c.pixels.size()) < config.min_cluster_px) continue;
    c.row_min = c.row_max = c.pixels.front().row;
    c.col_min = c.col_max = c.pixels.front().col;
    for (const PixelRC& p : c.pixels) {
      c.row_min = std::min(c.row_min, p.row);
      c.row_max = std::max(c.row_max, p.row);
      c.col_min = std::min(c.col_min, p.col);
      c.col_max = std::max(c.col_max, p.col);
    }
    kept.push_back(std::move(c));
  }
  return kept;
}

}  // namespace orthosonar::inference
