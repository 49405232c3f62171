// The integer CFAR path (8- and 16-bit images): column prefix sums in a ring along range,
// row prefix sums along bearing, whole rows at a time (dense rows) or the cells above the
// gate only (sparse rows); the hit columns collected per row.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception::detail {
namespace {

template <class Pixel, class Acc, class Sum>
class IntegerCfar {
 public:
  IntegerCfar(const Pixel* img, int rows, int cols, const CfarConfig& cfg, int64_t gate)
      : img_(img), rows_(rows), cols_(cols), C_(static_cast<size_t>(cols)), cfg_(cfg), gate_(gate) {
    // Extents beyond the image change nothing: clamp g and t to its size (along bearing,
    // to its width).
    const int64_t dim = std::max(rows, cols);
    g_ = std::min<int64_t>(cfg.guard_cells, dim);
    t_ = std::min<int64_t>(cfg.train_cells, dim);
    gb_ = std::min<int64_t>(cfg.guard_cells, cols);
    tb_ = std::min<int64_t>(cfg.train_cells, cols);
    cross_ = cfg.window == CfarWindow::kCross;
    const int64_t n_sides = cross_ ? 4 : 2;
    max_n_ = static_cast<int>(cfg.method == CfarMethod::kCa ? n_sides * t_ : t_);
    if constexpr (std::is_same_v<Pixel, uint8_t>) {
      if (max_n_ <= 4096) {
        table_ = &threshold_table(cfg.pfa, gate);
        if (!table_->prepare(max_n_)) table_ = nullptr;
      }
    }
    if (!table_) alpha_ = alpha_table(max_n_, cfg.pfa);
    // Vector selection: every cross product S_i N_j below 2^24 (S <= 255 t, N <= t).
    vector_ok_ = 255 * t_ * t_ < (int64_t{1} << 24);
    // Ring of column prefix sums: P between a cell's window ends (2(g + t) + 1 rows apart).
    K_ = static_cast<size_t>(std::min<int64_t>(2 * (g_ + t_) + 2, static_cast<int64_t>(rows) + 1));
    ring_.assign(K_ * C_, Acc{0});
    // Row prefix sums, padded: qpad_[pad_ + p] = Q[clamp(p, 0, cols)], so that a bearing
    // side's sum is one difference in every column, empty or truncated sides included.
    pad_ = static_cast<size_t>(gb_ + tb_ + 1);
    qpad_.assign(C_ + 2 * pad_ + 4, Acc{0});
    if (cross_) {
      counts_left_.resize(C_ + 4);
      counts_right_.resize(C_ + 4);
      for (int64_t c = 0; c < cols; ++c) {
        counts_left_[static_cast<size_t>(c)] = static_cast<int32_t>(std::clamp<int64_t>(c - gb_, 0, tb_));
        counts_right_[static_cast<size_t>(c)] = static_cast<int32_t>(std::clamp<int64_t>(cols - (c + gb_ + 1), 0, tb_));
      }
    }
    red_.assign(C_ + 4, Sum{0});
    nsel_.assign(C_ + 4, 0);
    cand_.assign(C_ + 4, 0);
    row_hits_.assign(static_cast<size_t>(rows), 0);
  }

  std::vector<Detection> run() {
    std::vector<Detection> out;
    if (gate_ >= static_cast<int64_t>(std::numeric_limits<Pixel>::max())) return out;
    size_t computed = 0;  // P_0 .. P_computed are in the ring
    for (int r = 0; r < rows_; ++r) {
      const int64_t R = r;
      const auto target = static_cast<size_t>(std::min<int64_t>(rows_, R + g_ + 1 + t_));
      while (computed < target) {  // P_{i+1} = P_i + row i
        add_row(prefix_row(computed), img_ + computed * C_, prefix_row(computed + 1), C_);
        ++computed;
      }
      line_ = img_ + static_cast<size_t>(r) * C_;
      const size_t n_above = gate_ < 0 ? C_ : count_above(line_, C_, gate_);
      if (n_above == 0) continue;
      // The sides in the fixed order; range counts depend on the row only.
      k_ = 0;
      const int nl = static_cast<int>(std::clamp<int64_t>(R - g_, 0, t_));
      const int ng = static_cast<int>(std::clamp<int64_t>(rows_ - (R + g_ + 1), 0, t_));
      if (nl > 0)
        sides_[k_++] = {prefix_row(static_cast<size_t>(R - g_)), prefix_row(static_cast<size_t>(R - g_ - nl)), 0, 0, nullptr, nl};
      if (ng > 0)
        sides_[k_++] = {prefix_row(static_cast<size_t>(R + g_ + 1 + ng)), prefix_row(static_cast<size_t>(R + g_ + 1)), 0, 0, nullptr, ng};
      first_bearing_ = k_;
      if (cross_) {
        const auto pad = static_cast<ptrdiff_t>(pad_), g = static_cast<ptrdiff_t>(gb_), t = static_cast<ptrdiff_t>(tb_);
        sides_[k_++] = {qpad_.data(), qpad_.data(), pad - g, pad - g - t, counts_left_.data(), 0};
        sides_[k_++] = {qpad_.data(), qpad_.data(), pad + g + 1 + t, pad + g + 1, counts_right_.data(), 0};
      }
      if (k_ == 0) continue;  // no training cell anywhere in this row
      size_t n_hits;
      if (n_above * 16 >= C_) {
        if (cross_) bearing_prefix();
        n_hits = dense_row(nl, ng);
      } else {
        // Few cells above the gate: test only those (bearing sums directly when cheaper).
        const size_t n_cand = columns_above(line_, C_, gate_, cand_.data());
        const bool prefix = cross_ && static_cast<int64_t>(n_cand) * 2 * tb_ > static_cast<int64_t>(C_);
        if (prefix) bearing_prefix();
        n_hits = 0;
        for (size_t i = 0; i < n_cand; ++i) {
          const int c = cand_[i];
          int64_t s;
          int n;
          if (prefix) {
            select_scalar<Sum>(cfg_.method, sides_, k_, c, s, n);
          } else {
            select_direct(c, s, n);
          }
          cand_[n_hits] = c;
          n_hits += decide(line_[c], s, n) ? 1u : 0u;
        }
      }
      row_hits_[static_cast<size_t>(r)] = n_hits;
      append_hits(n_hits);
    }
    // One allocation of the exact size: growing a large vector hit by hit costs more than
    // the whole test (each reallocation touches fresh pages).
    size_t total = 0;
    for (size_t n : row_hits_) total += n;
    out.reserve(total);
    size_t block = 0, pos = 0;
    for (int r = 0; r < rows_; ++r) {
      const Pixel* line = img_ + static_cast<size_t>(r) * C_;
      for (size_t i = 0; i < row_hits_[static_cast<size_t>(r)]; ++i) {
        if (pos == kBlock) {
          ++block;
          pos = 0;
        }
        const int c = blocks_[block][pos++];
        out.push_back({r, c, static_cast<float>(line[c])});
      }
    }
    return out;
  }

 private:
  Acc* prefix_row(size_t i) { return ring_.data() + (i % K_) * C_; }

  void bearing_prefix() {
    Acc* q = qpad_.data() + pad_;
    row_prefix(line_, q, C_);
    std::fill(qpad_.data(), q, Acc{0});
    std::fill(q + C_ + 1, q + C_ + 1 + pad_, q[C_]);
  }

  // select_scalar at column c with the bearing sums added up directly (a few cells).
  void select_direct(int c, int64_t& s, int& n) const {
    int64_t sums[4];
    int counts[4];
    int m = 0;
    for (int i = 0; i < first_bearing_; ++i) {
      sums[m] = side_sum<Sum>(sides_[i], c);
      counts[m++] = sides_[i].count;
    }
    if (cross_) {
      const int64_t C = c;
      const int64_t ranges[2][2] = {{std::max<int64_t>(0, C - gb_ - tb_), C - gb_},
                                    {C + gb_ + 1, std::min<int64_t>(cols_, C + gb_ + 1 + tb_)}};
      for (const auto& rg : ranges) {
        if (rg[1] <= rg[0]) continue;
        int64_t sum = 0;
        for (int64_t i = rg[0]; i < rg[1]; ++i) sum += line_[i];
        sums[m] = sum;
        counts[m++] = static_cast<int>(rg[1] - rg[0]);
      }
    }
    if (m == 0) {
      s = 0;
      n = 0;
      return;
    }
    choose(cfg_.method, sums, counts, m, s, n);
  }

  bool decide(Pixel x, int64_t s, int n) {
    if (table_) return s <= static_cast<int64_t>(table_->row(n)[x]);
    if (n == 0 || !(static_cast<int64_t>(x) > gate_)) return false;
    if (!(s > 0)) return x > 0;  // β = 0
    return ratio_test(static_cast<double>(static_cast<int64_t>(x) * n), alpha_[static_cast<size_t>(n)],
                      static_cast<double>(s));
  }

  // Every column of the current row; hits go to cand_ in column order.
  size_t dense_row(int nl, int ng) {
    // Interior columns [c0, c1): both bearing sides full (cross), or all columns (range).
    int64_t c0 = 0, c1 = cols_;
    if (cross_) {
      c0 = std::min<int64_t>(gb_ + tb_, cols_);
      c1 = std::max<int64_t>(c0, cols_ - gb_ - tb_);
    }
    // There every side has a constant count: nl, ng, t, t. With CA, or with equal counts
    // (SOCA / GOCA compare means as sums; equal sums are the same (S, N)), one (S, N).
    const int t = static_cast<int>(tb_);
    int counts[4], k = 0, n_total = 0;
    if (nl > 0) counts[k++] = nl;
    if (ng > 0) counts[k++] = ng;
    if (cross_) {
      counts[k++] = t;
      counts[k++] = t;
    }
    bool uniform = c1 > c0;
    for (int i = 0; i < k; ++i) {
      n_total += counts[i];
      uniform = uniform && (cfg_.method == CfarMethod::kCa || counts[i] == counts[0]);
    }
    const int n_uniform = cfg_.method == CfarMethod::kCa ? n_total : counts[0];
    n_uniform_ = n_uniform;
    if (!uniform) c0 = c1 = cols_;

    Sum* red = red_.data();
    int32_t* nsel = nsel_.data();
    const bool fused = uniform && table_ && table_->row(n_uniform) && table_->linear(n_uniform).ok &&
                       std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t> && kHaveSse2;
    // Columns outside [c0, c1): any counts.
    const bool vec = cfg_.method == CfarMethod::kCa || (vector_ok_ && first_bearing_ > 0);
    select_sides(cfg_.method, sides_, k_, vec, 0, c0, red, nsel);
    select_sides(cfg_.method, sides_, k_, vec, c1, cols_, red, nsel);
    if (!fused) {
      switch (cfg_.method) {
        case CfarMethod::kSoca: reduce_equal_sides<Reduce::kMin>(sides_, k_, c0, c1, red); break;
        case CfarMethod::kGoca: reduce_equal_sides<Reduce::kMax>(sides_, k_, c0, c1, red); break;
        case CfarMethod::kCa: reduce_equal_sides<Reduce::kSum>(sides_, k_, c0, c1, red); break;
      }
    }
    size_t n_hits = 0;
    auto decide_range = [&](int64_t lo, int64_t hi) {
      for (int64_t c = lo; c < hi; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += decide(line_[c], red[c], nsel[c]) ? 1u : 0u;
      }
    };
    decide_range(0, c0);
    if (table_) {
      const int32_t* smax = table_->row(n_uniform);
      if (fused) {
        const int64_t done = fused_uniform(c0, c1, smax, n_hits);
        // The rest (< 4 columns) with the table, from the sums.
        switch (cfg_.method) {
          case CfarMethod::kSoca: reduce_equal_sides<Reduce::kMin>(sides_, k_, done, c1, red); break;
          case CfarMethod::kGoca: reduce_equal_sides<Reduce::kMax>(sides_, k_, done, c1, red); break;
          case CfarMethod::kCa: reduce_equal_sides<Reduce::kSum>(sides_, k_, done, c1, red); break;
        }
        c0 = done;
      }
      for (int64_t c = c0; c < c1; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += red[c] <= smax[line_[c]] ? 1u : 0u;
      }
    } else {
      for (int64_t c = c0; c < c1; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += decide(line_[c], red[c], n_uniform) ? 1u : 0u;
      }
    }
    decide_range(c1, cols_);
    return n_hits;
  }

  // The interior of an 8-bit row with equal counts, 4 or 8 columns at a time (uniform_hits).
  int64_t fused_uniform(int64_t c0, int64_t c1, const int32_t* smax, size_t& n_hits) {
    if constexpr (std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t>) {
      const Linear& lin = table_->linear(n_uniform_);
      const bool narrow = lin.fits16 && 255 * n_uniform_ <= 32767;
      const Reduce r = cfg_.method == CfarMethod::kSoca   ? Reduce::kMin
                       : cfg_.method == CfarMethod::kGoca ? Reduce::kMax
                                                          : Reduce::kSum;
      return uniform_hits(r, k_, narrow, sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
    }
    (void)c1;
    (void)smax;
    (void)n_hits;
    return c0;
  }

  // Hit columns of every row, in blocks of kBlock (no reallocation, no copies).
  void append_hits(size_t n) {
    const int* src = cand_.data();
    while (n > 0) {
      if (blocks_.empty() || blocks_.back().size() == kBlock) {
        blocks_.emplace_back();
        blocks_.back().reserve(kBlock);
      }
      std::vector<int>& b = blocks_.back();
      const size_t take = std::min(n, kBlock - b.size());
      b.insert(b.end(), src, src + take);
      src += take;
      n -= take;
    }
  }

  const Pixel* img_;
  int rows_, cols_;
  size_t C_;
  const CfarConfig& cfg_;
  int64_t gate_;
  int64_t g_ = 0, t_ = 0, gb_ = 0, tb_ = 0;
  bool cross_ = true;
  int max_n_ = 0;
  ThresholdTable* table_ = nullptr;  // 8-bit images with α finite and >= 0
  std::vector<double> alpha_;        // otherwise
  bool vector_ok_ = false;
  size_t K_ = 1, pad_ = 1;
  std::vector<Acc> ring_, qpad_;
  std::vector<int32_t> counts_left_, counts_right_;
  std::vector<Sum> red_;
  std::vector<int32_t> nsel_;
  std::vector<int> cand_;
  static constexpr size_t kBlock = 8192;
  std::vector<std::vector<int>> blocks_;
  std::vector<size_t> row_hits_;
  // Current row.
  const Pixel* line_ = nullptr;
  Side<Acc> sides_[4];
  int k_ = 0, first_bearing_ = 0, n_uniform_ = 0;
};

template <class Pixel>
std::vector<Detection> detect_pixels(const Pixel* img, int rows, int cols, const CfarConfig& cfg) {
  if (rows <= 0 || cols <= 0 || cfg.train_cells <= 0 || cfg.guard_cells < 0) return {};
  const int64_t gate = integer_gate(cfg.gate);
  std::vector<Detection> out;
  // 32-bit sums when every sum of up to 4 sides fits in int32 (any realistic 8-bit image).
  const int64_t t = std::min<int64_t>(cfg.train_cells, std::max(rows, cols));
  bool done = false;
  if constexpr (std::is_same_v<Pixel, uint8_t>) {
    if (4 * 255 * t < (int64_t{1} << 31)) {
      out = IntegerCfar<Pixel, uint32_t, int32_t>(img, rows, cols, cfg, gate).run();
      done = true;
    }
  }
  if (!done) out = IntegerCfar<Pixel, uint64_t, int64_t>(img, rows, cols, cfg, gate).run();
  return filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

}  // namespace

std::vector<Detection> detect_integer(const uint8_t* img, int rows, int cols, const CfarConfig& cfg) {
  return detect_pixels(img, rows, cols, cfg);
}

std::vector<Detection> detect_integer(const uint16_t* img, int rows, int cols, const CfarConfig& cfg) {
  return detect_pixels(img, rows, cols, cfg);
}

}  // namespace orthosonar::perception::detail
