#include "core/inference/dbscan.hpp"

#include <catch2/catch.hpp>

using namespace orthosonar::inference;

namespace {
std::vector<PixelRC> blob(int r0, int c0, int rows, int cols) {
  std::vector<PixelRC> v;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) v.push_back({r0 + r, c0 + c});
  return v;
}
}  // namespace

TEST_CASE("dbscan separates two blobs farther apart than eps and orders them row-major", "[unit]") {
  auto pts = blob(50, 50, 6, 6);     // 36 px
  auto far = blob(10, 100, 7, 7);    // 49 px, earlier in row-major order
  pts.insert(pts.end(), far.begin(), far.end());
  const auto clusters = dbscan_clusters(pts, {});
  REQUIRE(clusters.size() == 2);
  CHECK(clusters[0].pixels.size() == 49);
  CHECK(clusters[0].row_min == 10);
  CHECK(clusters[0].col_max == 106);
  CHECK(clusters[1].pixels.size() == 36);
}

TEST_CASE("dbscan joins points within eps and keeps only clusters larger than 30 px", "[unit]") {
  // A dotted line with gaps of 5 px (= eps, inclusive) is one cluster.
  std::vector<PixelRC> line;
  for (int i = 0; i < 40; ++i) line.push_back({20, 5 * i});
  auto small = blob(100, 100, 5, 6);  // 30 px: dropped
  auto pts = line;
  pts.insert(pts.end(), small.begin(), small.end());
  const auto clusters = dbscan_clusters(pts, {});
  REQUIRE(clusters.size() == 1);
  CHECK(clusters[0].pixels.size() == 40);
  // Gaps of 6 px break it into single points: noise.
  std::vector<PixelRC> sparse;
  for (int i = 0; i < 40; ++i) sparse.push_back({20, 6 * i});
  const auto labels = dbscan_labels(sparse, {});
  for (int l : labels) CHECK(l == kNoise);
}

TEST_CASE("dbscan ignores duplicates and input order", "[unit]") {
  auto pts = blob(0, 0, 8, 8);
  auto shuffled = pts;
  std::reverse(shuffled.begin(), shuffled.end());
  shuffled.insert(shuffled.end(), pts.begin(), pts.begin() + 10);
  const auto a = dbscan_clusters(pts, {});
  const auto b = dbscan_clusters(shuffled, {});
  REQUIRE(a.size() == 1);
  REQUIRE(b.size() == 1);
  CHECK(a[0].pixels == b[0].pixels);
}
