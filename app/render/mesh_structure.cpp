#include "render/mesh_structure.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_set>

#include "core/error.h"
#include "metric/quality.h"
#include "metric/surface_metric.h"

namespace anisurf::render {

namespace {

glm::vec3 to_glm(const Vec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

// Angle of triangle corner c (radians).
double corner_angle(const SurfaceMesh& m, Corner c) {
  const Vec3& p = m.position(m.vertex(c));
  Vec3 a = m.position(m.vertex(SurfaceMesh::next(c))) - p;
  Vec3 b = m.position(m.vertex(SurfaceMesh::prev(c))) - p;
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

// Per-corner normals: angle-weighted triangle normals over the sector of the
// corner's vertex fan bounded by boundary, ridge and crease edges.
std::vector<glm::vec3> sector_normals(const SurfaceMesh& m, const std::vector<int>& live_triangles,
                                      double crease_angle_deg) {
  std::vector<Vec3> tn(static_cast<std::size_t>(m.triangle_capacity()));
  for (int t : live_triangles) tn[t] = normalized(m.triangle_normal(Triangle(t)));
  const double cos_crease = std::cos(crease_angle_deg * M_PI / 180.0);
  auto stops = [&](Corner e) {
    if (m.is_boundary_edge(e) || m.has_tag(e, kRidge)) return true;
    if (crease_angle_deg >= 180.0) return false;
    return dot(tn[SurfaceMesh::triangle(e).idx], tn[SurfaceMesh::triangle(m.opposite(e)).idx]) < cos_crease;
  };
  const int kMaxFan = 4096;  // guards against a broken fan
  std::vector<glm::vec3> out;
  out.reserve(3 * live_triangles.size());
  for (int t : live_triangles)
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(Triangle(t), k);
      Vec3 sum = corner_angle(m, c) * tn[t];
      bool looped = false;
      Corner cur = c;
      for (int i = 0; i < kMaxFan; ++i) {  // counter-clockwise: across the edge opposite next(cur)
        Corner e = SurfaceMesh::next(cur);
        if (stops(e)) break;
        Corner nxt = SurfaceMesh::next(m.opposite(e));
        if (nxt == c) { looped = true; break; }
        sum += corner_angle(m, nxt) * tn[SurfaceMesh::triangle(nxt).idx];
        cur = nxt;
      }
      cur = c;
      for (int i = 0; !looped && i < kMaxFan; ++i) {  // clockwise: across the edge opposite prev(cur)
        Corner e = SurfaceMesh::prev(cur);
        if (stops(e)) break;
        Corner nxt = SurfaceMesh::prev(m.opposite(e));
        if (nxt == c) break;
        sum += corner_angle(m, nxt) * tn[SurfaceMesh::triangle(nxt).idx];
        cur = nxt;
      }
      Vec3 n = normalized(sum);
      if (norm2(n) == 0) n = tn[t];
      out.push_back(to_glm(n));
    }
  return out;
}

}  // namespace

std::optional<TangentEllipse> tangent_ellipse(const SymTensor3& M, const Vec3& n) {
  if (norm2(n) == 0) return std::nullopt;
  const auto [t1, t2] = tangent_frame(normalized(n));
  SymTensor2 T = restrict_to_tangent(M, t1, t2);
  if (!is_spd(T)) return std::nullopt;
  SymEigen2 e = eigen_decompose(T);  // values ascending: the largest size first
  if (!(e.values[0] > 0)) return std::nullopt;
  const double c = std::cos(e.angle), s = std::sin(e.angle);
  Vec3 d0 = c * t1 + s * t2, d1 = -s * t1 + c * t2;
  return TangentEllipse{d0 / std::sqrt(e.values[0]), d1 / std::sqrt(e.values[1])};
}

std::vector<int> spread_order(const std::vector<Vec3>& points) {
  const int n = static_cast<int>(points.size());
  std::vector<int> order;
  order.reserve(points.size());
  BBox box;
  for (const auto& p : points) box.add(p);
  double extent = box.empty() ? 0.0 : std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z});
  std::vector<char> taken(points.size(), 0);
  std::vector<int> scrambled(points.size());
  for (int i = 0; i < n; ++i) scrambled[i] = i;
  auto mix = [](std::uint32_t x) {  // an integer hash (bijective on 32 bits)
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    return x ^ (x >> 16);
  };
  std::sort(scrambled.begin(), scrambled.end(),
            [&](int a, int b) { return mix(static_cast<std::uint32_t>(a)) < mix(static_cast<std::uint32_t>(b)); });
  if (extent > 0) {
    std::unordered_set<std::uint64_t> occupied;
    for (int level = 0; level <= 20 && static_cast<int>(order.size()) < n; ++level) {
      const double cell = extent / static_cast<double>(1 << level) * 1.0000001;
      auto key = [&](const Vec3& p) {
        auto q = [&](double x, double lo) { return static_cast<std::uint64_t>((x - lo) / cell) & 0x1fffff; };
        return q(p.x, box.lo.x) | (q(p.y, box.lo.y) << 21) | (q(p.z, box.lo.z) << 42);
      };
      occupied.clear();
      for (int i : order) occupied.insert(key(points[i]));
      // Within a level, candidates in a scrambled (deterministic) order, so
      // that a prefix ending inside the level is spread too.
      for (int j = 0; j < n; ++j) {
        const int i = scrambled[j];
        if (!taken[i] && occupied.insert(key(points[i])).second) {
          taken[i] = 1;
          order.push_back(i);
        }
      }
    }
  }
  for (int i = 0; i < n; ++i)
    if (!taken[i]) order.push_back(i);
  return order;
}

ScalarQuantity vertex_quantity(const MeshStructure& s, const std::string& name, const std::vector<double>& per_slot) {
  ScalarQuantity q{name, ScalarLocation::Vertex};
  q.values.assign(s.structure.geometry.positions.size(), std::numeric_limits<float>::quiet_NaN());
  const std::size_t n = std::min(per_slot.size(), s.draw_vertex.size());
  for (std::size_t v = 0; v < n; ++v)
    if (s.draw_vertex[v] >= 0) q.values[static_cast<std::size_t>(s.draw_vertex[v])] = static_cast<float>(per_slot[v]);
  q.set_range_from_data();
  return q;
}

MeshStructure make_mesh_structure(const SurfaceMesh& mesh, const std::string& name,
                                  const MeshStructureOptions& options) {
  MeshStructure out;
  SurfaceStructure& s = out.structure;
  s.name = name;

  // --- geometry: live, referenced vertices and live triangles, compact ------
  std::vector<int> live;
  out.draw_triangle.assign(static_cast<std::size_t>(mesh.triangle_capacity()), -1);
  out.draw_vertex.assign(static_cast<std::size_t>(mesh.vertex_capacity()), -1);
  for (Triangle t : mesh.triangles()) {
    out.draw_triangle[t.idx] = static_cast<int>(live.size());
    live.push_back(t.idx);
  }
  // Vertices used by a live triangle, numbered in mesh order.
  std::vector<char> used(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  for (int t : live)
    for (int k = 0; k < 3; ++k) used[mesh.vertex(Triangle(t), k).idx] = 1;
  std::vector<int> vertex_of_draw;
  for (Vertex v : mesh.vertices())
    if (used[v.idx]) {
      out.draw_vertex[v.idx] = static_cast<int>(vertex_of_draw.size());
      vertex_of_draw.push_back(v.idx);
    }
  TriangleSet& g = s.geometry;
  for (int v : vertex_of_draw) g.positions.push_back(to_glm(mesh.position(Vertex(v))));
  for (int t : live)
    g.triangles.emplace_back(out.draw_vertex[mesh.vertex(Triangle(t), 0).idx],
                             out.draw_vertex[mesh.vertex(Triangle(t), 1).idx],
                             out.draw_vertex[mesh.vertex(Triangle(t), 2).idx]);
  g.corner_normals = sector_normals(mesh, live, options.crease_angle_deg);

  // --- features: ridges, boundaries, cut edges, corners ---------------------
  Curves ridges{"ridges", {}, {0.05f, 0.30f, 0.85f}, 2.5f, true};
  Curves boundary{"boundary", {}, {0.85f, 0.10f, 0.10f}, 3.0f, true};
  Curves cuts{"non-manifold cuts", {}, {0.75f, 0.0f, 0.75f}, 3.0f, true};
  for (int t : live)
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(Triangle(t), k);
      if (mesh.canonical(c) != c) continue;
      glm::vec3 a = to_glm(mesh.position(mesh.edge_from(c))), b = to_glm(mesh.position(mesh.edge_to(c)));
      if (mesh.is_boundary_edge(c)) {
        auto& dst = mesh.has_tag(c, kNonManifold) ? cuts : boundary;
        dst.points.insert(dst.points.end(), {a, b});
      } else if (mesh.has_tag(c, kRidge)) {
        ridges.points.insert(ridges.points.end(), {a, b});
      }
    }
  for (Curves* c : {&ridges, &boundary, &cuts})
    if (!c->points.empty()) s.curves.push_back(std::move(*c));
  Markers corners{"corners", {}, {1.0f, 0.78f, 0.05f}, 4.5f, true};
  for (int v : vertex_of_draw)
    if (mesh.has_tag(Vertex(v), kCorner)) corners.positions.push_back(to_glm(mesh.position(Vertex(v))));
  if (!corners.positions.empty()) s.markers.push_back(std::move(corners));

  // --- the metric (engine/metric: field choice and checks) ----------------
  std::string candidate = options.metric_field;
  if (candidate.empty()) {  // metric_from_field's rule: first tensor, else first scalar
    for (const auto& f : mesh.fields())
      if (f.kind == FieldKind::Tensor) {
        candidate = f.name;
        break;
      }
    if (candidate.empty())
      for (const auto& f : mesh.fields())
        if (f.kind == FieldKind::Scalar) {
          candidate = f.name;
          break;
        }
  }
  std::vector<std::optional<SymTensor3>> metric;
  if (!candidate.empty()) {
    try {
      MetricField field = metric_from_field(mesh, candidate, options.vertex_origin);
      metric.assign(field.begin(), field.end());
      out.metric_field = candidate;
    } catch (const MetricError& e) {
      if (!options.metric_field.empty()) throw;
      out.metric_problem = "field '" + candidate + "' is not a metric: " + e.what();
    }
  }
  const bool has_metric = !out.metric_field.empty();
  const std::string metric_note = has_metric ? "metric: field '" + out.metric_field + "'" : "no metric: Euclidean";

  // --- quality (triangle) and edge lengths (edge) ---------------------------
  ScalarQuantity quality{quantity::kQuality, ScalarLocation::Triangle};
  ScalarQuantity length{quantity::kLength, ScalarLocation::Edge};
  quality.values.reserve(live.size());
  length.values.reserve(3 * live.size());
  for (int t : live) {
    std::array<Vec3, 3> p;
    std::array<int, 3> vi;
    for (int k = 0; k < 3; ++k) {
      vi[k] = mesh.vertex(Triangle(t), k).idx;
      p[k] = mesh.position(Vertex(vi[k]));
    }
    bool valid = !has_metric || (metric[vi[0]] && metric[vi[1]] && metric[vi[2]]);
    if (!valid) {
      quality.values.push_back(NAN);
      length.values.insert(length.values.end(), {NAN, NAN, NAN});
      continue;
    }
    if (has_metric) {
      quality.values.push_back(static_cast<float>(
          triangle_quality(p, {*metric[vi[0]], *metric[vi[1]], *metric[vi[2]]}, options.length_formula)));
    } else {
      quality.values.push_back(
          static_cast<float>(quality_from_lengths(norm(p[1] - p[2]), norm(p[2] - p[0]), norm(p[0] - p[1]))));
    }
    for (int k = 0; k < 3; ++k) {  // edge opposite corner k: from vertex k+1 to vertex k+2
      int a = (k + 1) % 3, b = (k + 2) % 3;
      Vec3 e = p[b] - p[a];
      double l = has_metric ? edge_length(*metric[vi[a]], *metric[vi[b]], e, options.length_formula) : norm(e);
      length.values.push_back(static_cast<float>(l));
    }
  }
  quality.range_min = 0.0f;
  quality.range_max = 1.0f;
  quality.note = "eq. 17, 1 = equilateral; " + metric_note;
  if (has_metric) {
    length.colormap = Colormap::Coolwarm;
    length.log_scale = true;
    length.range_min = 0.5f;
    length.range_max = 2.0f;
    length.note = "metric length (1 = unit); " + metric_note;
  } else {
    length.set_range_from_data();
    length.note = metric_note;
  }
  s.scalars.push_back(std::move(quality));
  s.scalars.push_back(std::move(length));

  // --- size, anisotropy, glyphs (tangent-plane ellipses) --------------------
  if (has_metric) {
    std::vector<Vec3> vn = vertex_normals(mesh);
    ScalarQuantity size{quantity::kSize, ScalarLocation::Vertex};
    ScalarQuantity aniso{quantity::kAniso, ScalarLocation::Vertex};
    size.log_scale = aniso.log_scale = true;
    std::vector<Vec3> glyph_points;
    std::vector<std::array<Vec3, 2>> glyph_axes;
    for (int v : vertex_of_draw) {
      std::optional<TangentEllipse> e;
      if (metric[v]) e = tangent_ellipse(*metric[v], mesh.dimension() == 2 ? Vec3(0, 0, 1) : vn[v]);
      if (!e) {
        size.values.push_back(NAN);
        aniso.values.push_back(NAN);
        continue;
      }
      double h1 = norm(e->major), h2 = norm(e->minor);
      size.values.push_back(static_cast<float>(std::sqrt(h1 * h2)));
      aniso.values.push_back(static_cast<float>(h1 / h2));
      glyph_points.push_back(mesh.position(Vertex(v)));
      glyph_axes.push_back({e->major, e->minor});
    }
    size.set_range_from_data();
    aniso.set_range_from_data();
    aniso.range_min = 1.0f;
    if (aniso.range_max <= 1.0f) aniso.range_max = 2.0f;
    size.note = "sqrt(h1 h2) in the tangent plane; " + metric_note;
    aniso.note = "h_max / h_min in the tangent plane; " + metric_note;
    s.scalars.push_back(std::move(size));
    s.scalars.push_back(std::move(aniso));

    EllipseGlyphs glyphs;
    glyphs.name = "metric glyphs";
    for (int i : spread_order(glyph_points)) {
      glyphs.centers.push_back(to_glm(glyph_points[i]));
      glyphs.axes_u.push_back(to_glm(glyph_axes[i][0]));
      glyphs.axes_v.push_back(to_glm(glyph_axes[i][1]));
    }
    const float n = static_cast<float>(std::max<std::size_t>(glyphs.centers.size(), 1));
    glyphs.density = options.glyph_density > 0 ? std::min(options.glyph_density, 1.0f) : std::min(1.0f, 2500.0f / n);
    if (options.glyph_scale > 0) {
      glyphs.scale = options.glyph_scale;
    } else {
      // The drawn glyphs are about sqrt(area / count) apart: scale the median
      // glyph (radius sqrt(h1 h2)) to 0.45 of that, so they nearly touch.
      double area = 0;
      for (int t : live) area += mesh.triangle_area(Triangle(t));
      std::vector<float> radii;
      for (const auto& a : glyph_axes) radii.push_back(static_cast<float>(std::sqrt(norm(a[0]) * norm(a[1]))));
      std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2), radii.end());
      const double median = radii.empty() ? 0.0 : radii[radii.size() / 2];
      const double spacing = std::sqrt(area / std::max(1.0, static_cast<double>(glyphs.drawn_count())));
      glyphs.scale = median > 0 && spacing > 0 ? static_cast<float>(0.45 * spacing / median) : 1.0f;
    }
    glyphs.enabled = false;  // shown on request (--glyphs, the panel)
    s.glyphs.push_back(std::move(glyphs));
  }

  // --- references (labels) and the file's scalar / vector fields -------------
  LabelQuantity refs{quantity::kReference, {}};
  for (int t : live) refs.triangle_labels.push_back(mesh.triangle_ref(Triangle(t)));
  s.labels.push_back(std::move(refs));
  for (const auto& f : mesh.fields()) {
    if (f.kind == FieldKind::Tensor) continue;
    Property<FieldValue> p = mesh.get_field(f.name);
    ScalarQuantity q{f.name, ScalarLocation::Vertex};
    for (int v : vertex_of_draw) {
      const FieldValue& x = p[Vertex(v)];
      double val = 0;
      if (f.ncomp == 1) {
        val = x[0];
      } else {
        for (int k = 0; k < f.ncomp && k < 6; ++k) val += x[k] * x[k];
        val = std::sqrt(val);
      }
      q.values.push_back(static_cast<float>(val));
    }
    q.set_range_from_data();
    q.note = f.ncomp == 1 ? "scalar field" : "vector field: magnitude";
    // A quantity of the same name exists already (e.g. a field named "size").
    bool clash = std::any_of(s.scalars.begin(), s.scalars.end(), [&](auto& o) { return o.name == q.name; });
    if (clash) q.name = "field " + q.name;
    s.scalars.push_back(std::move(q));
  }
  s.version = 1;
  return out;
}

void highlight(MeshStructure& s, const std::vector<int>& triangles, const std::vector<int>& vertices) {
  for (int t : triangles) {
    if (t < 0 || t >= static_cast<int>(s.draw_triangle.size()) || s.draw_triangle[t] < 0)
      throw Error("triangle " + std::to_string(t + 1) + " does not exist (the mesh has " +
                  std::to_string(s.structure.geometry.triangles.size()) + " triangles, numbered from 1)");
    s.structure.highlight_triangles.push_back(static_cast<std::uint32_t>(s.draw_triangle[t]));
  }
  if (!vertices.empty()) {
    Markers m{"highlighted vertices", {}, {1.0f, 0.15f, 0.55f}, 5.5f, true};
    for (int v : vertices) {
      if (v < 0 || v >= static_cast<int>(s.draw_vertex.size()) || s.draw_vertex[v] < 0)
        throw Error("vertex " + std::to_string(v + 1) + " does not exist (the mesh has " +
                    std::to_string(s.structure.geometry.positions.size()) + " vertices, numbered from 1)");
      m.positions.push_back(s.structure.geometry.positions[static_cast<std::size_t>(s.draw_vertex[v])]);
    }
    s.structure.markers.push_back(std::move(m));
  }
  ++s.structure.version;
}

}  // namespace anisurf::render
