#pragma once
// CFAR feature extraction on a polar sonar image (SPEC §3, paper §V-A).
//
// For each cell under test (CUT), training cells lie beyond `guard_cells` on each side:
//  - window kCross (paper, default): four averages, leading/lagging along range (rows)
//    and left/right along bearing (columns), each of `train_cells` cells on a line
//    through the CUT;
//  - window kRange (sonar-SLAM): two averages, leading/lagging along range.
// SOCA keeps the smallest average, GOCA the largest, CA the mean of all training cells.
// α = N (Pfa^(−1/N) − 1), N = number of training cells in the chosen average (all of them
// for CA); β = α μ. A cell is a detection when intensity > β and intensity > gate.
// Near an edge only the sides (and the cells) that exist are used; nothing outside the
// image is read. A CUT with no training cell at all is never a detection.
// Computed with prefix sums: O(1) per cell. Scale-invariant apart from the gate.
#include <vector>

#include "core/events.hpp"

namespace orthosonar::perception {

enum class CfarMethod { kSoca, kCa, kGoca };
enum class CfarWindow { kCross, kRange };

struct CfarConfig {
  CfarMethod method = CfarMethod::kSoca;
  CfarWindow window = CfarWindow::kCross;
  int train_cells = 20;  // per side
  int guard_cells = 5;   // per side
  double pfa = 0.1;      // design false-alarm probability
  double gate = 65.0;    // absolute intensity floor, in image units
  // Isolated-speckle filter after CFAR (sonar-SLAM filters its CFAR points the same way
  // with a radius outlier filter): keep a detection only when at least this many of its
  // 8 neighbours are detections too. 0 = off (SPEC §3 as written).
  int min_neighbours = 0;
};

// One detected pixel. Lists are sorted row-major (row, then col).
struct Detection {
  int row = 0;
  int col = 0;
  float intensity = 0;  // raw image value
};

std::vector<Detection> cfar_detect(const SonarPing& ping, const CfarConfig& config);

// The same on a plain row-major intensity array (rows x cols), for tests and tools.
std::vector<Detection> cfar_detect(const float* image, int rows, int cols,
                                   const CfarConfig& config);

// α for N training cells (paper: α = N (Pfa^(−1/N) − 1)).
double cfar_alpha(int n_train, double pfa);

const char* to_string(CfarMethod m);
const char* to_string(CfarWindow w);

}  // namespace orthosonar::perception
