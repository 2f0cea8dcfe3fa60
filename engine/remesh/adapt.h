// The adaptation pipeline, in memory, for every front end (the command line,
// the editor, scripts, library callers): features of T_G -> the metric of
// T_0 (metric/recipe.h: source, bounds, hausd, gradation) -> the surface T_G
// (G1 or polyhedral) -> T_1 located on T_G and T_0 -> the remeshing loop of
// the report's section 6 -> T_1 with its metric and T_0's solution fields
// interpolated (section 6). With cycles > 1 the output becomes the next T_0
// and the recipe's metric is derived again on it (the adapt -> recompute ->
// adapt loop of section 7.1), T_G staying the input's surface.
//
//   remesh::AdaptOptions o;
//   o.metric.source = MetricRecipe::Source::Hessian;
//   o.metric.expression = "100*x^2";
//   o.metric.error = 0.01;
//   o.cycles = 6;
//   remesh::AdaptResult r = remesh::adapt({std::move(mesh)}, o);
#pragma once
#include <functional>
#include <future>
#include <optional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "geometry/features.h"
#include "metric/recipe.h"
#include "remesh/remesher.h"

namespace anisurf::remesh {

enum class SurfaceKind {
  G1,          // the G1 Bezier surface at the parameters of the polyhedral projection (section 3)
  G1Closest,   // the closest point of the G1 surface (slower)
  Polyhedral,  // T_G's triangles
  Auto,        // G1, or Polyhedral where T_G is fine for the metric (resolve_surface)
};

// The remeshing options of every front end: the report's, with lmin 0.72 so
// that the edges end in [1/sqrt2, sqrt2], the band Mmg and the evaluators
// measure (the report's lmin 0.6 counts edges in [0.6, 0.707) as adapted).
RemeshOptions band_remesh_options();

struct AdaptOptions {
  MetricRecipe metric;
  FeatureOptions features;
  RemeshOptions remesh = band_remesh_options();
  // How T_0's metric is read between its vertices: the size linear follows a
  // sharp change between T_0's vertices best (sphere20k_band: q min 0.043 ->
  // 0.252 against the coefficients linear).
  MetricInterpolation interpolation = MetricInterpolation::LinearSize;
  LengthFormula length = LengthFormula::LinearMetric;  // eq. 6
  SurfaceKind surface = SurfaceKind::Auto;
  // Adaptation cycles (section 7.1): each adapted mesh is the next T_0, its
  // metric derived again from the recipe. They stop early at a fixed point:
  // a cycle whose vertex count is within `fixed_point` (relative) of the
  // previous cycle's.
  int cycles = 1;
  double fixed_point = 0.02;
  // A metric whose predicted output would need more memory than this is
  // refused before any pass, with the prediction in the message (bytes;
  // 0: the machine's physical memory). The estimate is
  // kBytesPerPredictedVertex per predicted vertex.
  double memory_limit = 0;
  // A metric the surface cannot carry (far longer edges than its curvature
  // allows in one direction, much shorter ones in the other) makes the
  // refinement run away from the prediction: the adaptation stops with
  // AdaptationStopped when a round ends with more than max_growth x the
  // predicted vertices + T_0's vertices, or a pass grows T_1 past
  // kPassOvershoot times that (set_growth_limits). 0: no limit.
  double max_growth = 8;
  // How far from the input the smooth surface may put vertices (its hausd
  // is the recipe's: use input_bound_of).
  InputBound input_bound;
  // Geometry protection: a metric from a field, a tensor expression or a
  // Hessian (protects_geometry) with no chordal deviation of its own
  // (metric.hausd 0) is intersected with the curvature metric of hausd =
  // protect_fraction x the bounding-box diagonal of T_G, which is then the
  // output's distance bound too (Mmg's default -hausd, relative to the
  // model). 0: off (`--hausd 0`), for size sources too.
  double protect_fraction = 1e-3;
  // Geometry protection of a size source (--size, iso; size_protected) with
  // no hausd: the size is met as asked, and the final pass splits onto the
  // input the edge midpoints and triangle centroids farther from it than
  // protect_size_fraction x the size there, beyond the smooth surface's own
  // sagitta (RemeshOptions::relative_distance_bound): the chords across a
  // feature narrower than the size, such as a rounded tip or a small
  // fillet. 0: off.
  double protect_size_fraction = 0.1;
  // Threads for the remeshing loop (remesh/parallel.h: regions remeshed at
  // once; the output depends on the count, not on the threads' timing) and
  // for the setup loops (thread_limit). 0: one per hardware thread.
  int threads = 0;
};

// True if a metric of `recipe`'s source gets the geometry protection
// (AdaptOptions::protect_fraction) when it has no hausd.
bool protects_geometry(const MetricRecipe& recipe);
// True if a metric of `recipe`'s source is a size (--size, iso) whose
// protection is the relative distance bound (AdaptOptions::protect_size_fraction).
bool size_protected(const MetricRecipe& recipe);
// The relative distance bound the options give the final pass: the
// remeshing options' own, or the size source's protection, or 0.
double size_protection_of(const AdaptOptions& options);
// The chordal deviation the adaptation of T_G (bounding-box diagonal
// `diagonal`) runs with: the recipe's, or the protection's, or 0.
double effective_hausd(const MetricRecipe& recipe, double protect_fraction, double diagonal);
inline double effective_hausd(const AdaptOptions& options, double diagonal) {
  return effective_hausd(options.metric, options.protect_fraction, diagonal);
}

// options.input_bound with the recipe's chordal deviation hausd.
InputBound input_bound_of(const AdaptOptions& options);
// options.remesh with the recipe's chordal deviation hausd (if any) as the
// cap of the feature curves' and the surface's sag (OperatorOptions::
// curve_max_sag, surface_max_sag).
RemeshOptions remesh_options_of(const AdaptOptions& options);

// The vertex count past which a cycle stops: max_growth x predicted + the
// vertices of T_0 (0: no limit, max_growth 0).
int vertex_limit(double max_growth, double predicted_vertices, int t0_vertices);

// How far a pass may take the mesh past the round's limit: a split pass
// refines everything before the collapses of its round thin it out (8.4 x
// the final count seen on a 121-vertex grid under a Hessian metric).
inline constexpr double kPassOvershoot = 8;

// RemeshOptions::max_round_vertices and max_vertices from max_growth, the
// metric's predicted vertices and T_0's vertex count.
void set_growth_limits(RemeshOptions& options, double max_growth, double predicted_vertices, int t0_vertices);

// Thrown by adapt() when a cycle's mesh grows past its vertex_limit: the
// message says how far, against what prediction, and which filters refused
// the operations that would have met the metric.
class AdaptationStopped : public Error {
 public:
  using Error::Error;
};

// The message of AdaptationStopped for the passes of a cycle whose last one
// went over its limit (options: the limits it ran with).
std::string over_limit_message(const std::vector<PassReport>& passes, const RemeshOptions& options,
                               double predicted_vertices, int t0_vertices, double max_growth);

// Peak memory per output vertex of an adaptation, with a margin: measured
// 150-170 bytes per output triangle (2 per vertex) on the large bench cases.
inline constexpr double kBytesPerPredictedVertex = 400;

// What an adaptation starts from.
struct AdaptInput {
  AdaptInput() = default;
  // T_0 alone (no file numbering, T_G = T_0).
  AdaptInput(SurfaceMesh t0) : mesh(std::move(t0)) {}  // NOLINT: implicit, remesh::adapt({mesh}, o)

  // T_0 (and T_G unless `geometry`): positions, tags, references and the
  // solution fields to interpolate (every field of the mesh).
  SurfaceMesh mesh;
  // File numbering of the vertex slots (BuildReport::vertex_origin), for
  // error messages; may be empty.
  std::vector<int> vertex_origin;
  // T_G when it is another mesh of the surface (e.g. a finer one); must
  // outlive the call.
  const SurfaceMesh* geometry = nullptr;
};

// One cycle: its metric, the passes, the state before and after.
struct CycleReport {
  int cycle = 1;
  std::string metric;  // MetricResult::description
  double complexity = 0;
  double predicted_vertices = 0;
  int scaling_steps = 0;
  PassReport initial, final;  // measured states of T_1 before and after the passes
  int inverted_before = 0, inverted_after = 0;
  std::vector<PassReport> passes;
  // Hessian sources: the estimated interpolation error of the output
  // (estimated_interpolation_error with the recipe's norm); NaN otherwise.
  double error_estimate = std::numeric_limits<double>::quiet_NaN();
  double setup_seconds = 0, remesh_seconds = 0;
};

struct AdaptResult {
  SurfaceMesh mesh;   // T_1, compact, with T_0's solution fields interpolated
  MetricField metric; // the target metric at T_1's vertices
  std::vector<CycleReport> cycles;
  bool fixed_point = false;  // the cycles stopped at a fixed point
  FeatureReport features;    // of T_G
  std::string surface;       // the name of the surface T_1 lies on
  // The hausd of the geometry protection (AdaptOptions::protect_fraction)
  // the adaptation ran with; 0: none (a hausd was given, or no protection).
  double protection_hausd = 0;
  // The relative distance bound of a size source's protection
  // (AdaptOptions::protect_size_fraction); 0: none.
  double size_protection = 0;
  double seconds = 0;
};

// Hooks for progress display; every one may be empty.
struct AdaptCallbacks {
  std::function<void(const std::string& step, double seconds)> setup_step;  // a setup step ended
  std::function<void(const CycleReport&)> cycle_started;  // metric built, T_1 located
  std::function<void(const PassReport&)> pass;            // after every pass
  std::function<void(const CycleReport&)> cycle_ended;
};

// Checks the options without a mesh; throws Error naming the bad value.
void check_options(const AdaptOptions& options);

// The surface T_1 is kept on, over `tg` (features tagged; outlives it;
// Auto: G1). `locator`, when valid, yields tg's locator being built on
// another thread: the frames and patches are computed meanwhile, and it is
// waited for last.
std::unique_ptr<GeometrySurface> make_geometry(const SurfaceMesh& tg, SurfaceKind kind,
                                               std::future<std::unique_ptr<Locator>> locator = {});
// Auto resolved for T_G, the metric at its vertices (T_G is T_0; empty
// `metric`: G1) and the chordal deviation hausd (0: none): Polyhedral when
// the metric refines no edge of T_G (each at most the report's lmax 1.4
// long in it, which the split pass leaves: a coarsening, whose vertices are
// mostly T_G's own; a refinement is rebuilt on the smooth surface) and the
// G1 surface would lie close to T_G's facets at every edge e of T_G: its
// sagitta |e| theta / 8 (theta: the dihedral angle at e, or on a feature
// curve the curve's turn at its ends) at most kFineGeometrySag times the
// size the metric asks along e, and at most kFineGeometryHausd x hausd.
// InputBound keeps a vertex on the G1 surface within 0.2 hausd of T_G
// anyway: where the facets lie within half the chordal deviation of the
// smooth surface, the output on them cannot be told apart from the one on
// G1 at the deviation asked for. The patches, frames and their memory (330
// bytes a triangle) would then change nothing measurable (a 500k-triangle
// sphere coarsened to 7k triangles: surface setup 9.5 -> 2.4 s, peak memory
// 360 -> 203 MB). Other kinds as given.
inline constexpr double kFineGeometrySag = 0.05;
inline constexpr double kFineGeometryHausd = 0.5;
SurfaceKind resolve_surface(SurfaceKind kind, const SurfaceMesh& tg, const MetricField& metric, double hausd = 0);
// The kind resolve_surface will return for T_G, when it is known before the
// metric: a kind other than Auto; G1 for a separate geometry, an empty T_G
// or an edge whose sagitta exceeds kFineGeometryHausd x hausd; nullopt
// otherwise (the metric decides).
std::optional<SurfaceKind> surface_before_metric(SurfaceKind kind, const SurfaceMesh& tg, double hausd,
                                                 bool separate_geometry);

// The control space of T_0 with `metric` as the options say (interpolation);
// `complexity`: the metric's on T_0 when known (NaN: computed).
std::unique_ptr<ControlSpace> make_control(const SurfaceMesh& t0, MetricField metric, bool t0_is_geometry,
                                           const AdaptOptions& options,
                                           double complexity = std::numeric_limits<double>::quiet_NaN());

// The whole pipeline; see the top of this file. Throws Error (MetricError,
// ExpressionError ...) before changing anything on bad options or a metric
// that cannot be built.
// The options are taken by value: a given metric (MetricRecipe::given) is
// moved through, not copied (std::move them when not needed after).
AdaptResult adapt(AdaptInput input, AdaptOptions options, const AdaptCallbacks& callbacks = {});

}  // namespace anisurf::remesh
