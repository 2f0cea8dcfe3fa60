// Triangle quality in a metric (report section 5.4, eq. 17). Every measure is
// 1 for a triangle equilateral in the metric and 0 for a degenerate one, and
// does not depend on the triangle's size.
#pragma once
#include <array>

#include "metric/length.h"
#include "metric/metric.h"

namespace anisurf {

// Eq. 17: c_K = 27 (p - l1)(p - l2)(p - l3) / p^3, p the half-perimeter
// (= 27 A^2 / p^4 by Heron). Lengths violating the triangle inequality give 0.
double quality_from_lengths(double l1, double l2, double l3);

// c_K with each edge measured from the metrics at its two ends (eq. 6 or 7):
// the criterion of the report's swaps (eval.py's q).
double triangle_quality(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M, LengthFormula formula);
// c_K with the three edges measured in the one metric M (eval.py's qc uses
// the metric at the centroid).
double triangle_quality_in(const std::array<Vec3, 3>& p, const SymTensor3& M);
// Mean ratio in the one metric M: 4 sqrt(3) A_M / (l1^2 + l2^2 + l3^2), with
// A_M the triangle's area measured in M (from the metric Gram matrix).
double mean_ratio_in(const std::array<Vec3, 3>& p, const SymTensor3& M);
// The metric at the centroid, interpolated from the vertex metrics.
inline SymTensor3 centroid_metric(const std::array<SymTensor3, 3>& M, MetricInterpolation how) {
  return interpolate_metric(M, {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0}, how);
}

}  // namespace anisurf
