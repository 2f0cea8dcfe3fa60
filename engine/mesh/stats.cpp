#include "mesh/stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace anisurf {

namespace {

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Boundary loops: follow boundary edges head to tail. At a vertex with several
// outgoing boundary edges (possible only after repairs), any unused one is taken.
int count_boundary_loops(const SurfaceMesh& m) {
  std::vector<int> out_count(m.vertex_capacity(), 0);
  std::vector<std::pair<int, int>> edges;  // (from, to)
  for (Triangle t : m.triangles()) {
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(t, k);
      if (m.is_boundary_edge(c)) edges.push_back({m.edge_from(c).idx, m.edge_to(c).idx});
    }
  }
  // union-find over boundary vertices joined by boundary edges: one loop per
  // component of the boundary graph (every boundary vertex has in = out).
  std::vector<int> parent(m.vertex_capacity());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> on(m.vertex_capacity(), 0);
  for (auto [a, b] : edges) {
    on[a] = on[b] = 1;
    int ra = find_root(parent, a), rb = find_root(parent, b);
    if (ra != rb) parent[ra] = rb;
  }
  int loops = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v)
    if (on[v] && find_root(parent, v) == v) ++loops;
  return loops;
}

}  // namespace

MeshStats compute_stats(const SurfaceMesh& m) {
  MeshStats s;
  s.vertices = m.n_vertices();
  s.triangles = m.n_triangles();
  s.bbox = m.bbox();
  std::vector<int> parent(m.vertex_capacity());
  std::iota(parent.begin(), parent.end(), 0);
  std::set<int> vrefs, trefs, erefs;
  double sum_edge = 0;
  s.min_edge = INFINITY;
  s.max_edge = 0;
  s.min_angle_deg = 180;
  for (Triangle th : m.triangles()) {
    s.area += m.triangle_area(th);
    if (m.triangle_ref(th) != 0) trefs.insert(m.triangle_ref(th));
    if (m.has_tag(th, kRequired)) ++s.required_triangles;
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(th, k);
      int a = m.edge_from(c).idx, b = m.edge_to(c).idx;
      int ra = find_root(parent, a), rb = find_root(parent, b);
      if (ra != rb) parent[ra] = rb;
      // angle at corner c
      Vec3 p = m.position(m.vertex(c));
      Vec3 u = m.position(Vertex(a)) - p, w = m.position(Vertex(b)) - p;
      double nu = norm(u), nw = norm(w);
      if (nu > 0 && nw > 0) {
        double cosang = std::clamp(dot(u, w) / (nu * nw), -1.0, 1.0);
        s.min_angle_deg = std::min(s.min_angle_deg, std::acos(cosang) * 180.0 / M_PI);
      } else {
        s.min_angle_deg = 0;
      }
      if (m.canonical(c) != c) continue;
      ++s.edges;
      double len = norm(m.position(Vertex(a)) - m.position(Vertex(b)));
      sum_edge += len;
      s.min_edge = std::min(s.min_edge, len);
      s.max_edge = std::max(s.max_edge, len);
      std::uint8_t tg = m.edge_tags(c);
      if (m.is_boundary_edge(c)) ++s.boundary_edges;
      if (tg & kRidge) ++s.ridge_edges;
      if (tg & kRequired) ++s.required_edges;
      if (tg & kListed) ++s.listed_edges;
      if (tg & kNonManifold) ++s.non_manifold_edges;
      if (m.edge_ref(c) != 0) erefs.insert(m.edge_ref(c));
    }
  }
  for (Vertex vh : m.vertices()) {
    if (m.has_tag(vh, kCorner)) ++s.corner_vertices;
    if (m.has_tag(vh, kRequired)) ++s.required_vertices;
    if (m.vertex_ref(vh) != 0) vrefs.insert(m.vertex_ref(vh));
    if (!m.is_isolated(vh) && find_root(parent, vh.idx) == vh.idx) ++s.components;
  }
  s.mean_edge = s.edges ? sum_edge / s.edges : 0;
  if (!s.edges) s.min_edge = 0;
  s.euler_characteristic = s.vertices - s.edges + s.triangles;
  s.boundary_loops = count_boundary_loops(m);
  s.vertex_refs = static_cast<int>(vrefs.size());
  s.triangle_refs = static_cast<int>(trefs.size());
  s.edge_refs = static_cast<int>(erefs.size());
  return s;
}

}  // namespace anisurf
