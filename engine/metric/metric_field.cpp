#include "metric/metric_field.h"

namespace anisurf {

namespace {

int file_index(int v, const std::vector<int>& vertex_origin) {
  return v < static_cast<int>(vertex_origin.size()) && vertex_origin[v] >= 0 ? vertex_origin[v] : v;
}

}  // namespace

std::string embedded_metric_name(const SurfaceMesh& mesh) {
  for (const FieldInfo& f : mesh.fields())
    if (f.name == "metric") return f.name;
  for (const FieldInfo& f : mesh.fields())
    if (f.kind == FieldKind::Tensor) return f.name;
  return {};
}

MetricField metric_from_field(const SurfaceMesh& mesh, const std::string& name,
                              const std::vector<int>& vertex_origin) {
  const FieldInfo* chosen = nullptr;
  for (const FieldInfo& f : mesh.fields()) {
    if (!name.empty()) {
      if (f.name == name) chosen = &f;
      continue;
    }
    if (f.kind == FieldKind::Tensor) {
      chosen = &f;
      break;
    }
    if (!chosen && f.kind == FieldKind::Scalar) chosen = &f;
  }
  if (!chosen)
    throw MetricError(name.empty() ? "no metric: the mesh has no tensor or scalar field (give a .sol)"
                                   : "no field named '" + name + "' on the mesh");
  const bool tensor = chosen->kind == FieldKind::Tensor;
  if (!(tensor && (chosen->ncomp == 6 || chosen->ncomp == 3)) && !(chosen->kind == FieldKind::Scalar && chosen->ncomp == 1))
    throw MetricError("field '" + chosen->name + "' is neither a size (1 scalar) nor a metric (3 or 6 tensor components)");
  const Property<FieldValue> p = mesh.get_field(chosen->name);
  MetricField metric(mesh.vertex_capacity(), SymTensor3::identity());
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    const FieldValue& f = p.at(i);
    if (!tensor) {
      const double h = f[0];
      if (!(h > 0) || !std::isfinite(h))
        throw MetricError("size at vertex " + std::to_string(file_index(i, vertex_origin) + 1) +
                          " (1-based): h = " + std::to_string(h) + ", expected a finite h > 0");
      metric[i] = isotropic_metric(h);
    } else if (chosen->ncomp == 6) {
      metric[i] = SymTensor3(f);
    } else {
      metric[i] = SymTensor3(f[0], f[1], f[2], 0, 0, 1);
    }
  }
  check_metric_field(mesh, metric, vertex_origin);
  return metric;
}

void check_metric_field(const SurfaceMesh& mesh, const MetricField& metric, const std::vector<int>& vertex_origin) {
  if (static_cast<int>(metric.size()) != mesh.vertex_capacity())
    throw MetricError("metric field has " + std::to_string(metric.size()) + " entries for " +
                      std::to_string(mesh.vertex_capacity()) + " vertex slots");
  for (Vertex v : mesh.vertices()) check_metric(metric[v.idx], file_index(v.idx, vertex_origin));
}

void set_metric_field(SurfaceMesh& mesh, const MetricField& metric, const std::string& name) {
  Property<FieldValue> p = mesh.get_field(name);
  if (!p) p = mesh.add_field(name, FieldKind::Tensor, 6);
  for (int i = 0; i < mesh.vertex_capacity() && i < static_cast<int>(metric.size()); ++i) p.at(i) = metric[i].m;
}

std::vector<std::array<int, 2>> mesh_edges(const SurfaceMesh& mesh) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(static_cast<std::size_t>(mesh.n_triangles()) * 3 / 2 + 16);
  for (Corner c : mesh.edges()) edges.push_back({mesh.edge_from(c).idx, mesh.edge_to(c).idx});
  return edges;
}

std::vector<Vec3> vertex_positions(const SurfaceMesh& mesh) {
  std::vector<Vec3> pos(mesh.vertex_capacity());
  for (Vertex v : mesh.vertices()) pos[v.idx] = mesh.position(v);
  return pos;
}

GradationReport gradate_metric(const SurfaceMesh& mesh, MetricField& metric, const GradationOptions& options) {
  return gradate_metric(vertex_positions(mesh), mesh_edges(mesh), metric, options);
}

void clamp_metric_field(const SurfaceMesh& mesh, MetricField& metric, const MetricBounds& bounds) {
  for (Vertex v : mesh.vertices()) metric[v.idx] = clamp_metric(metric[v.idx], bounds);
}

}  // namespace anisurf
