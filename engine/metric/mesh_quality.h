// Measuring a mesh against a metric field: edge lengths in the metric (eq. 6
// or 7), their share in the unit band [1/sqrt2, sqrt2], a histogram, the
// quality c_K of eq. 17 and the mean ratio, and the vertex count the metric
// predicts. The same measures as ../shared/bench/eval.py.
#pragma once
#include <array>
#include <vector>

#include "metric/length.h"
#include "metric/metric_field.h"

namespace anisurf {

struct MeshQualityOptions {
  LengthFormula length = LengthFormula::LinearMetric;        // edge lengths (and c_K from them)
  MetricInterpolation centroid = MetricInterpolation::Linear;  // metric at the centroid (qc, mean ratio)
};

// Upper bounds of the length histogram bins (the last bin is [5, inf)).
inline constexpr std::array<double, 9> kLengthBins = {0.3, 0.6, 0.70710678118654752, 0.9, 1.3,
                                                      1.4142135623730950, 2.0, 5.0, INFINITY};

struct MeshQuality {
  int vertices = 0, triangles = 0, edges = 0;
  double length_min = 0, length_mean = 0, length_max = 0;
  double in_band_share = 0;                  // share of edges with 1/sqrt2 <= l <= sqrt2, in [0, 1]
  std::array<int, kLengthBins.size()> histogram{};  // counts per bin [0,0.3) [0.3,0.6) ...
  double q_min = 0, q_mean = 0;    // eq. 17 with the edge lengths above
  double qc_min = 0, qc_mean = 0;  // eq. 17 in the metric at the centroid
  double mean_ratio_min = 0, mean_ratio_mean = 0;  // mean ratio in the metric at the centroid
  double complexity = 0;           // integral of sqrt(det M) on the surface
  double predicted_vertices = 0;   // 2 C / sqrt(3)
};

// Measures every live edge and triangle. Pre: one SPD metric per vertex slot.
MeshQuality measure_mesh_quality(const SurfaceMesh& mesh, const MetricField& metric,
                                 const MeshQualityOptions& options = {});

}  // namespace anisurf
