#include "geometry/sample.h"

#include <string>

#include "core/error.h"
#include "mesh/build.h"

namespace anisurf {

SurfaceMesh sample_surface(const SurfaceMesh& mesh, const BezierSurface& surface, int k) {
  if (k < 1) throw Error("sample_surface: the split factor must be at least 1, got " + std::to_string(k));
  if (surface.size() != mesh.triangle_capacity())
    throw Error("sample_surface: the surface was built over another mesh");
  MeshData d;
  d.dimension = 3;
  // 1. original vertices (compact numbering)
  std::vector<int> vid(mesh.vertex_capacity(), -1);
  for (Vertex vh : mesh.vertices()) {
    if (mesh.is_isolated(vh)) continue;
    const int id = static_cast<int>(d.vertices.size());
    vid[vh.idx] = id;
    d.vertices.push_back(mesh.position(vh));
    d.vertex_refs.push_back(mesh.vertex_ref(vh));
    if (mesh.has_tag(vh, kCorner)) d.corners.push_back(id);
    if (mesh.has_tag(vh, kRequired)) d.required_vertices.push_back(id);
  }
  // 2. points inside edges, once per edge (canonical corner), k - 1 each from
  // edge_from to edge_to
  std::vector<int> edge_first(static_cast<std::size_t>(mesh.corner_capacity()), -1);
  for (Corner e : mesh.edges()) {
    edge_first[e.idx] = static_cast<int>(d.vertices.size());
    const Triangle t = SurfaceMesh::triangle(e);
    const int kl = SurfaceMesh::local_index(e), a = (kl + 1) % 3, b = (kl + 2) % 3;
    const std::uint8_t tags = mesh.edge_tags(e);
    for (int m = 1; m < k; ++m) {
      Bary bc{0, 0, 0};
      bc[a] = double(k - m) / k;
      bc[b] = double(m) / k;
      const int id = static_cast<int>(d.vertices.size());
      d.vertices.push_back(surface.position(t, bc));
      d.vertex_refs.push_back(mesh.edge_ref(e));
      if (tags & kRequired) d.required_vertices.push_back(id);
    }
  }
  // vertex id of grid point (i, j) of triangle t: barycentric (k-i-j, i, j) / k
  auto grid_vertex = [&](Triangle t, int first_interior, int i, int j) -> int {
    const int l[3] = {k - i - j, i, j};
    int zeros = 0, nz = -1;
    for (int q = 0; q < 3; ++q)
      if (l[q] == 0) ++zeros;
      else nz = q;
    if (zeros == 2) return vid[mesh.vertex(t, nz).idx];
    for (int q = 0; q < 3; ++q) {
      if (l[q] != 0) continue;
      // on the edge opposite corner q, from v_{q+1} (steps = l[q+2])
      const Corner c = SurfaceMesh::corner(t, q);
      const int steps = l[(q + 2) % 3];
      const Corner e = mesh.canonical(c);
      return e == c ? edge_first[e.idx] + steps - 1 : edge_first[e.idx] + (k - steps) - 1;
    }
    // interior: row j, i from 1 to k - j - 1
    int idx = 0;
    for (int jj = 1; jj < j; ++jj) idx += k - jj - 1;
    return first_interior + idx + (i - 1);
  };
  // 3. interior points and triangles
  for (Triangle t : mesh.triangles()) {
    const int first_interior = static_cast<int>(d.vertices.size());
    for (int j = 1; j < k; ++j)
      for (int i = 1; i + j < k; ++i) {
        d.vertices.push_back(surface.position(t, {double(k - i - j) / k, double(i) / k, double(j) / k}));
        d.vertex_refs.push_back(0);
      }
    for (int j = 0; j < k; ++j)
      for (int i = 0; i + j < k; ++i) {
        const int p00 = grid_vertex(t, first_interior, i, j), p10 = grid_vertex(t, first_interior, i + 1, j),
                  p01 = grid_vertex(t, first_interior, i, j + 1);
        d.triangles.push_back({p00, p10, p01});
        d.triangle_refs.push_back(mesh.triangle_ref(t));
        if (mesh.has_tag(t, kRequired)) d.required_triangles.push_back(static_cast<int>(d.triangles.size()) - 1);
        if (i + j + 1 < k) {
          const int p11 = grid_vertex(t, first_interior, i + 1, j + 1);
          d.triangles.push_back({p10, p11, p01});
          d.triangle_refs.push_back(mesh.triangle_ref(t));
          if (mesh.has_tag(t, kRequired)) d.required_triangles.push_back(static_cast<int>(d.triangles.size()) - 1);
        }
      }
  }
  // 4. tagged edges: every sub-edge of a tagged or referenced edge
  for (Corner e : mesh.edges()) {
    const std::uint8_t tags = mesh.edge_tags(e);
    if (!(tags & (kListed | kRidge | kRequired)) && mesh.edge_ref(e) == 0) continue;
    int prev = vid[mesh.edge_from(e).idx];
    for (int m = 1; m <= k; ++m) {
      const int next = m < k ? edge_first[e.idx] + m - 1 : vid[mesh.edge_to(e).idx];
      const int id = static_cast<int>(d.edges.size());
      d.edges.push_back({prev, next});
      d.edge_refs.push_back(mesh.edge_ref(e));
      if (tags & kRidge) d.ridges.push_back(id);
      if (tags & kRequired) d.required_edges.push_back(id);
      prev = next;
    }
  }
  // ridge vertices inside ridge edges
  SurfaceMesh out;
  BuildOptions bo;
  bo.merge = BuildOptions::Merge::Never;
  bo.orient = false;
  build_mesh(d, out, bo, "sampled surface");
  // kRidge on the vertices of ridge edges (as detect_features does)
  for (Triangle t : out.triangles())
    for (int q = 0; q < 3; ++q) {
      const Corner c = SurfaceMesh::corner(t, q);
      if (!out.has_tag(c, kRidge)) continue;
      out.add_vertex_tag(out.edge_from(c), kRidge);
      out.add_vertex_tag(out.edge_to(c), kRidge);
    }
  return out;
}

}  // namespace anisurf
