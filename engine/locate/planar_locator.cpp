#include "locate/planar_locator.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "locate/closest_point.h"

namespace anisurf {

struct PlanarLocator::Data {
  const SurfaceMesh* mesh = nullptr;
  PlanarLocateOptions options;
  int n_slots = 0;
  std::vector<Vec3> tp;        // 3 positions per triangle slot (z = 0)
  std::vector<int> nb;         // 3 per slot: triangle across the edge opposite corner k, or -1
  std::vector<signed char> orientation;  // per slot: sign of the area (0: degenerate or deleted)
  AabbTree tree;               // triangles
  std::vector<int> bcorner;    // boundary edges: the corner opposite each
  std::vector<Vec3> bp;        // 2 positions per boundary edge
  AabbTree btree;              // boundary edges
};

namespace {

constexpr signed char kDeletedSlot = 2;

Vec3 flat(const Vec3& x) { return {x.x, x.y, 0.0}; }

}  // namespace

bool PlanarLocator::is_planar(const SurfaceMesh& mesh) {
  for (Vertex v : mesh.vertices())
    if (mesh.position(v).z != 0) return false;
  return true;
}

PlanarLocator::PlanarLocator(const SurfaceMesh& m, const PlanarLocateOptions& options) {
  for (Vertex v : m.vertices())
    if (m.position(v).z != 0)
      throw Error("planar point location: the mesh is not planar (vertex " + std::to_string(v.idx + 1) +
                  " has z = " + std::to_string(m.position(v).z) + "; expected a 2D mesh or z = 0)");
  auto d = std::make_shared<Data>();
  d->mesh = &m;
  d->options = options;
  d->n_slots = m.triangle_capacity();
  d->tp.assign(3 * static_cast<std::size_t>(d->n_slots), Vec3());
  d->nb.assign(3 * static_cast<std::size_t>(d->n_slots), -1);
  d->orientation.assign(static_cast<std::size_t>(d->n_slots), kDeletedSlot);
  std::vector<BBox> boxes(static_cast<std::size_t>(d->n_slots)), bboxes;
  for (Triangle th : m.triangles()) {
    const int t = th.idx;
    Vec3* p = &d->tp[3 * static_cast<std::size_t>(t)];
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(th, k);
      p[k] = m.position(m.vertex(c));
      boxes[t].add(p[k]);
      const Corner o = m.opposite(c);
      if (o.is_valid()) {
        d->nb[3 * t + k] = SurfaceMesh::triangle(o).idx;
      } else {
        d->bcorner.push_back(c.idx);
        d->bp.push_back(m.position(m.edge_from(c)));
        d->bp.push_back(m.position(m.edge_to(c)));
        BBox b;
        b.add(d->bp[d->bp.size() - 2]);
        b.add(d->bp.back());
        bboxes.push_back(b);
      }
    }
    const double a = orient2d(p[0], p[1], p[2]);
    d->orientation[t] = a > 0 ? 1 : (a < 0 ? -1 : 0);
  }
  d->tree.build(boxes);
  d->btree.build(bboxes);
  d_ = std::move(d);
}

PlanarLocator::PlanarLocator(const PlanarLocator& other) : d_(other.d_) {}
PlanarLocator& PlanarLocator::operator=(const PlanarLocator& other) {
  if (this != &other) {
    d_ = other.d_;
    wmark_.clear();
    smark_.clear();
    wstamp_ = sstamp_ = 0;
  }
  return *this;
}
PlanarLocator::PlanarLocator(PlanarLocator&&) noexcept = default;
PlanarLocator& PlanarLocator::operator=(PlanarLocator&&) noexcept = default;
PlanarLocator::~PlanarLocator() = default;

const SurfaceMesh& PlanarLocator::mesh() const { return *d_->mesh; }
int PlanarLocator::n_boundary_edges() const { return static_cast<int>(d_->bcorner.size()); }

PlanarLocator::WalkEnd PlanarLocator::walk(const Vec3& x, int& K, int& steps, std::array<double, 3>& areas) {
  const Data& D = *d_;
  if (wstamp_ == UINT32_MAX) {
    std::fill(wmark_.begin(), wmark_.end(), 0u);
    wstamp_ = 0;
  }
  ++wstamp_;
  for (;;) {
    if (wmark_[K] == wstamp_ || steps >= D.options.max_steps) return WalkEnd::Failed;  // a cycle
    wmark_[K] = wstamp_;
    const int s = D.orientation[K];
    if (s != 1 && s != -1) return WalkEnd::Failed;  // zero-area triangle: no sides to test
    const Vec3* p = &D.tp[3 * static_cast<std::size_t>(K)];
    // Oriented area of (x, edge opposite corner k) with the triangle's own
    // orientation made positive.
    for (int k = 0; k < 3; ++k) areas[k] = s * orient2d(p[(k + 1) % 3], p[(k + 2) % 3], x);
    // The most negative area (with two negative ones, the smaller) gives the edge to cross.
    int k = areas[0] <= areas[1] ? 0 : 1;
    if (areas[2] < areas[k]) k = 2;
    if (areas[k] >= 0) return WalkEnd::Inside;
    const int next = D.nb[3 * static_cast<std::size_t>(K) + k];
    if (next < 0) return WalkEnd::Stopped;  // a boundary edge
    K = next;
    ++steps;
  }
}

Location PlanarLocator::tree_result(const Vec3& x, int start, double bound2, int steps) {
  const Data& D = *d_;
  const int found =
      D.tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                     [&](int t, double) {
                       const Vec3* p = &D.tp[3 * static_cast<std::size_t>(t)];
                       return point_triangle_distance2(x, p[0], p[1], p[2]);
                     },
                     bound2);
  const int t = found >= 0 ? found : start;
  Location r;
  if (t < 0) return r;
  const Vec3* p = &D.tp[3 * static_cast<std::size_t>(t)];
  const TriangleClosest c = closest_point_on_triangle(x, p[0], p[1], p[2]);
  r.triangle = Triangle(t);
  r.bary = c.bary;
  r.point = c.point;
  r.distance = std::sqrt(c.distance2);
  r.steps = steps;
  r.used_fallback = true;
  return r;
}

Location PlanarLocator::locate(const Vec3& query, Hint hint) {
  const Data& D = *d_;
  const Vec3 x = flat(query);
  if (wmark_.size() != static_cast<std::size_t>(D.n_slots)) {
    wmark_.assign(static_cast<std::size_t>(D.n_slots), 0);
    smark_.assign(static_cast<std::size_t>(D.n_slots), 0);
    wstamp_ = sstamp_ = 0;
  }
  if (sstamp_ == UINT32_MAX) {
    std::fill(smark_.begin(), smark_.end(), 0u);
    sstamp_ = 0;
  }
  ++sstamp_;
  int K = hint.triangle.idx;
  if (K < 0 || K >= D.n_slots || D.orientation[K] == kDeletedSlot) return tree_result(x, -1, INFINITY, 0);

  int steps = 0;
  std::array<double, 3> areas{};
  // Best projection onto the boundary so far.
  int best_t = -1;
  TriangleClosest best;
  best.distance2 = INFINITY;
  // Boundary edges closer than the first stop, ascending (found once).
  std::vector<std::pair<double, int>> candidates;
  std::size_t next_candidate = 0;
  bool have_candidates = false;
  auto project_onto = [&](int t) {
    const Vec3* p = &D.tp[3 * static_cast<std::size_t>(t)];
    const TriangleClosest c = closest_point_on_triangle(x, p[0], p[1], p[2]);
    if (c.distance2 < best.distance2) {
      best = c;
      best_t = t;
    }
  };
  for (;;) {
    const WalkEnd end = walk(x, K, steps, areas);
    if (end == WalkEnd::Failed) return tree_result(x, best_t, best.distance2, steps);
    if (end == WalkEnd::Inside) {
      Location r;
      const double sum = areas[0] + areas[1] + areas[2];
      for (int k = 0; k < 3; ++k) r.bary[k] = std::max(0.0, areas[k]) / sum;
      r.triangle = Triangle(K);
      r.point = x;
      r.distance = 0;
      r.steps = steps;
      return r;
    }
    // Stopped on the boundary: project x onto K.
    smark_[K] = sstamp_;
    project_onto(K);
    if (!have_candidates) {
      have_candidates = true;
      D.btree.for_each_within([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                              best.distance2, [&](int e) {
                                const double d2 = point_segment_distance2(x, D.bp[2 * static_cast<std::size_t>(e)],
                                                                          D.bp[2 * static_cast<std::size_t>(e) + 1]);
                                if (d2 <= best.distance2) candidates.push_back({d2, e});
                              });
      std::sort(candidates.begin(), candidates.end());
    }
    // Restart from the closest boundary edge not tried yet, if as close as the best.
    K = -1;
    while (next_candidate < candidates.size() && candidates[next_candidate].first <= best.distance2) {
      const int t = SurfaceMesh::triangle(Corner(D.bcorner[candidates[next_candidate].second])).idx;
      ++next_candidate;
      if (smark_[t] != sstamp_) {
        // The edge's closest point is a point of the domain: the restart
        // begins no farther than that.
        K = t;
        smark_[t] = sstamp_;
        project_onto(t);
        break;
      }
    }
    if (K >= 0) continue;
    if (D.options.verify_exterior) {
      // Confirm: nothing of the domain strictly inside the ball of radius d0.
      Location r = tree_result(x, best_t, best.distance2, steps);
      if (r.triangle.idx != best_t) return r;
    }
    Location r;
    r.triangle = Triangle(best_t);
    r.bary = best.bary;
    r.point = best.point;
    r.distance = std::sqrt(best.distance2);
    r.steps = steps;
    r.used_fallback = D.options.verify_exterior;
    return r;
  }
}

}  // namespace anisurf
