#include "locate/locator.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>

#include "geometry/parallel_chunks.h"
#include "locate/closest_point.h"

namespace anisurf {

// Everything a query reads, built once from the mesh and shared by copies.
struct Locator::Data {
  const SurfaceMesh* mesh = nullptr;
  LocateOptions options;
  double scale = 0;  // bounding box diagonal

  // Triangles, by slot (deleted slots: tv(t)[0] < 0), read from the mesh's
  // corner table.
  int n_slots = 0;
  const int* tv(int t) const { return mesh->triangle_vertices(Triangle(t)); }
  // Per slot: a bounding ball (centroid, radius); the positions are the
  // mesh's (through tv), not copied.
  // A ball holding the triangle, in single precision (16 bytes): the
  // centre rounded, the radius measured from the rounded centre and rounded
  // up, so the ball still holds it and distances to it stay lower bounds.
  struct Tri {
    float c[3] = {0, 0, 0};
    float r = 0;
    Vec3 centre() const { return {c[0], c[1], c[2]}; }
  };
  std::vector<Tri> tri;
  std::vector<int> vt_first, vt;  // vertex -> incident triangles (CSR)
  std::vector<double> vclear;     // per vertex slot: clearance rho(v), minus a rounding margin
  AabbTree tree;

  // Feature edges (each edge once).
  std::vector<int> fe_corner;               // a corner opposite the edge
  std::vector<std::array<int, 2>> fe_v;     // endpoints
  std::vector<Vec3> fe_p;                   // 2 positions per edge
  std::vector<int> vf_first, vf;            // vertex -> incident feature edges (CSR)
  std::vector<double> vfclear;              // per vertex slot: clearance among feature edges
  std::vector<int> corner_fe;               // per corner: its feature edge or -1
  AabbTree fe_tree;

  // Fixed corners.
  std::vector<int> corners;  // vertex ids
  AabbTree corner_tree;

  const Vec3& pos(int t, int k) const { return mesh->position(Vertex(tv(t)[k])); }
  double tri_d2(const Vec3& x, int t) const { return point_triangle_distance2(x, pos(t, 0), pos(t, 1), pos(t, 2)); }
  TriangleClosest tri_closest(const Vec3& x, int t) const { return closest_point_on_triangle(x, pos(t, 0), pos(t, 1), pos(t, 2)); }
  double seg_d2(const Vec3& x, int e) const {
    return point_segment_distance2(x, fe_p[2 * static_cast<std::size_t>(e)], fe_p[2 * static_cast<std::size_t>(e) + 1]);
  }
  // No element outside the neighbourhood of the element with vertices v[0..n)
  // at positions p[0..n) is closer to x than d: true when |x - v| + d <= rho(v)
  // for one of them (triangle inequality; every element outside that
  // neighbourhood misses v).
  static bool certified(const Vec3& x, double d, const int* v, const Vec3* p, int n, const std::vector<double>& rho) {
    for (int k = 0; k < n; ++k)
      if (norm(x - p[k]) + d <= rho[v[k]]) return true;
    return false;
  }
  bool live_triangle(int t) const { return t >= 0 && t < n_slots && tv(t)[0] >= 0; }
  // The local index of t's vertex opposite the edge beyond which x's foot
  // on t's plane lies (its most negative barycentric coordinate); -1 when
  // the foot lies in t, or t is degenerate.
  int foot_beyond_edge(const Vec3& x, int t) const {
    const Vec3 &p0 = pos(t, 0), &p1 = pos(t, 1), &p2 = pos(t, 2);
    const Vec3 n = cross(p1 - p0, p2 - p0);
    const Vec3 a = p0 - x, b = p1 - x, c = p2 - x;
    const double w0 = dot(n, cross(b, c)), w1 = dot(n, cross(c, a)), w2 = dot(n, cross(a, b));
    if (!(std::min({w0, w1, w2}) < 0)) return -1;
    return w0 <= w1 ? (w0 <= w2 ? 0 : 2) : (w1 <= w2 ? 1 : 2);
  }
  // Triangle t's bounding ball is at least r from x: t is no closer than r.
  bool ball_beyond(const Vec3& x, int t, double r) const {
    const Tri& T = tri[static_cast<std::size_t>(t)];
    const double reach = r + T.r;
    return norm2(x - T.centre()) >= reach * reach;
  }

  // Per triangle slot, found on first use: a lower bound of the distance
  // from the triangle to the nearest triangle sharing no vertex with it, in
  // one byte: code k for scale x 2^(-k/4) (the largest such value not above
  // the clearance less a rounding margin), kClearZero for 0, kClearUnknown
  // before it is found. Queries on several threads may find the same code
  // at once; it depends on the mesh only. Allocated at the first use (meshes
  // whose vertex clearances certify every query never need it).
  static constexpr std::uint8_t kClearZero = 254, kClearUnknown = 255;
  mutable std::unique_ptr<std::atomic<std::uint8_t>[]> tclear;
  mutable std::once_flag tclear_once;
  double clearance_of_code(std::uint8_t k) const { return k >= kClearZero ? 0.0 : scale * std::exp2(-0.25 * k); }
  double triangle_clearance(int t) const;

  void build(const SurfaceMesh& m, const LocateOptions& o);
  void build_triangles();
  void compute_vertex_clearances();
  double across_link_bound2(int v, const Vec3& x) const;
  double searched_clearance2(int v, const Vec3& x, double bound2) const;
  bool incident(int t, int v) const {
    const int* a = tv(t);
    return a[0] == v || a[1] == v || a[2] == v;
  }
  void build_features();
  void build_corners();
};

namespace {

// A clearance lowered by a margin for rounding.
double with_margin(double clearance, double scale) {
  return std::max(0.0, clearance * (1 - 1e-9) - 1e-13 * scale);
}

BBox box_of(const Vec3* p, int n) {
  BBox b;
  for (int i = 0; i < n; ++i) b.add(p[i]);
  return b;
}

// CSR adjacency from (key, value) pairs with keys in [0, n_keys).
void build_csr(int n_keys, const std::vector<std::array<int, 2>>& pairs, std::vector<int>& first, std::vector<int>& out) {
  first.assign(static_cast<std::size_t>(n_keys) + 1, 0);
  for (const auto& p : pairs) ++first[static_cast<std::size_t>(p[0]) + 1];
  for (int i = 0; i < n_keys; ++i) first[i + 1] += first[i];
  out.assign(pairs.size(), 0);
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (const auto& p : pairs) out[static_cast<std::size_t>(fill[p[0]]++)] = p[1];
}

}  // namespace

void Locator::Data::build(const SurfaceMesh& m, const LocateOptions& o) {
  mesh = &m;
  options = o;
  scale = m.bbox().diagonal();
  build_triangles();
  build_features();
  build_corners();
}

void Locator::Data::build_triangles() {
  const SurfaceMesh& m = *mesh;
  n_slots = m.triangle_capacity();
  tri.assign(static_cast<std::size_t>(n_slots), Tri());
  // The triangles of each vertex (compressed rows, in triangle order).
  const int n_vertices = m.vertex_capacity();
  vt_first.assign(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (Triangle th : m.triangles())
    for (int k = 0; k < 3; ++k) ++vt_first[static_cast<std::size_t>(m.vertex(th, k).idx) + 1];
  for (int i = 0; i < n_vertices; ++i) vt_first[i + 1] += vt_first[i];
  vt.assign(static_cast<std::size_t>(vt_first.back()), 0);
  {
    std::vector<int> fill(vt_first.begin(), vt_first.end() - 1);
    for (Triangle th : m.triangles())
      for (int k = 0; k < 3; ++k) vt[static_cast<std::size_t>(fill[m.vertex(th, k).idx]++)] = th.idx;
  }
  {
    // The boxes live only while the tree is built.
    std::vector<BBox> boxes(static_cast<std::size_t>(n_slots));
    for (Triangle th : m.triangles()) {
      const int t = th.idx;
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = m.position(m.vertex(th, k));
      boxes[t] = box_of(p, 3);
      Tri& T = tri[t];
      const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
      for (int k = 0; k < 3; ++k) T.c[k] = static_cast<float>(c[k]);
      const Vec3 cf = T.centre();
      const double r = std::max({norm(p[0] - cf), norm(p[1] - cf), norm(p[2] - cf)});
      T.r = std::nextafter(static_cast<float>(r * (1 + 1e-6)), INFINITY);
      if (!std::isfinite(T.r)) T = Tri{{0, 0, 0}, INFINITY};  // beyond single precision: never culls
    }
    tree.build(boxes);
  }

  compute_vertex_clearances();
}

// A first bound of v's clearance (squared): the distance to the nearest of
// the triangles across the edges of v's link that are not incident to v (on
// a smooth sheet, where the clearance is reached); +inf without one.
double Locator::Data::across_link_bound2(int v, const Vec3& x) const {
  const SurfaceMesh& m = *mesh;
  double best = INFINITY;
  for (int i = vt_first[v]; i < vt_first[v + 1]; ++i) {
    const int t = vt[i];
    const int* a = tv(t);
    const int k = a[0] == v ? 0 : (a[1] == v ? 1 : 2);
    const Corner across = m.opposite(SurfaceMesh::corner(Triangle(t), k));
    if (!across.is_valid()) continue;
    const int u = SurfaceMesh::triangle(across).idx;
    if (incident(u, v)) continue;
    best = std::min(best, tri_d2(x, u));
  }
  return best;
}

// A triangle is passed over by its bounding ball only when the ball lies
// beyond the distance to beat by this factor: the rounding of the ball test
// never passes over a triangle the exact distance would keep.
constexpr double kBallSlack = 1 + 1e-9;

// v's clearance (squared) from a tree search of its own: below `bound2`, the
// nearest triangle not incident to v, else bound2.
double Locator::Data::searched_clearance2(int v, const Vec3& x, double bound2) const {
  double best = bound2;
  tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
               [&](int t, double nearest) -> double {
                 if (incident(t, v)) return INFINITY;
                 return ball_beyond(x, t, std::sqrt(nearest) * kBallSlack) ? INFINITY : tri_d2(x, t);
               },
               best);
  return best;
}

// The clearance of every vertex: the distance to the nearest triangle not
// incident to it (exact, as a search of its own would find it). Leaf by
// leaf of the tree, in parallel chunks of leaves: each vertex goes with the
// first leaf holding one of its triangles; the leaf's vertices take a first
// bound from across their links, and one search gathers the leaves within
// the largest of those bounds from the leaf's box (every triangle nearer a
// vertex than its bound is in one of them). A vertex whose bound is far
// larger than the leaf (or that has none) searches on its own.
void Locator::Data::compute_vertex_clearances() {
  const SurfaceMesh& m = *mesh;
  const int nv = m.vertex_capacity();
  vclear.assign(static_cast<std::size_t>(nv), 0.0);
  const std::vector<AabbTree::Node>& nodes = tree.nodes();
  std::vector<int> leaves;
  for (int i = 0; i < static_cast<int>(nodes.size()); ++i)
    if (nodes[i].is_leaf()) leaves.push_back(i);
  // The vertices of each leaf (compressed rows).
  const int n_leaves = static_cast<int>(leaves.size());
  std::vector<int> owned_first(static_cast<std::size_t>(n_leaves) + 1, 0), owned;
  owned.reserve(static_cast<std::size_t>(m.n_vertices()));
  {
    std::vector<char> taken(static_cast<std::size_t>(nv), 0);
    for (int l = 0; l < n_leaves; ++l) {
      const AabbTree::Node& leaf = nodes[leaves[l]];
      for (const int* t = tree.leaf_begin(leaf); t != tree.leaf_end(leaf); ++t)
        for (int k = 0; k < 3; ++k) {
          const int v = tv(*t)[k];
          if (!taken[v]) taken[v] = 1, owned.push_back(v);
        }
      owned_first[l + 1] = static_cast<int>(owned.size());
    }
  }
  run_chunks(n_leaves, chunk_count(n_leaves, 2048), [&](int, int begin, int end) {
    std::vector<int> batch;
    std::vector<const AabbTree::Node*> near;
    std::vector<double> bound2;
    for (int l = begin; l < end; ++l) {
      const AabbTree::Node& leaf = nodes[leaves[l]];
      const Vec3 lo = leaf.lower(), hi = leaf.upper();
      const double far2 = 4 * norm2(hi - lo);
      batch.clear();
      bound2.clear();
      double reach2 = 0;
      for (int i = owned_first[l]; i < owned_first[l + 1]; ++i) {
        const int v = owned[i];
        const Vec3 x = m.position(Vertex(v));
        const double b2 = across_link_bound2(v, x);
        if (!(b2 <= far2)) {
          vclear[v] = with_margin(std::sqrt(searched_clearance2(v, x, b2)), scale);
          continue;
        }
        batch.push_back(v);
        bound2.push_back(b2);
        reach2 = std::max(reach2, b2);
      }
      if (batch.empty()) continue;
      near.clear();
      tree.for_each_leaf_within([&](const Vec3& a, const Vec3& b) { return box_box_distance2(lo, hi, a, b); }, reach2,
                                [&](const AabbTree::Node& n) { near.push_back(&n); });
      for (std::size_t i = 0; i < batch.size(); ++i) {
        const int v = batch[i];
        const Vec3 x = m.position(Vertex(v));
        double best = bound2[i];
        double reach = std::sqrt(best) * kBallSlack;
        for (const AabbTree::Node* n : near) {
          if (!(box_point_distance2(n->lower(), n->upper(), x) < best)) continue;
          for (const int* t = tree.leaf_begin(*n); t != tree.leaf_end(*n); ++t) {
            if (incident(*t, v) || ball_beyond(x, *t, reach)) continue;
            const double d2 = tri_d2(x, *t);
            if (d2 < best) best = d2, reach = std::sqrt(best) * kBallSlack;
          }
        }
        vclear[v] = with_margin(std::sqrt(best), scale);
      }
    }
  });
}

double Locator::Data::triangle_clearance(int t) const {
  std::call_once(tclear_once, [&] {
    tclear = std::make_unique<std::atomic<std::uint8_t>[]>(static_cast<std::size_t>(n_slots));
    for (int u = 0; u < n_slots; ++u) tclear[static_cast<std::size_t>(u)].store(kClearUnknown, std::memory_order_relaxed);
  });
  std::atomic<std::uint8_t>& slot = tclear[static_cast<std::size_t>(t)];
  const std::uint8_t known = slot.load(std::memory_order_relaxed);
  if (known != kClearUnknown) return clearance_of_code(known);
  const int* v = tv(t);
  const std::array<Vec3, 3> p = {pos(t, 0), pos(t, 1), pos(t, 2)};
  BBox box;
  for (const Vec3& q : p) box.add(q);
  // A triangle whose bounding ball is as far from t's as the nearest so far
  // cannot be nearer: skipped before the exact distance.
  const Vec3 centre = tri[static_cast<std::size_t>(t)].centre();
  const double radius = tri[static_cast<std::size_t>(t)].r;
  double best = INFINITY;
  tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_box_distance2(box.lo, box.hi, lo, hi); },
               [&](int u, double nearest) -> double {
                 const int* w = tv(u);
                 for (int i = 0; i < 3; ++i)
                   if (w[i] == v[0] || w[i] == v[1] || w[i] == v[2]) return INFINITY;
                 const Tri& U = tri[static_cast<std::size_t>(u)];
                 const double gap = norm(centre - U.centre()) - radius - U.r;
                 if (gap > 0 && gap * gap >= nearest) return INFINITY;
                 return triangle_triangle_distance2(p, {pos(u, 0), pos(u, 1), pos(u, 2)});
               },
               best);
  const double clear = with_margin(std::sqrt(best), scale);
  std::uint8_t code = kClearZero;
  if (clear >= scale) {
    code = 0;
  } else if (clear > 0 && scale > 0) {
    double k = std::ceil(-4.0 * std::log2(clear / scale));
    while (k < kClearZero && clearance_of_code(static_cast<std::uint8_t>(k)) > clear) ++k;
    code = static_cast<std::uint8_t>(std::min<double>(k, kClearZero));
  }
  slot.store(code, std::memory_order_relaxed);
  return clearance_of_code(code);
}

void Locator::Data::build_features() {
  const SurfaceMesh& m = *mesh;
  corner_fe.assign(3 * static_cast<std::size_t>(n_slots), -1);
  std::vector<std::array<int, 2>> pairs;
  for (Corner c : m.edges()) {
    if (!(m.edge_tags(c) & options.feature_tags)) continue;
    const int e = static_cast<int>(fe_corner.size());
    fe_corner.push_back(c.idx);
    const Vertex a = m.edge_from(c), b = m.edge_to(c);
    fe_v.push_back({a.idx, b.idx});
    fe_p.push_back(m.position(a));
    fe_p.push_back(m.position(b));
    corner_fe[c.idx] = e;
    const Corner o = m.opposite(c);
    if (o.is_valid()) corner_fe[o.idx] = e;
    pairs.push_back({a.idx, e});
    pairs.push_back({b.idx, e});
  }
  // no feature curve: no feature query reads the corners' edges (project)
  if (fe_corner.empty()) std::vector<int>().swap(corner_fe);
  build_csr(m.vertex_capacity(), pairs, vf_first, vf);
  const int ne = static_cast<int>(fe_corner.size());
  std::vector<BBox> boxes(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) boxes[e] = box_of(&fe_p[2 * e], 2);
  fe_tree.build(boxes);

  // Clearance of each vertex on a feature curve: the distance to the nearest
  // feature edge not incident to it.
  vfclear.assign(static_cast<std::size_t>(m.vertex_capacity()), 0.0);
  for (Vertex vh : m.vertices()) {
    const int v = vh.idx;
    if (vf_first[v] == vf_first[v + 1]) continue;
    const Vec3 x = m.position(vh);
    double best = INFINITY;
    fe_tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                    [&](int e, double) -> double {
                      if (fe_v[e][0] == v || fe_v[e][1] == v) return INFINITY;
                      return seg_d2(x, e);
                    },
                    best);
    vfclear[v] = with_margin(std::sqrt(best), scale);
  }
}

void Locator::Data::build_corners() {
  const SurfaceMesh& m = *mesh;
  std::vector<BBox> boxes;
  for (Vertex vh : m.vertices()) {
    if (m.is_isolated(vh)) continue;
    if (!(m.vertex_tags(vh) & options.corner_tags)) continue;
    corners.push_back(vh.idx);
    BBox b;
    b.add(m.position(vh));
    boxes.push_back(b);
  }
  corner_tree.build(boxes);
}

// --- Locator ------------------------------------------------------------------

Locator::Locator(const SurfaceMesh& mesh, const LocateOptions& options) {
  auto d = std::make_shared<Data>();
  d->build(mesh, options);
  d_ = std::move(d);
}
Locator::Locator(const Locator& other) : d_(other.d_) {}
Locator& Locator::operator=(const Locator& other) {
  if (this != &other) {
    d_ = other.d_;
    tmark_.clear();
    fmark_.clear();
    stamp_ = 0;
  }
  return *this;
}
Locator::Locator(Locator&&) noexcept = default;
Locator& Locator::operator=(Locator&&) noexcept = default;
Locator::~Locator() = default;

const SurfaceMesh& Locator::mesh() const { return *d_->mesh; }
const LocateOptions& Locator::options() const { return d_->options; }
int Locator::n_feature_edges() const { return static_cast<int>(d_->fe_corner.size()); }
int Locator::n_corners() const { return static_cast<int>(d_->corners.size()); }
double Locator::clearance(Vertex v) const {
  return v.idx >= 0 && v.idx < static_cast<int>(d_->vclear.size()) ? d_->vclear[v.idx] : 0.0;
}
const AabbTree& Locator::tree() const { return d_->tree; }

void Locator::next_stamp() {
  if (tmark_.size() != static_cast<std::size_t>(d_->n_slots) || fmark_.size() != d_->fe_corner.size() ||
      stamp_ == UINT32_MAX) {
    tmark_.assign(static_cast<std::size_t>(d_->n_slots), 0);
    fmark_.assign(d_->fe_corner.size(), 0);
    stamp_ = 0;
  }
  ++stamp_;
}

Location Locator::project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) {
  if (constraint == Constraint::Fixed) {
    if (!d_->corners.empty()) return project_corner(x);
    constraint = Constraint::OnFeature;
  }
  if (constraint == Constraint::OnFeature && !d_->fe_corner.empty()) return project_feature(x, hints);
  return project_free(x, hints, -1);
}

Location Locator::free_result(const Vec3& x, int t, int steps, bool fallback) const {
  if (t < 0) return Location{};
  return free_result(d_->tri_closest(x, t), t, steps, fallback);
}

Location Locator::free_result(const TriangleClosest& c, int t, int steps, bool fallback) const {
  Location r;
  r.triangle = Triangle(t);
  r.bary = c.bary;
  r.point = c.point;
  r.distance = std::sqrt(c.distance2);
  r.steps = steps;
  r.used_fallback = fallback;
  r.constraint = Constraint::Free;
  return r;
}

namespace {
// The local index of the vertex opposite the edge holding a closest point
// (TriangleRegion::Edge01 -> 2, ...); -1 for the face and the vertices.
int opposite_local_vertex(TriangleRegion r) {
  switch (r) {
    case TriangleRegion::Edge01: return 2;
    case TriangleRegion::Edge12: return 0;
    case TriangleRegion::Edge20: return 1;
    default: return -1;
  }
}
}  // namespace

bool Locator::within(const Vec3& x, double tol, std::span<const Hint> hints) {
  // The first triangle found within tol (less a rounding margin) settles it: the
  // closest one is at least as close, below tol by more than any rounding of
  // the distance. Otherwise the search runs to its end and the closest
  // point decides, as project() would.
  const Location r = first_within(x, tol, hints);
  return r.is_valid() && norm(r.point - x) <= tol;
}

Location Locator::first_within(const Vec3& x, double tol, std::span<const Hint> hints) {
  return project_free(x, hints, tol * tol * (1 - 1e-9));
}

Location Locator::project_free(const Vec3& x, std::span<const Hint> hints, double accept2) {
  const Data& D = *d_;
  next_stamp();
  // K_0: the closest of the hinted triangles.
  // The closest point of K is kept for the result (cK).
  int K = -1;
  double dK = INFINITY;
  TriangleClosest cK;
  for (const Hint& h : hints) {
    const int t = h.triangle.idx;
    if (!D.live_triangle(t) || tmark_[t] == stamp_) continue;
    tmark_[t] = stamp_;
    const TriangleClosest c = D.tri_closest(x, t);
    if (c.distance2 < dK) {
      dK = c.distance2;
      K = t;
      cK = c;
    }
  }
  // The tree's search for a triangle closer than `bound`: those the walk
  // evaluated (marked) are not, nor those whose bounding ball is as far.
  auto global = [&](int start, double bound, int steps) {
    const int found = D.tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                                     [&](int t, double best) {
                                       if (tmark_[t] == stamp_ || D.ball_beyond(x, t, std::sqrt(best)))
                                         return double{INFINITY};
                                       return D.tri_d2(x, t);
                                     },
                                     bound);
    return free_result(x, found >= 0 ? found : start, steps, true);
  };
  if (K < 0) return global(-1, INFINITY, 0);
  if (dK < accept2) return free_result(cK, K, 0, false);
  int steps = 0;
  // First a straight walk towards x: from K across the edge beyond which
  // x's foot on the triangle's plane lies (its most negative barycentric
  // coordinate), one triangle a step, to the triangle holding that foot,
  // keeping the closest triangle met as K (every triangle it evaluates is
  // marked, and none is closer than K: the descent below starts as from a
  // hint). A point half an edge of T_1 away from its hints, many triangles
  // of a fine T_G, is reached in a few steps of one distance each, where
  // the descent evaluates whole fans.
  for (int t = K; steps < D.options.max_steps;) {
    const int across = D.foot_beyond_edge(x, t);
    if (across < 0) break;
    const Corner o = D.mesh->opposite(SurfaceMesh::corner(Triangle(t), across));
    if (!o.is_valid()) break;
    t = SurfaceMesh::triangle(o).idx;
    if (!D.live_triangle(t) || tmark_[t] == stamp_) break;
    tmark_[t] = stamp_;
    ++steps;
    const TriangleClosest c = D.tri_closest(x, t);
    if (c.distance2 < dK) {
      K = t;
      dK = c.distance2;
      cK = c;
      if (dK < accept2) return free_result(cK, K, steps, false);
    }
  }

  // Then across edges: while K's closest point to x lies inside one of its
  // edges, the triangle beyond that edge is the likeliest closer one; step
  // to it when it is closer (one distance a step, against the fans' dozen
  // below). A triangle evaluated and not taken is no closer than K, and K
  // only gets closer: every marked triangle stays at least as far as K.
  for (int edge_steps = 0; edge_steps < D.options.max_steps; ++edge_steps) {
    const int across = opposite_local_vertex(cK.region);
    if (across < 0) break;  // the face or a vertex: the fans decide
    const Corner o = D.mesh->opposite(SurfaceMesh::corner(Triangle(K), across));
    if (!o.is_valid()) break;
    const int t = SurfaceMesh::triangle(o).idx;
    if (!D.live_triangle(t) || tmark_[t] == stamp_) break;
    tmark_[t] = stamp_;
    const TriangleClosest c = D.tri_closest(x, t);
    if (!(c.distance2 < dK)) break;
    K = t;
    dK = c.distance2;
    cK = c;
    ++steps;
    if (dK < accept2) return free_result(cK, K, steps, false);
  }

  // Section 4.2: move to the closest unmarked triangle of the neighbourhood
  // E(K) while it is closer (ties stay: the closest point is the same).
  // Every marked triangle is at least as far as K. When a vertex of K is
  // clear of every triangle not incident to it by more than |x - vertex| +
  // d(x, K), only its own fan can hold a closer triangle: that fan alone is
  // searched, and K is the closest of all when none there is closer.
  auto closer_among = [&](int v, double rK, int& best, double& bd, TriangleClosest& cbest) {
    for (int i = D.vt_first[v]; i < D.vt_first[v + 1]; ++i) {
      const int t = D.vt[i];
      if (tmark_[t] == stamp_) continue;
      tmark_[t] = stamp_;
      // A triangle whose bounding ball is as far as K cannot be closer:
      // marked as evaluated without the exact distance.
      if (D.ball_beyond(x, t, rK)) continue;
      const TriangleClosest c = D.tri_closest(x, t);
      if (c.distance2 < bd) {
        bd = c.distance2;
        best = t;
        cbest = c;
      }
    }
  };
  for (;;) {
    int best = -1;
    double bd = INFINITY;
    TriangleClosest cbest;
    const int* v = D.tv(K);
    const double rK = std::sqrt(dK);
    int clear_vertex = -1;
    for (int k = 0; k < 3 && clear_vertex < 0; ++k)
      if (norm(x - D.pos(K, k)) + rK <= D.vclear[v[k]]) clear_vertex = v[k];
    if (clear_vertex >= 0) {
      closer_among(clear_vertex, rK, best, bd, cbest);
      if (best < 0 || !(bd < dK)) return free_result(cK, K, steps, false);
    } else {
      for (int k = 0; k < 3; ++k) closer_among(v[k], rK, best, bd, cbest);
      if (best < 0 || !(bd < dK)) {
        // Local minimum: every triangle of E(K) evaluated. One sharing no
        // vertex with K is at least K's clearance from it, so at least the
        // clearance less d(x, K) from x: no closer than K when that is >= d(x, K).
        if (2 * rK <= D.triangle_clearance(K)) return free_result(cK, K, steps, false);
        break;
      }
    }
    K = best;
    dK = bd;
    cK = cbest;
    ++steps;
    if (dK < accept2) return free_result(cK, K, steps, false);
    if (steps >= D.options.max_steps) return global(K, dK, steps);
  }
  return global(K, dK, steps);
}

Location Locator::feature_result(const Vec3& x, int e, int steps, bool fallback) const {
  const Data& D = *d_;
  Location r;
  const Corner c(D.fe_corner[e]);
  const Vec3& a = D.fe_p[2 * static_cast<std::size_t>(e)];
  const Vec3& b = D.fe_p[2 * static_cast<std::size_t>(e) + 1];
  const double t = closest_parameter_on_segment(x, a, b);
  r.point = t == 0 ? a : (t == 1 ? b : a + t * (b - a));
  r.distance = norm(x - r.point);
  r.triangle = SurfaceMesh::triangle(c);
  r.bary = {0, 0, 0};
  r.bary[SurfaceMesh::local_index(SurfaceMesh::next(c))] = 1 - t;
  r.bary[SurfaceMesh::local_index(SurfaceMesh::prev(c))] = t;
  r.steps = steps;
  r.used_fallback = fallback;
  r.constraint = Constraint::OnFeature;
  r.edge = c;
  return r;
}

Location Locator::project_feature(const Vec3& x, std::span<const Hint> hints) {
  const Data& D = *d_;
  next_stamp();
  // Start from the closest feature edge of the hinted triangles or at their vertices.
  int E = -1;
  double dE = INFINITY;
  auto consider = [&](int e) {
    if (fmark_[e] == stamp_) return;
    fmark_[e] = stamp_;
    const double d = D.seg_d2(x, e);
    if (d < dE) {
      dE = d;
      E = e;
    }
  };
  for (const Hint& h : hints) {
    const int t = h.triangle.idx;
    if (!D.live_triangle(t)) continue;
    for (int k = 0; k < 3; ++k) {
      const int e = D.corner_fe[3 * static_cast<std::size_t>(t) + k];
      if (e >= 0) consider(e);
      const int v = D.tv(t)[k];
      for (int i = D.vf_first[v]; i < D.vf_first[v + 1]; ++i) consider(D.vf[i]);
    }
  }
  auto global = [&](int start, double bound, int steps) {
    const int found =
        D.fe_tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                          [&](int e, double) { return D.seg_d2(x, e); }, bound);
    return feature_result(x, found >= 0 ? found : start, steps, true);
  };
  if (E < 0) return global(-1, INFINITY, 0);

  // The descent of section 4.2 along the feature curves: the neighbourhood of
  // an edge is the feature edges sharing an endpoint with it.
  int steps = 0;
  for (;;) {
    int best = -1;
    double bd = INFINITY;
    for (int j = 0; j < 2; ++j) {
      const int v = D.fe_v[E][j];
      for (int i = D.vf_first[v]; i < D.vf_first[v + 1]; ++i) {
        const int e = D.vf[i];
        if (fmark_[e] == stamp_) continue;
        fmark_[e] = stamp_;
        const double d = D.seg_d2(x, e);
        if (d < bd) {
          bd = d;
          best = e;
        }
      }
    }
    if (best < 0 || !(bd < dE)) break;
    E = best;
    dE = bd;
    if (++steps >= D.options.max_steps) return global(E, dE, steps);
  }
  if (Data::certified(x, std::sqrt(dE), D.fe_v[E].data(), &D.fe_p[2 * static_cast<std::size_t>(E)], 2, D.vfclear))
    return feature_result(x, E, steps, false);
  return global(E, dE, steps);
}

Location Locator::project_corner(const Vec3& x) {
  const Data& D = *d_;
  double best = INFINITY;
  const int i = D.corner_tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                                      [&](int k, double) { return norm2(x - D.mesh->position(Vertex(D.corners[k]))); },
                                      best);
  Location r;
  if (i < 0) return r;
  const Vertex v(D.corners[i]);
  const Corner c = D.mesh->corner(v);
  r.triangle = SurfaceMesh::triangle(c);
  r.bary = {0, 0, 0};
  r.bary[SurfaceMesh::local_index(c)] = 1;
  r.point = D.mesh->position(v);
  r.distance = std::sqrt(best);
  r.used_fallback = true;
  r.constraint = Constraint::Fixed;
  r.vertex = v;
  return r;
}

// --- helpers on T_1 -------------------------------------------------------------

Constraint vertex_constraint(const SurfaceMesh& mesh, Vertex v, std::uint8_t feature_tags, std::uint8_t corner_tags) {
  if (mesh.vertex_tags(v) & corner_tags) return Constraint::Fixed;
  // The two edges at v in each triangle of its fan (a boundary fan's last edge included).
  bool on_feature = false;
  for (Corner c : mesh.fan_corners(v))
    on_feature |= ((mesh.edge_tags(SurfaceMesh::next(c)) | mesh.edge_tags(SurfaceMesh::prev(c))) & feature_tags) != 0;
  return on_feature ? Constraint::OnFeature : Constraint::Free;
}

std::vector<Location> project_vertices(const SurfaceMesh& mesh, Locator& locator, std::vector<Hint>& hints,
                                       bool use_constraints, PropagationStats* stats) {
  const int nv = mesh.vertex_capacity();
  if (static_cast<int>(hints.size()) < nv) hints.resize(static_cast<std::size_t>(nv));
  std::vector<Location> out(static_cast<std::size_t>(nv));
  std::vector<int> from(static_cast<std::size_t>(nv), -2);  // -2 unseen, -1 seed, else the vertex that reached it
  PropagationStats st;
  std::deque<int> queue;
  const LocateOptions& o = locator.options();
  for (Vertex seed : mesh.vertices()) {
    const int s = seed.idx;
    if (from[s] != -2) continue;
    from[s] = -1;
    ++st.seeds;
    queue.push_back(s);
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      const Vertex vh(v);
      const Hint own = hints[v];
      const Hint start[2] = {own, from[v] >= 0 ? out[from[v]].hint() : Hint{}};
      const Constraint c = use_constraints ? vertex_constraint(mesh, vh, o.feature_tags, o.corner_tags) : Constraint::Free;
      out[v] = locator.project(mesh.position(vh), std::span<const Hint>(start, 2), c);
      hints[v] = out[v].hint();
      ++st.projected;
      st.steps += out[v].steps;
      if (out[v].used_fallback) ++st.fallbacks;
      for (Corner k : mesh.fan_corners(vh))
        for (Vertex w : {mesh.vertex(SurfaceMesh::next(k)), mesh.vertex(SurfaceMesh::prev(k))}) {
          if (from[w.idx] != -2) continue;
          from[w.idx] = v;
          queue.push_back(w.idx);
        }
    }
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace anisurf
