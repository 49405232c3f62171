// CFAR: false-alarm rate on exponential-power noise (CA, where α is exact), agreement
// with a brute-force reference (every method, window and edge), bit-identical agreement
// of the row-wise fast path with the previous per-cell implementation (random and
// realistic images, 8-bit, 16-bit and float, every config), and basic behaviour.
// Both references live in cfar_reference.hpp (shared with cfar_bench.cpp).
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "core/perception/cfar.hpp"
#include "core/perception/cfar_reference.hpp"
#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::perception;

namespace {

std::vector<float> exponential_noise(int rows, int cols, double mean, uint64_t seed) {
  Rng rng(seed);
  std::vector<float> img(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  for (float& x : img) x = static_cast<float>(rng.exponential(mean));
  return img;
}

double false_alarm_rate(CfarMethod method, CfarWindow window, double pfa) {
  const int rows = 1000, cols = 1000;
  const auto img = exponential_noise(rows, cols, 30.0, derive_seed(42, 7, static_cast<uint64_t>(1.0 / pfa)));
  CfarConfig cfg;
  cfg.method = method;
  cfg.window = window;
  cfg.pfa = pfa;
  cfg.gate = 0.0;
  return static_cast<double>(cfar_detect(img.data(), rows, cols, cfg).size()) / (rows * cols);
}

}  // namespace

TEST_CASE("CA-CFAR false-alarm rate matches Pfa on exponential noise", "[unit]") {
  for (CfarWindow w : {CfarWindow::kCross, CfarWindow::kRange}) {
    for (double pfa : {1e-2, 1e-3}) {
      const double rate = false_alarm_rate(CfarMethod::kCa, w, pfa);
      INFO("window " << to_string(w) << " pfa " << pfa << " measured " << rate);
      CHECK(rate > 0.7 * pfa);
      CHECK(rate < 1.3 * pfa);
    }
  }
}

TEST_CASE("SOCA raises and GOCA lowers the false-alarm rate relative to CA", "[unit]") {
  // α is the CA formula applied to the chosen average (SPEC §3), so taking the smallest
  // average must raise the realised rate and the largest must lower it.
  for (double pfa : {1e-2, 1e-3}) {
    const double ca = false_alarm_rate(CfarMethod::kCa, CfarWindow::kCross, pfa);
    const double soca = false_alarm_rate(CfarMethod::kSoca, CfarWindow::kCross, pfa);
    const double goca = false_alarm_rate(CfarMethod::kGoca, CfarWindow::kCross, pfa);
    INFO("pfa " << pfa << " ca " << ca << " soca " << soca << " goca " << goca);
    CHECK(soca > ca);
    CHECK(goca < ca);
  }
}

TEST_CASE("Prefix-sum CFAR equals the brute-force reference including edges", "[unit]") {
  Rng rng(5);
  for (int trial = 0; trial < 24; ++trial) {
    const int rows = 1 + static_cast<int>(rng.below(40)), cols = 1 + static_cast<int>(rng.below(40));
    std::vector<float> img(static_cast<size_t>(rows * cols));
    for (float& x : img) x = static_cast<float>(rng.below(256));
    CfarConfig cfg;
    cfg.method = static_cast<CfarMethod>(trial % 3);
    cfg.window = (trial / 3) % 2 == 0 ? CfarWindow::kCross : CfarWindow::kRange;
    cfg.train_cells = 1 + static_cast<int>(rng.below(12));
    cfg.guard_cells = static_cast<int>(rng.below(5));
    cfg.pfa = 0.05;
    cfg.gate = static_cast<double>(rng.below(100));
    const auto fast = cfar_detect(img.data(), rows, cols, cfg);
    const auto slow = reference::naive_detect(img.data(), rows, cols, cfg);
    INFO("trial " << trial << " " << rows << "x" << cols);
    REQUIRE(fast.size() == slow.size());
    for (size_t i = 0; i < fast.size(); ++i) {
      CHECK(fast[i].row == slow[i].row);
      CHECK(fast[i].col == slow[i].col);
    }
  }
}

TEST_CASE("CFAR finds a bright cell on a flat background and nothing on a flat image", "[unit]") {
  SonarPing p;
  p.rows = 100;
  p.cols = 80;
  p.image.assign(static_cast<size_t>(p.rows) * p.cols, 40);
  CfarConfig cfg;  // defaults: SOCA cross, gate 65
  CHECK(cfar_detect(p, cfg).empty());
  p.image[static_cast<size_t>(50 * p.cols + 30)] = 200;
  const auto d = cfar_detect(p, cfg);
  REQUIRE(d.size() == 1);
  CHECK(d[0].row == 50);
  CHECK(d[0].col == 30);
  CHECK(d[0].intensity == 200.0f);
  // 16-bit little-endian images read the same values.
  SonarPing w = p;
  w.bytes_per_pixel = 2;
  w.image.assign(2 * p.image.size(), 0);
  for (size_t i = 0; i < p.image.size(); ++i) w.image[2 * i] = p.image[i];
  const auto d2 = cfar_detect(w, cfg);
  REQUIRE(d2.size() == 1);
  CHECK(d2[0].row == 50);
  CHECK(d2[0].col == 30);
}

TEST_CASE("CFAR gate suppresses cells at or below it", "[unit]") {
  std::vector<float> img(50 * 50, 1.0f);
  img[25 * 50 + 25] = 65.0f;
  CfarConfig cfg;
  CHECK(cfar_detect(img.data(), 50, 50, cfg).empty());
  img[25 * 50 + 25] = 66.0f;
  CHECK(cfar_detect(img.data(), 50, 50, cfg).size() == 1);
}

TEST_CASE("CFAR alpha follows the paper formula", "[unit]") {
  CHECK(cfar_alpha(20, 0.1) == Approx(20.0 * (std::pow(0.1, -1.0 / 20.0) - 1.0)));
  CHECK(cfar_alpha(1, 0.5) == Approx(1.0));
}

TEST_CASE("min_neighbours removes isolated detections and keeps blobs", "[unit]") {
  std::vector<float> img(60 * 60, 10.0f);
  img[10 * 60 + 10] = 200.0f;  // isolated
  for (int r = 30; r < 33; ++r)
    for (int c = 40; c < 43; ++c) img[static_cast<size_t>(r * 60 + c)] = 200.0f;
  CfarConfig cfg;
  CHECK(cfar_detect(img.data(), 60, 60, cfg).size() == 10);
  cfg.min_neighbours = 3;
  const auto d = cfar_detect(img.data(), 60, 60, cfg);
  REQUIRE(d.size() == 9);
  CHECK(d.front().row == 30);
  CHECK(d.front().col == 40);
}

// ---------------------------------------------------------------------------------------
// Fast path == previous implementation, bit for bit.
namespace {

enum class Depth { k8, k16, kFloat };

const char* depth_name(Depth d) { return d == Depth::k8 ? "u8" : d == Depth::k16 ? "u16" : "float"; }

std::string describe(const CfarConfig& c, int rows, int cols, Depth d) {
  std::ostringstream os;
  os.precision(17);
  os << depth_name(d) << " " << rows << "x" << cols << " " << to_string(c.method) << " " << to_string(c.window)
     << " t=" << c.train_cells << " g=" << c.guard_cells << " pfa=" << c.pfa << " gate=" << c.gate
     << " min_n=" << c.min_neighbours;
  return os.str();
}

// Integer-valued test images (0 .. maxv) in one of several styles: uniform, tiny value
// range (many exactly tied means), exponential speckle, sparse bright cells on zero,
// saturated and zero blocks on speckle, constant.
std::vector<double> random_values(Rng& rng, int rows, int cols, double maxv, int style) {
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  std::vector<double> v(n, 0.0);
  const double mean = rng.uniform(0.02, 0.6) * maxv;
  auto speckle = [&] { return std::min(maxv, std::floor(rng.exponential(mean))); };
  switch (style) {
    case 0:
      for (double& x : v) x = static_cast<double>(rng.below(static_cast<uint64_t>(maxv) + 1));
      break;
    case 1: {
      const uint64_t k = 1 + rng.below(4);
      for (double& x : v) x = static_cast<double>(rng.below(k + 1));
      break;
    }
    case 2:
      for (double& x : v) x = speckle();
      break;
    case 3:
      for (double& x : v) x = rng.below(8) == 0 ? static_cast<double>(rng.below(static_cast<uint64_t>(maxv) + 1)) : 0.0;
      break;
    case 4: {
      for (double& x : v) x = speckle();
      const int blocks = 1 + static_cast<int>(rng.below(4));
      for (int b = 0; b < blocks; ++b) {
        const int r0 = static_cast<int>(rng.below(static_cast<uint64_t>(rows)));
        const int c0 = static_cast<int>(rng.below(static_cast<uint64_t>(cols)));
        const int h = 1 + static_cast<int>(rng.below(static_cast<uint64_t>(rows)));
        const int w = 1 + static_cast<int>(rng.below(static_cast<uint64_t>(cols)));
        const double value = rng.below(2) == 0 ? maxv : 0.0;
        for (int r = r0; r < std::min(rows, r0 + h); ++r)
          for (int c = c0; c < std::min(cols, c0 + w); ++c) v[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] = value;
      }
      break;
    }
    default: {
      const double value = rng.below(3) == 0 ? maxv : rng.below(2) == 0 ? 0.0 : std::floor(rng.uniform(0.0, maxv));
      for (double& x : v) x = value;
      break;
    }
  }
  return v;
}

SonarPing ping_from(const std::vector<double>& v, int rows, int cols, Depth d) {
  SonarPing p;
  p.rows = static_cast<uint16_t>(rows);
  p.cols = static_cast<uint16_t>(cols);
  p.bytes_per_pixel = static_cast<uint8_t>(d == Depth::k16 ? 2 : 1);
  p.image.resize(v.size() * static_cast<size_t>(p.bytes_per_pixel));
  for (size_t i = 0; i < v.size(); ++i) {
    const auto x = static_cast<uint16_t>(v[i]);
    if (d == Depth::k16) {
      p.image[2 * i] = static_cast<uint8_t>(x & 0xFF);
      p.image[2 * i + 1] = static_cast<uint8_t>(x >> 8);
    } else {
      p.image[i] = static_cast<uint8_t>(x);
    }
  }
  return p;
}

// Runs the fast path and the reference on the same image; returns "" when they agree.
std::string compare_once(const std::vector<double>& v, int rows, int cols, Depth d, const CfarConfig& cfg,
                         bool real_valued = false, size_t* n_detections = nullptr) {
  std::vector<Detection> fast, ref;
  if (d == Depth::kFloat) {
    std::vector<float> img(v.size());
    for (size_t i = 0; i < v.size(); ++i) img[i] = static_cast<float>(v[i]);
    fast = cfar_detect(img.data(), rows, cols, cfg);
    ref = reference::cfar(img.data(), rows, cols, cfg);
  } else {
    const SonarPing p = ping_from(v, rows, cols, d);
    fast = cfar_detect(p, cfg);
    ref = reference::cfar(p, cfg);
  }
  if (n_detections) *n_detections = ref.size();
  if (reference::same_detections(fast, ref)) return "";
  std::ostringstream os;
  os << describe(cfg, rows, cols, d) << (real_valued ? " real-valued" : "") << ": fast " << fast.size()
     << " detections, reference " << ref.size();
  for (size_t i = 0; i < std::min(fast.size(), ref.size()); ++i) {
    if (fast[i].row != ref[i].row || fast[i].col != ref[i].col || fast[i].intensity != ref[i].intensity) {
      os << "; first difference at #" << i << ": fast (" << fast[i].row << "," << fast[i].col << ") reference ("
         << ref[i].row << "," << ref[i].col << ")";
      break;
    }
  }
  return os.str();
}

// Configs that reach every branch: train/guard wider than the image, gates below 0, at
// and above the top of the pixel range, pfa giving α = 0, < 0, +inf and NaN.
CfarConfig random_config(Rng& rng, Depth d) {
  CfarConfig cfg;
  cfg.method = static_cast<CfarMethod>(rng.below(3));
  cfg.window = rng.below(2) == 0 ? CfarWindow::kCross : CfarWindow::kRange;
  const uint64_t tk = rng.below(20);
  cfg.train_cells = tk < 13 ? 1 + static_cast<int>(rng.below(12)) : tk < 16 ? 20 : tk < 19 ? 1 + static_cast<int>(rng.below(200)) : -static_cast<int>(rng.below(2));
  const uint64_t gk = rng.below(20);
  cfg.guard_cells = gk < 14 ? static_cast<int>(rng.below(6)) : gk < 16 ? 5 : gk < 19 ? static_cast<int>(rng.below(100)) : -1;
  const double maxv = d == Depth::k16 ? 65535.0 : 255.0;
  static const double gates[] = {-3.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 64.9, 65.0, 254.0, 254.5, 255.0, 256.0, 65534.0, 65535.0, 1e7};
  const uint64_t gk2 = rng.below(10);
  cfg.gate = gk2 < 5 ? gates[rng.below(std::size(gates))] : gk2 < 8 ? std::floor(rng.uniform(-2.0, maxv + 2.0)) : rng.uniform(-2.0, 0.5 * maxv);
  static const double pfas[] = {0.1, 0.1, 0.1, 0.05, 0.01, 1e-3, 1e-6, 0.3, 0.5, 0.9, 0.999999, 1.0, 1.5, 0.0, -0.2, 1e-300, 5e-324};
  cfg.pfa = rng.below(4) == 0 ? rng.uniform(1e-4, 0.5) : pfas[rng.below(std::size(pfas))];
  cfg.min_neighbours = rng.below(5) == 0 ? static_cast<int>(rng.below(9)) : 0;
  return cfg;
}

void random_size(Rng& rng, int& rows, int& cols) {
  const uint64_t k = rng.below(12);
  const int top = k < 5 ? 12 : k < 9 ? 70 : 160;
  rows = 1 + static_cast<int>(rng.below(static_cast<uint64_t>(top)));
  cols = 1 + static_cast<int>(rng.below(static_cast<uint64_t>(top)));
  if (k >= 10) {  // wide and short: interiors with long windows (N > 128, 32-bit lanes)
    rows = 1 + static_cast<int>(rng.below(24));
    cols = 200 + static_cast<int>(rng.below(300));
  }
}

// One random case from one seed; "" when fast and reference agree.
std::string random_case(uint64_t seed, Depth d) {
  Rng rng(seed);
  int rows, cols;
  random_size(rng, rows, cols);
  CfarConfig cfg = random_config(rng, d);
  if (cols >= 200 && rng.below(2) == 0) cfg.train_cells = 100 + static_cast<int>(rng.below(100));
  const double maxv = d == Depth::k16 ? (rng.below(3) == 0 ? 300.0 : 65535.0) : 255.0;
  const int style = static_cast<int>(rng.below(6));
  std::vector<double> v = random_values(rng, rows, cols, maxv, style);
  bool real_valued = false;
  if (d == Depth::kFloat && rng.below(2) == 0) {  // non-integer floats too
    real_valued = true;
    for (double& x : v) x = x * rng.uniform(0.5, 1.5) + (rng.below(4) == 0 ? 0.0 : rng.uniform(0.0, 1.0));
  }
  return compare_once(v, rows, cols, d, cfg, real_valued);
}

// Exponential speckle like a real ping: a weak near field, a bright curved wall, a
// seafloor band where about half of the cells are above the default gate.
std::vector<double> sonar_like(int rows, int cols, double maxv, double scale, uint64_t seed) {
  Rng rng(seed);
  std::vector<double> v(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double u = -1.0 + 2.0 * (c + 0.5) / cols;
      const double wall_row = 160.0 / std::max(0.2, std::cos(1.1 * u));
      double mean = r > 380 ? 95.0 : 12.0;
      if (std::abs(r - wall_row) < 2.0) mean = 180.0;
      v[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] =
          std::min(maxv, std::floor(rng.exponential(mean * scale)));
    }
  }
  return v;
}

}  // namespace

TEST_CASE("Fast CFAR equals the previous implementation on random images and configs", "[unit]") {
  // Seeded loops: many small images (most smaller than the window), every depth.
  for (Depth d : {Depth::k8, Depth::k16, Depth::kFloat}) {
    const int trials = d == Depth::k8 ? 4000 : 1500;
    int failures = 0;
    for (int i = 0; i < trials && failures < 5; ++i) {
      const std::string diff = random_case(derive_seed(20261201, static_cast<uint64_t>(d), static_cast<uint64_t>(i)), d);
      if (!diff.empty()) {
        ++failures;
        FAIL_CHECK("seed index " << i << ": " << diff);
      }
    }
    CHECK(failures == 0);
  }
}

TEST_CASE("Fast CFAR equals the previous implementation (property)", "[unit][property][rapidcheck]") {
  rc::prop("cfar_detect == reference_cfar", [] {
    const Depth d = *rc::gen::element(Depth::k8, Depth::k8, Depth::k16, Depth::kFloat);
    const uint64_t seed = *rc::gen::arbitrary<uint64_t>();
    const int rows = *rc::gen::inRange(1, 90), cols = *rc::gen::inRange(1, 90);
    CfarConfig cfg;
    cfg.method = *rc::gen::element(CfarMethod::kSoca, CfarMethod::kCa, CfarMethod::kGoca);
    cfg.window = *rc::gen::element(CfarWindow::kCross, CfarWindow::kRange);
    cfg.train_cells = *rc::gen::inRange(1, 30);
    cfg.guard_cells = *rc::gen::inRange(0, 9);
    cfg.gate = *rc::gen::element(-1.0, 0.0, 0.5, 3.0, 65.0, 200.0, 254.0, 255.0, 1000.0);
    cfg.pfa = *rc::gen::element(0.1, 0.05, 0.01, 1e-3, 0.5, 1.0, 2.0, 0.0);
    cfg.min_neighbours = *rc::gen::element(0, 0, 0, 1, 3, 8);
    const int style = *rc::gen::inRange(0, 6);
    Rng rng(seed);
    const double maxv = d == Depth::k16 ? 65535.0 : 255.0;
    const std::vector<double> v = random_values(rng, rows, cols, maxv, style);
    const std::string diff = compare_once(v, rows, cols, d, cfg);
    RC_LOG() << diff;
    RC_ASSERT(diff.empty());
  });
}

TEST_CASE("Fast CFAR equals the previous implementation on realistic speckle", "[unit]") {
  const int rows = 600, cols = 512;
  struct Image {
    Depth depth;
    std::vector<double> v;
  };
  const Image images[] = {
      {Depth::k8, sonar_like(rows, cols, 255.0, 1.0, 11)},
      {Depth::k16, sonar_like(rows, cols, 65535.0, 200.0, 12)},
      {Depth::kFloat, sonar_like(rows, cols, 255.0, 1.0, 13)},
  };
  for (const Image& img : images) {
    for (CfarMethod m : {CfarMethod::kSoca, CfarMethod::kCa, CfarMethod::kGoca}) {
      for (CfarWindow w : {CfarWindow::kCross, CfarWindow::kRange}) {
        for (double gate : {-1.0, 0.0, 65.0}) {
          CfarConfig cfg;
          cfg.method = m;
          cfg.window = w;
          // Long windows too (N > 128 cells: the 8-bit interior in 32-bit lanes).
          if (img.depth == Depth::k8 && gate == 65.0) cfg.train_cells = 140;
          cfg.gate = img.depth == Depth::k16 && gate > 0 ? gate * 200.0 : gate;
          for (int min_n : {0, 3}) {
            cfg.min_neighbours = min_n;
            size_t n = 0;
            const std::string diff = compare_once(img.v, rows, cols, img.depth, cfg, false, &n);
            INFO(describe(cfg, rows, cols, img.depth) << " detections " << n);
            CHECK(diff.empty());
            CHECK(n > 100);  // a meaningful comparison
          }
        }
      }
    }
  }
}

// The side-by-side benchmark (cfar_bench.cpp) times cfar_detect against the naive
// direct-summation loop on this image: all three must agree on it, bit for bit.
TEST_CASE("CFAR on the benchmark image equals both references", "[unit]") {
  struct Case {
    int rows, cols, targets;
  };
  for (const Case& k : {Case{600, 512, 300}, Case{150, 128, 20}}) {
    const SonarPing img = reference::speckle_with_targets(k.rows, k.cols, 20.0, k.targets, 37);
    for (CfarWindow w : {CfarWindow::kRange, CfarWindow::kCross}) {
      for (double gate : {-1.0, 0.0, 65.0}) {
        const CfarConfig cfg = reference::speckle_with_targets_config(w, gate);
        const auto fast = cfar_detect(img, cfg);
        const auto ref = reference::cfar(img, cfg);
        const auto naive = reference::naive_cfar(img, cfg);
        INFO(describe(cfg, k.rows, k.cols, Depth::k8) << " fast " << fast.size() << " reference " << ref.size()
                                                      << " naive " << naive.size());
        CHECK(reference::same_detections(fast, ref));
        CHECK(reference::same_detections(fast, naive));
        // Gate off: the design Pfa gives detections in the order of 10 % of the cells.
        if (gate < 0) CHECK(fast.size() * 20 > static_cast<size_t>(k.rows * k.cols));
        if (gate >= 65) CHECK(!fast.empty());
      }
    }
  }
}

TEST_CASE("The naive reference equals the fast path on random integer images", "[unit]") {
  for (Depth d : {Depth::k8, Depth::k16}) {
    int failures = 0;
    for (int i = 0; i < 600 && failures < 5; ++i) {
      Rng rng(derive_seed(20261205, static_cast<uint64_t>(d), static_cast<uint64_t>(i)));
      int rows, cols;
      random_size(rng, rows, cols);
      const CfarConfig cfg = random_config(rng, d);
      const double maxv = d == Depth::k16 ? 65535.0 : 255.0;
      const std::vector<double> v = random_values(rng, rows, cols, maxv, static_cast<int>(rng.below(6)));
      const SonarPing p = ping_from(v, rows, cols, d);
      const auto fast = cfar_detect(p, cfg);
      const auto naive = reference::naive_cfar(p, cfg);
      if (!reference::same_detections(fast, naive)) {
        ++failures;
        FAIL_CHECK("seed index " << i << ": " << describe(cfg, rows, cols, d) << ": fast " << fast.size()
                                 << " detections, naive " << naive.size());
      }
    }
    CHECK(failures == 0);
  }
}
