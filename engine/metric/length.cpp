#include "metric/length.h"

#include <algorithm>

#include <cmath>

namespace anisurf {

double length_linear_size(double l0, double l1) {
  if (l0 == l1) return l0;
  if (!(l0 > 0) || !(l1 > 0)) return 0.0;  // the size vanishes at one end: the integral diverges only in the limit
  // l0 l1 log(l0/l1) / (l0 - l1) = l0 u / (exp(u) - 1) with u = log(l0 / l1).
  const double u = std::log(l0 / l1);
  return l0 * u / std::expm1(u);
}

double length_fraction_parameter(double l0, double l1, double fraction, LengthFormula formula) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (!(l0 > 0) || !(l1 > 0) || std::fabs(l1 - l0) <= 1e-12 * (l0 + l1)) return fraction;
  double t;
  if (formula == LengthFormula::LinearMetric) {
    // F(t) = integral of sqrt(a + s (b - a)), a = l0^2, b = l1^2:
    // (2 / (3 (b - a))) ((a + t (b - a))^1.5 - a^1.5).
    const double a = l0 * l0, b = l1 * l1;
    const double target = std::pow(a, 1.5) + fraction * (std::pow(b, 1.5) - std::pow(a, 1.5));
    t = (std::pow(target, 2.0 / 3.0) - a) / (b - a);
  } else {
    // The size h = |e| / l linear in t: F(t) = |e| log(h(t) / h0) / (h1 - h0).
    const double h0 = 1 / l0, h1 = 1 / l1;
    t = h0 * std::expm1(fraction * std::log(h1 / h0)) / (h1 - h0);
  }
  return std::clamp(t, 0.0, 1.0);
}

SymTensor3 to_interpolation_space(const SymTensor3& M, MetricInterpolation how) {
  switch (how) {
    case MetricInterpolation::Linear: return M;
    case MetricInterpolation::Inverse: return inverse(M);
    case MetricInterpolation::LinearSize: return tensor_power(M, -0.5);
    case MetricInterpolation::LogEuclidean: return tensor_log(M);
  }
  return M;
}

namespace {

// Y Y for a symmetric Y.
SymTensor3 symmetric_square(const SymTensor3& Y) {
  SymTensor3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) out(j, i) = Y(i, 0) * Y(0, j) + Y(i, 1) * Y(1, j) + Y(i, 2) * Y(2, j);
  return out;
}

}  // namespace

SymTensor3 from_interpolation_space(const SymTensor3& X, MetricInterpolation how) {
  switch (how) {
    case MetricInterpolation::Linear: return X;
    case MetricInterpolation::Inverse: return inverse(X);
    // X^-2 as (X^-1)^2: no eigen-decomposition (the metric lookups of every
    // operator go through here).
    case MetricInterpolation::LinearSize: return symmetric_square(inverse(X));
    case MetricInterpolation::LogEuclidean: return tensor_exp(X);
  }
  return X;
}

namespace {

double adaptive_simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
                        double whole, double tol, int depth) {
  const double m = 0.5 * (a + b);
  const double lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  const double delta = left + right - whole;
  if (depth <= 0 || std::fabs(delta) <= 15.0 * tol) return left + right + delta / 15.0;
  return adaptive_simpson(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
         adaptive_simpson(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

}  // namespace

SymTensor3 interpolate_metric(const SymTensor3& M0, const SymTensor3& M1, double t, MetricInterpolation how) {
  if (how == MetricInterpolation::Linear) return (1.0 - t) * M0 + t * M1;
  return from_interpolation_space((1.0 - t) * to_interpolation_space(M0, how) + t * to_interpolation_space(M1, how), how);
}

SymTensor3 interpolate_metric(const std::array<SymTensor3, 3>& M, const std::array<double, 3>& w,
                              MetricInterpolation how) {
  if (how == MetricInterpolation::Linear) return w[0] * M[0] + w[1] * M[1] + w[2] * M[2];
  SymTensor3 X;
  for (int i = 0; i < 3; ++i) X += w[i] * to_interpolation_space(M[i], how);
  return from_interpolation_space(X, how);
}

double integrated_length(const std::function<SymTensor3(double)>& metric_at, const Vec3& e, double rel_tol) {
  const std::function<double(double)> f = [&](double t) { return metric_length(metric_at(t), e); };
  // Start from 4 panels so that a feature inside [0, 1] is seen by the samples.
  double total = 0;
  std::array<double, 5> fs;
  for (int k = 0; k <= 4; ++k) fs[k] = f(0.25 * k);
  const double scale = 0.25 * (fs[0] + fs[1] + fs[2] + fs[3] + fs[4]) + 1e-300;
  for (int k = 0; k < 4; ++k) {
    const double a = 0.25 * k, b = a + 0.25, m = 0.5 * (a + b);
    const double fm = f(m);
    const double whole = (b - a) / 6.0 * (fs[k] + 4.0 * fm + fs[k + 1]);
    total += adaptive_simpson(f, a, b, fs[k], fm, fs[k + 1], whole, 0.25 * rel_tol * scale, 40);
  }
  return total;
}

double integrated_edge_length(const SymTensor3& M0, const SymTensor3& M1, const Vec3& e, MetricInterpolation how,
                              double rel_tol) {
  const SymTensor3 X0 = to_interpolation_space(M0, how), X1 = to_interpolation_space(M1, how);
  return integrated_length([&](double t) { return from_interpolation_space((1.0 - t) * X0 + t * X1, how); }, e, rel_tol);
}

}  // namespace anisurf
