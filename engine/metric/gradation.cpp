#include "metric/gradation.h"

#include <cmath>
#include <algorithm>
#include <utility>
#include <vector>

namespace anisurf {

namespace {

// Whether the largest eigenvalue of Mq^-1 P is below `factor`: factor Mq - P
// positive definite, its L D L^T factorisation with positive pivots (no
// eigen-decomposition, no square root). False for non-finite entries.
bool contains_scaled(const SymTensor3& Mq, double factor, const SymTensor3& P) {
  const SymTensor3 A = factor * Mq - P;
  const auto& a = A.m;
  if (!(a[0] > 0)) return false;
  const double l10 = a[1] / a[0], l20 = a[3] / a[0];
  const double d1 = a[2] - l10 * a[1];
  if (!(d1 > 0)) return false;
  const double r21 = a[4] - l20 * a[1];  // d1 l21
  const double d2 = a[5] - l20 * a[3] - r21 * r21 / d1;
  return d2 > 0;
}

// propagate_metric with ln(ratio) computed once by the caller.
SymTensor3 propagated(const SymTensor3& Mp, const Vec3& e, GradationSpace space, double log_ratio) {
  if (space == GradationSpace::Metric) {
    const double eta = 1.0 / (1.0 + metric_length(Mp, e) * log_ratio);
    return (eta * eta) * Mp;
  }
  SymEigen3 d = eigen_decompose(Mp);
  const double len = norm(e);
  for (double& v : d.values) {
    const double g = 1.0 + std::sqrt(v) * len * log_ratio;
    v /= g * g;
  }
  return compose(d.values, d.vectors);
}

// The neighbours of each vertex along the edges, in compressed rows.
struct Adjacency {
  std::vector<int> start, neighbour;
  Adjacency(int n, const std::vector<std::array<int, 2>>& edges) : start(n + 1, 0), neighbour(2 * edges.size()) {
    for (const auto& e : edges) {
      ++start[e[0] + 1];
      ++start[e[1] + 1];
    }
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& e : edges) {
      neighbour[fill[e[0]]++] = e[1];
      neighbour[fill[e[1]]++] = e[0];
    }
  }
};

// The vertices whose metric is still to be spread to their neighbours, the
// finest first (largest trace, a proxy for the largest eigenvalue within a
// factor 3): a small size reaches its neighbourhood before the coarser ones
// it overrides, so most vertices are updated once or twice (first in first
// out, waves from successive sources updated each vertex ~30 times on a CAD
// part's curvature metric). Entries are pushed again when a metric grows;
// stale ones (key below the vertex's current trace) are skipped.
class WorkList {
 public:
  explicit WorkList(const std::vector<SymTensor3>& metric) : metric_(metric) {
    heap_.reserve(metric.size());
    for (int v = 0; v < static_cast<int>(metric.size()); ++v) heap_.push_back({trace(v), v});
    std::make_heap(heap_.begin(), heap_.end());
  }
  void push(int v) {
    heap_.push_back({trace(v), v});
    std::push_heap(heap_.begin(), heap_.end());
  }
  // The next vertex, or -1 when none is left.
  int pop() {
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end());
      const auto [key, v] = heap_.back();
      heap_.pop_back();
      if (key >= trace(v)) return v;
    }
    return -1;
  }

 private:
  double trace(int v) const {
    const auto& a = metric_[static_cast<std::size_t>(v)].m;
    return a[0] + a[2] + a[5];
  }
  const std::vector<SymTensor3>& metric_;
  std::vector<std::pair<double, int>> heap_;
};

// The largest edge_gradation_excess over the edges. An edge direction whose
// excess is below the largest so far (contains_scaled) is not measured.
double largest_excess(const std::vector<Vec3>& positions, const std::vector<std::array<int, 2>>& edges,
                      const std::vector<SymTensor3>& metric, const GradationOptions& options) {
  const double log_ratio = std::log(options.ratio);
  double worst = 1.0;
  for (const auto& e : edges)
    for (int side = 0; side < 2; ++side) {
      const int p = e[side], q = e[1 - side];
      const SymTensor3 P = propagated(metric[p], positions[q] - positions[p], options.space, log_ratio);
      if (contains_scaled(metric[q], worst * worst, P)) continue;
      worst = max_of(worst, std::sqrt(largest_generalized_eigenvalue(P, metric[q])));
    }
  return worst;
}

}  // namespace

SymTensor3 propagate_metric(const SymTensor3& Mp, const Vec3& e, const GradationOptions& options) {
  return propagated(Mp, e, options.space, std::log(options.ratio));
}

double gradation_excess(const SymTensor3& Mp, const SymTensor3& Mq, const Vec3& e, const GradationOptions& options) {
  return std::sqrt(largest_generalized_eigenvalue(propagate_metric(Mp, e, options), Mq));
}

double edge_gradation_excess(const SymTensor3& Mp, const SymTensor3& Mq, const Vec3& e,
                             const GradationOptions& options) {
  return max_of(gradation_excess(Mp, Mq, e, options), gradation_excess(Mq, Mp, -e, options));
}

GradationReport gradate_metric(const std::vector<Vec3>& positions, const std::vector<std::array<int, 2>>& edges,
                               std::vector<SymTensor3>& metric, const GradationOptions& options) {
  if (!(options.ratio > 1.0) || !std::isfinite(options.ratio))
    throw MetricError("gradation ratio must be a finite number > 1 (got " + std::to_string(options.ratio) + ")");
  if (metric.size() != positions.size())
    throw MetricError("gradation: " + std::to_string(metric.size()) + " metrics for " +
                      std::to_string(positions.size()) + " vertices");
  const int n = static_cast<int>(positions.size());
  for (const auto& e : edges) {
    if (e[0] < 0 || e[1] < 0 || e[0] >= n || e[1] >= n)
      throw MetricError("gradation: edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) +
                        ") refers to a vertex out of range");
    check_metric(metric[e[0]], e[0]);
    check_metric(metric[e[1]], e[1]);
  }
  const Adjacency adjacency(n, edges);
  GradationReport report;
  if (options.measure_excess) report.max_excess_before = largest_excess(positions, edges, metric, options);

  const double log_ratio = std::log(options.ratio);
  const double accept = (1.0 + options.tolerance) * (1.0 + options.tolerance);  // on eigenvalues of M_q^-1 P
  const long long cap = static_cast<long long>(options.max_updates_per_vertex) * std::max(n, 1);
  WorkList work(metric);
  std::vector<char> changed(n, 0);
  for (int p = work.pop(); p >= 0; p = work.pop()) {
    for (int k = adjacency.start[p]; k < adjacency.start[p + 1]; ++k) {
      const int q = adjacency.neighbour[k];
      const SymTensor3 P = propagated(metric[p], positions[q] - positions[p], options.space, log_ratio);
      ++report.edge_checks;
      if (contains_scaled(metric[q], accept, P)) continue;
      metric[q] = intersect(metric[q], P);
      ++report.updates;
      changed[q] = 1;
      work.push(q);
    }
    if (report.updates >= cap) {
      report.converged = false;
      break;
    }
  }
  for (char c : changed) report.vertices_changed += c;
  return report;
}

}  // namespace anisurf
