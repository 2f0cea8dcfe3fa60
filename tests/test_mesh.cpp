// The mesh core: corner table invariants, building from soups with repairs,
// free lists, compact(), properties, validate() catching corruption.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <ranges>

#include "core/error.h"
#include "core/packed_normal.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "mesh/operators.h"
#include "mesh/stats.h"
#include "mesh/surface_mesh.h"
#include "test_geometry_util.h"
#include "test_io_roundtrip.h"
#include "test_util.h"

using namespace anisurf;

namespace {

MeshData tetrahedron() {
  MeshData d;
  d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  d.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return d;
}

MeshData grid(int n) { return test::square_grid(n); }

void require_valid(const SurfaceMesh& m) {
  auto r = m.validate();
  INFO(r.summary());
  REQUIRE(r.ok());
}

// Every triangle's normal points to +z (grid meshes).
bool all_up(const SurfaceMesh& m) {
  for (int t = 0; t < m.triangle_capacity(); ++t)
    if (!m.is_deleted(Triangle(t)) && m.triangle_normal(Triangle(t)).z <= 0) return false;
  return true;
}

// A Moebius strip of 12 quads (24 triangles), one half twist.
MeshData moebius_strip() {
  MeshData d;
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n;
    for (int s = -1; s <= 1; s += 2) {
      double w = 0.3 * s;
      d.vertices.push_back({(1 + w * std::cos(a / 2)) * std::cos(a), (1 + w * std::cos(a / 2)) * std::sin(a),
                            w * std::sin(a / 2)});
    }
  }
  for (int i = 0; i < n; ++i) {
    int a0 = 2 * i, a1 = 2 * i + 1;
    int b0 = 2 * ((i + 1) % n), b1 = 2 * ((i + 1) % n) + 1;
    if (i == n - 1) std::swap(b0, b1);  // the half twist
    d.triangles.push_back({a0, b0, b1});
    d.triangles.push_back({a0, b1, a1});
  }
  return d;
}

// The fan of v walked with swing_ccw (independent of fan_corners/fan).
std::vector<Corner> walked_fan(const SurfaceMesh& m, Vertex v) {
  std::vector<Corner> out;
  const Corner start = m.corner(v);
  if (!start.is_valid()) return out;
  Corner c = start;
  do {
    out.push_back(c);
    c = m.swing_ccw(c);
  } while (c.is_valid() && c != start && out.size() <= static_cast<std::size_t>(m.corner_capacity()));
  return out;
}

// The one-ring of v from walked_fan: next vertex of each fan corner, then the
// vertex closing an open fan.
std::vector<Vertex> walked_ring(const SurfaceMesh& m, Vertex v) {
  std::vector<Vertex> out;
  const std::vector<Corner> fan = walked_fan(m, v);
  for (Corner c : fan) out.push_back(m.vertex(SurfaceMesh::next(c)));
  if (!fan.empty() && m.is_boundary(v)) out.push_back(m.vertex(SurfaceMesh::prev(fan.back())));
  return out;
}

template <class Range>
auto collect(const Range& r) {
  std::vector<std::ranges::range_value_t<Range>> out;
  for (auto h : r) out.push_back(h);
  return out;
}

// vertices(), triangles() and edges() visit every live element once, in
// increasing order, and nothing deleted; fan_corners and ring_vertices give
// the walked fan and ring of every vertex slot (deleted ones: empty).
void check_ranges_and_circulators(const SurfaceMesh& m) {
  int n = 0, last = -1;
  for (Vertex v : m.vertices()) {
    CHECK_FALSE(m.is_deleted(v));
    CHECK(v.idx > last);
    last = v.idx;
    ++n;
  }
  CHECK(n == m.n_vertices());
  n = 0, last = -1;
  for (Triangle t : m.triangles()) {
    CHECK_FALSE(m.is_deleted(t));
    CHECK(t.idx > last);
    last = t.idx;
    ++n;
  }
  CHECK(n == m.n_triangles());
  // edges: each edge of a live triangle exactly once
  std::vector<int> named(static_cast<std::size_t>(m.corner_capacity()), 0);
  n = 0, last = -1;
  for (Corner c : m.edges()) {
    CHECK_FALSE(m.is_deleted(SurfaceMesh::triangle(c)));
    CHECK(m.canonical(c) == c);
    CHECK(c.idx > last);
    last = c.idx;
    ++named[c.idx];
    if (m.opposite(c).is_valid()) ++named[m.opposite(c).idx];
    ++n;
  }
  CHECK(n == compute_stats(m).edges);
  for (Triangle t : m.triangles())
    for (int k = 0; k < 3; ++k) CHECK(named[SurfaceMesh::corner(t, k).idx] == 1);
  // circulators
  int fan_mismatches = 0, ring_mismatches = 0;
  for (int i = 0; i < m.vertex_capacity(); ++i) {
    const Vertex v(i);
    if (collect(m.fan_corners(v)) != walked_fan(m, v)) ++fan_mismatches;
    if (collect(m.ring_vertices(v)) != walked_ring(m, v)) ++ring_mismatches;
    if (m.is_deleted(v)) continue;
    CHECK(m.fan(v) == walked_fan(m, v));
    CHECK(one_ring(m, v) == walked_ring(m, v));
    CHECK(m.fan_corners(v).empty() == m.is_isolated(v));
    for (Corner c : m.fan_corners(v)) CHECK(m.vertex(c) == v);
  }
  CHECK(fan_mismatches == 0);
  CHECK(ring_mismatches == 0);
}

}  // namespace

static_assert(std::ranges::forward_range<VertexRange>);
static_assert(std::ranges::forward_range<TriangleRange>);
static_assert(std::ranges::forward_range<EdgeRange>);
static_assert(std::ranges::forward_range<FanCornerRange>);
static_assert(std::ranges::forward_range<RingVertexRange>);

TEST_CASE("tetrahedron: closed, consistent, Euler 2") {
  SurfaceMesh m;
  auto rep = build_mesh(tetrahedron(), m);
  require_valid(m);
  CHECK_FALSE(rep.repaired());
  auto s = compute_stats(m);
  CHECK(s.vertices == 4);
  CHECK(s.triangles == 4);
  CHECK(s.edges == 6);
  CHECK(s.euler_characteristic == 2);
  CHECK(s.boundary_edges == 0);
  CHECK(s.components == 1);
  for (int v = 0; v < 4; ++v) {
    CHECK(m.valence(Vertex(v)) == 3);
    CHECK_FALSE(m.is_boundary(Vertex(v)));
  }
  // outward normals: the centroid side
  Vec3 centre{0.25, 0.25, 0.25};
  for (int t = 0; t < 4; ++t) {
    Vec3 p = m.position(m.vertex(Triangle(t), 0));
    CHECK(dot(m.triangle_normal(Triangle(t)), p - centre) > 0);
  }
}

TEST_CASE("grid: boundary fans start at the boundary, swings are inverse") {
  SurfaceMesh m;
  build_mesh(grid(4), m);
  require_valid(m);
  auto s = compute_stats(m);
  CHECK(s.boundary_edges == 16);
  CHECK(s.boundary_loops == 1);
  CHECK(s.euler_characteristic == 1);
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    Vertex vh(v);
    for (Corner c : m.fan(vh)) {
      CHECK(m.vertex(c) == vh);
      Corner n = m.swing_ccw(c);
      if (n.is_valid()) CHECK(m.swing_cw(n) == c);
    }
    if (m.is_boundary(vh)) CHECK_FALSE(m.swing_cw(m.corner(vh)).is_valid());
  }
  // interior vertex of a regular grid: valence 6
  CHECK(m.valence(Vertex(6)) == 6);
  // find_edge gives the directed edge
  Corner e = m.find_edge(Vertex(0), Vertex(1));
  REQUIRE(e.is_valid());
  CHECK(m.edge_from(e) == Vertex(0));
  CHECK(m.edge_to(e) == Vertex(1));
  CHECK(m.is_boundary_edge(e));
}

TEST_CASE("build orients components and reports flips") {
  MeshData d = grid(3);
  // flip every other triangle
  for (std::size_t t = 0; t < d.triangles.size(); t += 2) std::swap(d.triangles[t][1], d.triangles[t][2]);
  SurfaceMesh m;
  auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(rep.flipped_triangles > 0);
  // consistent: all up or all down
  int up = 0;
  for (int t = 0; t < m.triangle_capacity(); ++t) up += m.triangle_normal(Triangle(t)).z > 0;
  CHECK((up == 0 || up == m.n_triangles()));
  CHECK(compute_stats(m).boundary_edges == 12);
}

TEST_CASE("build keeps a consistently oriented soup as given: corners in the input's order, every edge linked") {
  const MeshData d = grid(4);
  SurfaceMesh m;
  const auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(rep.flipped_triangles == 0);
  REQUIRE(m.n_triangles() == static_cast<int>(d.triangles.size()));
  for (int t = 0; t < m.n_triangles(); ++t)
    for (int k = 0; k < 3; ++k) CHECK(m.vertex(SurfaceMesh::corner(Triangle(t), k)).idx == d.triangles[t][k]);
  CHECK(compute_stats(m).boundary_edges == 16);
}

TEST_CASE("append_vertices and append_triangles: slots after the last, default properties, no links") {
  SurfaceMesh m;
  auto weight = m.add_vertex_property<double>("test:weight", 2.5);
  auto mark = m.add_triangle_property<int>("test:mark", 7);
  m.add_vertex({9, 9, 9});
  weight[Vertex(0)] = 1;
  const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  CHECK(m.append_vertices(p) == 1);
  const std::vector<std::array<int, 3>> t = {{1, 2, 3}, {1, 3, 4}};
  CHECK(m.append_triangles(t) == 0);
  CHECK(m.n_vertices() == 5);
  CHECK(m.n_triangles() == 2);
  CHECK(weight[Vertex(0)] == 1);
  for (int v = 1; v <= 4; ++v) {
    CHECK(m.position(Vertex(v)) == p[static_cast<std::size_t>(v - 1)]);
    CHECK(weight[Vertex(v)] == 2.5);
    CHECK_FALSE(m.corner(Vertex(v)).is_valid());
  }
  for (int k = 0; k < 6; ++k) {
    const Corner c(k);
    CHECK(m.vertex(c).idx == t[static_cast<std::size_t>(k / 3)][static_cast<std::size_t>(k % 3)]);
    CHECK_FALSE(m.opposite(c).is_valid());
  }
  CHECK(mark[Triangle(1)] == 7);
  // Linked across the diagonal 1-3 and given fans as a builder does: a
  // valid square.
  m.link(Corner(1), Corner(5));
  for (int k = 0; k < 6; ++k) m.set_vertex_corner(m.vertex(Corner(k)), Corner(k));
  for (int v = 1; v <= 4; ++v) m.update_vertex_corner(Vertex(v));
  m.delete_vertex(Vertex(0));
  m.update_boundary_tags();
  require_valid(m);
  CHECK(compute_stats(m).boundary_edges == 4);
}

TEST_CASE("build drops degenerate, duplicated triangles and unreferenced vertices") {
  MeshData d = grid(2);
  d.triangles.push_back(d.triangles[0]);                    // duplicate
  d.triangles.push_back({d.triangles[1][0], d.triangles[1][2], d.triangles[1][1]});  // reversed duplicate
  d.triangles.push_back({0, 0, 1});                         // degenerate
  d.vertices.push_back({5, 5, 5});                          // unreferenced
  SurfaceMesh m;
  auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(rep.duplicate_triangles == 2);
  CHECK(rep.degenerate_triangles == 1);
  CHECK(rep.unreferenced_vertices == 1);
  CHECK(m.n_triangles() == 8);
  CHECK(m.n_vertices() == 9);
  CHECK(rep.vertex_map.back() == -1);
  CHECK(rep.repaired());
}

TEST_CASE("non-manifold edge is cut, non-manifold vertex is split") {
  SUBCASE("three triangles on one edge") {
    MeshData d;
    d.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
    d.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    SurfaceMesh m;
    auto rep = build_mesh(d, m);
    require_valid(m);
    CHECK(rep.non_manifold_edges == 1);
    CHECK(compute_stats(m).non_manifold_edges >= 1);
  }
  SUBCASE("bow tie: two triangles touching at a vertex") {
    MeshData d;
    d.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    d.triangles = {{0, 1, 2}, {0, 3, 4}};
    SurfaceMesh m;
    auto rep = build_mesh(d, m);
    require_valid(m);
    CHECK(rep.non_manifold_vertices == 1);
    CHECK(m.n_vertices() == 6);
    CHECK(compute_stats(m).components == 2);
    // both copies come from file vertex 0
    int from0 = 0;
    for (int o : rep.vertex_origin) from0 += o == 0;
    CHECK(from0 == 2);
  }
}

TEST_CASE("Moebius strip: non-orientable, cut to stay valid") {
  MeshData d = moebius_strip();
  SurfaceMesh m;
  auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(rep.non_orientable_components == 1);
}

TEST_CASE("split vertices are welded with a tolerance relative to the box") {
  MeshData d = grid(2);
  MeshData s;  // every triangle with its own copies, with tiny noise
  for (const auto& t : d.triangles)
    for (int k = 0; k < 3; ++k) {
      Vec3 p = d.vertices[t[k]];
      p.x += 1e-13 * (k + 1);
      s.vertices.push_back(p);
    }
  for (int t = 0; t < static_cast<int>(d.triangles.size()); ++t) s.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  s.split_vertices = true;
  SurfaceMesh exact;
  build_mesh(s, exact);  // default: identical positions only, the noise keeps them apart
  require_valid(exact);
  CHECK(exact.n_vertices() > 9);
  BuildOptions weld;
  weld.merge_tolerance = 1e-9;
  SurfaceMesh m;
  auto rep = build_mesh(s, m, weld);
  require_valid(m);
  CHECK(m.n_vertices() == 9);
  CHECK(rep.merged_vertices == static_cast<int>(s.vertices.size()) - 9);
  CHECK(compute_stats(m).boundary_edges == 8);
}

TEST_CASE("identical positions: counted, merged on request, -0 equal to +0, the first vertex kept") {
  MeshData d;
  // Two triangles sharing an edge; vertices 4 and 5 repeat 1 and 2 (4 with -0.0).
  d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, -0.0, 0}, {0, 1, 0}};
  d.triangles = {{0, 1, 2}, {4, 3, 5}};
  SurfaceMesh kept, merged;
  const BuildReport a = build_mesh(d, kept);
  CHECK(a.unique_positions == 4);
  CHECK(kept.n_vertices() == 6);
  CHECK(kept.n_triangles() == 2);
  BuildOptions o;
  o.merge = BuildOptions::Merge::Always;
  const BuildReport b = build_mesh(d, merged, o);
  CHECK(b.unique_positions == 4);
  CHECK(b.merged_vertices == 2);
  REQUIRE(merged.n_vertices() == 4);
  CHECK(merged.validate().ok());
  int interior = 0;
  for (Corner c : merged.edges()) interior += merged.opposite(c).is_valid();
  CHECK(interior == 1);  // the two triangles share the merged edge
}

TEST_CASE("refused input names the problem") {
  SurfaceMesh m;
  MeshData empty;
  CHECK_THROWS_AS(build_mesh(empty, m, {}, "empty.obj"), TopologyError);
  try {
    build_mesh(empty, m, {}, "empty.obj");
  } catch (const TopologyError& e) {
    CHECK(std::string(e.what()).find("empty.obj") != std::string::npos);
    CHECK(std::string(e.what()).find("no triangle") != std::string::npos);
  }
  MeshData bad = tetrahedron();
  bad.triangles[2][1] = 7;
  CHECK_THROWS_AS(build_mesh(bad, m), TopologyError);
  MeshData nan = tetrahedron();
  nan.vertices[1].y = NAN;
  CHECK_THROWS_AS(build_mesh(nan, m), TopologyError);
  // Coordinates whose squares overflow (1e155, 1e308) are refused naming the vertex.
  for (double big : {1e155, -1e308}) {
    MeshData huge = tetrahedron();
    huge.vertices[2].x = big;
    CHECK_THROWS_WITH_AS(build_mesh(huge, m, {}, "huge.stl"), doctest::Contains("huge.stl: vertex 3 has a coordinate beyond"),
                         TopologyError);
  }
  MeshData large = tetrahedron();
  for (Vec3& p : large.vertices) p = p * 1e140;  // large but measurable: built
  CHECK_NOTHROW(build_mesh(large, m));
  CHECK(std::isfinite(m.bbox().diagonal()));
}

TEST_CASE("tags, references, normals and fields survive build and to_mesh_data") {
  MeshData d = grid(2);
  d.triangle_refs.assign(d.triangles.size(), 0);
  d.triangle_refs[3] = 7;
  d.vertex_refs.assign(d.vertices.size(), 0);
  d.vertex_refs[4] = 3;
  d.edges = {{0, 1}, {1, 2}, {0, 4}};
  d.edge_refs = {10, 11, 12};
  d.ridges = {2};
  d.required_edges = {0};
  d.corners = {0, 2};
  d.required_vertices = {8};
  d.required_triangles = {5};
  d.normals = {{0, 0, 1}};
  d.normal_at_vertex = {{4, 0}};
  FieldData f{{"h", FieldKind::Scalar, 1}, {}};
  for (std::size_t v = 0; v < d.vertices.size(); ++v) f.values.push_back(0.5 + v);
  d.fields.push_back(f);
  SurfaceMesh m;
  build_mesh(d, m);
  require_valid(m);
  Corner e = m.find_edge(Vertex(0), Vertex(4));
  if (!e.is_valid()) e = m.find_edge(Vertex(4), Vertex(0));
  REQUIRE(e.is_valid());
  CHECK(m.has_tag(e, kRidge));
  CHECK(m.edge_ref(e) == 12);
  CHECK(m.has_tag(Vertex(0), kCorner));
  CHECK(m.has_tag(Vertex(8), kRequired));
  CHECK(m.vertex_ref(Vertex(4)) == 3);
  CHECK(m.triangle_ref(Triangle(3)) == 7);
  CHECK(m.has_tag(Triangle(5), kRequired));
  auto field = m.get_field("h");
  REQUIRE(field);
  CHECK(field[Vertex(5)][0] == 5.5);

  MeshData back = to_mesh_data(m);
  CHECK(back.vertices == d.vertices);
  CHECK(back.triangles == d.triangles);
  CHECK(back.triangle_refs == d.triangle_refs);
  CHECK(back.vertex_refs == d.vertex_refs);
  CHECK(back.edges.size() == 3);
  CHECK(back.ridges.size() == 1);
  CHECK(back.required_edges.size() == 1);
  CHECK(back.corners == d.corners);
  CHECK(back.required_vertices == d.required_vertices);
  CHECK(back.required_triangles == d.required_triangles);
  CHECK(back.normal_at_vertex.size() == 1);
  REQUIRE(back.fields.size() == 1);
  CHECK(back.fields[0].values == f.values);
}

TEST_CASE("free lists: deleted slots are reused, compact renumbers properties") {
  SurfaceMesh m;
  build_mesh(grid(3), m);
  auto label = m.add_vertex_property<int>("label", -1);
  for (int v = 0; v < m.vertex_capacity(); ++v) label[Vertex(v)] = v;
  const int cap_t = m.triangle_capacity(), cap_v = m.vertex_capacity();
  // Remove the corner triangle at vertex 0 region: triangles using vertex 0.
  std::vector<Corner> fan0 = m.fan(Vertex(0));
  for (Corner c : fan0) m.delete_triangle(SurfaceMesh::triangle(c));
  m.delete_vertex(Vertex(0));
  require_valid(m);
  CHECK(m.n_vertices() == cap_v - 1);
  CHECK(m.has_garbage());
  // re-add: slots are reused, no growth
  Vertex v = m.add_vertex({0, 0, 0});
  CHECK(v.idx == 0);
  CHECK(label[v] == -1);  // reset to the default
  label[v] = 0;
  Triangle t = m.add_triangle(v, Vertex(1), Vertex(5));
  CHECK(t.idx < cap_t);
  require_valid(m);
  CHECK(m.triangle_capacity() == cap_t);
  CHECK(m.vertex_capacity() == cap_v);
  // delete an interior-free triangle and compact
  m.delete_triangle(Triangle(17));
  require_valid(m);
  CompactMap map = m.compact();
  require_valid(m);
  CHECK_FALSE(m.has_garbage());
  CHECK(map.triangle[17] == -1);
  CHECK(m.triangle_capacity() == m.n_triangles());
  for (int i = 0; i < m.vertex_capacity(); ++i) CHECK(label.vector().size() == static_cast<std::size_t>(m.vertex_capacity()));
}

TEST_CASE("absorb: another mesh moved in, free slots first, properties and tags carried, the part emptied") {
  SurfaceMesh whole;
  build_mesh(grid(3), whole);
  auto label = whole.add_vertex_property<int>("label", -1);
  for (Vertex v : whole.vertices()) label[v] = v.idx;
  for (Corner c : whole.fan(Vertex(0))) whole.delete_triangle(SurfaceMesh::triangle(c));
  whole.delete_vertex(Vertex(0));
  const int nv = whole.n_vertices(), nt = whole.n_triangles();
  const int cap_v = whole.vertex_capacity(), cap_t = whole.triangle_capacity();
  const int free_t = cap_t - nt;
  REQUIRE(free_t > 0);

  SurfaceMesh part;
  build_mesh(tetrahedron(), part);
  for (Vertex v : part.vertices()) part.position(v) = part.position(v) + Vec3{5, 0, 0};
  auto part_label = part.add_vertex_property<int>("label", -1);
  part.add_vertex_property<double>("only_in_part", 1.0);
  for (Vertex v : part.vertices()) part_label[v] = 100 + v.idx;
  part.set_vertex_tags(Vertex(2), kRequired);
  part.set_vertex_ref(Vertex(3), 7);
  part.set_triangle_ref(Triangle(1), 9);
  part.set_edge_ref(SurfaceMesh::corner(Triangle(0), 0), 4);
  const SurfaceMesh copy = part;

  const AbsorbMap map = whole.absorb(std::move(part), {});
  require_valid(whole);
  CHECK(part.vertex_capacity() == 0);
  CHECK(part.triangle_capacity() == 0);
  CHECK(whole.n_vertices() == nv + 4);
  CHECK(whole.n_triangles() == nt + 4);
  // The free vertex slot 0 and the free triangle slots are used first.
  CHECK(map.vertex[0] == 0);
  CHECK(whole.vertex_capacity() == cap_v + 3);
  CHECK(whole.triangle_capacity() == cap_t + std::max(0, 4 - free_t));
  CHECK_FALSE(whole.get_vertex_property<double>("only_in_part"));
  for (Vertex v : copy.vertices()) {
    const Vertex w(map.vertex[static_cast<std::size_t>(v.idx)]);
    CHECK(whole.position(w) == copy.position(v));
    CHECK(label[w] == 100 + v.idx);
    CHECK(whole.vertex_tags(w) == copy.vertex_tags(v));
    CHECK(whole.vertex_ref(w) == copy.vertex_ref(v));
  }
  for (Triangle t : copy.triangles()) {
    const Triangle w(map.triangle[static_cast<std::size_t>(t.idx)]);
    CHECK(whole.triangle_ref(w) == copy.triangle_ref(t));
    for (int k = 0; k < 3; ++k) {
      CHECK(whole.vertex(w, k).idx == map.vertex[static_cast<std::size_t>(copy.vertex(t, k).idx)]);
      const Corner c = SurfaceMesh::corner(t, k), wc = SurfaceMesh::corner(w, k);
      CHECK(whole.edge_ref(wc) == copy.edge_ref(c));
      CHECK(SurfaceMesh::triangle(whole.opposite(wc)).idx == map.triangle[static_cast<std::size_t>(SurfaceMesh::triangle(copy.opposite(c)).idx)]);
    }
  }
  // The grid's vertices and their labels are untouched.
  for (Vertex v : whole.vertices())
    if (whole.position(v).x < 4) CHECK(label[v] == v.idx);
}

TEST_CASE("release_links: a waiting mesh gives its links and vertex corners back, found again, a slit keeps them") {
  SurfaceMesh m;
  build_mesh(read_mesh_data(test::asset_file("demo.mesh")), m);
  // A hole, so that border edges and free slots are in the table too.
  const Vertex v(5);
  std::vector<Triangle> fan;
  for (Corner c : m.fan_corners(v)) fan.push_back(SurfaceMesh::triangle(c));
  for (Triangle t : fan) m.delete_triangle(t);
  m.delete_vertex(v);
  require_valid(m);
  auto opposites = [](const SurfaceMesh& mesh) {
    std::vector<int> o;
    for (int c = 0; c < 3 * mesh.triangle_capacity(); ++c)
      o.push_back(mesh.is_deleted(SurfaceMesh::triangle(Corner(c))) ? -2 : mesh.opposite(Corner(c)).idx);
    return o;
  };
  const std::vector<int> before = opposites(m);
  REQUIRE(std::count(before.begin(), before.end(), -1) > 0);

  SUBCASE("links found again from the triangles alone") {
    std::vector<int> border_corner;
    for (Vertex u : m.vertices()) border_corner.push_back(m.is_boundary(u) ? m.corner(u).idx : -1);
    CHECK_FALSE(m.links_released());
    CHECK(m.links_restorable());
    REQUIRE(m.release_links());
    CHECK(m.links_released());
    m.restore_links();
    CHECK_FALSE(m.links_released());
    require_valid(m);
    CHECK(opposites(m) == before);
    // A border vertex's corner is the most clockwise one again.
    std::size_t i = 0;
    for (Vertex u : m.vertices()) {
      if (border_corner[i] >= 0) CHECK(m.corner(u).idx == border_corner[i]);
      ++i;
    }
    m.restore_links();  // nothing to do
    CHECK(opposites(m) == before);
  }
  SUBCASE("compacted: the vertex corners are freed too and found again") {
    m.compact();
    const std::vector<int> compacted = opposites(m);
    std::vector<int> corners;
    for (Vertex u : m.vertices()) corners.push_back(m.corner(u).idx);
    REQUIRE(m.release_links());
    m.restore_links();
    require_valid(m);
    CHECK(opposites(m) == compacted);
    std::size_t i = 0;
    for (Vertex u : m.vertices()) {
      const bool in_fan = std::ranges::any_of(m.fan(u), [&](Corner k) { return k.idx == corners[i]; });
      CHECK(in_fan);
      if (m.is_boundary(u)) CHECK(m.corner(u).idx == corners[i]);
      ++i;
    }
  }
  SUBCASE("a slit whose two sides share their ends keeps its links") {
    // Unlink one interior edge: its two sides run a->b and b->a, both on
    // the border, which rebuilding from the triangles would join again.
    Corner c;
    for (int i = 0; i < 3 * m.triangle_capacity() && !c.is_valid(); ++i) {
      const Corner k(i);
      if (m.is_deleted(SurfaceMesh::triangle(k)) || m.is_boundary_edge(k)) continue;
      if (m.is_boundary(m.edge_from(k)) || m.is_boundary(m.edge_to(k))) continue;
      c = k;
    }
    REQUIRE(c.is_valid());
    const Corner o = m.opposite(c);
    const Vertex a = m.edge_from(c), b = m.edge_to(c);
    m.link(c, Corner());
    m.link(o, Corner());
    m.update_vertex_corner(a);
    m.update_vertex_corner(b);
    require_valid(m);
    CHECK_FALSE(m.links_restorable());
    const std::vector<int> slit = opposites(m);
    CHECK_FALSE(m.release_links());
    CHECK_FALSE(m.links_released());
    CHECK(opposites(m) == slit);
  }
}

TEST_CASE("add_triangle links neighbours, a copy is independent") {
  SurfaceMesh m;
  Vertex a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0}), c = m.add_vertex({1, 1, 0}),
         d = m.add_vertex({0, 1, 0});
  m.add_triangle(a, b, c);
  m.add_triangle(a, c, d);
  require_valid(m);
  CHECK(m.n_triangles() == 2);
  Corner e = m.find_edge(a, c);
  REQUIRE(e.is_valid());
  CHECK_FALSE(m.is_boundary_edge(e));
  SurfaceMesh copy = m;
  copy.position(a).x = 5;
  CHECK(m.position(a).x == 0);
  require_valid(copy);
}

TEST_CASE("validate detects corruption") {
  SurfaceMesh m;
  build_mesh(grid(2), m);
  require_valid(m);
  SUBCASE("asymmetric opposite link") {
    Corner c(0);
    Corner o = m.opposite(c);
    if (!o.is_valid()) {
      c = Corner(1);
      o = m.opposite(c);
    }
    REQUIRE(o.is_valid());
    m.link(c, Corner(2));
    CHECK_FALSE(m.validate().ok());
  }
  SUBCASE("wrong vertex corner") {
    m.set_vertex_corner(Vertex(4), Corner(0));
    CHECK_FALSE(m.validate().ok());
  }
  SUBCASE("degenerate triangle") {
    m.set_corner_vertex(Corner(0), m.vertex(Corner(1)));
    CHECK_FALSE(m.validate().ok());
  }
}

TEST_CASE("random deletions and re-insertions keep the invariants") {
  SurfaceMesh m;
  build_mesh(grid(8), m);
  std::mt19937 rng(42);
  for (int round = 0; round < 200; ++round) {
    // delete a random triangle whose removal keeps every vertex manifold:
    // all three of its vertices are interior or it has a boundary edge
    // adjacent to exactly the fan ends.
    int t = static_cast<int>(rng() % m.triangle_capacity());
    Triangle th(t);
    if (m.is_deleted(th)) continue;
    Vertex vs[3] = {m.vertex(th, 0), m.vertex(th, 1), m.vertex(th, 2)};
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(th, k);
      bool first = !m.swing_cw(c).is_valid(), last = !m.swing_ccw(c).is_valid();
      if (m.is_boundary(vs[k]) && !first && !last) ok = false;  // would split the fan
    }
    if (!ok) continue;
    m.delete_triangle(th);
    for (Vertex v : vs)
      if (m.is_isolated(v)) m.delete_vertex(v);
    require_valid(m);
    // and put it back half of the time
    if (round % 2 == 0) {
      bool live = true;
      for (Vertex v : vs) live = live && !m.is_deleted(v);
      if (live) {
        m.add_triangle(vs[0], vs[1], vs[2]);
        require_valid(m);
      }
    }
  }
  CHECK(all_up(m));
  m.compact();
  require_valid(m);
}

TEST_CASE("ranges and circulators: live elements once, fans and rings as walked") {
  SUBCASE("grid with random deletions (open fans, holes, free slots)") {
    SurfaceMesh m;
    build_mesh(grid(8), m);
    check_ranges_and_circulators(m);
    std::mt19937 rng(7);
    int deleted = 0;
    for (int round = 0; round < 300 && deleted < 25; ++round) {
      const Triangle t(static_cast<int>(rng() % m.triangle_capacity()));
      if (m.is_deleted(t)) continue;
      bool ok = true;  // keep every fan in one piece (as in the test above)
      for (int k = 0; k < 3; ++k) {
        const Corner c = SurfaceMesh::corner(t, k);
        const bool first = !m.swing_cw(c).is_valid(), last = !m.swing_ccw(c).is_valid();
        if (m.is_boundary(m.vertex(c)) && !first && !last) ok = false;
      }
      if (!ok) continue;
      const Vertex vs[3] = {m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2)};
      m.delete_triangle(t);
      for (Vertex v : vs)
        if (m.is_isolated(v)) m.delete_vertex(v);
      ++deleted;
    }
    require_valid(m);
    REQUIRE(m.has_garbage());
    check_ranges_and_circulators(m);
    // an empty range on a mesh without elements
    SurfaceMesh empty;
    CHECK(empty.vertices().empty());
    CHECK(empty.triangles().empty());
    CHECK(empty.edges().empty());
  }
  SUBCASE("non-manifold edge cut, bow tie split, Moebius strip cut") {
    MeshData three;
    three.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
    three.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    MeshData bow;
    bow.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    bow.triangles = {{0, 1, 2}, {0, 3, 4}};
    const MeshData moebius = moebius_strip();
    for (const MeshData* d : std::initializer_list<const MeshData*>{&three, &bow, &moebius}) {
      SurfaceMesh m;
      build_mesh(*d, m);
      require_valid(m);
      check_ranges_and_circulators(m);
    }
  }
  SUBCASE("every shared mesh and the benchmark inputs") {
    const std::string dir = test::shared_file("meshes");
    if (dir.empty()) {
      MESSAGE("skipped: ../shared/meshes not found (no shared test data)");
      return;
    }
    std::vector<std::string> paths;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      const std::string ext = e.path().extension().string();
      if (ext == ".bin" || ext == ".md") continue;
      paths.push_back(e.path().string());
    }
    for (const char* f : {"bench/inputs/hemi.mesh", "bench/inputs/sphere20k.mesh", "bench/inputs/square3d.mesh"})
      if (!test::shared_file(f).empty()) paths.push_back(test::shared_file(f));
    std::sort(paths.begin(), paths.end());
    for (const std::string& path : paths) {
      CAPTURE(path);
      SurfaceMesh m;
      try {
        m = load_mesh(path);
      } catch (const std::exception& ex) {
        FAIL_CHECK("loading threw: " << ex.what());
        continue;
      }
      check_ranges_and_circulators(m);
    }
  }
}

TEST_CASE("to_mesh_data of a mesh given away: the same data, the mesh left empty") {
  SurfaceMesh m;
  build_mesh(read_mesh_data(test::asset_file("demo.mesh")), m);
  m.set_vertex_ref(Vertex(3), 7);
  // Exactly equal: positions bit for bit, elements, references, corners.
  auto same = [](const MeshData& a, const MeshData& b) {
    test::check_same_mesh(b, a, true);
    CHECK(a.ridges == b.ridges);
  };
  {
    SurfaceMesh copy = m;
    const MeshData expected = to_mesh_data(m);
    const MeshData got = to_mesh_data(std::move(copy));
    same(got, expected);
    CHECK(copy.vertex_capacity() == 0);
    CHECK(copy.triangle_capacity() == 0);
  }
  // With deleted slots the positions are copied in the file's numbering.
  SurfaceMesh holes = m;
  const Vertex v(5);
  std::vector<Triangle> fan;
  for (Corner c : holes.fan_corners(v)) fan.push_back(SurfaceMesh::triangle(c));
  for (Triangle t : fan) holes.delete_triangle(t);
  holes.delete_vertex(v);
  REQUIRE(holes.n_vertices() < holes.vertex_capacity());
  const MeshData expected = to_mesh_data(holes);
  same(to_mesh_data(std::move(holes)), expected);
  CHECK(holes.vertex_capacity() == 0);
}

TEST_CASE("shrink_to_fit: a compacted mesh keeps every element, tag and property") {
  SurfaceMesh m;
  build_mesh(read_mesh_data(test::asset_file("demo.mesh")), m);
  auto p = m.add_vertex_property<double>("x", 0.0);
  for (Vertex v : m.vertices()) p[v] = m.position(v).x;
  const MeshData before = to_mesh_data(m);
  m.reserve(4 * m.vertex_capacity(), 4 * m.triangle_capacity());
  m.shrink_to_fit();
  CHECK(m.validate().ok());
  const MeshData after = to_mesh_data(m);
  CHECK(after.triangles == before.triangles);
  CHECK(after.edges == before.edges);
  p = m.get_vertex_property<double>("x");
  REQUIRE(p);
  for (Vertex v : m.vertices()) CHECK(p[v] == m.position(v).x);
}

TEST_CASE("packed normals: within 1e-4 radian of the unit vector packed, the zero vector kept") {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  double worst = 0;
  std::vector<Vec3> dirs = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  for (int i = 0; i < 200000; ++i) dirs.push_back(normalized(Vec3(g(rng), g(rng), g(rng))));
  for (const Vec3& n : dirs) {
    const Vec3 back = unpack_normal(pack_normal(n));
    CHECK(std::abs(norm(back) - 1) < 1e-12);
    worst = std::max(worst, std::atan2(norm(cross(n, back)), dot(n, back)));
  }
  CHECK(worst < 1e-4);
  CHECK(norm(unpack_normal(pack_normal(Vec3()))) == 0);
  CHECK(norm(unpack_normal(PackedNormal{})) == 0);
}
