// Metric tensors (report section 2, eq. 1 and 3): construction, the Jacobi
// eigen-decomposition against Eigen, sizes back, validity, intersection and
// clamping.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "metric/metric.h"

using namespace anisurf;

namespace {

// Random rotation from a random unit quaternion.
std::array<Vec3, 3> random_frame(std::mt19937& rng) {
  std::normal_distribution<double> g;
  double q[4];
  double n = 0;
  for (double& x : q) { x = g(rng); n += x * x; }
  n = std::sqrt(n);
  for (double& x : q) x /= n;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {Vec3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
          Vec3(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
          Vec3(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y))};
}

// Random SPD metric with sizes log-uniform in [h_lo, h_hi].
SymTensor3 random_metric(std::mt19937& rng, double h_lo, double h_hi, std::array<double, 3>* sizes = nullptr,
                         std::array<Vec3, 3>* dirs = nullptr) {
  std::uniform_real_distribution<double> u(std::log(h_lo), std::log(h_hi));
  std::array<double, 3> h = {std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng))};
  auto d = random_frame(rng);
  if (sizes) *sizes = h;
  if (dirs) *dirs = d;
  return metric_from_sizes(h, d);
}

Eigen::Matrix3d to_eigen(const SymTensor3& M) {
  Eigen::Matrix3d a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a(i, j) = M(i, j);
  return a;
}

double rel_diff(const SymTensor3& a, const SymTensor3& b) { return frobenius_norm(a - b) / frobenius_norm(b); }

// The intersection by simultaneous reduction, the eigen-decomposition of
// L^-1 M2 L^-T (M1 = L L^T) by Eigen's solver or by the Jacobi one.
SymTensor3 reference_intersection(const SymTensor3& M1, const SymTensor3& M2, bool jacobi) {
  Eigen::Matrix3d A, B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      A(i, j) = M1(i, j);
      B(i, j) = M2(i, j);
    }
  const Eigen::Matrix3d L = A.llt().matrixL();
  const Eigen::Matrix3d Li = L.inverse();
  const Eigen::Matrix3d C = Li * B * Li.transpose();
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  if (jacobi) {
    const SymEigen3 e = eigen_decompose(SymTensor3(C(0, 0), C(0, 1), C(1, 1), C(0, 2), C(1, 2), C(2, 2)));
    for (int k = 0; k < 3; ++k) {
      values(k) = e.values[k];
      vectors.col(k) = Eigen::Vector3d(e.vectors[k].x, e.vectors[k].y, e.vectors[k].z);
    }
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    values = es.eigenvalues();
    vectors = es.eigenvectors();
  }
  Eigen::Matrix3d R = A;
  for (int k = 0; k < 3; ++k)
    if (values(k) > 1) {
      const Eigen::Vector3d w = L * vectors.col(k);
      R += (values(k) - 1) * w * w.transpose();
    }
  return {R(0, 0), R(0, 1), R(1, 1), R(0, 2), R(1, 2), R(2, 2)};
}

// intersect(A, B) is about as close to Eigen's result as the Jacobi solver's is
// (round-off of tensors with sizes 1e-4 .. 10: condition numbers up to 1e10).
void check_intersection(const SymTensor3& A, const SymTensor3& B) {
  const SymTensor3 eigen = reference_intersection(A, B, false);
  const double jacobi_error = rel_diff(reference_intersection(A, B, true), eigen);
  CHECK(rel_diff(intersect(A, B), eigen) <= std::fmax(10 * jacobi_error, 1e-11));
}

}  // namespace

TEST_CASE("metric: the closed-form largest eigenvalue agrees with Jacobi, repeated eigenvalues included") {
  std::mt19937 rng(11);
  for (int k = 0; k < 2000; ++k) {
    const SymTensor3 M = random_metric(rng, 1e-3, 1.0);
    const double jacobi = eigen_decompose(M).values[2];
    CHECK(largest_eigenvalue(M) == doctest::Approx(jacobi).epsilon(1e-12));
    const SymTensor3 N = random_metric(rng, 1e-2, 1.0);
    CHECK(largest_generalized_eigenvalue(M, N) == doctest::Approx(generalized_eigenvalues(M, N)[2]).epsilon(1e-11));
  }
  const Vec3 a = normalized(Vec3(1, 2, 3)), b = normalized(cross(a, Vec3(0, 0, 1))), c = cross(a, b);
  for (const std::array<double, 3>& sizes : std::initializer_list<std::array<double, 3>>{
           {1, 1, 1}, {0.1, 1, 1}, {0.1, 0.1, 1}, {1e-4, 1, 1}, {1, 1, 1e-4}, {0.5, 0.5, 0.5 * (1 + 1e-12)}}) {
    const SymTensor3 M = metric_from_sizes(sizes, {a, b, c});
    CHECK(largest_eigenvalue(M) == doctest::Approx(eigen_decompose(M).values[2]).epsilon(1e-12));
  }
  CHECK(largest_eigenvalue(SymTensor3::diagonal(3, -7, 2)) == 3);
  CHECK(largest_eigenvalue(SymTensor3(1, 1, 1, 0, 0, 0)) == doctest::Approx(2).epsilon(1e-15));  // rank 1 block
  CHECK(std::isnan(largest_generalized_eigenvalue(SymTensor3::identity(), SymTensor3(1, 2, 1, 0, 0, 1))));
}

TEST_CASE("metric: the intersection is as accurate as with the Jacobi solver, strong anisotropy and equal eigenvalues") {
  std::mt19937 rng(5);
  for (int k = 0; k < 2000; ++k) {
    const SymTensor3 A = random_metric(rng, 1e-4, 10.0), B = random_metric(rng, 1e-4, 10.0);
    check_intersection(A, B);
    // B propagated from A, as the gradation does: a scaled copy of A, or A
    // with one direction stretched (a double eigenvalue of A^-1 B).
    for (double s : {0.5, 1.0, 2.0}) check_intersection(A, s * A);
    const Vec3 u = normalized(Vec3(1, -2, 0.5));
    const SymTensor3 C = A + 3.0 * quad(A, u) * SymTensor3::outer(u);
    check_intersection(A, C);
    CHECK(rel_diff(intersect(C, A), C) < 1e-12);
  }
}

TEST_CASE("metric: storage follows the .sol order m11 m12 m22 m13 m23 m33") {
  SymTensor3 M(1, 2, 3, 4, 5, 6);
  CHECK(M(0, 0) == 1);
  CHECK(M(0, 1) == 2);
  CHECK(M(1, 0) == 2);
  CHECK(M(1, 1) == 3);
  CHECK(M(0, 2) == 4);
  CHECK(M(2, 0) == 4);
  CHECK(M(1, 2) == 5);
  CHECK(M(2, 1) == 5);
  CHECK(M(2, 2) == 6);
  const Vec3 u(1, -2, 0.5);
  const Eigen::Vector3d ue(1, -2, 0.5);
  CHECK(quad(M, u) == doctest::Approx(ue.dot(to_eigen(M) * ue)).epsilon(1e-14));
  CHECK(det(M) == doctest::Approx(to_eigen(M).determinant()).epsilon(1e-14));
  const SymTensor3 Mi = inverse(SymTensor3(4, 1, 3, 0.5, -0.2, 2));
  const Eigen::Matrix3d prod = to_eigen(Mi) * to_eigen(SymTensor3(4, 1, 3, 0.5, -0.2, 2));
  CHECK((prod - Eigen::Matrix3d::Identity()).norm() < 1e-14);
}

TEST_CASE("metric: eq. 3, an isotropic metric gives every vector of length h the unit length") {
  const double h = 0.05;
  const SymTensor3 M = isotropic_metric(h);
  std::mt19937 rng(1);
  for (int k = 0; k < 10; ++k) {
    auto f = random_frame(rng);
    CHECK(metric_length(M, h * f[0]) == doctest::Approx(1.0).epsilon(1e-14));
  }
}

TEST_CASE("metric: eq. 1, h_i d_i has unit length and sizes come back with their directions") {
  // Sizes within a factor 100 of each other: the tensor's rounding (relative
  // to its largest eigenvalue) stays far below the tolerances.
  std::mt19937 rng(2);
  for (int k = 0; k < 200; ++k) {
    std::array<double, 3> h;
    std::array<Vec3, 3> d;
    const SymTensor3 M = random_metric(rng, 1e-2, 1.0, &h, &d);
    for (int i = 0; i < 3; ++i) CHECK(metric_length(M, h[i] * d[i]) == doctest::Approx(1.0).epsilon(1e-12));
    const SizesDirections sd = sizes_and_directions(M);
    CHECK(sd.sizes[0] >= sd.sizes[1]);
    CHECK(sd.sizes[1] >= sd.sizes[2]);
    // Each recovered pair satisfies M d = h^-2 d.
    const double lmax = 1.0 / (sd.sizes[2] * sd.sizes[2]);
    for (int i = 0; i < 3; ++i) {
      const Vec3 r = M * sd.directions[i] - (1.0 / (sd.sizes[i] * sd.sizes[i])) * sd.directions[i];
      CHECK(norm(r) <= 1e-14 * lmax);
    }
    std::array<double, 3> sorted = h;
    std::sort(sorted.begin(), sorted.end(), std::greater<double>());
    for (int i = 0; i < 3; ++i) CHECK(sd.sizes[i] == doctest::Approx(sorted[i]).epsilon(1e-11));
  }
}

TEST_CASE("metric: Jacobi eigen-decomposition agrees with Eigen's SelfAdjointEigenSolver") {
  std::mt19937 rng(3);
  double worst_vs_eigen = 0, worst_vs_exact = 0, worst_residual = 0, worst_orth = 0;
  for (int k = 0; k < 2000; ++k) {
    std::array<double, 3> h;
    const SymTensor3 M = random_metric(rng, 1e-6, 1e0, &h);  // size ratios up to 1e6
    const SymEigen3 e = eigen_decompose(M);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref(to_eigen(M));
    const double lmax = ref.eigenvalues()(2);
    std::array<double, 3> exact = {1 / (h[0] * h[0]), 1 / (h[1] * h[1]), 1 / (h[2] * h[2])};
    std::sort(exact.begin(), exact.end());
    // Backward stability: errors relative to the largest eigenvalue (the
    // stored tensor itself is only known to that accuracy).
    for (int i = 0; i < 3; ++i) {
      worst_vs_eigen = std::max(worst_vs_eigen, std::fabs(e.values[i] - ref.eigenvalues()(i)) / lmax);
      worst_vs_exact = std::max(worst_vs_exact, std::fabs(e.values[i] - exact[i]) / lmax);
    }
    worst_residual = std::max(worst_residual, rel_diff(compose(e.values, e.vectors), M));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        worst_orth = std::max(worst_orth, std::fabs(dot(e.vectors[i], e.vectors[j]) - (i == j ? 1.0 : 0.0)));
  }
  MESSAGE("max |lambda - lambda_Eigen| / lambda_max = " << worst_vs_eigen << ", vs exact " << worst_vs_exact
                                                        << ", reconstruction " << worst_residual
                                                        << ", orthogonality " << worst_orth);
  CHECK(worst_vs_eigen < 1e-14);
  CHECK(worst_vs_exact < 1e-14);
  CHECK(worst_residual < 1e-14);
  CHECK(worst_orth < 1e-14);
}

TEST_CASE("metric: Jacobi keeps tiny eigenvalues of graded diagonal-dominant tensors to full relative accuracy") {
  // diag(1, 1e-4, 1e-8) with small couplings: the eigenvalues are known to
  // relative accuracy from perturbation theory for graded matrices; compare
  // with the diagonal corrected to second order.
  const double a = 1, b = 1e-4, c = 1e-8, eps = 1e-3;
  const SymTensor3 M(a, eps * std::sqrt(a * b), b, 0, eps * std::sqrt(b * c), c);
  const SymEigen3 e = eigen_decompose(M);
  // Second-order perturbation: lambda_c ~ c - (eps^2 b c)/(b - c).
  const double lc = c - eps * eps * b * c / (b - c);
  CHECK(e.values[0] == doctest::Approx(lc).epsilon(1e-9));
  CHECK(e.values[0] * e.values[1] * e.values[2] == doctest::Approx(det(M)).epsilon(1e-13));
}

TEST_CASE("metric: eigen-decomposition of degenerate, diagonal, indefinite and non-finite tensors") {
  SymEigen3 e = eigen_decompose(SymTensor3::identity(7));
  for (double v : e.values) CHECK(v == 7);
  e = eigen_decompose(SymTensor3::diagonal(3, 1, 2));
  CHECK(e.values == std::array<double, 3>{1, 2, 3});
  CHECK(std::fabs(e.vectors[0].y) == 1);
  e = eigen_decompose(SymTensor3());
  for (double v : e.values) CHECK(v == 0);
  // Two equal eigenvalues (a rotated diag(1, 1, 100)).
  std::mt19937 rng(4);
  auto f = random_frame(rng);
  const SymTensor3 M = metric_from_sizes({1, 1, 0.1}, f);
  e = eigen_decompose(M);
  CHECK(e.values[0] == doctest::Approx(1).epsilon(1e-14));
  CHECK(e.values[1] == doctest::Approx(1).epsilon(1e-14));
  CHECK(e.values[2] == doctest::Approx(100).epsilon(1e-14));
  CHECK(std::fabs(dot(e.vectors[2], f[2])) == doctest::Approx(1).epsilon(1e-14));
  // Indefinite tensor: eigenvalues -1, 2, 5 in a rotated frame.
  e = eigen_decompose(compose({5, -1, 2}, f));
  CHECK(e.values[0] == doctest::Approx(-1).epsilon(1e-14));
  CHECK(e.values[1] == doctest::Approx(2).epsilon(1e-14));
  CHECK(e.values[2] == doctest::Approx(5).epsilon(1e-14));
  e = eigen_decompose(SymTensor3(1, NAN, 1, 0, 0, 1));
  CHECK(std::isnan(e.values[0]));
}

TEST_CASE("metric: closed-form 2x2 decomposition and eq. 1 in 2D") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), lh(std::log(1e-2), 0.0);
  for (int k = 0; k < 500; ++k) {
    const double h1 = std::exp(lh(rng)), h2 = std::exp(lh(rng)), a = ang(rng);
    const SymTensor2 M = metric_from_sizes(h1, h2, a);
    // h1 (cos a, sin a) has unit length.
    CHECK(quad(M, h1 * std::cos(a), h1 * std::sin(a)) == doctest::Approx(1).epsilon(1e-11));
    CHECK(quad(M, -h2 * std::sin(a), h2 * std::cos(a)) == doctest::Approx(1).epsilon(1e-11));
    const SymEigen2 e = eigen_decompose(M);
    const double lo = std::min(1 / (h1 * h1), 1 / (h2 * h2)), hi = std::max(1 / (h1 * h1), 1 / (h2 * h2));
    CHECK(e.values[0] == doctest::Approx(lo).epsilon(1e-11));
    CHECK(e.values[1] == doctest::Approx(hi).epsilon(1e-13));
    const SymTensor2 back = compose(e.values, e.angle);
    for (int i = 0; i < 3; ++i) CHECK(std::fabs(back.m[i] - M.m[i]) <= 1e-13 * hi);
  }
}

TEST_CASE("metric: validity checks name the vertex and the reason") {
  CHECK(is_spd(isotropic_metric(0.1)));
  CHECK_FALSE(is_spd(SymTensor3(1, 2, 1, 0, 0, 1)));  // eigenvalue -1
  CHECK_FALSE(is_spd(SymTensor3(1, 0, 1, 0, 0, 0)));  // singular
  CHECK_FALSE(is_spd(SymTensor3(1, 0, 1, 0, 0, INFINITY)));
  CHECK(is_spd(SymTensor2(2, 1, 1)));
  CHECK_FALSE(is_spd(SymTensor2(1, 1, 1)));
  CHECK(metric_problem(isotropic_metric(1)).empty());
  CHECK_NOTHROW(check_metric(isotropic_metric(1), 0));
  try {
    check_metric(SymTensor3(1, 0, 1, NAN, 0, 1), 41);
    FAIL("no exception");
  } catch (const MetricError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("vertex 42") != std::string::npos);
    CHECK(msg.find("m13") != std::string::npos);
  }
  try {
    check_metric(SymTensor3(1, 2, 1, 0, 0, 1), 6);
    FAIL("no exception");
  } catch (const MetricError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("vertex 7") != std::string::npos);
    CHECK(msg.find("not positive definite") != std::string::npos);
  }
}

TEST_CASE("metric: log, exp and powers are inverse to each other") {
  std::mt19937 rng(6);
  for (int k = 0; k < 100; ++k) {
    const SymTensor3 M = random_metric(rng, 1e-2, 1.0);  // condition number <= 1e4
    CHECK(rel_diff(tensor_exp(tensor_log(M)), M) < 1e-12);
    const SymTensor3 r = tensor_power(M, 0.5);
    const Eigen::Matrix3d rr = to_eigen(r) * to_eigen(r);
    CHECK((rr - to_eigen(M)).norm() / to_eigen(M).norm() < 1e-12);
    CHECK(rel_diff(tensor_power(M, -1), inverse(M)) < 1e-11);
  }
}

TEST_CASE("metric: the intersection is contained in both metrics and is the smallest such in the reduced basis") {
  std::mt19937 rng(7);
  for (int k = 0; k < 500; ++k) {
    const SymTensor3 A = random_metric(rng, 1e-2, 1.0), B = random_metric(rng, 1e-2, 1.0);
    const SymTensor3 I = intersect(A, B);
    CHECK(is_spd(I));
    // u^T I u >= max(u^T A u, u^T B u) for all u: I - A and I - B are PSD.
    const auto ga = generalized_eigenvalues(I, A), gb = generalized_eigenvalues(I, B);
    CHECK(ga[0] >= 1 - 1e-9);
    CHECK(gb[0] >= 1 - 1e-9);
    // Tight: in the basis of the simultaneous reduction the result is
    // diag(max(1, d_i)), so det(I) = det(A) prod max(1, d_i).
    const auto d = generalized_eigenvalues(B, A);
    double expect = det(A);
    for (double x : d) expect *= std::max(1.0, x);
    CHECK(det(I) == doctest::Approx(expect).epsilon(1e-8));
    // Symmetric in its arguments.
    CHECK(rel_diff(intersect(B, A), I) < 1e-8);
  }
  // Contained metric: the intersection is the larger one.
  const SymTensor3 small = isotropic_metric(1.0), big = isotropic_metric(0.1);
  CHECK(rel_diff(intersect(small, big), big) < 1e-14);
  CHECK(intersect(big, small) == big);
  // Orthogonal thin ellipses: diag(100, 1, 1) and diag(1, 100, 1) -> diag(100, 100, 1).
  CHECK(rel_diff(intersect(SymTensor3::diagonal(100, 1, 1), SymTensor3::diagonal(1, 100, 1)),
                 SymTensor3::diagonal(100, 100, 1)) < 1e-14);
}

TEST_CASE("metric: clamping sizes and anisotropy keeps the directions") {
  std::mt19937 rng(8);
  auto f = random_frame(rng);
  const SymTensor3 M = metric_from_sizes({10.0, 0.5, 1e-4}, f);
  MetricBounds b;
  b.hmin = 1e-3;
  b.hmax = 2.0;
  SizesDirections sd = sizes_and_directions(clamp_metric(M, b));
  // Tolerances: the input spans eigenvalues 1e-2 .. 1e8.
  CHECK(sd.sizes[0] == doctest::Approx(2.0).epsilon(1e-8));
  CHECK(sd.sizes[1] == doctest::Approx(0.5).epsilon(1e-8));
  CHECK(sd.sizes[2] == doctest::Approx(1e-3).epsilon(1e-12));
  CHECK(std::fabs(dot(sd.directions[0], f[0])) == doctest::Approx(1).epsilon(1e-10));
  b.max_anisotropy = 100;
  sd = sizes_and_directions(clamp_metric(M, b));
  CHECK(sd.sizes[0] == doctest::Approx(0.1).epsilon(1e-10));
  CHECK(sd.sizes[1] == doctest::Approx(0.1).epsilon(1e-10));
  CHECK(sd.sizes[2] == doctest::Approx(1e-3).epsilon(1e-12));
  b.hmin = 3;
  CHECK_THROWS_AS(clamp_metric(M, b), MetricError);
}
