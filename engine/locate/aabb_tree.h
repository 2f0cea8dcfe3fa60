// Bounding-box hierarchy over primitives given by their boxes (triangles,
// segments, points): the global search behind point location, which the
// report's local algorithms (section 4) lack.
//
// Flat arrays: nodes in one vector (the two children of a node are adjacent),
// primitive ids grouped by leaf in another. Built top-down with binned
// surface-area-heuristic splits (median split where the heuristic cannot
// separate the centroids). Queries take the distance functions as callables,
// so the tree knows nothing of what the primitives are.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/vec3.h"

namespace anisurf {

class AabbTree {
 public:
  // 32 bytes: the box in single precision, rounded outwards (it still holds
  // its primitives, so distances to it stay lower bounds); two siblings share
  // a cache line.
  struct Node {
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    int first = 0;  // leaf: first slot in the id array; inner: index of the left child
    int count = 0;  // leaf: number of primitives (> 0); inner: 0 (right child = first + 1)
    bool is_leaf() const { return count > 0; }
    Vec3 lower() const { return {lo[0], lo[1], lo[2]}; }
    Vec3 upper() const { return {hi[0], hi[1], hi[2]}; }
  };
  static_assert(sizeof(Node) == 32);
  static constexpr int kMaxLeafSize = 8;

  AabbTree() = default;
  // Builds over boxes[i] for primitive i; empty boxes (deleted slots) are left out.
  explicit AabbTree(const std::vector<BBox>& boxes) { build(boxes); }
  void build(const std::vector<BBox>& boxes);

  bool empty() const { return nodes_.empty(); }
  int n_primitives() const { return static_cast<int>(ids_.size()); }
  const std::vector<Node>& nodes() const { return nodes_; }
  // Primitive ids of a leaf.
  const int* leaf_begin(const Node& n) const { return ids_.data() + n.first; }
  const int* leaf_end(const Node& n) const { return ids_.data() + n.first + n.count; }
  int depth() const { return depth_; }

  // Best-first search for the primitive nearest to a query.
  //   box_d2(lo, hi): a lower bound of the squared distance from the query to
  //     anything inside the box [lo, hi];
  //   prim_d2(id, best_d2): the squared distance to primitive id, or any
  //     value >= best_d2 when it cannot be closer (+inf to skip it).
  // best_d2 is an exclusive upper bound on entry (INFINITY for none) and the
  // distance found on exit. Returns the primitive found, or -1 when none is
  // strictly closer than the bound given.
  template <class BoxD2, class PrimD2>
  int nearest(BoxD2&& box_d2, PrimD2&& prim_d2, double& best_d2) const;

  // Calls visit(id) for every primitive whose leaf box passes
  // box_d2(lo, hi) <= r2 (the caller filters the primitives themselves).
  template <class BoxD2, class Visit>
  void for_each_within(BoxD2&& box_d2, double r2, Visit&& visit) const;
  // Calls visit(leaf) for every leaf node whose box passes box_d2(lo, hi) <= r2.
  template <class BoxD2, class Visit>
  void for_each_leaf_within(BoxD2&& box_d2, double r2, Visit&& visit) const;

 private:
  static constexpr int kStackSize = 128;  // > the depth bound enforced by build()
  std::vector<Node> nodes_;
  std::vector<int> ids_;
  int depth_ = 0;
};

// Squared distance from p to the box [lo, hi] (0 inside).
inline double box_point_distance2(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d += e * e;
  }
  return d;
}

// Squared distance between boxes [alo, ahi] and [blo, bhi] (0 when they overlap).
inline double box_box_distance2(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = blo[k] > ahi[k] ? blo[k] - ahi[k] : (alo[k] > bhi[k] ? alo[k] - bhi[k] : 0.0);
    d += e * e;
  }
  return d;
}

template <class BoxD2, class PrimD2>
int AabbTree::nearest(BoxD2&& box_d2, PrimD2&& prim_d2, double& best_d2) const {
  if (nodes_.empty()) return -1;
  struct Item {
    int node;
    double d2;
  };
  Item stack[kStackSize];
  int top = 0;
  int found = -1;
  const double d_root = box_d2(nodes_[0].lower(), nodes_[0].upper());
  if (!(d_root < best_d2)) return -1;
  stack[top++] = {0, d_root};
  while (top > 0) {
    const Item it = stack[--top];
    if (!(it.d2 < best_d2)) continue;
    const Node& n = nodes_[it.node];
    if (n.is_leaf()) {
      for (const int* p = leaf_begin(n); p != leaf_end(n); ++p) {
        const double d = prim_d2(*p, best_d2);
        if (d < best_d2) {
          best_d2 = d;
          found = *p;
        }
      }
      continue;
    }
    const int l = n.first, r = n.first + 1;
    const double dl = box_d2(nodes_[l].lower(), nodes_[l].upper());
    const double dr = box_d2(nodes_[r].lower(), nodes_[r].upper());
    // Push the far child first so that the near one is searched first.
    if (dl <= dr) {
      if (dr < best_d2) stack[top++] = {r, dr};
      if (dl < best_d2) stack[top++] = {l, dl};
    } else {
      if (dl < best_d2) stack[top++] = {l, dl};
      if (dr < best_d2) stack[top++] = {r, dr};
    }
  }
  return found;
}

template <class BoxD2, class Visit>
void AabbTree::for_each_within(BoxD2&& box_d2, double r2, Visit&& visit) const {
  for_each_leaf_within(box_d2, r2, [&](const Node& leaf) {
    for (const int* p = leaf_begin(leaf); p != leaf_end(leaf); ++p) visit(*p);
  });
}

template <class BoxD2, class Visit>
void AabbTree::for_each_leaf_within(BoxD2&& box_d2, double r2, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[kStackSize];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (box_d2(n.lower(), n.upper()) > r2) continue;
    if (n.is_leaf()) {
      visit(n);
    } else {
      stack[top++] = n.first + 1;
      stack[top++] = n.first;
    }
  }
}

}  // namespace anisurf
