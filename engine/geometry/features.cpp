#include "geometry/features.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "geometry/parallel_chunks.h"

namespace anisurf {

namespace {

void check_vertex(const SurfaceMesh& mesh, int v, const char* what) {
  if (v < 0 || v >= mesh.vertex_capacity() || mesh.is_deleted(Vertex(v)) || mesh.is_isolated(Vertex(v)))
    throw Error(std::string("features: ") + what + " names vertex " + std::to_string(v) +
                ", which is not a vertex of a triangle (0-based ids, " + std::to_string(mesh.n_vertices()) +
                " vertices)");
}

Corner edge_of(const SurfaceMesh& mesh, const std::array<int, 2>& e, const char* what) {
  check_vertex(mesh, e[0], what);
  check_vertex(mesh, e[1], what);
  Corner c = mesh.find_edge(Vertex(e[0]), Vertex(e[1]));
  if (!c.is_valid()) c = mesh.find_edge(Vertex(e[1]), Vertex(e[0]));
  if (!c.is_valid())
    throw Error(std::string("features: ") + what + " names " + std::to_string(e[0]) + "-" + std::to_string(e[1]) +
                ", which is not an edge of the mesh");
  return c;
}

// Angle in radians between two unit-or-zero vectors (0 if one is zero).
double angle_between(const Vec3& a, const Vec3& b) {
  const double na = norm(a), nb = norm(b);
  if (!(na > 0) || !(nb > 0)) return 0;
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

}  // namespace

bool has_reliable_normal(const SurfaceMesh& mesh, Triangle t, double area_ratio) {
  double longest2 = 0;
  for (int k = 0; k < 3; ++k)
    longest2 = std::max(longest2, norm2(mesh.position(mesh.vertex(t, (k + 1) % 3)) - mesh.position(mesh.vertex(t, k))));
  return 0.5 * norm(mesh.triangle_normal(t)) > area_ratio * longest2;
}

std::vector<FeatureEdgeAt> feature_edges_at(const SurfaceMesh& mesh, Vertex v) {
  std::vector<FeatureEdgeAt> out;
  const Corner start = mesh.corner(v);
  if (!start.is_valid()) return out;
  if (mesh.is_boundary(v)) {
    // The fan starts at its most clockwise corner: the edge v -> next is open.
    out.push_back({SurfaceMesh::prev(start), mesh.vertex(SurfaceMesh::next(start))});
  }
  for (Corner c : mesh.fan_corners(v)) {
    // Edge between c's triangle and the next one counter-clockwise: prev(c) -> v.
    const Corner e = SurfaceMesh::next(c);
    if (is_feature_edge(mesh, e)) out.push_back({e, mesh.vertex(SurfaceMesh::prev(c))});
  }
  return out;
}

std::vector<std::vector<Corner>> smooth_sectors(const SurfaceMesh& mesh, Vertex v) {
  std::vector<std::vector<Corner>> out;
  const std::vector<Corner> fan = mesh.fan(v);
  if (fan.empty()) return out;
  const int n = static_cast<int>(fan.size());
  // Edge between fan[i] and fan[i+1] is opposite next(fan[i]).
  auto cut_after = [&](int i) { return is_feature_edge(mesh, SurfaceMesh::next(fan[i])); };
  int start = 0;
  if (!mesh.is_boundary(v)) {
    start = -1;
    for (int i = 0; i < n; ++i)
      if (cut_after(i)) {
        start = (i + 1) % n;
        break;
      }
    if (start < 0) {
      out.push_back(fan);
      return out;
    }
  }
  out.emplace_back();
  for (int k = 0; k < n; ++k) {
    const int i = (start + k) % n;
    out.back().push_back(fan[i]);
    if (k + 1 < n && cut_after(i)) out.emplace_back();
  }
  return out;
}

double curve_turn(const SurfaceMesh& mesh, Vertex v, const FeatureEdgeAt& a, const FeatureEdgeAt& b) {
  const Vec3& p = mesh.position(v);
  return std::numbers::pi - angle_between(mesh.position(a.other) - p, mesh.position(b.other) - p);
}

FeatureReport detect_features(SurfaceMesh& mesh, const FeatureOptions& options) {
  FeatureReport rep;
  mesh.update_boundary_tags();
  const double ridge_angle = (options.ridge_angle_deg - options.ridge_tolerance_deg) * std::numbers::pi / 180.0;
  const double corner_angle = options.corner_angle_deg * std::numbers::pi / 180.0;

  // 1. edges: file tags, dihedral angle, reference interfaces. Each edge is
  // judged on its own, in parallel chunks of corner slots (reading the mesh
  // only), then tagged in edge order.
  enum : std::uint8_t { kDropFileRidge = 1, kInterface = 2, kDetected = 4 };
  const int nc = mesh.corner_capacity();
  std::vector<std::uint8_t> verdict(static_cast<std::size_t>(nc), 0);
  run_chunks(nc, chunk_count(nc, 65536), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Corner c(i);
      if (!mesh.is_edge_corner(c)) continue;
      std::uint8_t v = 0;
      bool file_ridge = mesh.has_tag(c, kRidge);
      if (!options.keep_file_tags && file_ridge) {
        v |= kDropFileRidge;
        file_ridge = false;
      }
      const Corner o = mesh.opposite(c);
      if (o.is_valid() && !file_ridge) {
        const Triangle tri = SurfaceMesh::triangle(c), other = SurfaceMesh::triangle(o);
        if (options.reference_interfaces && mesh.triangle_ref(tri) != mesh.triangle_ref(other))
          v |= kInterface;
        else if (options.detect_ridges && has_reliable_normal(mesh, tri, options.degenerate_area_ratio) &&
                 has_reliable_normal(mesh, other, options.degenerate_area_ratio) &&
                 angle_between(mesh.triangle_normal(tri), mesh.triangle_normal(other)) >= ridge_angle)
          v |= kDetected;
      }
      verdict[static_cast<std::size_t>(i)] = v;
    }
  });
  for (Corner c : mesh.edges()) {
    const std::uint8_t v = verdict[static_cast<std::size_t>(c.idx)];
    if (v & kDropFileRidge) mesh.remove_edge_tag(c, kRidge);
    if (v & kInterface) {
      mesh.add_edge_tag(c, kRidge);
      ++rep.interface_edges;
    }
    if (v & kDetected) {
      mesh.add_edge_tag(c, kRidge);
      ++rep.detected_ridges;
    }
  }
  // 1b. blends: spokes of the piecewise planar sectors that turn by the
  // ridge angle at a vertex on two ridges or more (collected first: every
  // vertex sees the tags of step 1 only)
  if (options.detect_ridges && options.blend_angle_deg > 0) {
    const double blend_angle = options.blend_angle_deg * std::numbers::pi / 180.0;
    const double flat_angle = options.blend_flat_angle_deg * std::numbers::pi / 180.0;
    std::vector<Corner> blends, turning;
    std::vector<Vec3> normals;
    for (Vertex vh : mesh.vertices()) {
      if (mesh.is_isolated(vh)) continue;
      const auto fe = feature_edges_at(mesh, vh);
      if (std::count_if(fe.begin(), fe.end(), [&](const FeatureEdgeAt& f) { return mesh.has_tag(f.edge, kRidge); }) < 2)
        continue;
      for (const std::vector<Corner>& sector : smooth_sectors(mesh, vh)) {
        if (sector.size() < 2) continue;
        normals.clear();
        for (Corner c : sector) {
          const Triangle t = SurfaceMesh::triangle(c);
          if (has_reliable_normal(mesh, t, options.degenerate_area_ratio)) normals.push_back(mesh.triangle_normal(t));
        }
        double spread = 0;
        for (std::size_t i = 0; i < normals.size(); ++i)
          for (std::size_t j = i + 1; j < normals.size(); ++j) spread = std::max(spread, angle_between(normals[i], normals[j]));
        if (spread < ridge_angle) continue;
        // the edge between sector[i] and sector[i + 1] is opposite next(sector[i])
        turning.clear();
        bool planar_parts = true;
        for (std::size_t i = 0; i + 1 < sector.size() && planar_parts; ++i) {
          const Triangle a = SurfaceMesh::triangle(sector[i]), b = SurfaceMesh::triangle(sector[i + 1]);
          if (!has_reliable_normal(mesh, a, options.degenerate_area_ratio) ||
              !has_reliable_normal(mesh, b, options.degenerate_area_ratio))
            continue;
          const double turn = angle_between(mesh.triangle_normal(a), mesh.triangle_normal(b));
          if (turn >= blend_angle) {
            turning.push_back(SurfaceMesh::next(sector[i]));
          } else if (turn > flat_angle) {
            planar_parts = false;
          }
        }
        if (planar_parts) blends.insert(blends.end(), turning.begin(), turning.end());
      }
    }
    for (Corner c : blends)
      if (!mesh.has_tag(c, kRidge)) {
        mesh.add_edge_tag(c, kRidge);
        ++rep.blend_edges;
      }
  }
  // 2. user edits on edges
  for (const auto& e : options.add_ridges) mesh.add_edge_tag(edge_of(mesh, e, "add_ridges"), kRidge);
  for (const auto& e : options.remove_ridges) mesh.remove_edge_tag(edge_of(mesh, e, "remove_ridges"), kRidge);

  // 3. vertices: kRidge on ridge vertices, corners (each vertex writes its
  // own tags: parallel chunks of vertex slots). The vertices on feature
  // edges are counted on the way (the edges' tags are final).
  const int nv = mesh.vertex_capacity();
  const int vertex_chunks = chunk_count(nv, 32768);
  std::vector<int> feature_vertices(static_cast<std::size_t>(vertex_chunks), 0);
  run_chunks(nv, vertex_chunks, [&](int chunk, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Vertex vh(i);
      if (mesh.is_deleted(vh)) continue;
      mesh.remove_vertex_tag(vh, kRidge);
      if (!options.keep_file_tags) mesh.remove_vertex_tag(vh, kCorner);
      if (mesh.is_isolated(vh)) continue;
      const auto fe = feature_edges_at(mesh, vh);
      bool on_ridge = false;
      for (const auto& f : fe) on_ridge = on_ridge || mesh.has_tag(f.edge, kRidge);
      if (on_ridge) mesh.add_vertex_tag(vh, kRidge);
      if (fe.empty()) continue;
      ++feature_vertices[static_cast<std::size_t>(chunk)];
      bool corner = fe.size() != 2;
      if (!corner) corner = curve_turn(mesh, vh, fe[0], fe[1]) > corner_angle;
      if (corner) mesh.add_vertex_tag(vh, kCorner);
    }
  });
  for (int n : feature_vertices) rep.feature_vertices += n;
  for (int v : options.add_corners) {
    check_vertex(mesh, v, "add_corners");
    mesh.add_vertex_tag(Vertex(v), kCorner);
  }
  for (int v : options.remove_corners) {
    check_vertex(mesh, v, "remove_corners");
    mesh.remove_vertex_tag(Vertex(v), kCorner);
  }

  // 4. counts
  for (Corner c : mesh.edges()) {
    if (mesh.is_boundary_edge(c)) ++rep.boundary_edges;
    if (is_feature_edge(mesh, c)) ++rep.feature_edges;
  }
  for (Vertex vh : mesh.vertices())
    if (!mesh.is_isolated(vh) && mesh.has_tag(vh, kCorner)) ++rep.corners;
  return rep;
}

}  // namespace anisurf
