// Lengths in a metric field and interpolation of metrics (report section 2.2:
// eq. 2 and 4-7, Remark 2).
#pragma once
#include <array>
#include <functional>

#include "metric/metric.h"

namespace anisurf {

// How a metric given at vertices varies in between.
enum class MetricInterpolation {
  Linear,        // coefficients linear (section 2.2): M = sum w_i M_i
  Inverse,       // Remark 2: M = (sum w_i M_i^-1)^-1 (isotropic: h^2 linear)
  LinearSize,    // M^-1/2 linear (isotropic: h linear): the field for which eq. 7 is exact
  LogEuclidean,  // M = exp(sum w_i log M_i)
};

// Which closed form approximates the length of an edge from the lengths l0,
// l1 of its vector in the metrics at its two ends.
enum class LengthFormula {
  LinearMetric,  // eq. 6, exact when the metric coefficients vary linearly
  LinearSize,    // eq. 7 (Remark 2), exact for an isotropic metric with h linear
};

// Eq. 6: 2/3 (l0^2 + l0 l1 + l1^2) / (l0 + l1) (0 for l0 = l1 = 0).
// Inline: the remesher's inner loops measure edges all the time.
inline double length_linear_metric(double l0, double l1) {
  const double s = l0 + l1;
  if (!(s > 0)) return 0.0;
  return (2.0 / 3.0) * (l0 * l0 + l0 * l1 + l1 * l1) / s;
}
// Eq. 7: l0 l1 log(l0 / l1) / (l0 - l1), l0 when equal (stable near l0 = l1).
double length_linear_size(double l0, double l1);
// The parameter t in [0, 1] of the point of an edge whose length from the
// l0 end is `fraction` of the edge's (l0, l1: the edge measured in the
// metric of each end). Eq. 6's density sqrt((1 - t) l0^2 + t l1^2) or eq.
// 7's (the size linear along the edge) integrated and inverted in closed
// form; `fraction` itself when l0 = l1.
double length_fraction_parameter(double l0, double l1, double fraction, LengthFormula formula);
// Length of the edge vector e from the metrics at its ends (eq. 6 or 7).
inline double edge_length(const SymTensor3& M0, const SymTensor3& M1, const Vec3& e, LengthFormula formula) {
  if (M0 == M1) return metric_length(M0, e);  // both formulas: the length in the one metric
  const double l0 = metric_length(M0, e), l1 = metric_length(M1, e);
  return formula == LengthFormula::LinearMetric ? length_linear_metric(l0, l1) : length_linear_size(l0, l1);
}

// The space in which an interpolation scheme is linear: M (Linear), M^-1
// (Inverse), M^-1/2 (LinearSize), log M (LogEuclidean); and back. A field
// interpolated many times (T_0's) is stored there once.
SymTensor3 to_interpolation_space(const SymTensor3& M, MetricInterpolation how);
SymTensor3 from_interpolation_space(const SymTensor3& X, MetricInterpolation how);

// Metric at parameter t in [0, 1] between M0 (t = 0) and M1 (t = 1).
SymTensor3 interpolate_metric(const SymTensor3& M0, const SymTensor3& M1, double t, MetricInterpolation how);
// Metric at the point of barycentric coordinates w (sum 1) of a triangle
// whose vertex metrics are M (Remark 2's formula for Inverse).
SymTensor3 interpolate_metric(const std::array<SymTensor3, 3>& M, const std::array<double, 3>& w,
                              MetricInterpolation how);

// Eq. 2 along the straight segment t -> x0 + t e, t in [0, 1], for any metric
// `metric_at(t)`: adaptive Simpson quadrature to the relative tolerance
// (a reference for the closed forms; it resolves kinks by subdivision).
double integrated_length(const std::function<SymTensor3(double)>& metric_at, const Vec3& e,
                         double rel_tol = 1e-12);
// Eq. 2 with the metric interpolated between the ends as `how`.
double integrated_edge_length(const SymTensor3& M0, const SymTensor3& M1, const Vec3& e, MetricInterpolation how,
                              double rel_tol = 1e-12);

}  // namespace anisurf
