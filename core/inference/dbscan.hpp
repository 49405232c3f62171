#pragma once
// DBSCAN (Ester et al. 1996) over horizontal-sonar detections in image space (SPEC §8,
// paper §VI-A). Points are pixels (row, col); the neighbourhood is the closed Euclidean
// disc of radius eps_px. Neighbour search uses an exact lattice index (a dense array over
// the pixels' bounding box, visited at the disc's offsets), so every query returns exactly
// the neighbours a brute-force scan finds, in O(eps^2) per query.
//
// Determinism: points are processed in row-major order (duplicates removed), a cluster is
// grown breadth-first from its seed, a border point joins the first cluster that reaches
// it, and cluster ids are finally renumbered by each cluster's first member in row-major
// order. The result is a pure function of the set of input pixels.
#include <cstdint>
#include <vector>

namespace orthosonar::inference {

struct PixelRC {
  int row = 0;
  int col = 0;
  friend bool operator==(const PixelRC&, const PixelRC&) = default;
  friend auto operator<=>(const PixelRC&, const PixelRC&) = default;  // row-major
};

struct DbscanConfig {
  double eps_px = 5.0;        // neighbourhood radius, pixels
  int min_samples = 2;        // core point: >= min_samples points in its disc (itself included)
  int min_cluster_px = 31;    // keep clusters with more than 30 pixels
};

inline constexpr int kNoise = -1;

// Raw DBSCAN labels for `pixels` sorted row-major without duplicates (precondition):
// label[i] in {kNoise, 0, 1, ...}, ids ordered by first member. No size filter.
std::vector<int> dbscan_labels(const std::vector<PixelRC>& sorted_pixels, const DbscanConfig& config);

// The slow obvious reference (O(n^2) neighbour search) with the same visiting order; a
// test oracle for dbscan_labels.
std::vector<int> dbscan_labels_brute_force(const std::vector<PixelRC>& sorted_pixels,
                                           const DbscanConfig& config);

struct Cluster {
  std::vector<PixelRC> pixels;  // row-major
  int row_min = 0, row_max = 0, col_min = 0, col_max = 0;  // inclusive bounding box
};

// Clusters with more than min_cluster_px - 1 pixels, in order of their first member.
// Input in any order; duplicates are ignored.
std::vector<Cluster> dbscan_clusters(std::vector<PixelRC> pixels, const DbscanConfig& config);

}  // namespace orthosonar::inference
