// Anisotropic size gradation along the edges of a mesh (in the spirit of
// Alauzet, "Size gradation control of anisotropic meshes", 2010; the ratio
// plays the role of Mmg's -hgrad).
//
// The metric M_p of a vertex p, spread to a neighbour q across the edge
// e = q - p, becomes a propagated metric P_{p->q}:
//   metric space   : P = eta^2 M_p, eta = 1 / (1 + l_{M_p}(e) ln(ratio)):
//                    every size grows by the same factor, at most about
//                    `ratio` per unit metric length;
//   physical space : P = sum_i lambda_i / (1 + sqrt(lambda_i) |e| ln(ratio))^2
//                    v_i v_i^T: every size h_i grows by |e| ln(ratio).
// The field is graded when M_q contains P_{p->q} (u^T M_q u >= u^T P u for
// every u) for every edge in both directions. gradate_metric() enforces it by
// M_q <- M_q intersected with P_{p->q} (section 2.2's simultaneous reduction),
// so sizes only ever decrease, with a work list of vertices to revisit.
#pragma once
#include <array>
#include <vector>

#include "metric/metric.h"

namespace anisurf {

enum class GradationSpace { Metric, Physical };

struct GradationOptions {
  double ratio = 1.3;  // size growth ratio (Mmg's default -hgrad 1.3); must be > 1
  GradationSpace space = GradationSpace::Metric;
  // An edge is accepted when its excess (see gradation_excess) is at most
  // 1 + tolerance; below that nothing is changed (so a second run is a no-op).
  double tolerance = 1e-2;
  // Safety cap on metric updates, times the number of vertices.
  int max_updates_per_vertex = 200;
  // Measure GradationReport::max_excess_before (one more pass over the
  // edges, with a generalized eigenvalue per edge not yet graded).
  bool measure_excess = false;
};

struct GradationReport {
  long long edge_checks = 0;  // propagations tested
  long long updates = 0;      // metrics reduced
  int vertices_changed = 0;   // distinct vertices whose metric changed
  double max_excess_before = 1.0;  // largest gradation_excess over the edges before (measure_excess)
  bool converged = true;      // false if the update cap was hit
};

// P_{p->q}: M_p spread across the edge vector e = x_q - x_p (see above).
SymTensor3 propagate_metric(const SymTensor3& Mp, const Vec3& e, const GradationOptions& options);
// How far M_q is from containing P_{p->q}: sqrt of the largest eigenvalue of
// M_q^-1 P_{p->q}, i.e. the largest ratio h_q(u) / h_P(u) of sizes over
// directions u; <= 1 when the edge is graded from p to q.
double gradation_excess(const SymTensor3& Mp, const SymTensor3& Mq, const Vec3& e, const GradationOptions& options);
// max of both directions of the edge.
double edge_gradation_excess(const SymTensor3& Mp, const SymTensor3& Mq, const Vec3& e,
                             const GradationOptions& options);

// Grades the vertex metrics `metric` (one per position) along `edges`
// (pairs of vertex indices). Throws MetricError if options.ratio <= 1, an edge
// is out of range or a metric on an edge is not SPD (naming the vertex).
GradationReport gradate_metric(const std::vector<Vec3>& positions, const std::vector<std::array<int, 2>>& edges,
                               std::vector<SymTensor3>& metric, const GradationOptions& options = {});

}  // namespace anisurf
