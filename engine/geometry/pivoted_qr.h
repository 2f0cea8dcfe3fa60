// Householder QR with column pivoting for the small dense least-squares
// systems of the local fits (metric/hessian.cpp, geometry/normals.cpp).
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

}  // namespace anisurf
