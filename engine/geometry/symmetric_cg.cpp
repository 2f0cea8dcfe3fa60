#include "geometry/symmetric_cg.h"

#include <algorithm>
#include <barrier>
#include <cmath>
#include <limits>

#include "geometry/parallel_chunks.h"

namespace anisurf {

void SymmetricColumns::add(int r, int c, double v) {
  const int* first = inner.data() + outer[c];
  const int* last = inner.data() + outer[c + 1];
  value[static_cast<std::size_t>(std::lower_bound(first, last, r) - inner.data())] += v;
}

namespace {

// Entries per block of the partial sums (the unit of the fixed summation
// order) and the fewest entries worth a thread.
constexpr int kBlock = 2048;
constexpr int kMinPerThread = 16384;

double sum_in_order(const std::vector<double>& parts) {
  double s = 0;
  for (double p : parts) s += p;
  return s;
}

}  // namespace

CgReport solve_conjugate_gradient(const SymmetricColumns& A, const std::vector<double>& b, double tolerance,
                                  int max_iterations, std::vector<double>& x) {
  const int n = A.n;
  x.assign(static_cast<std::size_t>(n), 0.0);
  CgReport report;
  if (n == 0) return report;
  const int blocks = (n + kBlock - 1) / kBlock;
  const int threads = std::clamp(n / kMinPerThread, 1, std::min(available_threads(), blocks));
  std::vector<double> r(b), z(n), p(n), q(n), inv_diag(n, 1.0);
  std::vector<double> dot_a(blocks), dot_b(blocks);
  std::barrier sync(threads);
  // Shared scalars, written by thread 0 between two barriers.
  double rz = 0, alpha = 0, beta = 0, threshold = 0, rhs2 = 0, res2 = 0;
  bool stop = false;

  auto team_member = [&](int t) {
    const int b0 = blocks * t / threads, b1 = blocks * (t + 1) / threads;
    auto for_blocks = [&](auto&& per_block) {
      for (int blk = b0; blk < b1; ++blk) per_block(blk, blk * kBlock, std::min(n, (blk + 1) * kBlock));
    };
    // z = D^-1 r at i; returns r . z there.
    auto precondition = [&](int i) {
      z[i] = inv_diag[i] * r[i];
      return r[i] * z[i];
    };
    for_blocks([&](int blk, int i0, int i1) {
      double srz = 0, sbb = 0;
      for (int i = i0; i < i1; ++i) {
        for (int k = A.outer[i]; k < A.outer[i + 1]; ++k)
          if (A.inner[k] == i && A.value[k] != 0) inv_diag[i] = 1.0 / A.value[k];
        srz += precondition(i);
        p[i] = z[i];
        sbb += b[i] * b[i];
      }
      dot_a[blk] = srz;
      dot_b[blk] = sbb;
    });
    sync.arrive_and_wait();
    if (t == 0) {
      rz = sum_in_order(dot_a);
      rhs2 = sum_in_order(dot_b);
      res2 = rhs2;
      threshold = std::max(tolerance * tolerance * rhs2, std::numeric_limits<double>::min());
      stop = !(rhs2 > 0) || res2 < threshold || max_iterations <= 0;
    }
    sync.arrive_and_wait();
    while (!stop) {
      // q = A p (column u is row u), and p . q
      for_blocks([&](int blk, int i0, int i1) {
        double s = 0;
        for (int u = i0; u < i1; ++u) {
          double y = 0;
          for (int k = A.outer[u]; k < A.outer[u + 1]; ++k) y += A.value[k] * p[A.inner[k]];
          q[u] = y;
          s += p[u] * y;
        }
        dot_a[blk] = s;
      });
      sync.arrive_and_wait();
      if (t == 0) alpha = rz / sum_in_order(dot_a);
      sync.arrive_and_wait();
      for_blocks([&](int blk, int i0, int i1) {
        double srr = 0, srz = 0;
        for (int i = i0; i < i1; ++i) {
          x[i] += alpha * p[i];
          r[i] -= alpha * q[i];
          srr += r[i] * r[i];
          srz += precondition(i);
        }
        dot_a[blk] = srz;
        dot_b[blk] = srr;
      });
      sync.arrive_and_wait();
      if (t == 0) {
        ++report.iterations;
        res2 = sum_in_order(dot_b);
        const double rz_next = sum_in_order(dot_a);
        beta = rz_next / rz;
        rz = rz_next;
        stop = res2 < threshold || report.iterations >= max_iterations || !std::isfinite(res2);
      }
      sync.arrive_and_wait();
      if (stop) break;
      for_blocks([&](int, int i0, int i1) {
        for (int i = i0; i < i1; ++i) p[i] = z[i] + beta * p[i];
      });
      sync.arrive_and_wait();
    }
  };
  run_chunks(threads, threads, [&](int t, int, int) { team_member(t); });
  report.relative_residual = rhs2 > 0 ? std::sqrt(res2 / rhs2) : 0.0;
  report.converged = res2 < threshold;
  return report;
}

}  // namespace anisurf
