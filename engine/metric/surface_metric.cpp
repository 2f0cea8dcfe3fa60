#include "metric/surface_metric.h"

#include "metric/length.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "geometry/parallel_chunks.h"

namespace anisurf {

std::array<Vec3, 2> tangent_frame(const Vec3& n) {
  // Start from the axis least aligned with n.
  const Vec3 a = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z) ? Vec3(1, 0, 0)
                 : std::fabs(n.y) <= std::fabs(n.z)                                   ? Vec3(0, 1, 0)
                                                                                      : Vec3(0, 0, 1);
  const Vec3 t1 = normalized(a - dot(a, n) * n);
  return {t1, cross(n, t1)};
}

SymTensor2 restrict_to_tangent(const SymTensor3& M, const Vec3& t1, const Vec3& t2) {
  const Vec3 m1 = M * t1;
  return {dot(t1, m1), dot(t2, m1), quad(M, t2)};
}

SymTensor2 restrict_to_tangent(const SymTensor3& M, const Vec3& unit_normal) {
  const auto f = tangent_frame(unit_normal);
  return restrict_to_tangent(M, f[0], f[1]);
}

SymTensor3 extend_from_tangent(const SymTensor2& T, const Vec3& t1, const Vec3& t2, double normal_value) {
  const Vec3 n = cross(t1, t2);
  SymTensor3 out = T.m[0] * SymTensor3::outer(t1) + T.m[2] * SymTensor3::outer(t2) + normal_value * SymTensor3::outer(n);
  // Symmetric part of T12 (t1 t2^T + t2 t1^T).
  const Vec3& a = t1;
  const Vec3& b = t2;
  out += T.m[1] * SymTensor3(2 * a.x * b.x, a.x * b.y + a.y * b.x, 2 * a.y * b.y, a.x * b.z + a.z * b.x,
                             a.y * b.z + a.z * b.y, 2 * a.z * b.z);
  return out;
}

std::vector<Vec3> vertex_normals(const SurfaceMesh& mesh) {
  std::vector<Vec3> n(mesh.vertex_capacity());
  for (Triangle t : mesh.triangles()) {
    const Vec3 tn = mesh.triangle_normal(t);  // twice the area
    for (int k = 0; k < 3; ++k) n[mesh.vertex(t, k).idx] += tn;
  }
  for (Vec3& v : n) v = normalized(v);
  return n;
}

namespace {

// Triangle t's share of the complexity: its area times the mean of
// sqrt(det) of its vertices' metrics restricted to its plane.
template <class MetricAt>
double triangle_complexity(const SurfaceMesh& mesh, Triangle t, const MetricAt& metric_at) {
  const Vec3 tn = mesh.triangle_normal(t);
  const double area2 = norm(tn);
  if (!(area2 > 0)) return 0;
  const auto frame = tangent_frame(tn / area2);
  double s = 0;
  for (int k = 0; k < 3; ++k)
    s += std::sqrt(max_of(det(restrict_to_tangent(metric_at(mesh.vertex(t, k)), frame[0], frame[1])), 0.0));
  return 0.5 * area2 * s / 3.0;
}

}  // namespace

double metric_complexity(const SurfaceMesh& mesh, const std::function<SymTensor3(Vertex)>& metric_at) {
  double c = 0;
  for (Triangle t : mesh.triangles()) c += triangle_complexity(mesh, t, metric_at);
  return c;
}

double metric_complexity(const SurfaceMesh& mesh, const MetricField& metric) {
  // Blocks of triangle slots on the threads, their sums added in block
  // order: the same value for any thread count.
  constexpr int kBlock = 1 << 15;
  const int n = mesh.triangle_capacity();
  const int blocks = (n + kBlock - 1) / kBlock;
  const auto metric_at = [&metric](Vertex v) -> const SymTensor3& { return metric[v.idx]; };
  std::vector<double> sums(static_cast<std::size_t>(blocks), 0.0);
  run_chunks(blocks, chunk_count(blocks, 1), [&](int, int begin, int end) {
    for (int b = begin; b < end; ++b) {
      double c = 0;
      for (int i = b * kBlock, last = std::min(n, (b + 1) * kBlock); i < last; ++i)
        if (!mesh.is_deleted(Triangle(i))) c += triangle_complexity(mesh, Triangle(i), metric_at);
      sums[static_cast<std::size_t>(b)] = c;
    }
  });
  double c = 0;
  for (double x : sums) c += x;
  return c;
}

double predicted_vertices(const SurfaceMesh& mesh, const MetricField& metric) {
  return predicted_vertices(mesh, metric, metric_complexity(mesh, metric));
}

double predicted_vertices(const SurfaceMesh& mesh, const MetricField& metric, double complexity) {
  double boundary = 0;
  int corners = 0, boundary_edges = 0;
  for (Triangle t : mesh.triangles()) {
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(t, k);
      ++corners;
      if (!mesh.is_boundary_edge(c)) continue;
      ++boundary_edges;
      const Vertex a = mesh.vertex(SurfaceMesh::next(c)), b = mesh.vertex(SurfaceMesh::prev(c));
      boundary += edge_length(metric[a.idx], metric[b.idx], mesh.position(b) - mesh.position(a),
                              LengthFormula::LinearMetric);
    }
  }
  const int edges = (corners + boundary_edges) / 2;
  const int euler = mesh.n_vertices() - edges + mesh.n_triangles();
  return std::max(predicted_vertex_count(complexity) + 0.5 * boundary + euler, 3.0);
}

}  // namespace anisurf
