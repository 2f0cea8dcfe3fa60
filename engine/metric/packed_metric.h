// A metric tensor stored in 24 bytes (the remesher's per-vertex metric, half
// the 48 of SymTensor3): its factors M = L D L^T (L unit lower triangular,
// D diagonal) in single precision.
//
// Rounding the factors, not the coefficients, keeps anisotropic metrics
// exact enough: the length of an edge in M moves by about 6e-8 x
// sqrt(lambda_max / lambda_e) of itself (lambda_e the eigenvalue seen along
// the edge), where rounded coefficients move it by 6e-8 x lambda_max /
// lambda_e (a size ratio of 1e4 between two directions: 6e-8 x 1e4 against
// 6e-8 x 1e8, i.e. 6 times the length). For a symmetric positive
// (semi-)definite M, L D L^T without pivoting is stable (d_j l_ij^2 <= M_ii).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

#include "metric/metric.h"

namespace anisurf {

struct PackedMetric {
  // d1, l21, d2, l31, l32, d3: M = L D L^T with L = [1 0 0; l21 1 0; l31 l32 1].
  std::array<float, 6> f{1, 0, 1, 0, 0, 1};

  // The factors of M (a pivot below a rounding of the diagonal's scale is
  // taken as 0, its column of L as 0: a semi-definite M stays one).
  static PackedMetric pack(const SymTensor3& M) {
    const double scale = std::max({std::abs(M.m[0]), std::abs(M.m[2]), std::abs(M.m[5])});
    const double tiny = 1e-14 * scale;
    auto pivot = [&](double d) { return d > tiny ? d : 0.0; };
    const double d1 = pivot(M.m[0]);
    const double l21 = d1 > 0 ? M.m[1] / d1 : 0.0;
    const double l31 = d1 > 0 ? M.m[3] / d1 : 0.0;
    const double d2 = pivot(M.m[2] - l21 * l21 * d1);
    const double l32 = d2 > 0 ? (M.m[4] - l31 * l21 * d1) / d2 : 0.0;
    const double d3 = pivot(M.m[5] - l31 * l31 * d1 - l32 * l32 * d2);
    PackedMetric p;
    p.f = {static_cast<float>(d1), static_cast<float>(l21), static_cast<float>(d2),
           static_cast<float>(l31), static_cast<float>(l32), static_cast<float>(d3)};
    return p;
  }

  // L D L^T in double precision.
  SymTensor3 unpack() const {
    const double d1 = f[0], l21 = f[1], d2 = f[2], l31 = f[3], l32 = f[4], d3 = f[5];
    return SymTensor3(d1, l21 * d1, l21 * l21 * d1 + d2, l31 * d1, l31 * l21 * d1 + l32 * d2,
                      l31 * l31 * d1 + l32 * l32 * d2 + d3);
  }

  friend bool operator==(const PackedMetric& a, const PackedMetric& b) { return a.f == b.f; }
};

}  // namespace anisurf
