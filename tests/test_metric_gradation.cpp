// Anisotropic size gradation: never increases a size, leaves no edge above
// the ratio, is idempotent and converges (checked by sampling directions, not
// with the code under test).
#include <doctest/doctest.h>

#include <random>

#include "metric/gradation.h"

using namespace anisurf;

namespace {

struct Grid {
  std::vector<Vec3> pos;
  std::vector<std::array<int, 2>> edges;
};

// n x n vertices on [0,1]^2 (slightly wavy in z), edges of a triangulated grid.
Grid make_grid(int n) {
  Grid g;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      g.pos.emplace_back(x, y, 0.05 * std::sin(3 * x) * std::cos(2 * y));
    }
  auto id = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) g.edges.push_back({id(i, j), id(i + 1, j)});
      if (j + 1 < n) g.edges.push_back({id(i, j), id(i, j + 1)});
      if (i + 1 < n && j + 1 < n) g.edges.push_back({id(i, j), id(i + 1, j + 1)});
    }
  return g;
}

SymTensor3 random_spd(std::mt19937& rng, double h_lo, double h_hi) {
  std::uniform_real_distribution<double> u(std::log(h_lo), std::log(h_hi));
  std::normal_distribution<double> g;
  Vec3 a = normalized(Vec3(g(rng), g(rng), g(rng)));
  Vec3 b = normalized(cross(a, Vec3(g(rng), g(rng), g(rng))));
  return metric_from_sizes({std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng))}, {a, b, cross(a, b)});
}

// Unit directions to sample sizes h_M(u) = (u^T M u)^-1/2.
std::vector<Vec3> sample_directions(int n) {
  std::mt19937 rng(99);
  std::normal_distribution<double> g;
  std::vector<Vec3> out = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  while (static_cast<int>(out.size()) < n) out.push_back(normalized(Vec3(g(rng), g(rng), g(rng))));
  return out;
}
double size_in(const SymTensor3& M, const Vec3& u) { return 1.0 / std::sqrt(quad(M, u)); }

// Largest h_q(u) / h_p(u) over sampled u divided by the metric-space bound
// 1 + l_{M_p}(e) ln(ratio), both directions of every edge.
double worst_metric_space_ratio(const Grid& g, const std::vector<SymTensor3>& M, double ratio,
                                const std::vector<Vec3>& dirs) {
  double worst = 0;
  for (const auto& e : g.edges)
    for (int s = 0; s < 2; ++s) {
      const int p = e[s], q = e[1 - s];
      const double bound = 1.0 + metric_length(M[p], g.pos[q] - g.pos[p]) * std::log(ratio);
      for (const Vec3& u : dirs) worst = std::max(worst, size_in(M[q], u) / size_in(M[p], u) / bound);
    }
  return worst;
}

}  // namespace

TEST_CASE("gradation: propagated metrics follow the two growth laws") {
  const SymTensor3 Mp = SymTensor3::diagonal(1e4, 1e2, 1);  // sizes 0.01, 0.1, 1
  const Vec3 e(0.02, 0, 0);                                  // metric length 2
  GradationOptions o;
  o.ratio = 1.5;
  const SymTensor3 P = propagate_metric(Mp, e, o);
  const double eta = 1 / (1 + 2 * std::log(1.5));
  CHECK(size_in(P, Vec3(1, 0, 0)) == doctest::Approx(0.01 / eta).epsilon(1e-14));
  CHECK(size_in(P, Vec3(0, 0, 1)) == doctest::Approx(1.0 / eta).epsilon(1e-14));
  o.space = GradationSpace::Physical;
  const SymTensor3 Q = propagate_metric(Mp, e, o);
  CHECK(size_in(Q, Vec3(1, 0, 0)) == doctest::Approx(0.01 + 0.02 * std::log(1.5)).epsilon(1e-13));
  CHECK(size_in(Q, Vec3(0, 1, 0)) == doctest::Approx(0.1 + 0.02 * std::log(1.5)).epsilon(1e-13));
  CHECK(size_in(Q, Vec3(0, 0, 1)) == doctest::Approx(1.0 + 0.02 * std::log(1.5)).epsilon(1e-13));
  // Excess: M_q = M_p is graded (sizes only grow along the edge).
  CHECK(gradation_excess(Mp, Mp, e, o) <= 1.0);
  // M_q with a size 3 times that of p along x: excess 3 eta.
  o.space = GradationSpace::Metric;
  CHECK(gradation_excess(Mp, SymTensor3::diagonal(1e4 / 9, 1e2, 1), e, o) ==
        doctest::Approx(3 * eta).epsilon(1e-12));
  std::vector<SymTensor3> one(1, Mp);
  GradationOptions bad;
  bad.ratio = 1.0;
  CHECK_THROWS_AS(gradate_metric({Vec3()}, {}, one, bad), MetricError);
  std::vector<SymTensor3> two = {Mp, SymTensor3(1, 2, 1, 0, 0, 1)};
  CHECK_THROWS_WITH_AS(gradate_metric({Vec3(), Vec3(1, 0, 0)}, {{0, 1}}, two, GradationOptions{}),
                       doctest::Contains("vertex 2"), MetricError);
}

TEST_CASE("gradation: a random anisotropic field on a grid, metric and physical space") {
  const Grid g = make_grid(30);
  std::mt19937 rng(21);
  std::vector<SymTensor3> original;
  for (size_t i = 0; i < g.pos.size(); ++i) original.push_back(random_spd(rng, 1e-3, 0.2));
  const auto dirs = sample_directions(200);
  for (GradationSpace space : {GradationSpace::Metric, GradationSpace::Physical}) {
    GradationOptions o;
    o.ratio = 1.3;
    o.space = space;
    o.measure_excess = true;
    std::vector<SymTensor3> M = original;
    const GradationReport r = gradate_metric(g.pos, g.edges, M, o);
    MESSAGE(std::string(space == GradationSpace::Metric ? "metric" : "physical")
            << " space: " << r.updates << " updates, " << r.edge_checks << " checks, " << r.vertices_changed
            << " vertices changed, max excess before " << r.max_excess_before);
    CHECK(r.converged);
    CHECK(r.updates > 0);
    CHECK(r.max_excess_before > 2);
    // Never increases a size (sampled directions, and the whole ellipsoid).
    double worst_growth = 0;
    for (size_t i = 0; i < M.size(); ++i) {
      for (const Vec3& u : dirs) worst_growth = std::max(worst_growth, size_in(M[i], u) / size_in(original[i], u));
      CHECK(generalized_eigenvalues(original[i], M[i])[2] <= 1 + 1e-12);
    }
    CHECK(worst_growth <= 1 + 1e-12);
    // No edge above the ratio.
    double worst_excess = 0;
    for (const auto& e : g.edges)
      worst_excess = std::max(worst_excess, edge_gradation_excess(M[e[0]], M[e[1]], g.pos[e[1]] - g.pos[e[0]], o));
    CHECK(worst_excess <= 1 + 1.01 * o.tolerance);
    if (space == GradationSpace::Metric) CHECK(worst_metric_space_ratio(g, M, o.ratio, dirs) <= 1 + 1.01 * o.tolerance);
    // Idempotent: a second pass changes nothing, bit for bit.
    std::vector<SymTensor3> again = M;
    const GradationReport r2 = gradate_metric(g.pos, g.edges, again, o);
    CHECK(r2.updates == 0);
    CHECK(again == M);
    CHECK(r2.max_excess_before <= 1 + 1.01 * o.tolerance);
  }
}

TEST_CASE("gradation: a single small size spreads geometrically in metric space") {
  // A line of vertices 0.01 apart, isotropic size 1 except 0.01 at vertex 0.
  std::vector<Vec3> pos;
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i < 200; ++i) {
    pos.emplace_back(0.01 * i, 0, 0);
    if (i) edges.push_back({i - 1, i});
  }
  std::vector<SymTensor3> M(pos.size(), isotropic_metric(1.0));
  M[0] = isotropic_metric(0.01);
  GradationOptions o;
  o.ratio = 2.0;
  gradate_metric(pos, edges, M, o);
  // Metric space: h_{i+1} = h_i (1 + (0.01 / h_i) ln 2) = h_i + 0.01 ln 2 (the
  // edge has metric length 0.01 / h_i): linear growth until the size reaches 1.
  for (int i = 1; i < 50; ++i) {
    const double expect = std::min(1.0, 0.01 + i * 0.01 * std::log(2.0));
    CHECK(size_in(M[i], Vec3(1, 0, 0)) == doctest::Approx(expect).epsilon(1e-9));
  }
  CHECK(size_in(M[199], Vec3(1, 0, 0)) == doctest::Approx(1.0).epsilon(1e-12));
}
