#include "metric/gradation.h"

#include <cmath>
#include <deque>

namespace anisurf {

SymTensor3 propagate_metric(const SymTensor3& Mp, const Vec3& e, const GradationOptions& options) {
  const double log_ratio = std::log(options.ratio);
  if (options.space == GradationSpace::Metric) {
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

double gradation_excess(const SymTensor3& Mp, const SymTensor3& Mq, const Vec3& e, const GradationOptions& options) {
  return std::sqrt(generalized_eigenvalues(propagate_metric(Mp, e, options), Mq)[2]);
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
  // Adjacency in compressed rows.
  std::vector<int> start(n + 1, 0), nbr(2 * edges.size());
  for (const auto& e : edges) {
    ++start[e[0] + 1];
    ++start[e[1] + 1];
  }
  for (int i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& e : edges) {
    nbr[fill[e[0]]++] = e[1];
    nbr[fill[e[1]]++] = e[0];
  }

  GradationReport report;
  for (const auto& e : edges)
    report.max_excess_before =
        std::fmax(report.max_excess_before,
                  edge_gradation_excess(metric[e[0]], metric[e[1]], positions[e[1]] - positions[e[0]], options));

  const double accept = (1.0 + options.tolerance) * (1.0 + options.tolerance);  // on eigenvalues of M_q^-1 P
  const long long cap = static_cast<long long>(options.max_updates_per_vertex) * std::max(n, 1);
  std::deque<int> work;
  std::vector<char> queued(n, 1), changed(n, 0);
  for (int i = 0; i < n; ++i) work.push_back(i);
  while (!work.empty()) {
    const int p = work.front();
    work.pop_front();
    queued[p] = 0;
    for (int k = start[p]; k < start[p + 1]; ++k) {
      const int q = nbr[k];
      const SymTensor3 P = propagate_metric(metric[p], positions[q] - positions[p], options);
      ++report.edge_checks;
      if (generalized_eigenvalues(P, metric[q])[2] <= accept) continue;
      metric[q] = intersect(metric[q], P);
      ++report.updates;
      changed[q] = 1;
      if (!queued[q]) {
        queued[q] = 1;
        work.push_back(q);
      }
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
