#include "mesh/operators.h"

#include <algorithm>
#include <array>

namespace anisurf {

namespace {

using M = SurfaceMesh;

// Per-edge data (tags + reference) moved with an edge to a new corner.
struct EdgeData {
  std::uint8_t tags = 0;
  int ref = 0;
};

EdgeData edge_data(const SurfaceMesh& m, Corner c) { return {m.edge_tags(c), m.edge_ref(c)}; }

// Links a and b (either may be invalid) and gives both the data d.
void link_with(SurfaceMesh& m, Corner a, Corner b, EdgeData d) {
  if (a.is_valid()) {
    m.link(a, b);
    if (!b.is_valid()) m.link(a, Corner());
    m.set_edge_tags(a, d.tags);
    m.set_edge_ref(a, d.ref);
  } else if (b.is_valid()) {
    m.link(b, Corner());
    m.set_edge_tags(b, d.tags);
    m.set_edge_ref(b, d.ref);
  }
}

std::uint8_t boundary_free(std::uint8_t t) { return static_cast<std::uint8_t>(t & ~kBoundary); }

// Number of times w appears in the one-ring of v (more than once only next
// to cut edges).
int ring_count(const SurfaceMesh& m, Vertex v, Vertex w) {
  int n = 0;
  for (Vertex x : m.ring_vertices(v)) n += x == w;
  return n;
}

// True if w appears in the one-ring of v before the position `it`.
bool seen_before(const SurfaceMesh& m, Vertex v, RingVertexIterator it) {
  const Vertex w = *it;
  for (auto x = m.ring_vertices(v).begin(); x != it; ++x)
    if (*x == w) return true;
  return false;
}

// Link condition of the edge b-d with opposite vertices a and e (e invalid
// on a boundary edge): the rings of b and d share exactly `expected`
// vertices, each a or e. Shared vertices are counted with multiplicity, as
// the intersection of the two rings sorted as multisets (min of the two
// counts per vertex).
bool is_link_condition_ok_walking(const SurfaceMesh& m, Vertex b, Vertex d, Vertex a, Vertex e, int expected) {
  int shared = 0;
  const RingVertexRange ring_b = m.ring_vertices(b);
  for (auto it = ring_b.begin(); it != ring_b.end(); ++it) {
    const Vertex w = *it;
    const int in_d = ring_count(m, d, w);
    if (in_d == 0 || seen_before(m, b, it)) continue;
    const int k = std::min(in_d, ring_count(m, b, w));
    if (w != a && w != e) return false;
    shared += k;
  }
  return shared == expected;
}

// The ring of v in the order of ring_vertices, into out (at most kMax
// entries); false when it holds more.
template <std::size_t kMax>
bool ring_into(const SurfaceMesh& m, Vertex v, std::array<int, kMax>& out, int& n) {
  n = 0;
  for (Vertex x : m.ring_vertices(v)) {
    if (n == static_cast<int>(kMax)) return false;
    out[static_cast<std::size_t>(n++)] = x.idx;
  }
  return true;
}

int count_in(const int* first, const int* last, int w) {
  int n = 0;
  for (const int* x = first; x != last; ++x) n += *x == w;
  return n;
}

// is_link_condition_ok_walking on the two rings read once into arrays (the
// same counts in the same order); rings longer than the arrays are walked.
bool is_link_condition_ok(const SurfaceMesh& m, Vertex b, Vertex d, Vertex a, Vertex e, int expected) {
  constexpr std::size_t kMax = 64;
  std::array<int, kMax> rb, rd;
  int nb = 0, nd = 0;
  if (!ring_into(m, b, rb, nb) || !ring_into(m, d, rd, nd)) return is_link_condition_ok_walking(m, b, d, a, e, expected);
  const int* b0 = rb.data();
  int shared = 0;
  for (int i = 0; i < nb; ++i) {
    const int w = rb[static_cast<std::size_t>(i)];
    const int in_d = count_in(rd.data(), rd.data() + nd, w);
    if (in_d == 0 || count_in(b0, b0 + i, w) > 0) continue;
    const int k = std::min(in_d, count_in(b0, b0 + nb, w));
    if (w != a.idx && w != e.idx) return false;
    shared += k;
  }
  return shared == expected;
}

}  // namespace

std::vector<Vertex> one_ring(const SurfaceMesh& m, Vertex v) {
  std::vector<Vertex> ring;
  ring.reserve(8);
  for (Vertex w : m.ring_vertices(v)) ring.push_back(w);
  return ring;
}

// --- swap (section 5.4) ---------------------------------------------------------

bool can_flip(const SurfaceMesh& m, Corner c) {
  Corner o = m.opposite(c);
  if (!o.is_valid()) return false;
  if (M::triangle(o) == M::triangle(c)) return false;
  Vertex a = m.vertex(c), e = m.vertex(o);
  if (a == e) return false;
  // the new diagonal a-e must not exist already
  for (Vertex w : m.ring_vertices(a))
    if (w == e) return false;
  return true;
}

Corner flip(SurfaceMesh& m, Corner c) {
  Corner o = m.opposite(c);
  const Corner c0 = c, c1 = M::next(c), c2 = M::prev(c);
  const Corner o0 = o, o1 = M::next(o), o2 = M::prev(o);
  const Vertex a = m.vertex(c0), b = m.vertex(c1), d = m.vertex(c2), e = m.vertex(o0);
  const Corner A1 = m.opposite(c1), A2 = m.opposite(c2), B1 = m.opposite(o1), B2 = m.opposite(o2);
  const EdgeData dA1 = edge_data(m, c1), dA2 = edge_data(m, c2), dB1 = edge_data(m, o1), dB2 = edge_data(m, o2);
  const EdgeData diag{boundary_free(static_cast<std::uint8_t>(0)), 0};
  // triangle(c) = (a, b, e), triangle(o) = (e, d, a)
  m.set_corner_vertex(c0, a);
  m.set_corner_vertex(c1, b);
  m.set_corner_vertex(c2, e);
  m.set_corner_vertex(o0, e);
  m.set_corner_vertex(o1, d);
  m.set_corner_vertex(o2, a);
  for (Corner x : {c0, c1, c2, o0, o1, o2}) m.link(x, Corner());
  link_with(m, c0, B1, dB1);  // b -> e
  link_with(m, c1, o1, diag); // e -> a / a -> e
  link_with(m, c2, A2, dA2);  // a -> b
  link_with(m, o0, A1, dA1);  // d -> a
  link_with(m, o2, B2, dB2);  // e -> d
  m.set_vertex_corner(a, c0);
  m.set_vertex_corner(b, c1);
  m.set_vertex_corner(d, o1);
  m.set_vertex_corner(e, o0);
  for (Vertex v : {a, b, d, e}) m.update_vertex_corner(v);
  return c1;
}

// --- split (section 5.3) --------------------------------------------------------

Vertex split(SurfaceMesh& m, Corner c, const Vec3& p) {
  const Corner o = m.opposite(c);
  const Corner c0 = c, c1 = M::next(c), c2 = M::prev(c);
  const Vertex a = m.vertex(c0), b = m.vertex(c1), d = m.vertex(c2);
  const Corner A1 = m.opposite(c1);
  const EdgeData dA1 = edge_data(m, c1), dEdge = edge_data(m, c0);
  const EdgeData none{};
  const int tref0 = m.triangle_ref(M::triangle(c0));
  const std::uint8_t ttag0 = m.triangle_tags(M::triangle(c0));

  const Vertex mid = m.add_vertex(p);
  // triangle(c) becomes (a, b, mid); t2 = (a, mid, d)
  m.set_corner_vertex(c2, mid);
  const Triangle t2 = m.allocate_triangle();
  const Corner t20 = M::corner(t2, 0), t21 = M::corner(t2, 1), t22 = M::corner(t2, 2);
  m.set_corner_vertex(t20, a);
  m.set_corner_vertex(t21, mid);
  m.set_corner_vertex(t22, d);
  m.set_triangle_ref(t2, tref0);
  m.set_triangle_tags(t2, ttag0);
  link_with(m, c1, t22, none);  // a - mid
  link_with(m, t21, A1, dA1);   // d - a

  if (!o.is_valid()) {
    link_with(m, c0, Corner(), dEdge);   // b - mid on the boundary
    link_with(m, t20, Corner(), dEdge);  // mid - d on the boundary
  } else {
    const Corner o0 = o, o1 = M::next(o), o2 = M::prev(o);
    const Vertex e = m.vertex(o0);
    (void)e;
    const Corner B1 = m.opposite(o1);
    const EdgeData dB1 = edge_data(m, o1);
    const int tref1 = m.triangle_ref(M::triangle(o0));
    const std::uint8_t ttag1 = m.triangle_tags(M::triangle(o0));
    // triangle(o) = (e, d, b) becomes (e, d, mid); t3 = (e, mid, b)
    m.set_corner_vertex(o2, mid);
    const Triangle t3 = m.allocate_triangle();
    const Corner t30 = M::corner(t3, 0), t31 = M::corner(t3, 1), t32 = M::corner(t3, 2);
    m.set_corner_vertex(t30, m.vertex(o0));
    m.set_corner_vertex(t31, mid);
    m.set_corner_vertex(t32, b);
    m.set_triangle_ref(t3, tref1);
    m.set_triangle_tags(t3, ttag1);
    link_with(m, c0, t30, dEdge);  // b - mid
    link_with(m, t20, o0, dEdge);  // mid - d
    link_with(m, o1, t32, none);   // e - mid
    link_with(m, t31, B1, dB1);    // b - e
    m.set_vertex_corner(b, c1);
  }
  m.set_vertex_corner(mid, t21);
  m.set_vertex_corner(d, t22);
  for (Vertex v : {a, b, d, mid}) m.update_vertex_corner(v);
  if (o.is_valid()) m.update_vertex_corner(m.vertex(o));
  return mid;
}

// --- collapse (section 5.1) -------------------------------------------------------

bool can_collapse(const SurfaceMesh& m, Corner c) {
  const Vertex b = m.edge_from(c), d = m.edge_to(c);
  if (b == d) return false;
  const Corner o = m.opposite(c);
  const bool boundary_edge = !o.is_valid();
  if (!boundary_edge && m.is_boundary(b) && m.is_boundary(d)) return false;
  const Vertex a = m.vertex(c);
  const Vertex e = boundary_edge ? Vertex() : m.vertex(o);
  // link condition: common neighbours are exactly the opposite vertices
  if (!is_link_condition_ok(m, b, d, a, e, boundary_edge ? 1 : 2)) return false;
  // a triangle whose two other edges are on the boundary would dangle
  if (m.is_boundary_edge(M::next(c)) && m.is_boundary_edge(M::prev(c))) return false;
  if (!boundary_edge && m.is_boundary_edge(M::next(o)) && m.is_boundary_edge(M::prev(o))) return false;
  // an interior opposite vertex of valence 3 would be left with two folded triangles
  if (!m.is_boundary(a) && m.valence(a) <= 3) return false;
  if (!boundary_edge && !m.is_boundary(e) && m.valence(e) <= 3) return false;
  // a boundary opposite vertex of valence 2 would lose its only triangle
  if (m.is_boundary(a) && m.valence(a) <= 2) return false;
  if (!boundary_edge && m.is_boundary(e) && m.valence(e) <= 2) return false;
  return true;
}

Vertex collapse(SurfaceMesh& m, Corner c) {
  const Vertex b = m.edge_from(c), d = m.edge_to(c);
  const Corner o = m.opposite(c);
  const Corner c0 = c, c1 = M::next(c), c2 = M::prev(c);
  const Vertex a = m.vertex(c0);
  const Corner A1 = m.opposite(c1), A2 = m.opposite(c2);
  auto merged = [&](Corner x, Corner y) {
    EdgeData dx = edge_data(m, x), dy = edge_data(m, y);
    std::uint8_t tags = static_cast<std::uint8_t>((dx.tags | dy.tags) & ~kBoundary);
    return EdgeData{tags, dx.ref != 0 ? dx.ref : dy.ref};
  };
  const EdgeData dA = merged(c2, c1);
  const Triangle t0 = M::triangle(c0);
  Triangle t1;
  Vertex e;
  Corner B1, B2;
  EdgeData dB;
  if (o.is_valid()) {
    const Corner o1 = M::next(o), o2 = M::prev(o);
    t1 = M::triangle(o);
    e = m.vertex(o);
    B1 = m.opposite(o1);
    B2 = m.opposite(o2);
    dB = merged(o1, o2);
  }
  // every triangle of b now uses d
  // (the swing reads the opposite links only, which this loop leaves alone)
  for (Corner x : m.fan_corners(b)) m.set_corner_vertex(x, d);
  // the two edges on each side become one
  link_with(m, A1, A2, dA);
  if (o.is_valid()) link_with(m, B1, B2, dB);
  m.release_triangle(t0);
  if (t1.is_valid()) m.release_triangle(t1);
  m.delete_vertex(b);
  // incident corners of the vertices around the removed triangles
  auto first_live = [&](std::initializer_list<Corner> cands) {
    for (Corner x : cands)
      if (x.is_valid() && !m.is_deleted(M::triangle(x))) return x;
    return Corner();
  };
  m.set_vertex_corner(a, first_live({A1.is_valid() ? M::next(A1) : Corner(), A2.is_valid() ? M::prev(A2) : Corner()}));
  m.set_vertex_corner(d, first_live({A1.is_valid() ? M::prev(A1) : Corner(), A2.is_valid() ? M::next(A2) : Corner(),
                                     B1.is_valid() ? M::prev(B1) : Corner(), B2.is_valid() ? M::next(B2) : Corner()}));
  if (e.is_valid())
    m.set_vertex_corner(e, first_live({B1.is_valid() ? M::next(B1) : Corner(), B2.is_valid() ? M::prev(B2) : Corner()}));
  m.update_vertex_corner(a);
  m.update_vertex_corner(d);
  if (e.is_valid()) m.update_vertex_corner(e);
  return d;
}

}  // namespace anisurf
