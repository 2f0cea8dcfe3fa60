// The small dense least-squares systems of the local fits
// (metric/hessian.cpp, geometry/normals.cpp): Householder QR with column
// pivoting, the normal equations where a system is well conditioned by far,
// and solve_full_rank_least_squares choosing between them.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

#include "core/vec3.h"

namespace anisurf {

// Householder QR with column pivoting (the remaining column of largest norm
// first) of the small dense systems of the fits, storage reused from one
// factorisation to the next.
class PivotedQR {
 public:
  static constexpr int kMaxColumns = 9;

  // Factorises the m x n matrix A stored by columns (m >= n, n at most
  // kMaxColumns). False when its numerical rank is below n: a pivot |R_kk|
  // at most `threshold` times the largest one.
  bool factor_full_rank(const double* A, int m, int n, double threshold) {
    m_ = m;
    n_ = n;
    qr_.assign(A, A + static_cast<std::ptrdiff_t>(m_) * n_);
    for (int j = 0; j < n_; ++j) exact_norm2_[j] = norm2_[j] = tail_norm2(j, 0);
    double largest = 0;
    for (int k = 0; k < n_; ++k) {
      swap_columns(k, column_of_largest_norm(k));
      diagonal_[k] = reflect_column(k);
      largest = max_of(largest, std::fabs(diagonal_[k]));
      for (int j = k + 1; j < n_; ++j) {
        apply_reflector(k, column(j));
        downdate_norm(j, k);
      }
    }
    for (int k = 0; k < n_; ++k)
      if (!(std::fabs(diagonal_[k]) > threshold * largest)) return false;
    return true;
  }

  // The least-squares solution x (n values) of A x = b (m values), A of full rank.
  void solve(const double* b, double* x) {
    rhs_.assign(b, b + m_);
    for (int k = 0; k < n_; ++k) apply_reflector(k, rhs_.data());
    std::array<double, kMaxColumns> y{};
    for (int k = n_ - 1; k >= 0; --k) {
      double sum = rhs_[k];
      for (int j = k + 1; j < n_; ++j) sum -= column(j)[k] * y[j];
      y[k] = sum / diagonal_[k];
    }
    for (int k = 0; k < n_; ++k) x[permutation_[k]] = y[k];
  }

 private:
  double* column(int j) { return qr_.data() + static_cast<std::ptrdiff_t>(j) * m_; }

  // The squared norm of rows k.. of column j.
  double tail_norm2(int j, int k) {
    const double* c = column(j);
    double sum = 0;
    for (int i = k; i < m_; ++i) sum += c[i] * c[i];
    return sum;
  }

  // Among columns k.., the one whose rows k.. have the largest norm.
  int column_of_largest_norm(int k) const {
    int best = k;
    for (int j = k + 1; j < n_; ++j)
      if (norm2_[j] > norm2_[best]) best = j;
    return best;
  }

  // After step k: the norm of rows k+1.. of column j is that of rows k..
  // less row k's entry, computed again when the difference has lost half of
  // its digits to the cancellation.
  void downdate_norm(int j, int k) {
    const double r = column(j)[k];
    norm2_[j] -= r * r;
    if (norm2_[j] <= 1e-8 * exact_norm2_[j]) exact_norm2_[j] = norm2_[j] = tail_norm2(j, k + 1);
  }

  void swap_columns(int k, int j) {
    if (k == 0) std::iota(permutation_.begin(), permutation_.begin() + n_, 0);
    if (j == k) return;
    std::swap_ranges(column(k), column(k) + m_, column(j));
    std::swap(permutation_[k], permutation_[j]);
    std::swap(norm2_[k], norm2_[j]);
    std::swap(exact_norm2_[k], exact_norm2_[j]);
  }

  // Turns rows k.. of column k into (beta, 0, ...) by the reflector
  // I - tau v v^T, v = (1, v_k+1, ...) stored below the diagonal; returns beta.
  double reflect_column(int k) {
    double* c = column(k);
    double tail2 = 0;
    for (int i = k + 1; i < m_; ++i) tail2 += c[i] * c[i];
    const double x0 = c[k];
    if (tail2 == 0) {
      tau_[k] = 0;
      return x0;
    }
    const double beta = -std::copysign(std::sqrt(x0 * x0 + tail2), x0);
    tau_[k] = (beta - x0) / beta;
    const double scale = 1.0 / (x0 - beta);
    for (int i = k + 1; i < m_; ++i) c[i] *= scale;
    c[k] = beta;
    return beta;
  }

  // Applies reflector k to rows k.. of the vector y.
  void apply_reflector(int k, double* y) {
    if (tau_[k] == 0) return;
    const double* v = column(k);
    double w = y[k];
    for (int i = k + 1; i < m_; ++i) w += v[i] * y[i];
    w *= tau_[k];
    y[k] -= w;
    for (int i = k + 1; i < m_; ++i) y[i] -= w * v[i];
  }

  int m_ = 0, n_ = 0;
  std::vector<double> qr_, rhs_;
  std::array<double, kMaxColumns> tau_{}, diagonal_{};
  // Per column: the squared norm of its rows below the current step, and
  // that norm when it was last summed from the entries.
  std::array<double, kMaxColumns> norm2_{}, exact_norm2_{};
  std::array<int, kMaxColumns> permutation_{};
};

namespace detail {

// solve_well_conditioned for N columns (a compile-time count: the products
// unroll).
template <int N>
bool solve_well_conditioned_n(const double* A, int m, const double* b, double* x, double min_pivot_ratio) {
  // The lower triangle of A^T A by rows of A (each row's outer product), and A^T b.
  double G[N][N] = {}, r[N] = {};
  for (int k = 0; k < m; ++k) {
    double row[N];
    for (int i = 0; i < N; ++i) row[i] = A[static_cast<std::ptrdiff_t>(i) * m + k];
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j <= i; ++j) G[i][j] += row[i] * row[j];
      r[i] += row[i] * b[k];
    }
  }
  double largest = 0;
  for (int i = 0; i < N; ++i) largest = std::max(largest, G[i][i]);
  if (!(largest > 0) || !std::isfinite(largest)) return false;
  // Cholesky G = L L^T in place (L in the lower triangle).
  for (int j = 0; j < N; ++j) {
    double d = G[j][j];
    for (int k = 0; k < j; ++k) d -= G[j][k] * G[j][k];
    if (!(d > min_pivot_ratio * largest)) return false;
    const double l = std::sqrt(d);
    G[j][j] = l;
    for (int i = j + 1; i < N; ++i) {
      double v = G[i][j];
      for (int k = 0; k < j; ++k) v -= G[i][k] * G[j][k];
      G[i][j] = v / l;
    }
  }
  // L L^T out = rhs: L y = rhs, then L^T out = y.
  auto solve_gram = [&](const double* rhs, double* out) {
    double y[N];
    for (int i = 0; i < N; ++i) {
      double v = rhs[i];
      for (int k = 0; k < i; ++k) v -= G[i][k] * y[k];
      y[i] = v / G[i][i];
    }
    for (int i = N - 1; i >= 0; --i) {
      double v = y[i];
      for (int k = i + 1; k < N; ++k) v -= G[k][i] * out[k];
      out[i] = v / G[i][i];
    }
  };
  double sol[N], fix[N], g[N] = {};
  solve_gram(r, sol);
  // One step of refinement on the residual (corrected semi-normal
  // equations): the normal equations' rounding, which grows with the square
  // of the condition, falls to the QR's order.
  for (int k = 0; k < m; ++k) {
    double row[N];
    for (int i = 0; i < N; ++i) row[i] = A[static_cast<std::ptrdiff_t>(i) * m + k];
    double res = b[k];
    for (int i = 0; i < N; ++i) res -= row[i] * sol[i];
    for (int i = 0; i < N; ++i) g[i] += row[i] * res;
  }
  solve_gram(g, fix);
  for (int i = 0; i < N; ++i) {
    x[i] = sol[i] + fix[i];
    if (!std::isfinite(x[i])) return false;
  }
  return true;
}

}  // namespace detail

// The least-squares solution x (n values) of A x = b by the normal
// equations (A^T A x = A^T b, Cholesky, one step of refinement), for the
// systems the QR above would find of full rank by far: A (m x n, by
// columns, m >= n; n 5 or 9, the fits' column counts) is taken only when
// every pivot of A^T A is above `min_pivot_ratio` times its largest diagonal
// entry (a pivot is the squared distance of a column from the span of those
// before it: at 1e-6, every column stands off the others by 1e-3 of the
// longest, far above the rank tests of the fits, 1e-8 and 1e-10 of R's
// diagonal). False otherwise (x then holds no solution): the caller solves
// by the pivoted QR. Less work than the QR on the fits' 12-40 x 5-9 systems.
inline bool solve_well_conditioned(const double* A, int m, int n, const double* b, double* x,
                                   double min_pivot_ratio = 1e-6) {
  if (m < n) return false;
  switch (n) {
    case 5: return detail::solve_well_conditioned_n<5>(A, m, b, x, min_pivot_ratio);
    case 9: return detail::solve_well_conditioned_n<9>(A, m, b, x, min_pivot_ratio);
    default: return false;  // the fits' column counts only: the QR takes the others
  }
}

// The least-squares solution x (n values) of A x = b (A m x n by columns)
// when A has full rank by `rank_threshold` (PivotedQR::factor_full_rank): by
// the normal equations where A is well conditioned by far
// (solve_well_conditioned; only for thresholds up to 1e-6 of R's diagonal,
// so no system the QR would refuse is solved there), else by `qr`. False
// (x undefined) when the rank is below n.
inline bool solve_full_rank_least_squares(PivotedQR& qr, const double* A, int m, int n, const double* b, double* x,
                                          double rank_threshold) {
  constexpr double kLargestFastThreshold = 1e-6;
  if (rank_threshold <= kLargestFastThreshold && solve_well_conditioned(A, m, n, b, x)) return true;
  if (!qr.factor_full_rank(A, m, n, rank_threshold)) return false;
  std::fill(x, x + n, 0.0);
  qr.solve(b, x);
  return true;
}

}  // namespace anisurf
