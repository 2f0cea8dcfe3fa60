// The remeshing loop of the report's section 6 on top of the local operators
// of section 5: splits of edges longer than lmax (longest first), collapses of
// edges shorter than lmin (shortest first), each followed by local swaps
// around the modified vertex, global swap passes, smoothing passes (eq. 19),
// a cache of the last modifications against cycles (Remark 5), and the final
// optimisation (interior vertices of valence < 4 removed, 8-10 smoothing
// passes). Swap and smoothing passes after the first visit only the
// neighbourhoods of what changed since.
//
//   Remesher r(adapted_mesh);
//   PassReport s = r.step(PassKind::Split);   // one named pass
//   std::vector<PassReport> all = r.run();    // the schedule: rounds until (almost) nothing changes, then the final pass
//   while (!r.finished()) show(r.advance());  // or the same schedule a pass at a time
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <string_view>
#include <vector>

#include "core/flat_map64.h"
#include "metric/mesh_quality.h"
#include "remesh/edge_queue.h"
#include "remesh/operators.h"

namespace anisurf::remesh {

struct RemeshOptions {
  OperatorOptions op;                // lmax 1.4, lmin 0.6 and the filters
  int max_rounds = 30;               // rounds per stage in run() (the Schedule below)
  // run() stops when a round splits and collapses at most this share of the
  // vertices (0: only when nothing changes).
  double converged_share = 0.01;
  // ... or when the rounds stagnate: the last stagnation_rounds rounds each
  // split and collapse at most stagnation_share of the vertices and none of
  // them raised the share of edges in band by more than stagnation_band_gain
  // above the best before them (a metric the surface cannot follow keeps a
  // few edges moving back and forth: on falcon.mesh's ungraded curvature
  // metric ~40 changes a round for 20 rounds at a band share within 0.5%).
  // 0 rounds: off.
  int stagnation_rounds = 3;
  double stagnation_share = 0.1;
  double stagnation_band_gain = 0.002;
  // ... or when, after balance_after_rounds rounds of the stage, a round's
  // splits and collapses differ by less than balance_share of the larger:
  // they undo each other's work and the vertex count no longer moves (Mmg's
  // rule for its surface and volume loops; on falcon.mesh's ungraded
  // curvature metric rounds 6-10 each split ~40 edges and collapse as many,
  // the band share within 0.5%). 0 rounds: off.
  int balance_after_rounds = 4;
  double balance_share = 0.1;
  int smoothing_passes = 1;          // smoothing passes per round
  // A move that raises the worst quality of its fan by less than this
  // leaves its neighbourhood unmarked: the next smoothing and swap passes
  // visit the vertices near the moves that mattered (0: near every move).
  double smoothing_spread_gain = 1e-2;
  int final_smoothing_passes = 10;   // section 6's final optimisation: "about 8-10"
  // ... of which the first final_full_passes visit every vertex, the others
  // only the vertices with a triangle of quality below final_visit_quality
  // in their fan (where the last passes still gain: on bunny.off at hausd
  // 3e-4, moves of fans above 0.9 raised their worst quality by < 1e-3).
  int final_full_passes = 3;
  double final_visit_quality = 0.9;
  // The final smoothing moves no vertex that would shorten an edge below
  // lmin, unless its fan holds a triangle below keep_lmin_quality
  // (OperatorOptions::move_keeps_lmin): no collapse follows it to remove
  // such an edge (ours, not the report's).
  bool final_keeps_lmin = true;
  int cache_size = 10;               // Remark 5: the last 10 modifications
  int relaxed_smoothing_passes = 4;  // Remark 4: the first passes accept a slightly worse quality
  double relaxed_quality_factor = 0.9;
  bool initial_swaps = true;         // section 6: an initial swap pass improves the result
  // Final optimisation (ours, not the report's): swaps toward valence 6 in
  // isotropic regions before the smoothing, each allowed to lower the worst
  // quality of its two triangles to this share of the old.
  bool valence_swaps = true;
  double valence_swap_gain = 0.6;
  // Final optimisation (ours): after the smoothing, the vertices of the
  // triangles below repair_quality are removed into a neighbour where that
  // raises the worst quality of the triangles replaced by the factor
  // repair_gain (can_collapse_for_quality: a vertex squeezed where its
  // fan cannot be shaped, its edges at lmin), the worst first; the
  // smoothing then runs again around them. 0: off.
  double repair_quality = 0.8;
  double repair_gain = 1.05;
  // Final optimisation (ours): then the free vertices of the triangles below
  // relocate_quality, the worst first, are moved where the worst quality of
  // their fan is largest (can_move_for_worst: eq. 19's barycentre is where
  // the edges' lengths balance, not where the worst triangle is best),
  // when that raises it by the factor relocate_gain and the fan's summed
  // quality does not fall (below relocate_trade_quality: falls by no more
  // than the worst gains), a triangle whose vertices' metrics differ by
  // more than 5% only kept from getting worse; at most relocate_sweeps
  // sweeps. 0: off.
  double relocate_quality = 0.9;
  double relocate_gain = 1.01;
  double relocate_trade_quality = 0.8;
  int relocate_sweeps = 1;
  bool local_swaps = true;           // section 6, step 2: swaps around each split / collapse
  // ... except after a collapse that leaves an edge of its fan to collapse
  // next (ours): the fan changes again at once, so its swaps wait for the
  // collapse that settles it, or for the swap pass after the collapse pass,
  // which visits every vertex the collapses touched. A coarsening that
  // merges a fine mesh fan by fan tries each fan's swaps once, not after
  // every one of its collapses.
  bool defer_unsettled_swaps = true;
  int max_local_swap_visits = 4;     // ... at most this many swaps per edge of the vertex's link at the start
  int max_swap_visits = 8;           // a swap pass ends after this many visits per edge it started with
  // Budget of a split or collapse pass (a guard against cycles that grows
  // with the mesh: a refinement multiplies the triangles many times over in
  // one pass): at most pops_per_triangle * max(triangles at the start,
  // triangles now) + pops_base edges taken from its heap.
  int pops_per_triangle = 20;
  int pops_base = 1000;
  // Remark 6: for metrics far from the initial mesh, run() first adapts to
  // `relaxation_stages` relaxed metrics (ControlSpace::set_relaxation with
  // t = 1/(n+1) ... n/(n+1)), then to the target. 0: off.
  int relaxation_stages = 0;
  // PassReport::touched is filled (the editor shows it); off saves 4 bytes
  // per touched vertex and pass for batch runs.
  bool record_touched = true;
  // The split passes remember the edges found not to sag off the input (a
  // cache: the output is the same without it, only slower).
  bool sag_memo = true;
  // The split and collapse passes of the rounds remember the edges they
  // refused, and refuse them again, unplanned and for the same reason, while
  // nothing changed within a ring of either end (a cache: a plan depends on
  // the two fans and the rings around them only, so the output is the same
  // without it, only slower: the late rounds of a coarsening refuse the
  // same few thousand edges again and again).
  bool refusal_memo = true;
  // run() measures the state (histogram, quality) after every pass; off:
  // only after the last pass of each round and the final pass (a sweep over
  // the mesh saved per pass; step() always measures).
  bool measure_every_pass = true;
  // Split passes work in generations: the edges longer than lmax at the
  // start, longest first, then a swap pass around the new vertices, again
  // with the long edges left. On a coarse mesh this refines like 1:4
  // subdivisions; splitting longest-first with local swaps after each split
  // and the new long edges in the same heap also splits the long medians of
  // half-split triangles and overshoots (isofine with midpoint splits: 313k
  // vertices after the first pass, 218k at the end, 96k collapses to get
  // there). A generation that splits under few_splits_share of the vertices
  // is the last: the few long edges left are split the classic way.
  bool split_by_generation = true;
  int max_split_generations = 64;
  double few_splits_share = 0.01;
  // Guards against a metric the surface cannot carry (edges longer than its
  // curvature allows in one direction, much shorter in the other: the
  // refinement runs away from the metric's prediction). A round that ends
  // with more than max_round_vertices vertices, or a pass that grows the
  // mesh past max_vertices (checked with the interrupt, every 256
  // operations: a split pass overshoots the round's count before its
  // collapses, so this one is the larger), is reported `over_limit` and
  // the schedule ends there. 0: no limit. adapt() sets both from
  // AdaptOptions::max_growth (set_growth_limits).
  int max_round_vertices = 0;
  int max_vertices = 0;
  // The share of the mesh the metric predicts that this mesh is: the
  // arrays are reserved for that share (a region of run_in_regions holds
  // part of the output; a reservation many times its size would put each
  // of its small arrays on huge pages of 2 MB).
  double reserve_share = 1.0;
  // The output's distance to the input: at the end of the final pass, the
  // edges whose midpoint and the triangles whose centroid lie farther from
  // T_G (the points bench/surfdist measures) than distance_bound (absolute:
  // the chordal deviation --hausd as a bound; 0: none) or than
  // relative_distance_bound times the size the metric asks for along the
  // edge (its length over its metric length; for a triangle, the mean over
  // its edges; 0: none), whichever is smaller, are split onto the input
  // (can_split_onto_input; a triangle at its longest edge), the farthest
  // first, in at most bound_sweeps sweeps over the mesh. The relative bound
  // catches the chords that cut across what the size cannot follow (a
  // rounded edge of radius below the size) when no hausd is given; off by
  // default (0.25 lowers the band of a coarse smooth input such as hemi.mesh
  // on its G1 surface from 97% to 79%).
  // The relative bound is measured beyond the smooth surface's own
  // deviation from T_G at the point (InputBound's natural sagitta). At
  // most max_bound_split_share x the vertices are split so.
  double distance_bound = 0;
  double relative_distance_bound = 0;
  // Sharp edges kept sharp (ours, not the report's): at the end of the
  // final pass, a feature edge of T_1 between two triangles that keeps less
  // than crease_keep of the dihedral angle of the input edge under it (the
  // triangles beside it reach past a crease narrower than the size, or the
  // smooth surface rounds a crease of a coarse input) has its triangle that
  // turns farthest from the input's facet on its side split at its longer
  // other edge, onto the input: that apex comes closer to the crease.
  // crease_sweeps sweeps; no edge shorter than op.lmin is split so, and at
  // most max_bound_split_share x the vertices (0 keep: off).
  double crease_keep = 0.6;
  int crease_sweeps = 4;
  double max_bound_split_share = 0.25;
  int bound_sweeps = 8;
  double bound_split_turn_deg = 80;
};

enum class PassKind { Split, Collapse, Swap, Smooth, Final };
std::string_view pass_name(PassKind k);

inline constexpr int kRejectionCount = static_cast<int>(Rejection::kCount);

// What one pass did.
struct PassReport {
  PassKind kind = PassKind::Split;
  int round = 0;  // the schedule's round when the pass ran (Schedule::round): 0 for the initial swaps
  int splits = 0, collapses = 0, swaps = 0, moves = 0;
  int removed_vertices = 0;  // final pass: interior vertices of valence < 4
  // Final pass with RemeshOptions::distance_bound: the splits that brought
  // points back within it (counted in `splits` too), and the edge midpoints
  // and triangle centroids still beyond it when the pass ended.
  int bound_splits = 0;
  int beyond_bound = 0;
  // Final pass: the splits that brought triangles closer to a crease of the
  // input (RemeshOptions::crease_keep; counted in `splits` too).
  int crease_splits = 0;
  int split_unprojected = 0;  // splits at the straight midpoint (projection refused)
  // Refusals per filter (indexed by Rejection), all operators together;
  // what counts as a refusal: refuse() in remesher.cpp.
  std::array<int, kRejectionCount> rejected{};
  // Of those, the refusals the refusal memo answered without a plan
  // (RemeshOptions::refusal_memo).
  int remembered_refusals = 0;
  // State after the pass: sizes, edge lengths in the metric (bins of
  // kLengthBins: 0, 0.3, 0.6, 0.71, 0.9, 1.3, 1.41, 2, 5), quality eq. 17.
  int vertices = 0, triangles = 0, edges = 0;
  std::array<int, kLengthBins.size()> histogram{};
  double in_band_share = 0;
  double length_min = 0, length_max = 0;
  double q_min = 0, q_mean = 0;
  double seconds = 0;
  // False for the passes run() did not measure (RemeshOptions::
  // measure_every_pass off): of the state, only vertices and triangles are set.
  bool measured = true;
  // The pass stopped early (Remesher::set_interrupt): the mesh is valid, the
  // pass is not complete.
  bool interrupted = false;
  // The mesh grew past RemeshOptions::max_vertices during the pass (which
  // stopped: interrupted is set too) or past max_round_vertices at the end
  // of the round: the mesh is valid, the schedule is done.
  bool over_limit = false;
  // Vertex slots created, kept or moved by the pass (the elements it
  // touched), each once, in the order of their first change; empty when
  // RemeshOptions::record_touched is off.
  std::vector<int> touched;
  // run_in_regions (remesh/parallel.h): the region the pass ran on, the
  // band around the regions' borders being the last (-1: the whole mesh).
  int region = -1;
  int changes() const { return splits + collapses + swaps + moves + removed_vertices; }
};

// The state after `from` (sizes, edge lengths, quality) into `to`.
void copy_state(const PassReport& from, PassReport& to);

// Where run()'s schedule stands: initial swaps; per relaxation stage
// (Remark 6), rounds (Remesher::round_plan: split, collapse, swap,
// smoothing) until a round splits and collapses at most converged_share of
// the vertices (or max_rounds rounds); the final optimisation. The loop
// levels, outermost first: cycle (adapt.h, outside the remesher) > stage >
// round > pass > generation (split passes only). A value, so that a caller
// stepping the schedule (the editor) can keep it beside a copy of the mesh
// and resume from there (Remesher::set_schedule).
struct Schedule {
  enum class Phase { Initial, Round, Final, Done };
  Phase phase = Phase::Initial;
  int stage = 0;               // relaxation stage, 0 .. relaxation_stages
  bool stage_started = false;  // the stage's metric is set
  int round = 0;               // rounds so far, all stages (PassReport::round)
  int stage_rounds = 0;        // rounds of this stage
  int pass = 0;                // next pass of the round: an index into Remesher::round_plan()
  int round_changes = 0;       // splits + collapses of the round so far
  int round_splits = 0;        // ... of which splits
  // The rounds of the stage that ended (the stagnation test).
  std::vector<double> round_band;   // in-band share at the end of the round
  std::vector<int> round_change;    // splits + collapses
};

class Remesher {
 public:
  // The adapted mesh must outlive the remesher.
  explicit Remesher(AdaptedMesh& mesh, const RemeshOptions& options = {});

  // One named pass; returns what it did and the state after it.
  PassReport step(PassKind kind);
  // Section 6's loop (the Schedule above) from where it stands to its end,
  // or until `stop` returns true after a pass (advance() resumes it).
  std::vector<PassReport> run(const std::function<void(const PassReport&)>& progress = {},
                              const std::function<bool()>& stop = {});
  // run()'s schedule one pass at a time: the next pass, performed by
  // advance() (pre: !finished()). run() = advance() until finished, with
  // `progress` after each pass and a `stop` check between passes.
  PassKind next_pass() const;
  PassReport advance();
  // The passes of one round (section 6, steps 1-2, then sections 5.4-5.5 over
  // the mesh): split, collapse, swap, then smoothing_passes smoothings.
  std::vector<PassKind> round_plan() const;
  bool finished() const { return schedule_.phase == Schedule::Phase::Done; }
  const Schedule& schedule() const { return schedule_; }
  // Resumes the schedule at `s` (the mesh being the one `s` was taken with):
  // the stage's relaxed metric is set again, every vertex is visited anew.
  void set_schedule(const Schedule& s);
  // A check polled within the passes (every 256 operations or vertices):
  // when it returns true the pass ends after the operation in progress,
  // reported `interrupted`; advance() then leaves the schedule at that pass.
  // For an interactive caller whose user pauses a long pass. The same poll
  // ends a pass, and the schedule, when the mesh grows past
  // RemeshOptions::max_vertices (PassReport::over_limit).
  void set_interrupt(std::function<bool()> check) { interrupt_ = std::move(check); }

  // The state of the mesh now (histogram, quality) without changing it.
  PassReport measure() const;
  const RemeshOptions& options() const { return options_; }
  // Remark 5: true if edge a-b was created by a modification of another kind
  // than `undoing` among the last cache_size ones (the passes refuse to undo it).
  bool in_cache(Vertex a, Vertex b, PassKind undoing) const;
  AdaptedMesh& adapted() { return mesh_; }
  // Section 6, step 2: the swaps around v after a split or collapse, tried
  // on its link edges while they improve (each swap brings two new link
  // edges); returns the count. Leaves no link edge of v that can_swap
  // accepts, unless max_local_swap_visits swaps per starting link edge ran out.
  int local_swaps(Vertex v, PassReport& r);

 private:
  struct Modification {
    PassKind kind;
    std::vector<std::array<int, 2>> created;  // edges created (sorted vertex pairs)
  };
  // step(), taking the state from `previous` (the report of the pass just
  // before, null if none) when the pass changed nothing; without `measure`,
  // only the sizes.
  PassReport step(PassKind kind, const PassReport* previous, bool measure);
  // Keeps the state of r (the mesh's now) for the next pass of the schedule.
  PassReport record_state(PassReport r);
  PassReport advance_schedule();
  // The report of the schedule's last pass, if it still holds the mesh's state.
  const PassReport* previous() const { return has_last_ ? &last_ : nullptr; }
  // Remark 6: sets stage `stage`'s relaxed metric (t = (stage + 1) / (stages + 1)).
  void set_stage_metric(int stage);
  // The first pass of a stage: its metric is set, every vertex is visited anew.
  void begin_stage();
  // After the last pass of a round: the next round, the next stage or the
  // final pass, by the round's changes (converged_share) and max_rounds.
  void end_round();
  // The stage's last rounds stagnate (RemeshOptions::stagnation_rounds).
  bool stagnated() const;
  // The round's splits and collapses balance (RemeshOptions::balance_share).
  bool balanced() const;
  // Polls the interrupt check (every 256 calls); sticky within a pass.
  bool interrupted(PassReport& r);
  void split_pass(PassReport& r);
  void collapse_pass(PassReport& r);
  // Section 6, step 1 (with Remark 5) for the edges outside [lmin, lmax] on
  // one side (Edges: SplitEdges or CollapseEdges in remesher.cpp): a heap of
  // them, the farthest from the band first; each popped edge is checked
  // again, refused if in the cache, planned (can_split / can_collapse) and
  // applied; when follow_new_edges, the edges of the new vertex still
  // outside join the heap. Returns the number of operations applied.
  template <class Edges>
  int priority_pass(PassReport& r, bool follow_new_edges);
  // The apply step of priority_pass, with its bookkeeping (cache, touched,
  // and step 2's local swaps when following the new edges); returns the
  // vertex whose edges are followed (invalid: none).
  Vertex apply(PassReport& r, Corner c, const SplitPlan& plan, bool follow_new_edges);
  Vertex apply(PassReport& r, Corner c, const CollapsePlan& plan, bool follow_new_edges);
  void swap_pass(PassReport& r);
  // Visits the marked vertices (all of them: visit_below > 1) or those of
  // them with a triangle of quality below visit_below in their fan;
  // `keep_lmin`: OperatorOptions::move_keeps_lmin.
  void smooth_pass(PassReport& r, double visit_below = INFINITY, bool keep_lmin = false);
  void final_pass(PassReport& r);
  // The final pass's smoothing passes over the marked vertices (section 6,
  // "8-10 times"): the first full_passes visit them all, the others those
  // with a triangle below final_visit_quality in their fan; until one moves nothing.
  void final_smoothing(PassReport& r, int full_passes);
  // The vertices of the triangles below `quality` with their triangle's
  // quality, the worst first (a vertex once per such triangle).
  std::vector<std::pair<double, int>> vertices_of_triangles_below(double quality) const;
  // The final pass's repair (RemeshOptions::repair_quality); returns the
  // count of vertices removed.
  int repair_poor_fans(PassReport& r);
  // The final pass's relocation of the worst triangles' vertices
  // (RemeshOptions::relocate_quality); returns the count of moves.
  int relocate_worst(PassReport& r);
  // The end of the final pass with a distance bound (RemeshOptions::
  // distance_bound): the sweeps of splits onto the input.
  void bound_distance(PassReport& r);
  // The end of the final pass: the sweeps of RemeshOptions::crease_keep.
  void keep_creases(PassReport& r);
  // The edge (apex, end) to split so that the feature edge of corner c keeps
  // its crease; {-1, -1} when it keeps it already or cannot be helped.
  std::array<int, 2> crease_spoke(Corner c);
  // An edge to split for the bound: its point's distance to T_G and the
  // bound there. For a triangle's centroid, a-b is its longest edge and c
  // its third vertex (the other edges are tried when that split is
  // refused); -1 for an edge's midpoint.
  struct BeyondBound {
    double distance, bound;
    int a, b;
    int c = -1;
  };
  // The edges to split for the bound, the farthest first: those whose
  // midpoint, and the longest of the triangles whose centroid, lies beyond it;
  // over the whole mesh, or over the triangles around `around` (the
  // vertices a sweep added: nothing else changed).
  std::vector<BeyondBound> edges_beyond_bound(const std::vector<Vertex>* around = nullptr);
  // Final pass: swaps of interior edges that bring the four vertices'
  // valences closer to 6, where the metric is isotropic and alike at the
  // four, accepted by can_swap with the worst quality allowed to drop to
  // valence_swap_gain of the old one. Returns the count.
  int valence_swaps(PassReport& r);
  void remember(PassKind kind, Vertex v);
  // The mesh's state into r (counts, lengths, qualities), on the threads
  // of parallel_chunks when `parallel` (the same figures).
  void fill_state(PassReport& r, bool parallel) const;
  // Records v as touched by the pass and marks it and its neighbours for the
  // next swap and smoothing passes (which only visit marked vertices: the
  // first ones, and the final optimisation, visit all).
  void touch(PassReport& r, Vertex v);
  void record_touched(PassReport& r, Vertex v);
  // Marks v for the next swap and smoothing passes and stamps it.
  void mark(Vertex v);
  // Marks v for the next swap and smoothing passes only.
  void activate(Vertex v);
  // The vertex changed (the sag memo of its edges is stale), without marking
  // it for the next swap and smoothing passes: forget_triangle over its fan.
  void stamp(Vertex v);
  // The sag memo of t's three corner slots cleared (t rewritten by a swap:
  // its vertices stay, the edges its slots name change).
  void forget_triangle(Triangle t);
  void mark_all();
  // edge_sags_off_input for the edge named by corner c, remembered for the
  // edges found not to sag: such an edge is not measured again until one of
  // its ends is stamped (moved, created, or its fan rewritten). The memo is
  // one bit per corner slot (at the edge's lower corner), and a stamp of v
  // clears the bits of every corner of v's fan: the edges at v and the slots
  // of the triangles around it. A split's and a collapse's triangles all lie
  // in the fan of the vertex it stamps (the new vertex, the survivor), and a
  // swap forgets its two triangles, so a slot rewritten with another edge
  // starts without a bit.
  bool edge_sags(Corner c);
  // Reserves the mesh arrays for the size the target metric asks for.
  void reserve_for_metric();
  bool reserved_ = false;

  AdaptedMesh& mesh_;
  RemeshOptions options_;
  std::deque<Modification> cache_;
  int smoothing_done_ = 0;
  std::vector<std::uint8_t> swap_active_, smooth_active_;  // per vertex slot
  std::vector<std::array<int, 3>> swap_retries_;  // swap_pass: the edges queued again (kept for the next pass)
  Schedule schedule_;
  PassReport last_;  // the state after the last pass of the schedule (valid if has_last_)
  bool has_last_ = false;
  std::function<bool()> interrupt_;
  long long interrupt_polls_ = 0;
  EdgeQueueStorage queue_;  // split / collapse passes
  std::vector<std::uint8_t> touched_mark_;  // per vertex slot: in the pass's touched list
  // Per corner slot, a bit: the edge it names (at its lower corner) was
  // found not to sag and neither end was stamped since (edge_sags).
  std::vector<std::uint64_t> flat_bits_;

  // The refusal memo (RemeshOptions::refusal_memo). Every change of a
  // vertex's position, metric or fan sets its clock to the next tick
  // (note_change); a refusal is remembered with the tick it was planned at,
  // and holds while no vertex of the edge's ends and rings has a later one.
  struct Refusal {
    std::uint64_t tick = 0;
    Rejection why = Rejection::None;
  };
  struct RefusalMemo {
    FlatMap64<Refusal> current, previous;  // this pass's refusals, the last pass's (by edge_key)
  };
  void note_change(Vertex v);
  // The refusal remembered for edge (a, b) when it still holds (kept for the
  // pass after this one), else nullptr.
  const Refusal* remembered_refusal(RefusalMemo& memo, Vertex a, Vertex b);
  // A new pass of that kind: the last pass's refusals become the ones to consult.
  void start_refusal_pass(RefusalMemo& memo);
  void forget_refusals();
  std::uint64_t tick_ = 0;
  std::vector<std::uint64_t> changed_at_;  // per vertex slot: the tick of its last change
  RefusalMemo split_refusals_, collapse_refusals_;
  bool memo_on_ = false;  // the pass running is a round's (step() from the schedule)
};

}  // namespace anisurf::remesh
