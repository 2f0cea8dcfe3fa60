#include "remesh/adapt.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <vector>
#include <string>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>

#include "core/error.h"
#include "core/huge_pages.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "geometry/parallel_chunks.h"
#include "metric/surface_metric.h"
#include "remesh/parallel.h"

namespace anisurf::remesh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Times the setup steps and reports each to the callback.
class StepTimer {
 public:
  explicit StepTimer(const AdaptCallbacks& cb) : cb_(cb), t_(Clock::now()) {}
  void done(const char* step) {
    const double s = seconds_since(t_);
    if (cb_.setup_step) cb_.setup_step(step, s);
    total_ += s;
    t_ = Clock::now();
  }
  double total() const { return total_; }
  void restart() {
    total_ = 0;
    t_ = Clock::now();
  }

 private:
  const AdaptCallbacks& cb_;
  Clock::time_point t_;
  double total_ = 0;
};

// The target metric stored on T_1's vertices by the data-transfer hook,
// moved out of the mesh; the remesher's other per-vertex data (hints,
// normals) go too: T_1 leaves with its positions, tags and fields.
MetricField take_adapted_metric(SurfaceMesh& t1) {
  // The other working properties go first: the field is built beside the
  // mesh at its smallest.
  for (const std::string& name : t1.vertex_properties().names())
    if (name.rfind("remesh:", 0) == 0 && name != kMetricProperty && name != kIsotropicMetricProperty)
      t1.vertex_properties().remove(name);
  MetricField m;
  if (stores_isotropic_metric(t1)) {
    m.reserve(static_cast<std::size_t>(t1.vertex_capacity()));
    for (double lambda : t1.get_vertex_property<double>(kIsotropicMetricProperty).vector())
      m.push_back(SymTensor3::identity(lambda));
  } else {
    // The packed factors' pages go back as they are read: the six doubles
    // a vertex grow beside what is left of them, not beside all.
    const std::vector<PackedMetric>& packed = t1.get_vertex_property<PackedMetric>(kMetricProperty).vector();
    m.reserve(packed.size());
    // Each chunk's release starts where the previous one's whole pages ended.
    constexpr std::size_t kChunk = 1 << 14, kPage = 4096;
    const auto base = reinterpret_cast<std::uintptr_t>(packed.data());
    std::uintptr_t released = base;
    for (std::size_t begin = 0; begin < packed.size(); begin += kChunk) {
      const std::size_t end = std::min(packed.size(), begin + kChunk);
      for (std::size_t i = begin; i < end; ++i) m.push_back(packed[i].unpack());
      const std::uintptr_t upto = base + end * sizeof(PackedMetric);
      release_pages(reinterpret_cast<const void*>(released), upto - released);
      released = std::max(released, upto & ~(kPage - 1));
    }
  }
  t1.vertex_properties().remove(kIsotropicMetricProperty);
  t1.vertex_properties().remove(kMetricProperty);
  m.resize(static_cast<std::size_t>(t1.vertex_capacity()), SymTensor3::identity(1.0));
  return m;
}

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

// Refuses a metric whose predicted output cannot fit in memory.
void check_predicted_size(double predicted_vertices, double limit) {
  if (!(limit > 0)) limit = physical_memory_bytes();
  const double bytes = predicted_vertices * kBytesPerPredictedVertex;
  if (!(limit > 0) || (std::isfinite(bytes) && bytes <= limit)) return;
  char msg[320];
  std::snprintf(msg, sizeof msg,
                "the metric predicts %.3g vertices, about %.3g GB at %.0f bytes per vertex, over the %.3g GB "
                "available: refused (check the metric's scale, or bound it with hmin)",
                predicted_vertices, bytes / 1e9, kBytesPerPredictedVertex, limit / 1e9);
  throw Error(msg);
}

// The filters that refused most often over `passes`, with their counts:
// "deviation 5123, quality 310".
std::string main_refusals(const std::vector<PassReport>& passes, int how_many) {
  std::array<long long, kRejectionCount> total{};
  for (const PassReport& p : passes)
    for (int k = 0; k < kRejectionCount; ++k) total[static_cast<std::size_t>(k)] += p.rejected[static_cast<std::size_t>(k)];
  std::vector<int> order;
  for (int k = 1; k < kRejectionCount; ++k)
    if (total[static_cast<std::size_t>(k)] > 0) order.push_back(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return total[static_cast<std::size_t>(a)] > total[static_cast<std::size_t>(b)];
  });
  std::string out;
  for (std::size_t i = 0; i < order.size() && static_cast<int>(i) < how_many; ++i) {
    if (!out.empty()) out += ", ";
    out += std::string(rejection_name(static_cast<Rejection>(order[i]))) + " " +
           std::to_string(total[static_cast<std::size_t>(order[i])]);
  }
  return out.empty() ? "none" : out;
}

bool is_fixed_point(const std::vector<CycleReport>& cycles, double tolerance) {
  if (cycles.size() < 2) return false;
  const double a = cycles[cycles.size() - 2].final.vertices, b = cycles.back().final.vertices;
  return std::abs(b - a) <= tolerance * a;
}

}  // namespace

int vertex_limit(double max_growth, double predicted_vertices, int t0_vertices) {
  if (!(max_growth > 0) || !std::isfinite(predicted_vertices)) return 0;
  const double limit = max_growth * predicted_vertices + t0_vertices;
  return limit < static_cast<double>(std::numeric_limits<int>::max()) ? static_cast<int>(std::ceil(limit)) : 0;
}

void set_growth_limits(RemeshOptions& options, double max_growth, double predicted_vertices, int t0_vertices) {
  options.max_round_vertices = vertex_limit(max_growth, predicted_vertices, t0_vertices);
  options.max_vertices = vertex_limit(kPassOvershoot * max_growth, predicted_vertices, t0_vertices);
}

std::string over_limit_message(const std::vector<PassReport>& passes, const RemeshOptions& options,
                               double predicted_vertices, int t0_vertices, double max_growth) {
  const PassReport* last = passes.empty() ? nullptr : &passes.back();
  const bool in_pass = last && last->interrupted;
  const int limit = in_pass ? options.max_vertices : options.max_round_vertices;
  const double factor = in_pass ? kPassOvershoot * max_growth : max_growth;
  char head[480];
  std::snprintf(head, sizeof head,
                "adaptation stopped %s round %d: the mesh %s %d vertices, past %d = %g x the %.0f vertices the "
                "metric predicts + the %d of the input: the surface cannot carry this metric (edges the metric "
                "wants long are refused, their neighbours short: ",
                in_pass ? "in" : "after", last ? last->round : 0, in_pass ? "grew to" : "kept",
                last ? last->vertices : 0, limit, factor, predicted_vertices, t0_vertices);
  return std::string(head) + "refusals " + main_refusals(passes, 3) +
         "). Lower the metric's anisotropy where the surface is curved (--max-aniso, --hmax, or intersect it "
         "with a curvature metric: --hausd), or raise the growth limit (--max-growth; 0: none).";
}


RemeshOptions band_remesh_options() {
  RemeshOptions o;
  o.op.lmin = 0.72;
  return o;
}

InputBound input_bound_of(const AdaptOptions& options) {
  InputBound b = options.input_bound;
  if (options.metric.hausd > 0) b.hausd = options.metric.hausd;
  return b;
}

RemeshOptions remesh_options_of(const AdaptOptions& options) {
  RemeshOptions r = options.remesh;
  // Vertices lie within hausd / 5 of the input (InputBound), so that a
  // segment's midpoint within 0.7 hausd of it keeps the triangles' centroids
  // (4/3 of their edges' sag on a sphere) within 1.2 hausd.
  const double chordal = 0.7 * options.metric.hausd;
  if (chordal > 0 && !(r.op.curve_max_sag > 0)) r.op.curve_max_sag = chordal;
  if (chordal > 0 && !(r.op.surface_max_sag > 0)) r.op.surface_max_sag = chordal;
  // What the operators' sag tests leave beyond hausd (splits refused across
  // an input's creases, smoothing in the final pass) the final pass splits
  // onto the input.
  if (options.metric.hausd > 0 && !(r.distance_bound > 0)) r.distance_bound = options.metric.hausd;
  r.relative_distance_bound = size_protection_of(options);
  return r;
}

bool size_protected(const MetricRecipe& recipe) {
  return recipe.source == MetricRecipe::Source::Size || recipe.source == MetricRecipe::Source::Iso;
}

double size_protection_of(const AdaptOptions& options) {
  if (options.remesh.relative_distance_bound > 0) return options.remesh.relative_distance_bound;
  if (options.metric.hausd > 0 || !(options.protect_fraction > 0) || !size_protected(options.metric)) return 0;
  return options.protect_size_fraction;
}

bool protects_geometry(const MetricRecipe& recipe) {
  using S = MetricRecipe::Source;
  switch (recipe.source) {
    case S::Given:
    case S::Tensor:
    case S::Hessian:
    case S::HessianField: return true;
    case S::Iso:
    case S::Size:
    case S::Curvature: return false;
  }
  return false;
}

double effective_hausd(const MetricRecipe& recipe, double protect_fraction, double diagonal) {
  if (recipe.hausd > 0) return recipe.hausd;
  if (!(protect_fraction > 0) || !protects_geometry(recipe) || !(diagonal > 0)) return 0;
  return protect_fraction * diagonal;
}

void check_options(const AdaptOptions& o) {
  check_recipe(o.metric);
  if (!(o.remesh.op.lmin > 0) || !(o.remesh.op.lmax > o.remesh.op.lmin))
    throw Error("the edge length band needs 0 < lmin < lmax");
  if (o.cycles < 1) throw Error("the number of cycles must be >= 1");
  if (!(o.fixed_point >= 0)) throw Error("the fixed-point tolerance must be >= 0");
  if (o.remesh.max_rounds < 1) throw Error("the number of rounds must be >= 1");
  if (o.remesh.relaxation_stages < 0) throw Error("the number of relaxation stages must be >= 0");
  if (!(o.memory_limit >= 0)) throw Error("the memory limit must be >= 0 bytes");
  if (!(o.max_growth >= 0) || !std::isfinite(o.max_growth)) throw Error("the growth limit must be a number >= 0");
  if (o.threads < 0 || o.threads > 1024) throw Error("the number of threads must be between 0 (all cores) and 1024");
  if (!(o.protect_fraction >= 0) || !std::isfinite(o.protect_fraction))
    throw Error("the geometry protection's fraction of the diagonal must be a number >= 0");
  if (!(o.protect_size_fraction >= 0) || !std::isfinite(o.protect_size_fraction))
    throw Error("the geometry protection's fraction of the size must be a number >= 0");
}

std::unique_ptr<GeometrySurface> make_geometry(const SurfaceMesh& tg, SurfaceKind kind,
                                               std::future<std::unique_ptr<Locator>> locator) {
  auto take_locator = [&] {
    std::unique_ptr<Locator> built = locator.valid() ? locator.get() : nullptr;
    return built ? std::move(*built) : Locator(tg);
  };
  if (kind == SurfaceKind::Polyhedral) return std::make_unique<PolyhedralSurface>(take_locator());
  const BezierGeometry::Mode mode =
      kind == SurfaceKind::G1Closest ? BezierGeometry::Mode::Closest : BezierGeometry::Mode::Parametric;
  auto surface = std::make_shared<const BezierSurface>(tg, compute_frames(tg));
  return std::make_unique<BezierGeometry>(std::move(surface), mode, take_locator());
}

namespace {

// The angle (radians) between the normals of the triangles of edge c.
double dihedral_angle(const SurfaceMesh& m, Corner c) {
  const Vec3 a = m.triangle_normal(SurfaceMesh::triangle(c));
  const Vec3 b = m.triangle_normal(SurfaceMesh::triangle(m.opposite(c)));
  return vector_angle(a, b);
}

// The turn of the feature curve through v (curve_turn) where exactly two
// feature edges meet at a vertex that is no corner, else 0 (a corner ends
// its curves).
double regular_curve_turn(const SurfaceMesh& m, Vertex v) {
  if (m.has_tag(v, kCorner) || m.has_tag(v, kRequired)) return 0;
  const std::vector<FeatureEdgeAt> f = feature_edges_at(m, v);
  return f.size() == 2 ? curve_turn(m, v, f[0], f[1]) : 0;
}

// The turn resolve_surface weighs at edge c of T_G: the dihedral angle, or
// on a feature curve or the boundary the curve's turn at its ends.
double edge_turn(const SurfaceMesh& tg, Corner c) {
  return is_feature_edge(tg, c) || !tg.opposite(c).is_valid()
             ? std::max(regular_curve_turn(tg, tg.edge_from(c)), regular_curve_turn(tg, tg.edge_to(c)))
             : dihedral_angle(tg, c);
}

// Whether pred(c) holds for every edge of tg (each at its canonical corner),
// judged in parallel chunks of corner slots, each stopping at the first
// edge that fails (a chunk's failure stops the others).
template <class Pred>
bool every_edge(const SurfaceMesh& tg, Pred pred) {
  const int nc = tg.corner_capacity();
  std::atomic<bool> failed{false};
  run_chunks(nc, chunk_count(nc, 65536), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      if ((i & 1023) == 0 && failed.load(std::memory_order_relaxed)) return;
      const Corner c(i);
      if (tg.is_edge_corner(c) && !pred(c)) {
        failed = true;
        return;
      }
    }
  });
  return !failed.load();
}

}  // namespace

std::optional<SurfaceKind> surface_before_metric(SurfaceKind kind, const SurfaceMesh& tg, double hausd,
                                                 bool separate_geometry) {
  if (kind != SurfaceKind::Auto) return kind;
  if (separate_geometry || tg.n_triangles() == 0) return SurfaceKind::G1;
  if (!(hausd > 0)) return std::nullopt;
  const double abs_bound = kFineGeometryHausd * hausd;
  const bool fine = every_edge(tg, [&](Corner c) {
    const Vec3 e = tg.position(tg.edge_to(c)) - tg.position(tg.edge_from(c));
    return norm(e) * edge_turn(tg, c) / 8 <= abs_bound;
  });
  if (!fine) return SurfaceKind::G1;
  return std::nullopt;
}

SurfaceKind resolve_surface(SurfaceKind kind, const SurfaceMesh& tg, const MetricField& metric, double hausd) {
  if (kind != SurfaceKind::Auto) return kind;
  if (metric.size() != static_cast<std::size_t>(tg.vertex_capacity()) || tg.n_triangles() == 0)
    return SurfaceKind::G1;
  const double abs_bound = hausd > 0 ? kFineGeometryHausd * hausd : std::numeric_limits<double>::infinity();
  const double unsplit = OperatorOptions{}.lmax;
  const bool fine = every_edge(tg, [&](Corner c) {
    const Vertex a = tg.edge_from(c), b = tg.edge_to(c);
    const Vec3 e = tg.position(b) - tg.position(a);
    const double theta = edge_turn(tg, c);
    const double l = std::max(metric_length(metric[a.idx], e), metric_length(metric[b.idx], e));
    return l <= unsplit && l * theta / 8 <= kFineGeometrySag && norm(e) * theta / 8 <= abs_bound;
  });
  return fine ? SurfaceKind::Polyhedral : SurfaceKind::G1;
}

std::unique_ptr<ControlSpace> make_control(const SurfaceMesh& t0, MetricField metric, bool t0_is_geometry,
                                           const AdaptOptions& options, double complexity) {
  return std::make_unique<ControlSpace>(t0, std::move(metric), t0_is_geometry, options.interpolation, "metric",
                                        complexity);
}

AdaptResult adapt(AdaptInput input, AdaptOptions options, const AdaptCallbacks& cb) {
  check_options(options);
  const auto t_start = Clock::now();
  // The setup loops use as many threads as the remeshing (restored on return).
  const int threads = options.threads > 0 ? options.threads : available_threads();
  struct ThreadLimit {
    int saved = thread_limit().exchange(0);
    explicit ThreadLimit(int n) { thread_limit() = n; }
    ~ThreadLimit() { thread_limit() = saved; }
  } limit_scope(threads);
  AdaptResult result;
  StepTimer timer(cb);

  // T_G: the input, or the separate geometry, with its features; T_0 (and
  // T_1, a copy of it) carries the same tags. With several cycles T_0 moves
  // on to the adapted meshes and T_G stays a copy of the input (same
  // numbering: the first cycle's T_0 is still T_G).
  SurfaceMesh t0 = std::move(input.mesh);
  const bool separate = input.geometry != nullptr;
  result.features = detect_features(t0, options.features);
  SurfaceMesh tg_storage;
  if (separate) {
    tg_storage = *input.geometry;
    result.features = detect_features(tg_storage, options.features);
  } else if (options.cycles > 1) {
    tg_storage = t0;
  }
  const SurfaceMesh& tg = separate || options.cycles > 1 ? tg_storage : t0;
  timer.done("features");
  if (!(options.metric.hausd > 0)) {
    options.metric.hausd = effective_hausd(options, tg.bbox().diagonal());
    result.protection_hausd = options.metric.hausd;
  }
  result.size_protection = size_protection_of(options);

  std::unique_ptr<GeometrySurface> geometry;
  // With two threads or more and T_G of 4096 triangles or more, the
  // locator of T_G (either surface has one) is built on a thread of its own
  // while the first metric is, and so are the frames and patches when the
  // surface's kind does not wait for the metric (surface_before_metric); a
  // metric refused then waits for them.
  std::future<std::unique_ptr<Locator>> early_locator;
  std::future<std::unique_ptr<GeometrySurface>> early_geometry;
  if (threads > 1 && tg.n_triangles() >= 4096) {
    early_locator = std::async(std::launch::async, [&tg] { return std::make_unique<Locator>(tg); });
    if (const auto kind = surface_before_metric(options.surface, tg, options.metric.hausd, separate))
      early_geometry = std::async(std::launch::async, [&tg, kind, locator = std::move(early_locator)]() mutable {
        return make_geometry(tg, *kind, std::move(locator));
      });
  }
  // The recipe of every cycle; a given metric is kept apart and moved into
  // the cycle's metric (a Given source's next one is the metric carried onto
  // the adapted mesh).
  MetricField given = std::move(options.metric.given);
  const MetricRecipe& recipe = options.metric;
  for (int cycle = 1; cycle <= options.cycles; ++cycle) {
    const bool t0_is_geometry = cycle == 1 && !separate;
    CycleReport report;
    report.cycle = cycle;
    MetricRecipe cycle_recipe = recipe;
    cycle_recipe.given = std::move(given);
    MetricResult metric =
        build_metric(t0, std::move(cycle_recipe), cycle == 1 ? input.vertex_origin : std::vector<int>{});
    report.metric = metric.description;
    report.complexity = metric.complexity;
    report.predicted_vertices = metric.predicted_vertices;
    report.scaling_steps = metric.scaling_steps;
    check_predicted_size(metric.predicted_vertices, options.memory_limit);
    timer.done("metric");
    if (!geometry) {  // after the first metric (unless started early): a metric refused costs no surface
      // Auto is judged on T_G's own metric (T_0 is T_G in the first cycle).
      if (early_geometry.valid()) {
        geometry = early_geometry.get();
      } else {
        const SurfaceKind kind =
            resolve_surface(options.surface, tg, separate ? MetricField{} : metric.metric, options.metric.hausd);
        geometry = make_geometry(tg, kind, std::move(early_locator));
      }
      result.surface = geometry->name();
      timer.done("surface (frames, Bezier patches, locator)");
    }
    auto control = make_control(t0, std::move(metric.metric), t0_is_geometry, options, metric.complexity);
    auto adapted = std::make_unique<AdaptedMesh>(t0, *geometry, *control, options.length, cycle == 1 && separate,
                                                  input_bound_of(options));
    timer.done("T_1 located on T_G and T_0");
    report.setup_seconds = timer.total();

    RemeshOptions remesh_options = remesh_options_of(options);
    set_growth_limits(remesh_options, options.max_growth, report.predicted_vertices, t0.n_vertices());
    report.initial = Remesher(*adapted, remesh_options).measure();
    report.inverted_before = adapted->count_inverted();
    if (cb.cycle_started) cb.cycle_started(report);
    const auto t_run = Clock::now();
    ParallelOptions parallel;
    parallel.threads = threads;
    report.passes = run_in_regions(*adapted, remesh_options, parallel, [&](const PassReport& r) {
      if (cb.pass) cb.pass(r);
    });
    if (!report.passes.empty() && report.passes.back().over_limit)
      throw AdaptationStopped(over_limit_message(report.passes, remesh_options, report.predicted_vertices,
                                                 t0.n_vertices(), options.max_growth));
    report.remesh_seconds = seconds_since(t_run);
    // The serial schedule's final pass measured the whole mesh as it ends
    // (regions report their own parts; an interrupted pass is not the end).
    const PassReport* last_pass = report.passes.empty() ? nullptr : &report.passes.back();
    if (last_pass && last_pass->region < 0 && last_pass->measured && !last_pass->interrupted) {
      copy_state(*last_pass, report.final);
    } else {
      report.final = Remesher(*adapted, remesh_options).measure();
    }
    report.inverted_after = adapted->count_inverted();

    SurfaceMesh t1 = std::move(adapted->mesh());
    adapted.reset();
    control.reset();
    result.cycles.push_back(std::move(report));
    CycleReport& done = result.cycles.back();
    result.fixed_point = is_fixed_point(result.cycles, options.fixed_point);
    const bool last = cycle == options.cycles || result.fixed_point;
    if (last) geometry.reset();  // freed before T_1 is compacted and the output written
    t1.compact();
    MetricField t1_metric = take_adapted_metric(t1);
    if (recipe.is_hessian())
      done.error_estimate = estimated_interpolation_error(t1, recipe_hessian(t1, recipe), recipe.lp);
    if (cb.cycle_ended) cb.cycle_ended(done);
    if (last) {
      result.metric = std::move(t1_metric);
      result.mesh = std::move(t1);
      break;
    }
    if (recipe.source == MetricRecipe::Source::Given) given = std::move(t1_metric);
    t0 = std::move(t1);
    timer.restart();
  }
  result.seconds = seconds_since(t_start);
  return result;
}

}  // namespace anisurf::remesh
