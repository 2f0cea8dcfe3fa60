#include "metric/gradation.h"

#include <cmath>
#include <deque>

namespace anisurf {

namespace {

// Whether the largest eigenvalue of Mq^-1 P is below `factor`: factor Mq - P
// positive definite (a Cholesky factorisation, no eigen-decomposition).
bool contains_scaled(const SymTensor3& Mq, double factor, const SymTensor3& P) {
  return is_spd(factor * Mq - P);
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

// The vertices whose metric is still to be spread to their neighbours, first
// in first out, each queued once at a time (all of them at the start).
class WorkList {
 public:
  explicit WorkList(int n) : queued_(n, 1) {
    for (int v = 0; v < n; ++v) fifo_.push_back(v);
  }
  void push(int v) {
    if (queued_[v]) return;
    queued_[v] = 1;
    fifo_.push_back(v);
  }
  // The next vertex, or -1 when none is left.
  int pop() {
    if (fifo_.empty()) return -1;
    const int v = fifo_.front();
    fifo_.pop_front();
    queued_[v] = 0;
    return v;
  }

 private:
  std::deque<int> fifo_;
  std::vector<char> queued_;
};

// The largest edge_gradation_excess over the edges.
double largest_excess(const std::vector<Vec3>& positions, const std::vector<std::array<int, 2>>& edges,
                      const std::vector<SymTensor3>& metric, const GradationOptions& options) {
  double worst = 1.0;
  for (const auto& e : edges)
    worst = std::fmax(worst, edge_gradation_excess(metric[e[0]], metric[e[1]], positions[e[1]] - positions[e[0]], options));
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
  return std::fmax(gradation_excess(Mp, Mq, e, options), gradation_excess(Mq, Mp, -e, options));
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
  report.max_excess_before = largest_excess(positions, edges, metric, options);

  const double log_ratio = std::log(options.ratio);
  const double accept = (1.0 + options.tolerance) * (1.0 + options.tolerance);  // on eigenvalues of M_q^-1 P
  const long long cap = static_cast<long long>(options.max_updates_per_vertex) * std::max(n, 1);
  WorkList work(n);
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
