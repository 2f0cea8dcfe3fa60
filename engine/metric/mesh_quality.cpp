#include "metric/mesh_quality.h"

#include <algorithm>
#include <cmath>

#include "metric/quality.h"
#include "metric/surface_metric.h"

namespace anisurf {

MeshQuality measure_mesh_quality(const SurfaceMesh& mesh, const MetricField& metric, const MeshQualityOptions& options) {
  MeshQuality q;
  q.vertices = mesh.n_vertices();
  q.triangles = mesh.n_triangles();
  // Edge lengths, stored per corner so that triangles reuse them.
  std::vector<double> corner_length(static_cast<std::size_t>(mesh.corner_capacity()), 0.0);
  const double lo = 1.0 / std::sqrt(2.0), hi = std::sqrt(2.0);
  double sum = 0;
  int in_band = 0;
  q.length_min = INFINITY;
  q.length_max = 0;
  for (Corner c : mesh.edges()) {  // each edge from its canonical corner
    const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
    const double l = edge_length(metric[a.idx], metric[b.idx], mesh.position(b) - mesh.position(a), options.length);
    corner_length[c.idx] = l;
    const Corner o = mesh.opposite(c);
    if (o.is_valid()) corner_length[o.idx] = l;
    ++q.edges;
    sum += l;
    q.length_min = std::min(q.length_min, l);
    q.length_max = std::max(q.length_max, l);
    if (l >= lo && l <= hi) ++in_band;
    const auto bin = std::upper_bound(kLengthBins.begin(), kLengthBins.end(), l) - kLengthBins.begin();
    ++q.histogram[std::min<std::size_t>(bin, kLengthBins.size() - 1)];
  }
  if (q.edges) {
    q.length_mean = sum / q.edges;
    q.in_band_share = static_cast<double>(in_band) / q.edges;
  } else {
    q.length_min = 0;
  }
  double qs = 0, qcs = 0, mrs = 0;
  q.q_min = q.qc_min = q.mean_ratio_min = q.triangles ? INFINITY : 0.0;
  for (Triangle tr : mesh.triangles()) {
    const std::array<double, 3> l = {corner_length[SurfaceMesh::corner(tr, 0).idx],
                                     corner_length[SurfaceMesh::corner(tr, 1).idx],
                                     corner_length[SurfaceMesh::corner(tr, 2).idx]};
    const double qk = quality_from_lengths(l[0], l[1], l[2]);
    const std::array<Vec3, 3> p = {mesh.position(mesh.vertex(tr, 0)), mesh.position(mesh.vertex(tr, 1)),
                                   mesh.position(mesh.vertex(tr, 2))};
    const SymTensor3 Mc = centroid_metric(
        {metric[mesh.vertex(tr, 0).idx], metric[mesh.vertex(tr, 1).idx], metric[mesh.vertex(tr, 2).idx]},
        options.centroid);
    const double qc = triangle_quality_in(p, Mc), mr = mean_ratio_in(p, Mc);
    qs += qk;
    qcs += qc;
    mrs += mr;
    q.q_min = std::min(q.q_min, qk);
    q.qc_min = std::min(q.qc_min, qc);
    q.mean_ratio_min = std::min(q.mean_ratio_min, mr);
  }
  if (q.triangles) {
    q.q_mean = qs / q.triangles;
    q.qc_mean = qcs / q.triangles;
    q.mean_ratio_mean = mrs / q.triangles;
  }
  q.complexity = metric_complexity(mesh, metric);
  q.predicted_vertices = predicted_vertex_count(q.complexity);
  return q;
}

}  // namespace anisurf
