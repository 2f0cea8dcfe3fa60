#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "geometry/parallel_chunks.h"
#include "geometry/symmetric_cg.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// A sparse symmetric positive definite matrix of size n: a ring of
// couplings to the next `band` unknowns with random weights, made
// diagonally dominant, in both the compressed form and a dense copy.
struct TestSystem {
  SymmetricColumns A;
  Eigen::MatrixXd dense;
};

TestSystem make_system(int n, int band, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> w(-1.0, 1.0);
  std::vector<std::map<int, double>> cols(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int k = 1; k <= band; ++k) {
      const int j = (i + k) % n;
      const double v = w(rng);
      cols[i][j] += v;
      cols[j][i] += v;
    }
  for (int i = 0; i < n; ++i) {
    double off = 0;
    for (const auto& [j, v] : cols[i]) off += std::abs(v);
    cols[i][i] += off + 0.5 + std::abs(w(rng));
  }
  TestSystem s;
  s.A.n = n;
  s.dense = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) {
    for (const auto& [r, v] : cols[c]) {
      s.A.inner.push_back(r);
      s.A.value.push_back(v);
      s.dense(r, c) = v;
    }
    s.A.outer.push_back(static_cast<int>(s.A.inner.size()));
  }
  return s;
}

}  // namespace

TEST_CASE("conjugate gradients: the solution of a sparse SPD system to the tolerance, the same for any thread count") {
  // Large enough for the team of threads (16384 unknowns a thread).
  const int n = 40000;
  const TestSystem s = make_system(n, 3, 7);
  std::vector<double> b(static_cast<std::size_t>(n));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& v : b) v = u(rng);
  std::vector<double> x1, x2;
  CgReport r1, r2;
  {
    test::ThreadLimitScope one(1);
    r1 = solve_conjugate_gradient(s.A, b, 1e-10, 1000, x1);
  }
  {
    test::ThreadLimitScope two(2);
    r2 = solve_conjugate_gradient(s.A, b, 1e-10, 1000, x2);
  }
  MESSAGE("n " << n << ": " << r1.iterations << " iterations, relative residual " << r1.relative_residual);
  CHECK(r1.converged);
  CHECK(r1.relative_residual <= 1e-10);
  CHECK(r1.iterations == r2.iterations);
  CHECK(x1 == x2);  // bit for bit: sums over fixed blocks in a fixed order
  // The residual measured independently of the solver.
  double res2 = 0, b2 = 0;
  for (int u_ = 0; u_ < n; ++u_) {
    double y = 0;
    for (int k = s.A.outer[u_]; k < s.A.outer[u_ + 1]; ++k) y += s.A.value[k] * x1[s.A.inner[k]];
    res2 += (b[u_] - y) * (b[u_] - y);
    b2 += b[u_] * b[u_];
  }
  CHECK(std::sqrt(res2 / b2) <= 2e-10);
}

TEST_CASE("conjugate gradients: matches a dense solve, a zero right-hand side gives zero, the iteration cap is reported") {
  const TestSystem s = make_system(60, 4, 3);
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(60, -1.0, 2.0);
  std::vector<double> bv(b.data(), b.data() + b.size()), x;
  const CgReport r = solve_conjugate_gradient(s.A, bv, 1e-12, 500, x);
  CHECK(r.converged);
  const Eigen::VectorXd expected = s.dense.ldlt().solve(b);
  for (int i = 0; i < 60; ++i) CHECK(x[i] == doctest::Approx(expected(i)).epsilon(1e-9));

  const CgReport zero = solve_conjugate_gradient(s.A, std::vector<double>(60, 0.0), 1e-12, 500, x);
  CHECK(zero.iterations == 0);
  for (double v : x) CHECK(v == 0.0);

  const CgReport capped = solve_conjugate_gradient(s.A, bv, 1e-14, 2, x);
  CHECK(capped.iterations == 2);
  CHECK_FALSE(capped.converged);
  CHECK(capped.relative_residual > 1e-14);
}
