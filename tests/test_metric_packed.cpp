// PackedMetric: the remesher's 24-byte metric per vertex (L D L^T factors in
// single precision) keeps edge lengths of strongly anisotropic metrics.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "metric/length.h"
#include "metric/packed_metric.h"

using namespace anisurf;

namespace {

// A metric with sizes h = (h0, h1, h2) along a random orthonormal frame.
struct Frame {
  SymTensor3 M;
  std::array<Vec3, 3> axes;
  std::array<double, 3> h;
};

Frame random_metric(std::mt19937& rng, double h_lo, double h_hi) {
  std::uniform_real_distribution<double> u(std::log(h_lo), std::log(h_hi));
  std::normal_distribution<double> g;
  const Vec3 a = normalized(Vec3(g(rng), g(rng), g(rng)));
  const Vec3 b = normalized(cross(a, Vec3(g(rng), g(rng), g(rng))));
  Frame f;
  f.axes = {a, b, cross(a, b)};
  f.h = {std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng))};
  f.M = metric_from_sizes(f.h, f.axes);
  return f;
}

double relative_length_error(const SymTensor3& exact, const SymTensor3& packed, const Vec3& e) {
  const double l = metric_length(exact, e);
  return std::fabs(metric_length(packed, e) - l) / l;
}

}  // namespace

TEST_CASE("packed metric: lengths along every direction of metrics with sizes 1e4 apart stay within 1e-3") {
  std::mt19937 rng(5);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const Frame f = random_metric(rng, 1e-5, 1e-1);
    const SymTensor3 P = PackedMetric::pack(f.M).unpack();
    // The axes (the largest size's is where rounded coefficients fail) and
    // random directions.
    std::normal_distribution<double> g;
    for (const Vec3& e : {f.axes[0], f.axes[1], f.axes[2], Vec3(g(rng), g(rng), g(rng))})
      worst = std::max(worst, relative_length_error(f.M, P, e));
  }
  MESSAGE("worst relative length error " << worst);
  CHECK(worst < 1e-3);
}

TEST_CASE("packed metric: an isotropic metric comes back to single precision, a semi-definite one stays so") {
  for (double lambda : {1.0, 4e-6, 2.5e9}) {
    const SymTensor3 P = PackedMetric::pack(SymTensor3::identity(lambda)).unpack();
    for (int i = 0; i < 6; ++i) CHECK(std::fabs(P.m[i] - SymTensor3::identity(lambda).m[i]) <= 1e-7 * lambda);
  }
  // Sizes 0.01 and 0.02 in the plane x + y = 0 rotated about z; nothing along
  // its normal (lambda 0).
  const Vec3 a = normalized(Vec3(1, 1, 0)), b(0, 0, 1), n = normalized(Vec3(1, -1, 0));
  SymTensor3 M = metric_from_sizes({0.01, 0.02, 1.0}, {a, b, n});
  M = M - SymTensor3(n.x * n.x, n.x * n.y, n.y * n.y, n.x * n.z, n.y * n.z, n.z * n.z);  // lambda_n = 1 -> 0
  const SymTensor3 P = PackedMetric::pack(M).unpack();
  for (double c : P.m) CHECK(std::isfinite(c));
  CHECK(quad(P, n) <= 1e-6 * quad(M, a));
  CHECK(relative_length_error(M, P, a) < 1e-6);
  CHECK(relative_length_error(M, P, b) < 1e-6);
}
