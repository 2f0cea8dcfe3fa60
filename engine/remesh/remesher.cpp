#include "remesh/remesher.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <utility>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "mesh/operators.h"
#include "metric/quality.h"
#include "metric/surface_metric.h"

namespace anisurf::remesh {

namespace {

// A crease split's new vertex (RemeshOptions::crease_keep) is the
// projection of the midpoint, or a fallback of can_split_onto_input within
// this share of the size the metric asks for from the input.
constexpr double kCreaseSplitBound = 0.1;

using M = SurfaceMesh;
using Clock = std::chrono::steady_clock;

// The order key of a collapse of metric length l: l rounded down to 5 bits
// of mantissa (steps of 1/32 to 1/64 of the length). Edges within a step
// are taken in the order of their first vertex's slot instead of their
// exact lengths: slots near each other lie near each other in the mesh (as
// the input numbers them), so a coarsening walks the mesh in runs instead
// of jumping across it at every pop.
float order_key(double length) {
  const float f = static_cast<float>(length);
  if (!(f > 0) || !std::isfinite(f)) return f;
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) & ~((std::uint32_t{1} << 18) - 1));
}

// The corner naming edge a -> b: `hint` while it still names it (the corner
// recorded when the edge was queued), else found around a.
Corner edge_corner(const SurfaceMesh& mesh, int hint, Vertex a, Vertex b) {
  if (hint >= 0 && hint < mesh.corner_capacity()) {
    const Corner c(hint);
    if (!mesh.is_deleted(M::triangle(c)) && mesh.edge_from(c) == a && mesh.edge_to(c) == b) return c;
  }
  return find_edge_corner(mesh, a, b);
}

std::array<int, 2> key(Vertex a, Vertex b) { return a.idx < b.idx ? std::array{a.idx, b.idx} : std::array{b.idx, a.idx}; }

// The key of the edge from a to b in the refusal memo: directed, as a plan
// is (a collapse tries its options in an order set by the edge's direction,
// and reports the last refusal).
std::uint64_t edge_key(Vertex a, Vertex b) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.idx)) << 32 | static_cast<std::uint32_t>(b.idx);
}

// Counts a refusal of the operator of a `pass` pass (PassKind::Final: the
// removal of a vertex of valence < 4; smoothing within the final pass counts
// as PassKind::Smooth). The rule, one for every pass: a refusal is an element
// the pass chose to change and could not. Passes over all elements try many
// the operator never applies to, which are not refusals: feature edges in a
// swap pass (Rejection::Feature), fixed vertices (Fixed) and vertices at
// their optimum (NoGain) in smoothing. The swaps tried around a vertex
// (local swaps, section 6 step 2, and the final pass's valence swaps) are
// opportunities, never counted.
void refuse(PassReport& r, PassKind pass, Rejection why) {
  const bool never_applies = (pass == PassKind::Swap && why == Rejection::Feature) ||
                             (pass == PassKind::Smooth && (why == Rejection::Fixed || why == Rejection::NoGain));
  if (!never_applies) ++r.rejected[static_cast<std::size_t>(why)];
}

// The two sides of the band [lmin, lmax] for Remesher::priority_pass:
// which edges are outside, the queue order that takes the farthest first, the
// operator's plan.
struct SplitEdges {
  static constexpr PassKind kind = PassKind::Split;
  using Order = LongestFirst;
  // Too long, or (section 5's fidelity) too far off the input surface.
  template <class Sags>
  static bool outside(Sags&& sags, Corner c, double length, const OperatorOptions& o) {
    return length > o.lmax || sags(c);
  }
  // The exact length: refinement splits the longest edge first (taking a
  // split's generation in the order of the slots lowers the mean quality).
  static float key(double length) { return static_cast<float>(length); }
  static SplitPlan plan(AdaptedMesh& m, Corner c, double length, const OperatorOptions& o) {
    return length > o.lmax ? can_split(m, c, o) : can_split_for_sag(m, c, o);
  }
};
struct CollapseEdges {
  static constexpr PassKind kind = PassKind::Collapse;
  using Order = ShortestFirst;
  template <class Sags>
  static bool outside(Sags&&, Corner, double length, const OperatorOptions& o) { return length < o.lmin; }
  static float key(double length) { return order_key(length); }
  static CollapsePlan plan(AdaptedMesh& m, Corner c, double length, const OperatorOptions& o) {
    return can_collapse(m, c, o, length);
  }
};

// The edges of the triangles around v that are opposite v.
std::vector<std::array<int, 2>> link_edges(const SurfaceMesh& mesh, Vertex v) {
  std::vector<std::array<int, 2>> out;
  for (Corner c : mesh.fan_corners(v)) out.push_back({mesh.vertex(M::next(c)).idx, mesh.vertex(M::prev(c)).idx});
  return out;
}

}  // namespace

std::string_view pass_name(PassKind k) {
  switch (k) {
    case PassKind::Split: return "split";
    case PassKind::Collapse: return "collapse";
    case PassKind::Swap: return "swap";
    case PassKind::Smooth: return "smooth";
    case PassKind::Final: return "final";
  }
  return "?";
}

Remesher::Remesher(AdaptedMesh& mesh, const RemeshOptions& options) : mesh_(mesh), options_(options) { mark_all(); }

void Remesher::reserve_for_metric() {
  // The adapted mesh has about 2 C / sqrt(3) vertices (C the metric area of
  // the surface, metric/surface_metric.h). Reserving that (with a margin for
  // edges shorter than 1) up front spares the copies a growing array makes,
  // each of which briefly holds the old and the new buffer; capacity never
  // written is not resident, so the margin costs address space only.
  const ControlSpace& control = mesh_.control();
  const double vertices =
      1.5 * std::clamp(options_.reserve_share, 0.0, 1.0) * predicted_vertex_count(control.target_complexity());
  SurfaceMesh& m = mesh_.mesh();
  constexpr double kMaxVertices = 25e6;  // a bound on the reservation, not on the mesh
  if (!(vertices > m.vertex_capacity())) return;
  const int nv = static_cast<int>(std::min(vertices, kMaxVertices));
  try {
    m.reserve(nv, 2 * nv + 16);
  } catch (const std::bad_alloc&) {
    // No room to reserve: the arrays grow as they go.
  }
}

void Remesher::mark_all() {
  const std::size_t n = static_cast<std::size_t>(mesh_.mesh().vertex_capacity());
  swap_active_.assign(n, 1);
  smooth_active_.assign(n, 1);
  flat_bits_.assign(flat_bits_.size(), 0);
}

bool Remesher::edge_sags(Corner c) {
  const SurfaceMesh& mesh = mesh_.mesh();
  // One direction for the measure, whichever corner names the edge.
  Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
  if (b.idx < a.idx) std::swap(a, b);
  const Corner o = mesh.opposite(c);
  const std::size_t slot = static_cast<std::size_t>(o.is_valid() && o.idx < c.idx ? o.idx : c.idx);
  const std::size_t word = slot / 64;
  const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
  if (word < flat_bits_.size() && (flat_bits_[word] & bit)) return false;
  const bool sags = edge_sags_off_input(mesh_, a, b, is_feature_edge(mesh, c), options_.op);
  if (!sags && options_.sag_memo) {
    if (word >= flat_bits_.size())
      flat_bits_.resize(std::max<std::size_t>(word + 1, (3 * static_cast<std::size_t>(mesh.triangle_capacity()) + 63) / 64), 0);
    flat_bits_[word] |= bit;
  }
  return sags;
}

bool Remesher::interrupted(PassReport& r) {
  if (r.interrupted) return true;
  if (++interrupt_polls_ % 256 != 0) return false;
  if (options_.max_vertices > 0 && mesh_.mesh().n_vertices() > options_.max_vertices) {
    r.over_limit = true;
    r.interrupted = true;
    return true;
  }
  if (interrupt_) r.interrupted = interrupt_();
  return r.interrupted;
}

void Remesher::mark(Vertex v) {
  activate(v);
  stamp(v);
}

void Remesher::activate(Vertex v) {
  note_change(v);
  const std::size_t i = static_cast<std::size_t>(v.idx);
  if (i >= swap_active_.size()) {
    const std::size_t n = std::max<std::size_t>(i + 1, static_cast<std::size_t>(mesh_.mesh().vertex_capacity()));
    swap_active_.resize(n, 0);
    smooth_active_.resize(n, 0);
  }
  swap_active_[i] = 1;
  smooth_active_[i] = 1;
}

void Remesher::stamp(Vertex v) {
  note_change(v);
  if (flat_bits_.empty()) return;
  const SurfaceMesh& mesh = mesh_.mesh();
  if (mesh.is_isolated(v)) return;
  for (Corner c : mesh.fan_corners(v)) forget_triangle(M::triangle(c));
}

void Remesher::forget_triangle(Triangle t) {
  const std::size_t first = 3 * static_cast<std::size_t>(t.idx);
  for (std::size_t slot = first; slot < first + 3; ++slot)
    if (slot / 64 < flat_bits_.size()) flat_bits_[slot / 64] &= ~(std::uint64_t{1} << (slot % 64));
}

void Remesher::note_change(Vertex v) {
  const std::size_t i = static_cast<std::size_t>(v.idx);
  if (i >= changed_at_.size())
    changed_at_.resize(std::max<std::size_t>(i + 1, static_cast<std::size_t>(mesh_.mesh().vertex_capacity())), 0);
  changed_at_[i] = ++tick_;
}

const Remesher::Refusal* Remesher::remembered_refusal(RefusalMemo& memo, Vertex a, Vertex b) {
  const std::uint64_t key = edge_key(a, b);
  Refusal* found = memo.current.find(key);
  if (!found) {
    const Refusal* before = memo.previous.find(key);
    if (!before) return nullptr;
    found = memo.current.insert_or_assign(key, *before);
  }
  const std::uint64_t tick = found->tick;
  const SurfaceMesh& mesh = mesh_.mesh();
  auto changed = [&](Vertex v) {
    const std::size_t i = static_cast<std::size_t>(v.idx);
    return i < changed_at_.size() && changed_at_[i] > tick;
  };
  bool stale = changed(a) || changed(b);
  for (Vertex end : {a, b})
    for (Vertex w : mesh.ring_vertices(end)) stale = stale || changed(w);
  if (stale) {
    memo.current.erase(key);
    return nullptr;
  }
  return found;
}

void Remesher::start_refusal_pass(RefusalMemo& memo) {
  memo.previous.clear();
  memo.previous.swap(memo.current);
}

void Remesher::forget_refusals() {
  for (RefusalMemo* memo : {&split_refusals_, &collapse_refusals_}) {
    memo->current.clear();
    memo->previous.clear();
  }
}

void Remesher::record_touched(PassReport& r, Vertex v) {
  if (!options_.record_touched) return;
  const std::size_t i = static_cast<std::size_t>(v.idx);
  if (i >= touched_mark_.size()) touched_mark_.resize(std::max<std::size_t>(i + 1, static_cast<std::size_t>(mesh_.mesh().vertex_capacity())), 0);
  if (touched_mark_[i]) return;
  touched_mark_[i] = 1;
  r.touched.push_back(v.idx);
}

void Remesher::touch(PassReport& r, Vertex v) {
  record_touched(r, v);
  mark(v);
  for (Vertex w : mesh_.mesh().ring_vertices(v)) activate(w);
}

void Remesher::remember(PassKind kind, Vertex v) {
  if (options_.cache_size <= 0) return;
  Modification mod{kind, {}};
  for (Vertex w : mesh_.mesh().ring_vertices(v)) mod.created.push_back(key(v, w));
  cache_.push_back(std::move(mod));
  while (static_cast<int>(cache_.size()) > options_.cache_size) cache_.pop_front();
}

bool Remesher::in_cache(Vertex a, Vertex b, PassKind undoing) const {
  const auto k = key(a, b);
  for (const Modification& m : cache_) {
    if (m.kind == undoing) continue;
    for (const auto& e : m.created)
      if (e == k) return true;
  }
  return false;
}

int Remesher::local_swaps(Vertex v, PassReport& r) {
  if (!options_.local_swaps) return 0;
  SurfaceMesh& mesh = mesh_.mesh();
  int n = 0;
  // Each improving swap replaces a link edge by a spoke of v and brings two
  // new link edges (the only ones whose triangles changed): a queue of the
  // link edges to try, each swap adding its two, at most
  // max_local_swap_visits swaps per link edge v started with.
  std::vector<std::array<int, 2>> queue = link_edges(mesh, v);
  const std::size_t max_swaps = static_cast<std::size_t>(std::max(0, options_.max_local_swap_visits)) * queue.size();
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto e = queue[head];
    const Corner c = find_edge_corner(mesh, Vertex(e[0]), Vertex(e[1]));
    if (!c.is_valid()) continue;
    const SwapPlan plan = can_swap(mesh_, c, options_.op);
    if (plan.why != Rejection::None) continue;
    const Corner d = swap(mesh_, c);
    ++n;
    ++r.swaps;
    // The two triangles rewritten: the sag memo of their slots is stale, and
    // each holds one new link edge (the side opposite v).
    for (Corner x : {d, mesh.opposite(d)}) {
      forget_triangle(M::triangle(x));
      for (int k = 0; k < 3; ++k) note_change(mesh.vertex(M::triangle(x), k));
      const Corner cv = mesh.corner_of(M::triangle(x), v);
      if (cv.is_valid()) queue.push_back({mesh.vertex(M::next(cv)).idx, mesh.vertex(M::prev(cv)).idx});
    }
    if (static_cast<std::size_t>(n) >= max_swaps) break;
  }
  return n;
}

void Remesher::split_pass(PassReport& r) {
  if (!options_.split_by_generation) {
    priority_pass<SplitEdges>(r, true);
    return;
  }
  // Generations: every edge longer than lmax now, longest first, without the
  // swaps in between; then a swap pass around what changed, which turns
  // the triangles whose three edges were split into 1:4 subdivisions; again
  // with the long edges left, until none is.
  for (int generation = 0; generation < options_.max_split_generations && !r.interrupted; ++generation) {
    const int changes = priority_pass<SplitEdges>(r, false);
    if (changes == 0) break;
    if (options_.local_swaps) swap_pass(r);
    // A few long edges left (each generation scans the whole mesh): they
    // are split the classic way, longest first, following the new edges.
    if (changes < options_.few_splits_share * mesh_.mesh().n_vertices()) {
      priority_pass<SplitEdges>(r, true);
      break;
    }
  }
}

template <class Edges>
int Remesher::priority_pass(PassReport& r, bool follow_new_edges) {
  SurfaceMesh& mesh = mesh_.mesh();
  const OperatorOptions& o = options_.op;
  EdgeQueue<typename Edges::Order> queue(queue_);
  // A collapse's swaps wait until its fan has no edge left to collapse.
  const bool defer = Edges::kind == PassKind::Collapse && options_.defer_unsettled_swaps;
  auto sags = [this](Corner c) { return edge_sags(c); };
  RefusalMemo* memo = !memo_on_ || !options_.refusal_memo ? nullptr
                      : Edges::kind == PassKind::Split ? &split_refusals_
                                                       : &collapse_refusals_;
  queue.reserve(static_cast<std::size_t>(mesh.n_triangles()) * 3 / 2 + 16);  // every edge at once
  for (Corner c : mesh.edges()) {
    const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
    const double l = mesh_.length(a, b);
    if (Edges::outside(sags, c, l, o)) queue.append(Edges::key(l), a.idx, b.idx, c.idx);
  }
  queue.start();
  // Splits only add triangles, collapses only remove them: the budget
  // follows a refinement and keeps its start through a coarsening.
  const long long start_triangles = mesh.n_triangles();
  auto budget = [&] {
    const long long triangles = std::max<long long>(start_triangles, mesh.n_triangles());
    return static_cast<long long>(options_.pops_per_triangle) * triangles + options_.pops_base;
  };
  long long pops = 0;
  int changes = 0;
  while (!queue.empty() && pops++ < budget() && !interrupted(r)) {
    const QueuedEdgeTaken it = queue.pop();
    const Vertex a(it.a), b(it.b);
    const Corner c = edge_corner(mesh, it.corner, a, b);
    if (!c.is_valid()) continue;
    const double length = mesh_.length(a, b);
    if (!Edges::outside(sags, c, length, o)) continue;
    if (in_cache(a, b, Edges::kind)) {  // Remark 5
      refuse(r, Edges::kind, Rejection::Cache);
      continue;
    }
    if (memo) {
      if (const Refusal* known = remembered_refusal(*memo, mesh.edge_from(c), mesh.edge_to(c))) {
        refuse(r, Edges::kind, known->why);
        ++r.remembered_refusals;
        continue;
      }
    }
    const auto plan = Edges::plan(mesh_, c, length, o);
    if (plan.why != Rejection::None) {
      refuse(r, Edges::kind, plan.why);
      if (memo) memo->current.insert_or_assign(edge_key(mesh.edge_from(c), mesh.edge_to(c)), {tick_, plan.why});
      continue;
    }
    ++changes;
    const Vertex v = apply(r, c, plan, follow_new_edges && !defer);
    if (!follow_new_edges || !v.is_valid()) continue;
    auto queue_ring = [&] {
      bool queued = false;
      for_ring_edges(mesh, v, [&](Vertex w, Corner e) {
        const double l = mesh_.length(v, w);
        if (!Edges::outside(sags, e, l, o)) return;
        queue.push(Edges::key(l), v.idx, w.idx, -1);
        queued = true;
      });
      return queued;
    };
    if (!queue_ring() && defer && local_swaps(v, r) > 0) queue_ring();
  }
  return changes;
}

Vertex Remesher::apply(PassReport& r, Corner c, const SplitPlan& plan, bool follow_new_edges) {
  SurfaceMesh& mesh = mesh_.mesh();
  if (plan.swap_instead) {  // figure 14: a swap instead of the split
    const Corner d = swap(mesh_, c);
    ++r.swaps;
    touch(r, mesh.edge_from(d));
    touch(r, mesh.edge_to(d));
    return Vertex();
  }
  const Vertex v = split(mesh_, c, plan);
  ++r.splits;
  if (!plan.projected) ++r.split_unprojected;
  remember(PassKind::Split, v);
  touch(r, v);
  if (follow_new_edges) local_swaps(v, r);
  return v;
}

Vertex Remesher::apply(PassReport& r, Corner, const CollapsePlan& plan, bool follow_new_edges) {
  const Vertex v = collapse(mesh_, plan);
  ++r.collapses;
  remember(PassKind::Collapse, v);
  if (follow_new_edges) local_swaps(v, r);
  touch(r, v);
  return v;
}

void Remesher::collapse_pass(PassReport& r) { priority_pass<CollapseEdges>(r, true); }

void Remesher::swap_pass(PassReport& r) {
  SurfaceMesh& mesh = mesh_.mesh();
  // First in, first out: the active edges as they are now (a, b, the corner
  // naming a -> b), then the edges queued again around each swap. The first
  // list is sized exactly (a sweep counts it) and the second is kept apart,
  // its consumed front dropped as it grows: one queue grown by doubling held
  // its old and new storage together, the remesher's peak of memory.
  using Entry = std::array<int, 3>;
  std::vector<std::uint8_t> active(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  swap_active_.resize(active.size(), 0);
  active.swap(swap_active_);
  auto queued = [&](Corner c) {
    return !mesh.is_boundary_edge(c) && (active[mesh.edge_from(c).idx] || active[mesh.edge_to(c).idx]);
  };
  std::size_t count = 0;
  for (Corner c : mesh.edges()) count += queued(c) ? 1 : 0;
  std::vector<Entry> first;
  first.reserve(count);
  for (Corner c : mesh.edges())
    if (queued(c)) first.push_back({mesh.edge_from(c).idx, mesh.edge_to(c).idx, c.idx});
  std::vector<Entry>& again = swap_retries_;
  again.clear();
  std::size_t head = 0, again_head = 0;
  long long budget = static_cast<long long>(options_.max_swap_visits) * static_cast<long long>(first.size()) + 16;
  while ((head < first.size() || again_head < again.size()) && budget-- > 0 && !interrupted(r)) {
    Entry e;
    if (head < first.size()) {
      e = first[head++];
    } else {
      e = again[again_head++];
      if (again_head >= 4096 && 2 * again_head >= again.size()) {
        again.erase(again.begin(), again.begin() + static_cast<std::ptrdiff_t>(again_head));
        again_head = 0;
      }
    }
    const Corner c = edge_corner(mesh, e[2], Vertex(e[0]), Vertex(e[1]));
    if (!c.is_valid()) continue;
    const SwapPlan plan = can_swap(mesh_, c, options_.op);
    if (plan.why != Rejection::None) {
      refuse(r, PassKind::Swap, plan.why);
      continue;
    }
    const Corner d = swap(mesh_, c);
    ++r.swaps;
    // Section 5.4: the four edges around the new diagonal are tried again.
    const Corner od = mesh.opposite(d);
    for (Corner x : {M::next(d), M::prev(d), M::next(od), M::prev(od)})
      again.push_back({mesh.edge_from(x).idx, mesh.edge_to(x).idx, x.idx});
    for (Corner x : {d, od}) {
      record_touched(r, mesh.vertex(x));
      record_touched(r, mesh.edge_from(x));
      activate(mesh.vertex(x));
      activate(mesh.edge_from(x));
      forget_triangle(M::triangle(x));
    }
  }
  again.clear();
}

void Remesher::smooth_pass(PassReport& r, double visit_below, bool keep_lmin) {
  SurfaceMesh& mesh = mesh_.mesh();
  // The worst quality of v's fan is below visit_below.
  auto worth_visiting = [&](Vertex v) {
    if (!(visit_below <= 1)) return true;
    for (Corner c : mesh.fan(v))
      if (mesh_.quality(M::triangle(c)) < visit_below) return true;
    return false;
  };
  OperatorOptions o = options_.op;
  if (smoothing_done_ < options_.relaxed_smoothing_passes) o.move_quality_factor = options_.relaxed_quality_factor;
  o.move_keeps_lmin = keep_lmin;
  std::vector<std::uint8_t> active(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  smooth_active_.resize(active.size(), 0);
  active.swap(smooth_active_);
  for (Vertex v : mesh.vertices()) {
    if (interrupted(r)) break;
    if (!active[v.idx] || mesh.is_isolated(v) || !worth_visiting(v)) continue;
    const MovePlan plan = can_move(mesh_, v, o);
    if (plan.why != Rejection::None) {
      refuse(r, PassKind::Smooth, plan.why);
      continue;
    }
    move(mesh_, v, plan);
    ++r.moves;
    if (plan.quality_after - plan.quality_before >= options_.smoothing_spread_gain) {
      touch(r, v);
    } else {
      record_touched(r, v);
      stamp(v);  // moved: its edges' sag memo (edge_sags) is stale
    }
  }
  ++smoothing_done_;
}

void Remesher::final_pass(PassReport& r) {
  SurfaceMesh& mesh = mesh_.mesh();
  // Section 6, final optimisation 1: interior vertices of valence < 4.
  OperatorOptions o = options_.op;
  o.lmax = INFINITY;  // the remaining edges exist already
  for (Vertex v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    if (mesh_.kind(v) != VertexKind::Free || mesh.valence(v) >= 4) continue;
    const CollapsePlan plan = can_remove_vertex(mesh_, v, o);
    if (plan.why != Rejection::None) {
      refuse(r, PassKind::Final, plan.why);
      continue;
    }
    const Vertex k = collapse(mesh_, plan);
    ++r.removed_vertices;
    local_swaps(k, r);
    touch(r, k);
  }
  // Before the smoothing: swaps toward valence 6 where the metric is
  // isotropic (the smoothing then reaches better worst shapes:
  // sphere20k_iso q min 0.692 -> 0.738, hemi 0.682 -> 0.709).
  if (options_.valence_swaps) valence_swaps(r);
  // 2: the vertices are barycentred (section 5.5) 8-10 times.
  mark_all();
  final_smoothing(r, options_.final_full_passes);
  // The repairs' neighbourhoods are smoothed again (repair_poor_fans marks them alone).
  if (!r.interrupted && options_.repair_quality > 0 && repair_poor_fans(r) > 0) final_smoothing(r, 0);
  if (!r.interrupted && options_.relocate_quality > 0)
    for (int sweep = 0; sweep < options_.relocate_sweeps && !r.interrupted; ++sweep)
      if (relocate_worst(r) == 0) break;
  if (!r.interrupted) bound_distance(r);
  if (!r.interrupted) keep_creases(r);
}

void Remesher::final_smoothing(PassReport& r, int full_passes) {
  for (int p = 0; p < options_.final_smoothing_passes && !r.interrupted; ++p) {
    const int before = r.moves;
    smooth_pass(r, p < full_passes ? INFINITY : options_.final_visit_quality, options_.final_keeps_lmin);
    if (r.moves == before) break;
  }
}

std::vector<std::pair<double, int>> Remesher::vertices_of_triangles_below(double quality) const {
  const SurfaceMesh& mesh = mesh_.mesh();
  std::vector<std::pair<double, int>> poor;
  for (Triangle t : mesh.triangles()) {
    const double q = mesh_.quality(t);
    if (q < quality)
      for (int k = 0; k < 3; ++k) poor.push_back({q, mesh.vertex(t, k).idx});
  }
  std::sort(poor.begin(), poor.end());
  return poor;
}

int Remesher::repair_poor_fans(PassReport& r) {
  SurfaceMesh& mesh = mesh_.mesh();
  const std::vector<std::pair<double, int>> poor = vertices_of_triangles_below(options_.repair_quality);
  // Each vertex tried once (collapses free slots, they add none); the next
  // smoothing visits the repairs' neighbourhoods only.
  std::vector<std::uint8_t> tried(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  smooth_active_.assign(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  int removed = 0;
  for (const auto& [q, i] : poor) {
    const Vertex v(i);
    if (interrupted(r)) break;
    if (std::exchange(tried[static_cast<std::size_t>(i)], std::uint8_t{1})) continue;
    if (mesh.is_deleted(v) || mesh.is_isolated(v)) continue;
    const CollapsePlan plan = can_collapse_for_quality(mesh_, v, options_.op, options_.repair_gain);
    if (plan.why != Rejection::None) {
      refuse(r, PassKind::Final, plan.why);
      continue;
    }
    const Vertex k = collapse(mesh_, plan);
    ++r.collapses;
    ++removed;
    local_swaps(k, r);
    touch(r, k);
  }
  return removed;
}

int Remesher::relocate_worst(PassReport& r) {
  SurfaceMesh& mesh = mesh_.mesh();
  // Each vertex of the poor triangles tried once.
  const std::vector<std::pair<double, int>> poor = vertices_of_triangles_below(options_.relocate_quality);
  std::vector<std::uint8_t> tried(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  OperatorOptions o = options_.op;
  o.move_keeps_lmin = options_.final_keeps_lmin;
  int moved = 0;
  for (const auto& [q, i] : poor) {
    const Vertex v(i);
    if (interrupted(r)) break;
    if (std::exchange(tried[static_cast<std::size_t>(i)], std::uint8_t{1})) continue;
    if (mesh.is_deleted(v) || mesh.is_isolated(v)) continue;
    const MovePlan plan = can_move_for_worst(mesh_, v, o, options_.relocate_gain, options_.relocate_trade_quality);
    if (plan.why != Rejection::None) {
      // A vertex that may not move this way, or has nothing to gain, is not a refusal.
      if (plan.why != Rejection::Fixed && plan.why != Rejection::NoGain) refuse(r, PassKind::Final, plan.why);
      continue;
    }
    move(mesh_, v, plan);
    ++r.moves;
    ++moved;
    record_touched(r, v);
    stamp(v);  // moved: its edges' sag memo (edge_sags) is stale
  }
  return moved;
}

std::array<int, 2> Remesher::crease_spoke(Corner c) {
  SurfaceMesh& mesh = mesh_.mesh();
  const Corner o = mesh.opposite(c);
  if (!o.is_valid()) return {-1, -1};
  const Vertex u = mesh.edge_from(c), w = mesh.edge_to(c);
  const Vec3 n1 = mesh.triangle_normal(M::triangle(c)), n2 = mesh.triangle_normal(M::triangle(o));
  if (!(norm2(n1) > 0) || !(norm2(n2) > 0)) return {-1, -1};
  // The input's feature edge under the middle of the edge, and its facets.
  GeometrySurface& geometry = mesh_.geometry();
  const SurfaceMesh& tg = geometry.mesh();
  const std::array<Hint, 2> hints = {mesh_.hint_g(u), mesh_.hint_g(w)};
  const Projection p = geometry.project(0.5 * (mesh.position(u) + mesh.position(w)), hints, Constraint::OnFeature);
  if (p.location.constraint != Constraint::OnFeature || !p.location.edge.is_valid()) return {-1, -1};
  const Corner ic = p.location.edge, io = tg.opposite(ic);
  if (!io.is_valid()) return {-1, -1};
  const Vec3 m1 = tg.triangle_normal(M::triangle(ic)), m2 = tg.triangle_normal(M::triangle(io));
  if (!(norm2(m1) > 0) || !(norm2(m2) > 0)) return {-1, -1};
  if (vector_angle(n1, n2) >= options_.crease_keep * vector_angle(m1, m2)) return {-1, -1};
  // Each triangle lies left of its own direction along the edge: the one
  // running the way the input edge runs in ic's triangle faces m1.
  const Vec3 along = tg.position(tg.edge_to(ic)) - tg.position(tg.edge_from(ic));
  const bool same = dot(mesh.position(w) - mesh.position(u), along) > 0;
  const double turn1 = vector_angle(n1, same ? m1 : m2), turn2 = vector_angle(n2, same ? m2 : m1);
  const Corner side = turn1 >= turn2 ? c : o;
  // The longer of the side's two other edges, in the metric.
  const Vertex apex = mesh.vertex(side);
  const Vertex a = mesh.edge_from(side), b = mesh.edge_to(side);
  const double la = mesh_.length(apex, a), lb = mesh_.length(apex, b);
  if (!(std::max(la, lb) >= options_.op.lmin)) return {-1, -1};
  return {apex.idx, (la >= lb ? a : b).idx};
}

void Remesher::keep_creases(PassReport& r) {
  if (!(options_.crease_keep > 0)) return;
  SurfaceMesh& mesh = mesh_.mesh();
  const double budget = options_.max_bound_split_share * mesh.n_vertices();
  int splits = 0;
  for (int sweep = 0; sweep < options_.crease_sweeps; ++sweep) {
    std::vector<std::array<int, 2>> spokes;
    for (Triangle t : mesh.triangles())
      for (int k = 0; k < 3; ++k) {
        const Corner c = M::corner(t, k);
        const Corner o = mesh.opposite(c);
        // Each edge between two triangles once, at its smaller corner.
        if (!o.is_valid() || o.idx < c.idx || !is_feature_edge(mesh, c)) continue;
        const std::array<int, 2> spoke = crease_spoke(c);
        if (spoke[0] >= 0) spokes.push_back(spoke);
      }
    int done = 0;
    for (const auto& [apex, end] : spokes) {
      if (interrupted(r) || splits + done >= budget) break;
      // A spoke split earlier in the sweep (two creases share it) is gone.
      const Corner e = find_edge_corner(mesh, Vertex(apex), Vertex(end));
      if (!e.is_valid()) continue;
      const double metric_length = mesh_.length(Vertex(apex), Vertex(end));
      const double size = norm(mesh.position(Vertex(end)) - mesh.position(Vertex(apex))) / metric_length;
      const SplitPlan plan = can_split_onto_input(mesh_, e, options_.bound_split_turn_deg, kCreaseSplitBound * size, true);
      if (plan.why != Rejection::None) {
        refuse(r, PassKind::Final, plan.why);
        continue;
      }
      apply(r, e, plan, false);
      ++done;
    }
    splits += done;
    if (done == 0 || r.interrupted || splits >= budget) break;
  }
  r.crease_splits += splits;
}

std::vector<Remesher::BeyondBound> Remesher::edges_beyond_bound(const std::vector<Vertex>* around) {
  SurfaceMesh& mesh = mesh_.mesh();
  const double absolute = options_.distance_bound > 0 ? options_.distance_bound : INFINITY;
  const double relative = options_.relative_distance_bound;
  // The relative share of the size the metric asks for along edge u-w.
  auto relative_bound = [&](Vertex u, Vertex w) {
    if (!(relative > 0)) return std::numeric_limits<double>::infinity();
    const double metric_length = mesh_.length(u, w);
    if (!(metric_length > 0)) return std::numeric_limits<double>::infinity();
    return relative * norm(mesh.position(w) - mesh.position(u)) / metric_length;
  };
  // The bound at a point: the absolute one, or the relative one beyond the
  // smooth surface's own deviation from T_G there (a coarse smooth input
  // lies inside the surface its vertices ask for: section 7.2).
  auto bound_at = [&](const AdaptedMesh::InputDistance& d, double relative_part) {
    return std::min(absolute, relative_part + d.natural);
  };
  // The triangles to look at: all, or the fans of `around` (marked).
  std::vector<char> chosen;
  std::vector<Triangle> subset;
  if (around) {
    chosen.assign(static_cast<std::size_t>(mesh.triangle_capacity()), 0);
    for (Vertex v : *around) {
      if (mesh.is_deleted(v) || mesh.is_isolated(v)) continue;
      for (Corner c : mesh.fan_corners(v)) {
        const Triangle t = M::triangle(c);
        if (!chosen[static_cast<std::size_t>(t.idx)]) subset.push_back(t);
        chosen[static_cast<std::size_t>(t.idx)] = 1;
      }
    }
  }
  std::vector<BeyondBound> out;
  auto check = [&](Triangle t) {
    const std::array<Vertex, 3> v = {mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2)};
    double relative_sum = 0;
    for (int k = 0; k < 3; ++k) {
      const Corner e = M::corner(t, k);
      const Vertex u = mesh.edge_from(e), w = mesh.edge_to(e);
      const double rel = relative_bound(u, w);
      relative_sum += rel;
      // Each edge once: at its canonical corner (the edge of corner k runs
      // from vertex k + 1 to k + 2) when both its triangles are looked at.
      const Corner o = mesh.opposite(e);
      if (o.is_valid() && o.idx < e.idx && (!around || chosen[static_cast<std::size_t>(M::triangle(o).idx)])) continue;
      const Vec3 mid = 0.5 * (mesh.position(u) + mesh.position(w));
      // Within the bound's least value of a triangle of T_G near it: no search.
      if (mesh_.distance_to_hinted_input(mid, {u, w}) <= std::min(absolute, rel)) continue;
      const auto d = mesh_.distance_to_input(mid, {u, w});
      const double bound = bound_at(d, rel);
      if (d.distance > bound) out.push_back({d.distance, bound, u.idx, w.idx});
    }
    const Vec3 pa = mesh.position(v[0]), pb = mesh.position(v[1]), pc = mesh.position(v[2]);
    const Vec3 centroid = (pa + pb + pc) / 3.0;
    if (mesh_.distance_to_hinted_input(centroid, {v[0], v[1], v[2]}) <= std::min(absolute, relative_sum / 3)) return;
    const auto d = mesh_.distance_to_input(centroid, {v[0], v[1], v[2]});
    const double bound = bound_at(d, relative_sum / 3);
    if (!(d.distance > bound)) return;
    const double lab = norm2(pb - pa), lbc = norm2(pc - pb), lca = norm2(pa - pc);
    if (lab >= lbc && lab >= lca) out.push_back({d.distance, bound, v[0].idx, v[1].idx, v[2].idx});
    else if (lbc >= lca) out.push_back({d.distance, bound, v[1].idx, v[2].idx, v[0].idx});
    else out.push_back({d.distance, bound, v[2].idx, v[0].idx, v[1].idx});
  };
  if (around) {
    for (Triangle t : subset) check(t);
  } else {
    for (Triangle t : mesh.triangles()) check(t);
  }
  std::sort(out.begin(), out.end(), [](const BeyondBound& x, const BeyondBound& y) { return x.distance > y.distance; });
  return out;
}

void Remesher::bound_distance(PassReport& r) {
  if (!(options_.distance_bound > 0) && !(options_.relative_distance_bound > 0)) return;
  SurfaceMesh& mesh = mesh_.mesh();
  // A guard: the bound fixes a few chords; a surface that asks for more
  // than max_bound_split_share of the mesh in splits is left as it is, with
  // the count of what stays beyond.
  const double budget = options_.max_bound_split_share * mesh.n_vertices();
  // The first sweep looks at the whole mesh, the next ones at the triangles
  // around the vertices the previous one added.
  std::vector<Vertex> added;
  int splits_in_all = 0;
  for (int sweep = 0; sweep < options_.bound_sweeps; ++sweep) {
    const std::vector<BeyondBound> beyond = edges_beyond_bound(sweep == 0 ? nullptr : &added);
    if (sweep == 0) r.beyond_bound = static_cast<int>(beyond.size());
    // The last sweep's splits left more beyond the bound around them than
    // they added vertices: the splits no longer converge (a fillet curved
    // too tightly for the size, where each split of a longest edge leaves
    // two triangles as far off): the sweeps stop there.
    if (sweep > 0 && beyond.size() > added.size()) break;
    added.clear();
    for (const BeyondBound& it : beyond) {
      if (interrupted(r) || splits_in_all >= budget) break;
      // An edge split earlier in the sweep is gone (its halves wait for the next one).
      Corner c = find_edge_corner(mesh, Vertex(it.a), Vertex(it.b));
      if (!c.is_valid()) continue;
      SplitPlan plan = can_split_onto_input(mesh_, c, options_.bound_split_turn_deg, it.bound);
      // A centroid beyond: when its longest edge cannot be split, the
      // longer, then the shorter of the two others.
      if (plan.why != Rejection::None && it.c >= 0 && !mesh.is_deleted(Vertex(it.c))) {
        const Vertex a(it.a), b(it.b), v(it.c);
        std::array<std::array<Vertex, 2>, 2> others = {{{b, v}, {v, a}}};
        if (norm2(mesh.position(a) - mesh.position(v)) > norm2(mesh.position(b) - mesh.position(v)))
          std::swap(others[0], others[1]);
        for (const auto& [x, y] : others) {
          const Corner e = find_edge_corner(mesh, x, y);
          if (!e.is_valid()) continue;
          const SplitPlan other = can_split_onto_input(mesh_, e, options_.bound_split_turn_deg, it.bound);
          if (other.why != Rejection::None) continue;
          c = e;
          plan = other;
          break;
        }
      }
      if (plan.why != Rejection::None) {
        refuse(r, PassKind::Final, plan.why);
        continue;
      }
      // The halves of a chord split onto the input are often thin: the swaps
      // around the new vertex that improve quality (eq. 17) follow.
      const Vertex k = apply(r, c, plan, false);
      local_swaps(k, r);
      added.push_back(k);
      ++splits_in_all;
    }
    if (added.empty() || r.interrupted || splits_in_all >= budget) break;
  }
  r.bound_splits += splits_in_all;
  // What stays beyond the bound, over the whole mesh (for the report).
  if (splits_in_all > 0) r.beyond_bound = static_cast<int>(edges_beyond_bound().size());
}

int Remesher::valence_swaps(PassReport& r) {
  SurfaceMesh& mesh = mesh_.mesh();
  OperatorOptions o = options_.op;
  o.swap_gain = options_.valence_swap_gain;
  // Valences, counted on first use and kept up to date across the swaps.
  std::vector<int> valence(static_cast<std::size_t>(mesh.vertex_capacity()), -1);
  auto valence_of = [&](Vertex v) -> int& {
    int& k = valence[static_cast<std::size_t>(v.idx)];
    if (k < 0) k = mesh.valence(v);
    return k;
  };
  auto deviation = [&](Vertex v, int delta) {
    if (mesh_.kind(v) != VertexKind::Free) return 0;
    const int d = valence_of(v) + delta - 6;
    return d * d;
  };
  // The metrics of the four vertices isotropic and alike: valence 6 is the
  // regular mesh there (in a stretched metric the regular mesh is another
  // one, and a trade of quality for valence can cross a jump of the metric).
  auto nearly_isotropic = [&](std::initializer_list<Vertex> vs) {
    double lo = INFINITY, hi = 0;
    for (Vertex v : vs) {
      const SymTensor3& M = mesh_.metric(v);
      const double mean = trace(M) / 3;
      if (!(frobenius_norm(M - SymTensor3::identity(mean)) <= 0.25 * mean)) return false;
      lo = std::min(lo, mean);
      hi = std::max(hi, mean);
    }
    return hi <= 1.5 * lo;
  };
  // The interior edges now, each with a corner naming it (a swap rewrites
  // its two triangles: a corner that no longer names its edge is looked up);
  // only those whose ends pass the metric test (the list of a large
  // anisotropic mesh would add to its peak memory for nothing).
  struct EdgeAt {
    int a, b, corner;
  };
  std::vector<EdgeAt> edges;
  for (Corner c : mesh.edges()) {
    if (mesh.is_boundary_edge(c)) continue;
    const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
    if (nearly_isotropic({a, b})) edges.push_back({a.idx, b.idx, c.idx});
  }
  int n = 0;
  for (const EdgeAt& e : edges) {
    const Vertex a(e.a), b(e.b);
    Corner c(e.corner);
    if (mesh.is_deleted(M::triangle(c)) || mesh.edge_from(c) != a || mesh.edge_to(c) != b) c = find_edge_corner(mesh, a, b);
    if (!c.is_valid() || mesh.is_boundary_edge(c)) continue;
    const Vertex p = mesh.vertex(c), q = mesh.vertex(mesh.opposite(c));
    const int before = deviation(a, 0) + deviation(b, 0) + deviation(p, 0) + deviation(q, 0);
    const int after = deviation(a, -1) + deviation(b, -1) + deviation(p, 1) + deviation(q, 1);
    if (after >= before) continue;
    if (!nearly_isotropic({a, b, p, q})) continue;
    // The new diagonal stays in [lmin, lmax] (the passes are over: nothing
    // would split or collapse it).
    const double l = mesh_.length(p, q);
    if (l > o.lmax || l < o.lmin) continue;
    if (can_swap(mesh_, c, o).why != Rejection::None) continue;
    swap(mesh_, c);
    --valence_of(a);
    --valence_of(b);
    ++valence_of(p);
    ++valence_of(q);
    ++r.swaps;
    ++n;
    for (Vertex v : {a, b, p, q}) touch(r, v);
  }
  return n;
}

namespace {

// The state of PassReport over a range of triangle slots, added up block by
// block in slot order (the same sums on any number of threads).
struct StateSums {
  int edges = 0, in_band = 0;
  std::array<int, kLengthBins.size()> histogram{};
  double length_min = INFINITY, length_max = 0, q_min = 1, q_sum = 0;
  void add(const StateSums& o) {
    edges += o.edges;
    in_band += o.in_band;
    for (std::size_t b = 0; b < histogram.size(); ++b) histogram[b] += o.histogram[b];
    length_min = std::min(length_min, o.length_min);
    length_max = std::max(length_max, o.length_max);
    q_min = std::min(q_min, o.q_min);
    q_sum += o.q_sum;
  }
};

constexpr int kStateBlock = 16384;  // triangle slots a block

}  // namespace

void Remesher::fill_state(PassReport& r, bool parallel) const {
  const SurfaceMesh& mesh = mesh_.mesh();
  // One sweep over the triangles, the three lengths of each (every edge is
  // measured from both sides: no array of lengths, whose memory would add
  // to the peak of a large refinement); an edge is counted at its canonical
  // corner (the edge of corner k runs from vertex k + 1 to k + 2).
  auto sweep = [&](int begin, int end, StateSums& s) {
    for (int i = begin; i < end; ++i) {
      const Triangle tr(i);
      if (mesh.is_deleted(tr)) continue;
      std::array<double, 3> len;
      for (int k = 0; k < 3; ++k) {
        const Corner c = M::corner(tr, k);
        const double le = mesh_.length(mesh.edge_from(c), mesh.edge_to(c));
        len[static_cast<std::size_t>(k)] = le;
        const Corner o = mesh.opposite(c);
        if (o.is_valid() && o.idx < c.idx) continue;  // counted at o
        ++s.edges;
        s.length_min = std::min(s.length_min, le);
        s.length_max = std::max(s.length_max, le);
        std::size_t bin = 0;
        while (bin + 1 < kLengthBins.size() && le >= kLengthBins[bin]) ++bin;
        ++s.histogram[bin];
        if (le >= kLengthBins[2] && le <= kLengthBins[5]) ++s.in_band;
      }
      const double q = quality_from_lengths(len[2], len[0], len[1]);
      s.q_min = std::min(s.q_min, q);
      s.q_sum += q;
    }
  };
  const int slots = mesh.triangle_capacity();
  const int blocks = (slots + kStateBlock - 1) / kStateBlock;
  std::vector<StateSums> block_sums(static_cast<std::size_t>(blocks));
  auto sweep_blocks = [&](int, int first, int last) {
    for (int b = first; b < last; ++b)
      sweep(b * kStateBlock, std::min(slots, (b + 1) * kStateBlock), block_sums[static_cast<std::size_t>(b)]);
  };
  if (parallel)
    run_chunks(blocks, chunk_count(blocks, 4), sweep_blocks);
  else
    sweep_blocks(0, 0, blocks);
  StateSums total;
  for (const StateSums& b : block_sums) total.add(b);
  r.vertices = mesh.n_vertices();
  r.triangles = mesh.n_triangles();
  r.edges = total.edges;
  r.histogram = total.histogram;
  r.length_min = total.length_min;
  r.length_max = total.length_max;
  r.q_min = total.q_min;
  r.in_band_share = r.edges ? static_cast<double>(total.in_band) / r.edges : 0.0;
  r.q_mean = r.triangles ? total.q_sum / r.triangles : 0.0;
}

void copy_state(const PassReport& from, PassReport& to) {
  to.vertices = from.vertices;
  to.triangles = from.triangles;
  to.edges = from.edges;
  to.histogram = from.histogram;
  to.in_band_share = from.in_band_share;
  to.length_min = from.length_min;
  to.length_max = from.length_max;
  to.q_min = from.q_min;
  to.q_mean = from.q_mean;
}

PassReport Remesher::measure() const {
  PassReport r;
  r.round = schedule_.round;
  fill_state(r, true);
  return r;
}

PassReport Remesher::step(PassKind kind) {
  has_last_ = false;  // the schedule's shortcut (an unchanged state) no longer holds
  forget_refusals();  // the mesh may have been edited since the last pass
  memo_on_ = false;
  return step(kind, nullptr, true);
}

PassReport Remesher::step(PassKind kind, const PassReport* previous, bool measure) {
  const auto t0 = Clock::now();
  // At the first pass: a remesher made to measure the mesh changes nothing.
  if (!reserved_) {
    reserve_for_metric();
    reserved_ = true;
  }
  PassReport r;
  r.kind = kind;
  r.round = schedule_.round;
  if (kind == PassKind::Split) start_refusal_pass(split_refusals_);
  if (kind == PassKind::Collapse) start_refusal_pass(collapse_refusals_);
  if (kind == PassKind::Final) forget_refusals();
  switch (kind) {
    case PassKind::Split: split_pass(r); break;
    case PassKind::Collapse: collapse_pass(r); break;
    case PassKind::Swap: swap_pass(r); break;
    case PassKind::Smooth: smooth_pass(r); break;
    case PassKind::Final: final_pass(r); break;
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  for (int v : r.touched) touched_mark_[static_cast<std::size_t>(v)] = 0;
  if (!measure) {
    r.measured = false;
    r.vertices = mesh_.mesh().n_vertices();
    r.triangles = mesh_.mesh().n_triangles();
  } else if (previous && previous->measured && r.changes() == 0) {
    // Every change of the mesh is counted: a pass without any left the
    // state of the previous one (within run(), nothing else touches the mesh).
    copy_state(*previous, r);
  } else {
    fill_state(r, false);
  }
  return r;
}

void Remesher::set_schedule(const Schedule& s) {
  forget_refusals();
  schedule_ = s;
  has_last_ = false;
  mark_all();
  if (s.phase != Schedule::Phase::Initial && s.stage_started) set_stage_metric(s.stage);
}

std::vector<PassKind> Remesher::round_plan() const {
  std::vector<PassKind> plan = {PassKind::Split, PassKind::Collapse, PassKind::Swap};
  plan.insert(plan.end(), static_cast<std::size_t>(std::max(0, options_.smoothing_passes)), PassKind::Smooth);
  return plan;
}

PassKind Remesher::next_pass() const {
  switch (schedule_.phase) {
    case Schedule::Phase::Initial: return options_.initial_swaps ? PassKind::Swap : PassKind::Split;
    case Schedule::Phase::Round: return round_plan()[static_cast<std::size_t>(schedule_.pass)];
    case Schedule::Phase::Final:
    case Schedule::Phase::Done: break;
  }
  return PassKind::Final;
}

PassReport Remesher::record_state(PassReport r) {
  last_ = r;
  last_.touched = {};
  has_last_ = true;
  return r;
}

PassReport Remesher::advance() {
  // An interrupted pass leaves the schedule where it was (the pass is done
  // again, from the mesh it left, by the next advance()).
  const Schedule before = schedule_;
  PassReport r = advance_schedule();
  if (r.over_limit) {
    schedule_.phase = Schedule::Phase::Done;
  } else if (r.interrupted) {
    schedule_ = before;
  }
  return r;
}

// Section 6's schedule, one pass per call:
//   1. an initial swap pass ("the final result is better if this initial
//      optimization is carried out");
//   2. per stage (Remark 6: the relaxed metrics, then the target), rounds of
//      round_plan() (steps 1-2 for every edge, then swaps and smoothing over
//      what changed) until a round splits and collapses at most
//      converged_share of the vertices, the rounds stagnate, a round's
//      splits and collapses balance, or max_rounds rounds;
//   3. the final optimisation (vertices of valence < 4, smoothing 8-10 times).
PassReport Remesher::advance_schedule() {
  Schedule& s = schedule_;
  switch (s.phase) {
    case Schedule::Phase::Done: throw std::logic_error("Remesher::advance: the schedule is done");
    case Schedule::Phase::Initial:
      s.phase = Schedule::Phase::Round;
      if (options_.initial_swaps) return record_state(step(PassKind::Swap, previous(), options_.measure_every_pass));
      break;
    case Schedule::Phase::Final:
      s.phase = Schedule::Phase::Done;
      return record_state(step(PassKind::Final, previous(), true));
    case Schedule::Phase::Round: break;
  }
  if (!s.stage_started) begin_stage();
  if (s.pass == 0) {
    ++s.round;
    ++s.stage_rounds;
    s.round_changes = 0;
    s.round_splits = 0;
  }
  const std::vector<PassKind> plan = round_plan();
  const bool round_end = static_cast<std::size_t>(s.pass) + 1 == plan.size();
  memo_on_ = true;  // a round's split and collapse passes consult the refusal memo
  PassReport r = step(plan[static_cast<std::size_t>(s.pass)], previous(), round_end || options_.measure_every_pass);
  memo_on_ = false;
  s.round_changes += r.splits + r.collapses;  // only the split and collapse passes make either
  s.round_splits += r.splits;
  if (round_end) {
    s.round_band.push_back(r.in_band_share);
    s.round_change.push_back(s.round_changes);
    end_round();
    r.over_limit = options_.max_round_vertices > 0 && mesh_.mesh().n_vertices() > options_.max_round_vertices;
  } else {
    ++s.pass;
  }
  return record_state(std::move(r));
}

void Remesher::set_stage_metric(int stage) {
  forget_refusals();  // every metric changes
  const int stages = std::max(0, options_.relaxation_stages);
  if (stages == 0) return;
  mesh_.control().set_relaxation(static_cast<double>(stage + 1) / (stages + 1));
  mesh_.refresh_values();
}

void Remesher::begin_stage() {
  schedule_.stage_started = true;
  if (options_.relaxation_stages <= 0) return;
  set_stage_metric(schedule_.stage);
  mark_all();
  has_last_ = false;
}

void Remesher::end_round() {
  Schedule& s = schedule_;
  s.pass = 0;
  const bool converged = s.round_changes <= options_.converged_share * mesh_.mesh().n_vertices();
  if (!converged && !stagnated() && !balanced() && s.stage_rounds < options_.max_rounds) return;
  s.round_band.clear();
  s.round_change.clear();
  if (s.stage < std::max(0, options_.relaxation_stages)) {
    ++s.stage;
    s.stage_rounds = 0;
    s.stage_started = false;
  } else {
    s.phase = Schedule::Phase::Final;
  }
}

bool Remesher::stagnated() const {
  const Schedule& s = schedule_;
  const std::size_t k = static_cast<std::size_t>(std::max(0, options_.stagnation_rounds));
  const std::size_t n = s.round_band.size();
  if (k == 0 || n <= k) return false;
  const double few = options_.stagnation_share * mesh_.mesh().n_vertices();
  const double before = *std::max_element(s.round_band.begin(), s.round_band.end() - static_cast<std::ptrdiff_t>(k));
  for (std::size_t i = n - k; i < n; ++i)
    if (s.round_change[i] > few || s.round_band[i] > before + options_.stagnation_band_gain) return false;
  return true;
}

bool Remesher::balanced() const {
  const Schedule& s = schedule_;
  if (options_.balance_after_rounds <= 0 || s.stage_rounds <= options_.balance_after_rounds) return false;
  const int splits = s.round_splits, collapses = s.round_changes - s.round_splits;
  return std::abs(splits - collapses) < options_.balance_share * std::max(splits, collapses);
}

std::vector<PassReport> Remesher::run(const std::function<void(const PassReport&)>& progress,
                                      const std::function<bool()>& stop) {
  std::vector<PassReport> out;
  while (!finished()) {
    out.push_back(advance());
    if (progress) progress(out.back());
    if (stop && stop()) break;
  }
  return out;
}

}  // namespace anisurf::remesh
