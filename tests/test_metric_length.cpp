// Edge lengths in a metric (eq. 2, 6, 7), metric interpolation (section 2.2,
// Remark 2, log-Euclidean) and triangle quality (eq. 17, mean ratio).
#include <doctest/doctest.h>

#include <random>

#include "metric/length.h"
#include "metric/quality.h"

using namespace anisurf;

namespace {

SymTensor3 random_spd(std::mt19937& rng, double h_lo, double h_hi) {
  std::uniform_real_distribution<double> u(std::log(h_lo), std::log(h_hi));
  std::normal_distribution<double> g;
  Vec3 a(g(rng), g(rng), g(rng));
  a = normalized(a);
  Vec3 b = normalized(cross(a, Vec3(g(rng), g(rng), g(rng))));
  return metric_from_sizes({std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng))}, {a, b, cross(a, b)});
}

Vec3 random_vec(std::mt19937& rng, double scale) {
  std::normal_distribution<double> g;
  return scale * Vec3(g(rng), g(rng), g(rng));
}

double rel_diff(const SymTensor3& a, const SymTensor3& b) { return frobenius_norm(a - b) / frobenius_norm(b); }

}  // namespace

TEST_CASE("length: eq. 6 is exact when the metric coefficients vary linearly along the edge") {
  std::mt19937 rng(11);
  double worst = 0;
  for (int k = 0; k < 300; ++k) {
    const SymTensor3 A = random_spd(rng, 1e-3, 1.0), B = random_spd(rng, 1e-3, 1.0);
    const Vec3 e = random_vec(rng, 0.1);
    const double closed = edge_length(A, B, e, LengthFormula::LinearMetric);
    const double integral = integrated_edge_length(A, B, e, MetricInterpolation::Linear, 1e-13);
    worst = std::max(worst, std::fabs(closed - integral) / integral);
  }
  MESSAGE("eq. 6 vs adaptive quadrature, worst relative difference " << worst);
  CHECK(worst < 1e-10);
  // Eq. 5 by hand: l0 = 1, l1 = 2: int_0^1 sqrt(1 + 3t) dt = 2/9 (8 - 1) = 14/9.
  CHECK(length_linear_metric(1.0, 2.0) == doctest::Approx(14.0 / 9.0).epsilon(1e-15));
  CHECK(length_linear_metric(3.0, 3.0) == doctest::Approx(3.0).epsilon(1e-15));
  CHECK(length_linear_metric(0.0, 0.0) == 0.0);
}

TEST_CASE("length: eq. 7 is exact for an isotropic metric whose size varies linearly") {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> lh(std::log(1e-3), 0.0);
  double worst = 0, worst_interp = 0;
  for (int k = 0; k < 300; ++k) {
    const double h0 = std::exp(lh(rng)), h1 = std::exp(lh(rng));
    const Vec3 e = random_vec(rng, 0.1);
    const double closed = edge_length(isotropic_metric(h0), isotropic_metric(h1), e, LengthFormula::LinearSize);
    // Exact integral of |e| / h(t) for h linear.
    const double exact = norm(e) * std::log(h1 / h0) / (h1 - h0);
    const double integral =
        integrated_length([&](double t) { return isotropic_metric(h0 + t * (h1 - h0)); }, e, 1e-13);
    worst = std::max({worst, std::fabs(closed - exact) / exact, std::fabs(integral - exact) / exact});
    // The LinearSize interpolation is that field.
    const double via_interp = integrated_edge_length(isotropic_metric(h0), isotropic_metric(h1), e,
                                                     MetricInterpolation::LinearSize, 1e-13);
    worst_interp = std::max(worst_interp, std::fabs(via_interp - exact) / exact);
  }
  CHECK(worst < 1e-10);
  CHECK(worst_interp < 1e-10);
  // Also exact for proportional anisotropic metrics M1 = s^2 M0 (same shape, size linear).
  const SymTensor3 M0 = random_spd(rng, 1e-2, 1.0);
  const Vec3 e = random_vec(rng, 0.1);
  const double closed = edge_length(M0, 9.0 * M0, e, LengthFormula::LinearSize);
  const double integral = integrated_edge_length(M0, 9.0 * M0, e, MetricInterpolation::LinearSize, 1e-13);
  CHECK(closed == doctest::Approx(integral).epsilon(1e-10));
  // Eq. 6 is not exact for that field: a measured difference, not a rounding.
  const double eq6 = edge_length(isotropic_metric(0.01), isotropic_metric(0.1), Vec3(0.05, 0, 0),
                                 LengthFormula::LinearMetric);
  const double eq7 = edge_length(isotropic_metric(0.01), isotropic_metric(0.1), Vec3(0.05, 0, 0),
                                 LengthFormula::LinearSize);
  CHECK(eq7 == doctest::Approx(0.05 * std::log(10.0) / 0.09).epsilon(1e-14));
  CHECK(eq6 > 1.5 * eq7);
}

TEST_CASE("length: eq. 7 is stable near l0 = l1 and symmetric") {
  CHECK(length_linear_size(2.0, 2.0) == 2.0);
  // Series: L = sqrt(l0 l1) (1 - u^2/24 + ...), u = log(l0/l1).
  const double l0 = 1.0, l1 = 1.0 + 1e-9;
  CHECK(length_linear_size(l0, l1) == doctest::Approx(0.5 * (l0 + l1)).epsilon(1e-15));
  CHECK(length_linear_size(3.0, 0.5) == doctest::Approx(length_linear_size(0.5, 3.0)).epsilon(1e-15));
  CHECK(length_linear_size(3.0, 0.5) == doctest::Approx(3.0 * 0.5 * std::log(6.0) / 2.5).epsilon(1e-15));
  // Ordering: eq. 7 (harmonic-like mean) <= eq. 6 (quadratic-like mean).
  CHECK(length_linear_size(3.0, 0.5) < length_linear_metric(3.0, 0.5));
}

TEST_CASE("interpolation: closed forms of the four schemes") {
  const SymTensor3 A = SymTensor3::diagonal(1, 4, 100), B = SymTensor3::diagonal(16, 1, 1);
  for (auto how : {MetricInterpolation::Linear, MetricInterpolation::Inverse, MetricInterpolation::LinearSize,
                   MetricInterpolation::LogEuclidean}) {
    CHECK(rel_diff(interpolate_metric(A, B, 0.0, how), A) < 1e-14);
    CHECK(rel_diff(interpolate_metric(A, B, 1.0, how), B) < 1e-14);
    CHECK(rel_diff(interpolate_metric({A, B, A}, {0.0, 1.0, 0.0}, how), B) < 1e-14);
  }
  // Diagonal (commuting) tensors, t = 1/2, entrywise: arithmetic, harmonic,
  // h-linear and geometric means of the eigenvalues.
  auto entry = [](double a, double b, MetricInterpolation how) {
    switch (how) {
      case MetricInterpolation::Linear: return 0.5 * (a + b);
      case MetricInterpolation::Inverse: return 1.0 / (0.5 / a + 0.5 / b);
      case MetricInterpolation::LinearSize: return std::pow(0.5 / std::sqrt(a) + 0.5 / std::sqrt(b), -2.0);
      case MetricInterpolation::LogEuclidean: return std::sqrt(a * b);
    }
    return 0.0;
  };
  for (auto how : {MetricInterpolation::Linear, MetricInterpolation::Inverse, MetricInterpolation::LinearSize,
                   MetricInterpolation::LogEuclidean}) {
    const SymTensor3 M = interpolate_metric(A, B, 0.5, how);
    CHECK(rel_diff(M, SymTensor3::diagonal(entry(1, 16, how), entry(4, 1, how), entry(100, 1, how))) < 1e-14);
  }
}

TEST_CASE("interpolation: Remark 2 and log-Euclidean on general triangles") {
  std::mt19937 rng(13);
  for (int k = 0; k < 100; ++k) {
    const std::array<SymTensor3, 3> M = {random_spd(rng, 1e-2, 1), random_spd(rng, 1e-2, 1),
                                         random_spd(rng, 1e-2, 1)};
    std::uniform_real_distribution<double> u(0, 1);
    double a = u(rng), b = u(rng);
    if (a + b > 1) { a = 1 - a; b = 1 - b; }
    const std::array<double, 3> w = {1 - a - b, a, b};
    // Remark 2: M(p)^-1 = sum w_i M_i^-1.
    const SymTensor3 Mi = interpolate_metric(M, w, MetricInterpolation::Inverse);
    const SymTensor3 expect_inv = w[0] * inverse(M[0]) + w[1] * inverse(M[1]) + w[2] * inverse(M[2]);
    CHECK(rel_diff(inverse(Mi), expect_inv) < 1e-10);
    CHECK(is_spd(Mi));
    // Log-Euclidean: det M(p) = prod det(M_i)^w_i.
    const SymTensor3 Ml = interpolate_metric(M, w, MetricInterpolation::LogEuclidean);
    const double expect_det = std::exp(w[0] * std::log(det(M[0])) + w[1] * std::log(det(M[1])) +
                                       w[2] * std::log(det(M[2])));
    CHECK(det(Ml) == doctest::Approx(expect_det).epsilon(1e-9));
    // Linear: the coefficients.
    const SymTensor3 Mlin = interpolate_metric(M, w, MetricInterpolation::Linear);
    CHECK(rel_diff(Mlin, w[0] * M[0] + w[1] * M[1] + w[2] * M[2]) < 1e-15);
  }
}

TEST_CASE("quality: eq. 17 and the mean ratio are 1 for equilateral triangles in the metric") {
  // eval.py: q = 27 (p-l1)(p-l2)(p-l3) / p^3 with p the half-perimeter.
  CHECK(quality_from_lengths(1, 1, 1) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(quality_from_lengths(0.01, 0.01, 0.01) == doctest::Approx(1.0).epsilon(1e-15));
  // Right isosceles (1, 1, sqrt 2): c_K = 27 (p-1)^2 (p - sqrt2) / p^3, mean ratio sqrt(3)/2.
  const double p = 1 + std::sqrt(0.5);
  CHECK(quality_from_lengths(1, 1, std::sqrt(2.0)) ==
        doctest::Approx(27 * (p - 1) * (p - 1) * (p - std::sqrt(2.0)) / (p * p * p)).epsilon(1e-14));
  CHECK(mean_ratio_in({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, SymTensor3::identity()) ==
        doctest::Approx(std::sqrt(3.0) / 2).epsilon(1e-15));
  CHECK(quality_from_lengths(1, 2, 3) == 0.0);  // flat
  CHECK(quality_from_lengths(1, 1, 3) == 0.0);  // not a triangle
  CHECK(mean_ratio_in({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}, SymTensor3::identity()) == 0.0);

  // A triangle equilateral of side 1 in an anisotropic metric: the image of a
  // unit equilateral triangle under M^-1/2.
  std::mt19937 rng(14);
  for (int k = 0; k < 50; ++k) {
    const SymTensor3 M = random_spd(rng, 1e-3, 1.0);
    const SymTensor3 R = tensor_power(M, -0.5);
    const Vec3 o = random_vec(rng, 1);
    const std::array<Vec3, 3> unit = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(0.75), 0)};
    const std::array<Vec3, 3> t = {o + R * unit[0], o + R * unit[1], o + R * unit[2]};
    CHECK(triangle_quality_in(t, M) == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(mean_ratio_in(t, M) == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(triangle_quality(t, {M, M, M}, LengthFormula::LinearMetric) == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(metric_length(M, t[1] - t[0]) == doctest::Approx(1.0).epsilon(1e-9));
  }
  // The image of the unit triangle under diag(100, 1, 1)^-1/2 is poor in the
  // Euclidean metric: sides 0.1, sqrt(0.05^2 + 0.75) twice, area 0.1 sqrt(3)/4.
  {
    const std::array<Vec3, 3> t = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.05, std::sqrt(0.75), 0)};
    const double s2 = 0.01 + 2 * (0.0025 + 0.75);
    CHECK(mean_ratio_in(t, SymTensor3::identity()) ==
          doctest::Approx(4 * std::sqrt(3.0) * (0.1 * std::sqrt(3.0) / 4) / s2).epsilon(1e-14));
    CHECK(mean_ratio_in(t, SymTensor3::diagonal(100, 1, 1)) == doctest::Approx(1.0).epsilon(1e-14));
  }
  // Heron: c_K = 27 A^2 / p^4 = (mean ratio * sum l^2 / (4 sqrt 3))^2 * 27 / p^4.
  const std::array<Vec3, 3> t = {Vec3(0, 0, 0), Vec3(2, 0.3, 0), Vec3(0.4, 1.1, 0.2)};
  const SymTensor3 M = SymTensor3(3, 0.5, 2, 0.1, -0.3, 1);
  const double l1 = metric_length(M, t[1] - t[0]), l2 = metric_length(M, t[2] - t[1]), l3 = metric_length(M, t[0] - t[2]);
  const double area = mean_ratio_in(t, M) * (l1 * l1 + l2 * l2 + l3 * l3) / (4 * std::sqrt(3.0));
  const double ph = 0.5 * (l1 + l2 + l3);
  CHECK(triangle_quality_in(t, M) == doctest::Approx(27 * area * area / (ph * ph * ph * ph)).epsilon(1e-12));
}

TEST_CASE("length: length_fraction_parameter puts the point at the asked share of the edge's metric length") {
  // Checked against the adaptive quadrature of eq. 2 over [0, t], with the
  // field each formula is exact for (metric coefficients linear: eq. 6;
  // size linear: eq. 7).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> lh(std::log(1e-3), 0.0), uf(0.0, 1.0);
  double worst6 = 0, worst7 = 0;
  for (int k = 0; k < 200; ++k) {
    const double h0 = std::exp(lh(rng)), h1 = std::exp(lh(rng)), f = uf(rng);
    const Vec3 e = random_vec(rng, 0.1);
    const SymTensor3 M0 = isotropic_metric(h0), M1 = isotropic_metric(h1);
    const double l0 = metric_length(M0, e), l1 = metric_length(M1, e);
    // Eq. 6's field: M linear in t.
    const double t6 = length_fraction_parameter(l0, l1, f, LengthFormula::LinearMetric);
    const double part6 = integrated_length([&](double s) { return (1 - s * t6) * M0 + (s * t6) * M1; }, t6 * e, 1e-13);
    const double whole6 = integrated_edge_length(M0, M1, e, MetricInterpolation::Linear, 1e-13);
    worst6 = std::max(worst6, std::fabs(part6 - f * whole6) / whole6);
    // Eq. 7's field: h linear in t.
    const double t7 = length_fraction_parameter(l0, l1, f, LengthFormula::LinearSize);
    const double part7 = integrated_length([&](double s) { return isotropic_metric(h0 + s * t7 * (h1 - h0)); }, t7 * e, 1e-13);
    const double whole7 = norm(e) * std::log(h1 / h0) / (h1 - h0);
    worst7 = std::max(worst7, std::fabs(part7 - f * whole7) / whole7);
  }
  CHECK(worst6 < 1e-8);
  CHECK(worst7 < 1e-8);
  // Equal ends: the fraction itself; the ends map to the ends.
  CHECK(length_fraction_parameter(2.0, 2.0, 0.3, LengthFormula::LinearMetric) == 0.3);
  CHECK(length_fraction_parameter(1.0, 5.0, 0.0, LengthFormula::LinearMetric) == doctest::Approx(0.0));
  CHECK(length_fraction_parameter(1.0, 5.0, 1.0, LengthFormula::LinearSize) == doctest::Approx(1.0));
  // The short end of the edge (l small: large size) takes more of the parameter.
  CHECK(length_fraction_parameter(1.0, 5.0, 0.5, LengthFormula::LinearMetric) > 0.5);
}
