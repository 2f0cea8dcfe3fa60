#include "editor/session.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/features.h"
#include "io/mesh_io.h"
#include "metric/expression.h"
#include "metric/hessian.h"
#include "metric/surface_metric.h"
#include "remesh/adapted_mesh.h"

namespace anisurf::editor {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Metric with sizes h along the unit tangent d, h_across across it (in the
// plane of n) and h_normal along n.
SymTensor3 oriented_metric(const Vec3& n, const Vec3& d, double h_along, double h_across, double h_normal) {
  return metric_from_sizes({h_along, h_across, h_normal}, {d, cross(n, d), n});
}

// Log-Euclidean blend (1 - w) A + w B, w in [0, 1].
SymTensor3 blend(const SymTensor3& A, const SymTensor3& B, double w) {
  if (w <= 0) return A;
  if (w >= 1) return B;
  const SymTensor3 la = tensor_log(A), lb = tensor_log(B);
  SymTensor3 l;
  for (int i = 0; i < 6; ++i) l.m[i] = (1 - w) * la.m[i] + w * lb.m[i];
  return tensor_exp(l);
}

// The iso size whose metric predicts as many vertices as the mesh has (the
// prediction of report section 2.2: its area term scales as 1 / h^2, its
// boundary term as 1 / h), found by fixed-point steps h <- h sqrt(N(h) / n):
// the input's own density, so that adapting right after opening keeps the
// mesh's size. 1/40 of the diagonal on a mesh without area.
double density_size(const SurfaceMesh& mesh) {
  const BBox b = mesh.bbox();
  const double fallback = std::max(norm(b.hi - b.lo) / 40.0, 1e-9);
  const double n = std::max(3, mesh.n_vertices());
  double h = fallback;
  for (int step = 0; step < 30; ++step) {
    const MetricField iso(static_cast<std::size_t>(mesh.vertex_capacity()), SymTensor3::identity(1.0 / (h * h)));
    const double ratio = predicted_vertices(mesh, iso) / n;
    if (!std::isfinite(ratio) || !(ratio > 0)) return fallback;
    h *= std::sqrt(ratio);
    if (std::fabs(ratio - 1) < 1e-3) break;
  }
  return std::isfinite(h) && h > 0 ? h : fallback;
}

}  // namespace

std::string absolute_path(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path a = std::filesystem::absolute(path, ec);
  return ec ? path : a.lexically_normal().string();
}

const char* source_name(MetricSettings::Source s) {
  switch (s) {
    case MetricSettings::Source::Iso: return "iso";
    case MetricSettings::Source::Size: return "size";
    case MetricSettings::Source::Hessian: return "hessian";
    case MetricSettings::Source::Curvature: return "curvature";
    case MetricSettings::Source::Sol: return "sol";
  }
  return "?";
}

std::string source_line(const MetricSettings& s) {
  switch (s.source) {
    case MetricSettings::Source::Iso: return "metric iso " + num(s.iso);
    case MetricSettings::Source::Size: return "metric size " + s.size_expr;
    case MetricSettings::Source::Hessian: return "metric hessian " + s.hessian_expr + " " + num(s.hessian_error);
    case MetricSettings::Source::Curvature: return "metric curvature " + num(s.hausd);
    case MetricSettings::Source::Sol: return "metric sol " + s.sol_path;
  }
  return {};
}

EditorSession::EditorSession() = default;

EditorSession::~EditorSession() {
  collect_analysis(true);
  forget_metric_jobs();                             // a build reads T_0
  if (distance_job_.valid()) distance_job_.wait();  // it reads T_G
  retire_adaptation();
  wait_retired();
  if (geometry_.valid()) geometry_.wait();  // it reads input_
}

void EditorSession::log(const std::string& line) { journal_.push_back(line); }

void EditorSession::changed() {
  ++version_;
  dirty_ = true;
  changed_at_ = std::chrono::steady_clock::now();
}

std::unique_ptr<Adaptation> EditorSession::make_adaptation() const {
  // The metric's chordal deviation (given or the geometry protection's)
  // bounds the vertices and the output's distance as in `anisurf adapt`.
  AdaptSettings a = adapt_settings_;
  a.metric.hausd = effective_hausd(settings_);
  // The source decides the size protection (remesh::size_protection_of).
  a.metric.source = settings_.source == MetricSettings::Source::Size  ? MetricRecipe::Source::Size
                    : settings_.source == MetricSettings::Source::Iso ? MetricRecipe::Source::Iso
                                                                      : MetricRecipe::Source::Given;
  return std::make_unique<Adaptation>(*input_, metric_, a, t0_snapshot_, geometry_, geometry_lock_, geometry_mesh_ == nullptr);
}

std::shared_ptr<const Snapshot> EditorSession::initial_snapshot() const {
  auto s = std::make_shared<Snapshot>();
  s->mesh = *input_;
  s->metric = metric_;
  s->placement = count_placements(s->mesh);
  s->label = "initial";
  return s;
}

void EditorSession::open(const std::string& mesh_path, const std::string& sol_path) {
  // A pair whose writer was killed between its renames is completed first.
  for (const std::string& p : {mesh_path, sol_path})
    if (!p.empty()) finish_interrupted_commits(p);
  BuildReport report;
  auto mesh = std::make_unique<SurfaceMesh>(load_mesh(mesh_path, &report));
  if (mesh->n_triangles() == 0) throw Error(mesh_path + ": the mesh has no triangles");
  MetricField sol_metric;
  // A mesh format with fields inside (.msh, .vtu ...) may carry its metric:
  // then it is the loaded metric, the file its own "sol" (as `anisurf adapt`).
  const std::string embedded = sol_path.empty() ? embedded_metric_name(*mesh) : std::string();
  if (!embedded.empty()) {
    try {
      sol_metric = metric_from_field(*mesh, embedded, report.vertex_origin);
    } catch (const MetricError& e) {
      throw Error(mesh_path + ": field '" + embedded + "': " + e.what());
    }
    mesh->remove_field(embedded);
  }
  if (!sol_path.empty()) {
    // The editor keeps the metric apart: the fields go on a copy, T_0 has none.
    SurfaceMesh with_fields = *mesh;
    attach_fields(with_fields, read_sol(sol_path, report.input_vertices), report);
    try {
      sol_metric = metric_from_field(with_fields, {}, report.vertex_origin);
    } catch (const MetricError& e) {
      throw Error(sol_path + ": " + e.what());
    }
  }
  // Features listed in the file (a mesh the editor saved) are kept as they
  // are: detecting ridges again on an adapted mesh finds others.
  bool listed = false;
  for (Corner c : mesh->edges()) listed = listed || (mesh->edge_tags(c) & (kRidge | kRequired)) != 0;
  std::vector<char> file_corner(static_cast<std::size_t>(mesh->vertex_capacity()), 0);
  for (Vertex v : mesh->vertices())
    if (mesh->has_tag(v, kCorner)) file_corner[static_cast<std::size_t>(v.idx)] = 1, listed = true;
  FeatureOptions fo;
  fo.detect_ridges = !listed;
  FeatureReport features = detect_features(*mesh, fo);
  if (listed) {
    // detect_features() adds corners where a curve turns; of those only the
    // ones the curves need (an end or a branch) stay.
    features.corners = 0;
    for (Vertex v : mesh->vertices()) {
      if (!mesh->has_tag(v, kCorner)) continue;
      if (!file_corner[static_cast<std::size_t>(v.idx)] && feature_edges_at(*mesh, v).size() == 2)
        mesh->remove_vertex_tag(v, kCorner);
      else
        ++features.corners;
    }
  }

  retire_adaptation();
  wait_retired();  // their workers read the old mesh
  forget_metric_jobs();  // so does a metric build
  if (geometry_.valid()) geometry_.wait();  // and the old geometry's construction
  forget_distance();  // its measure reads the old T_G
  std::swap(input_, mesh);
  geometry_mesh_.reset();
  cycle_ = 0;
  metric_painted_ = false;
  geometry_ = start_geometry(*input_, adapt_settings_);
  geometry_lock_ = std::make_shared<std::mutex>();
  vertex_origin_ = report.vertex_origin;
  mesh_path_ = mesh_path;
  forget_input_state();
  MetricSettings s = settings_;
  MetricField m;
  const double density = density_size(*input_);
  if (!sol_path.empty() || !embedded.empty()) {
    s.source = MetricSettings::Source::Sol;
    s.sol_path = sol_path.empty() ? mesh_path : sol_path;
    // A loaded metric is used as given: no gradation, no bounds.
    s.hgrad = 1;
    s.hausd_bound = 0;
    s.hmin = 0;
    s.hmax = std::numeric_limits<double>::infinity();
    s.max_aniso = std::numeric_limits<double>::infinity();
    // As compute_metric() (and `anisurf adapt`): the recipe with the metric given.
    m = build_metric(*input_, metric_recipe(s, std::move(sol_metric)), vertex_origin_).metric;
  } else {
    if (s.source == MetricSettings::Source::Sol) s.source = MetricSettings::Source::Iso;
    s.sol_path.clear();  // the previous mesh's metric file does not fit this mesh
    // A default iso size from the mesh (its own density: density_size); the
    // settings of the previous mesh may not suit this one (an expression
    // undefined here, bounds): then the iso size without bounds.
    const double h = density;
    if (s.source == MetricSettings::Source::Iso) s.iso = h;
    try {
      m = compute_metric(s);
    } catch (const std::exception&) {
      s = MetricSettings{};
      s.iso = h;
      m = compute_metric(s);
    }
  }
  // The brush at the model's scale: a tenth of the diagonal, half the
  // input's density (a stroke refines).
  {
    const BBox b = input_->bbox();
    brush_.radius = std::max(norm(b.hi - b.lo) / 10.0, 1e-9);
    brush_.size = 0.5 * density;
  }
  base_metric_ = m;
  metric_ = std::move(m);
  settings_ = s;
  predicted_vertices_ = anisurf::predicted_vertices(*input_, metric_);
  t0_snapshot_ = initial_snapshot();
  ++opened_;
  features_ = features;
  features_from_file_ = listed;
  written_.clear();
  journal_.clear();
  logged_brush_ = "brush set 1";
  logged_direction_.clear();
  log("open " + mesh_path + (sol_path.empty() ? "" : " " + sol_path));
  ++version_;
  dirty_ = false;
  changed_at_ = std::chrono::steady_clock::now();
}

MetricRecipe EditorSession::metric_recipe(const MetricSettings& s, MetricField loaded) const {
  // For a Sol source with `loaded` given, the file is not read.
  using S = MetricRecipe::Source;
  MetricRecipe r;
  r.bounds = {s.hmin, s.hmax, s.max_aniso};
  r.hgrad = s.hgrad;
  r.hausd = effective_hausd(s);
  switch (s.source) {
    case MetricSettings::Source::Iso:
      r.source = S::Iso;
      r.iso = s.iso;
      break;
    case MetricSettings::Source::Size:
      r.source = S::Size;
      r.expression = s.size_expr;
      break;
    case MetricSettings::Source::Hessian:
      if (!(s.hessian_error > 0)) throw Error("metric hessian: the error must be > 0");
      r.source = S::Hessian;
      r.expression = s.hessian_expr;
      r.error = s.hessian_error;
      break;
    case MetricSettings::Source::Curvature:
      if (!(s.hausd > 0)) throw Error("metric curvature: hausd must be > 0");
      r.source = S::Curvature;
      r.hausd = s.hausd;
      break;
    case MetricSettings::Source::Sol: {
      r.source = S::Given;
      if (!loaded.empty()) {
        r.given = std::move(loaded);
        break;
      }
      BuildReport report;
      SurfaceMesh copy = load_mesh(mesh_path_, &report);
      if (copy.vertex_capacity() != input_->vertex_capacity())
        throw Error(s.sol_path + ": does not match the mesh's vertices");
      // The metric inside the mesh file itself (open), or a .sol beside it.
      const bool inside = s.sol_path == mesh_path_;
      if (!inside) attach_fields(copy, read_sol(s.sol_path, report.input_vertices), report);
      try {
        r.given = metric_from_field(copy, inside ? embedded_metric_name(copy) : std::string(), report.vertex_origin);
      } catch (const MetricError& e) {
        throw Error(s.sol_path + ": " + e.what());
      }
      break;
    }
  }
  return r;
}

double EditorSession::effective_hausd(const MetricSettings& s) const {
  if (s.source == MetricSettings::Source::Curvature) return s.hausd;
  // A loaded metric is used as given: only a hausd bound the user sets.
  if (s.source == MetricSettings::Source::Sol) return s.hausd_bound > 0 ? s.hausd_bound : 0;
  MetricRecipe r;
  r.hausd = s.hausd_bound > 0 ? s.hausd_bound : 0;
  r.source = s.source == MetricSettings::Source::Iso    ? MetricRecipe::Source::Iso
             : s.source == MetricSettings::Source::Size ? MetricRecipe::Source::Size
                                                         : MetricRecipe::Source::Hessian;
  return remesh::effective_hausd(r, adapt_settings_.protect_fraction, input_ ? geometry_input().bbox().diagonal() : 0);
}

MetricField EditorSession::compute_metric(const MetricSettings& s) const {
  // The engine's recipe (the same chain as `anisurf adapt`): source, bounds,
  // hausd bound, gradation.
  return build_metric(*input_, metric_recipe(s), vertex_origin_).metric;
}

void EditorSession::apply_metric(MetricField m, const MetricSettings& s, bool reset_adaptation) {
  metric_ = std::move(m);
  settings_ = s;
  predicted_vertices_ = anisurf::predicted_vertices(*input_, metric_);
  t0_snapshot_ = initial_snapshot();
  if (reset_adaptation) retire_adaptation();
  selection_ = {};
  changed();
}

void EditorSession::set_settings(const MetricSettings& s) {
  if (!input_) throw Error("no mesh: open one first");
  if (stroke_) end_stroke();
  install_settings(s, compute_metric(s));  // throws before anything changes
}

void EditorSession::install_settings(const MetricSettings& s, MetricField m) {
  if (stroke_) end_stroke();
  MetricEdit e;
  e.what = "metric " + std::string(source_name(s.source));
  e.settings_before = settings_;
  e.settings_after = s;
  for (Vertex v : input_->vertices()) {
    e.vertices.push_back(v.idx);
    e.before.push_back(metric_[v.idx]);
    e.after.push_back(m[v.idx]);
  }
  e.base_before = std::make_shared<const MetricField>(base_metric_);
  e.base_after = std::make_shared<const MetricField>(m);
  base_metric_ = m;
  metric_painted_ = false;
  undo_.push_back(std::move(e));
  redo_.clear();
  const MetricSettings old = settings_;
  apply_metric(std::move(m), s, true);
  if (s.source != old.source || source_line(s) != source_line(old)) log(source_line(s));
  if (s.hgrad != old.hgrad) log("hgrad " + num(s.hgrad));
  if (s.hausd_bound != old.hausd_bound) log("hausd " + num(s.hausd_bound));
  if (s.hmin != old.hmin) log("hmin " + num(s.hmin));
  if (s.hmax != old.hmax) log("hmax " + num(std::isinf(s.hmax) ? 0.0 : s.hmax));
  if (s.max_aniso != old.max_aniso) log("max-aniso " + num(std::isinf(s.max_aniso) ? 0.0 : s.max_aniso));
}

// --- the metric built in the background ---------------------------------------

void EditorSession::request_metric(const MetricSettings& s, bool apply) {
  if (!input_) throw Error("no mesh: open one first");
  poll_metric();
  if (apply) {
    apply_error_.clear();
    pending_apply_.reset();
    // An apply in progress for other settings is superseded: built, not installed.
    if (metric_job_.valid() && metric_job_apply_ && !(metric_job_of_ == s)) metric_job_apply_ = false;
    if (s == settings_ && !metric_painted_) return;
    if (built_of_ && *built_of_ == s) {
      install_settings(s, MetricField(*built_));
      return;
    }
    if (failed_of_ && *failed_of_ == s) {
      apply_error_ = failed_error_;
      return;
    }
    if (metric_job_.valid()) {
      if (metric_job_of_ == s)
        metric_job_apply_ = true;
      else
        pending_apply_ = s;
      return;
    }
    start_metric_job(s, true);
  } else {
    pending_preview_.reset();
    if ((built_of_ && *built_of_ == s) || (failed_of_ && *failed_of_ == s) || s == settings_) return;
    if (metric_job_.valid()) {
      if (!(metric_job_of_ == s)) pending_preview_ = s;
      return;
    }
    start_metric_job(s, false);
  }
}

void EditorSession::start_metric_job(const MetricSettings& s, bool apply) {
  metric_job_of_ = s;
  metric_job_apply_ = apply;
  metric_job_start_ = std::chrono::steady_clock::now();
  // The build reads T_0, its origin, its file and T_G: open() and
  // next_cycle() wait for it (forget_metric_jobs()) before they change them.
  metric_job_ = std::async(std::launch::async, [this, s] {
    // Below the window's thread, as the adaptation's worker: the window keeps
    // drawing. Best effort: ignored if refused.
    setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 5);
    Built b;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      auto m = std::make_shared<const MetricField>(compute_metric(s));
      b.predicted = anisurf::predicted_vertices(*input_, *m);
      b.metric = std::move(m);
    } catch (const std::exception& e) {
      b.error = e.what();
    }
    b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return b;
  });
}

void EditorSession::poll_metric() {
  if (metric_job_.valid() && metric_job_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    Built b = metric_job_.get();
    last_metric_seconds_ = b.seconds;
    const MetricSettings s = metric_job_of_;
    const bool apply = metric_job_apply_;
    metric_job_apply_ = false;
    if (b.metric) {
      built_of_ = s;
      built_ = std::move(b.metric);
      built_predicted_ = b.predicted;
      if (apply) install_settings(s, MetricField(*built_));
    } else {
      failed_of_ = s;
      failed_error_ = b.error;
      if (apply) apply_error_ = b.error;
    }
  }
  if (metric_job_.valid()) return;
  // The waiting requests: an apply first, then a preview.
  if (pending_apply_) {
    const MetricSettings s = *pending_apply_;
    pending_apply_.reset();
    if (built_of_ && *built_of_ == s)
      install_settings(s, MetricField(*built_));
    else
      start_metric_job(s, true);
  }
  if (!metric_job_.valid() && pending_preview_) {
    const MetricSettings s = *pending_preview_;
    pending_preview_.reset();
    if (!(built_of_ && *built_of_ == s) && !(failed_of_ && *failed_of_ == s)) start_metric_job(s, false);
  }
}

void EditorSession::forget_metric_jobs() {
  if (metric_job_.valid()) metric_job_.wait();
  metric_job_ = {};
  metric_job_apply_ = false;
  pending_apply_.reset();
  pending_preview_.reset();
  built_of_.reset();
  built_.reset();
  failed_of_.reset();
  failed_error_.clear();
  apply_error_.clear();
}

double EditorSession::metric_build_seconds() const {
  if (!metric_job_.valid()) return 0;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - metric_job_start_).count();
}

std::optional<double> EditorSession::preview(const MetricSettings& s) const {
  if (s == settings_) return predicted_vertices_;
  if (built_of_ && *built_of_ == s) return built_predicted_;
  return std::nullopt;
}

std::string EditorSession::metric_error(const MetricSettings& s) const {
  return failed_of_ && *failed_of_ == s ? failed_error_ : std::string();
}

double EditorSession::predict_vertices(const MetricSettings& s) const {
  if (!input_) return 0;
  return anisurf::predicted_vertices(*input_, compute_metric(s));
}

// --- painting ---------------------------------------------------------------

const std::vector<Vec3>& EditorSession::vertex_normals_cached() {
  if (normals_.empty()) normals_ = vertex_normals(*input_);
  return normals_;
}

const std::vector<SymTensor3>& EditorSession::curvature_cached() {
  if (curvature_.empty()) curvature_ = recover_curvature(*input_);
  return curvature_;
}

void EditorSession::begin_stroke() {
  open_stroke();
  log("stroke begin");
}

void EditorSession::open_stroke() {
  if (!input_) throw Error("no mesh: open one first");
  if (stroke_) end_stroke();
  stroke_.emplace();
  const char* modes[] = {"paint", "smooth", "erase"};
  stroke_->what = modes[static_cast<int>(brush_.mode)];
  stroke_->settings_before = stroke_->settings_after = settings_;
  stroke_index_.assign(static_cast<std::size_t>(input_->vertex_capacity()), -1);
}

void EditorSession::dab(const Vec3& centre, const Vec3& direction) {
  if (!input_) throw Error("no mesh: open one first");
  const bool own = !stroke_;
  const Brush& b = brush_;
  if (!(b.radius > 0) || !(b.size > 0) || !(b.stretch >= 1) || !(b.strength > 0))
    throw Error("brush: need radius > 0, size > 0, stretch >= 1 and strength > 0");
  const SurfaceMesh& mesh = *input_;
  const auto& normals = vertex_normals_cached();
  const double r2 = b.radius * b.radius;
  const MetricBounds bounds{settings_.hmin, settings_.hmax, settings_.max_aniso};
  std::vector<std::pair<int, SymTensor3>> updates;
  for (Vertex vertex : mesh.vertices()) {
    if (mesh.is_isolated(vertex)) continue;
    const int v = vertex.idx;
    const double d2 = norm2(mesh.position(vertex) - centre);
    if (d2 >= r2) continue;
    const double s = d2 / r2;
    const double w = std::clamp(b.strength * (1 - s) * (1 - s), 0.0, 1.0);
    SymTensor3 target;
    if (b.mode == Brush::Mode::Erase) {
      target = base_metric_[v];
    } else if (b.mode == Brush::Mode::Smooth) {
      // Log-Euclidean mean of the one-ring (and the vertex).
      SymTensor3 sum = tensor_log(metric_[v]);
      int n = 1;
      for (Corner c : mesh.fan_corners(Vertex(v))) {
        const SymTensor3 l = tensor_log(metric_[mesh.vertex(SurfaceMesh::next(c)).idx]);
        for (int i = 0; i < 6; ++i) sum.m[i] += l.m[i];
        ++n;
      }
      for (double& x : sum.m) x /= n;
      target = tensor_exp(sum);
    } else {
      const Vec3 nrm = norm2(normals[v]) > 0 ? normals[v] : Vec3(0, 0, 1);
      Vec3 dir = direction;
      if (b.direction != Brush::Direction::Stroke) {
        const SizesDirections sd = sizes_and_directions(curvature_cached()[v]);
        // Tangent eigenvectors: the two directions least aligned with the normal.
        std::array<int, 3> idx = {0, 1, 2};
        std::sort(idx.begin(), idx.end(),
                  [&](int a, int c) { return std::abs(dot(sd.directions[a], nrm)) < std::abs(dot(sd.directions[c], nrm)); });
        const SymTensor3& K = curvature_cached()[v];
        const double k0 = std::abs(quad(K, sd.directions[idx[0]])), k1 = std::abs(quad(K, sd.directions[idx[1]]));
        const bool want_max = b.direction == Brush::Direction::MaxCurvature;
        dir = sd.directions[(k0 >= k1) == want_max ? idx[0] : idx[1]];
      }
      Vec3 t = dir - dot(dir, nrm) * nrm;
      if (b.stretch > 1 && norm2(t) > 1e-24) {
        t = normalized(t);
        target = oriented_metric(nrm, t, b.size * b.stretch, b.size, b.size * b.stretch);
      } else {
        target = isotropic_metric(b.size);
      }
      target = clamp_metric(target, bounds);
    }
    updates.emplace_back(v, blend(metric_[v], target, w));
  }
  // Nothing changes unless every painted metric is one (sizes out of range
  // overflow 1/h^2).
  for (const auto& [v, M] : updates)
    if (!is_finite(M) || !is_spd(M))
      throw Error("the brush gives no metric at vertex " + std::to_string(v + 1) + " (" + metric_problem(M) +
                  "): size or stretch out of range");
  if (own) open_stroke();  // after the checks: a refused dab leaves no stroke open
  MetricEdit& e = *stroke_;
  for (auto& [v, M] : updates) {
    if (stroke_index_[v] < 0) {
      stroke_index_[v] = static_cast<int>(e.vertices.size());
      e.vertices.push_back(v);
      e.before.push_back(metric_[v]);
      e.after.push_back(M);
    } else {
      e.after[stroke_index_[v]] = M;
    }
    metric_[v] = M;
  }
  if (!updates.empty()) {
    metric_painted_ = true;
    retire_adaptation();
    predicted_vertices_ = anisurf::predicted_vertices(mesh, metric_);
    t0_snapshot_ = initial_snapshot();
    changed();
  }
  static const char* mode_words[] = {"set", "smooth", "erase"};
  static const char* dir_words[] = {"stroke", "max-curvature", "min-curvature"};
  const std::string brush_line = std::string("brush ") + mode_words[static_cast<int>(b.mode)] + " " + num(b.strength);
  const std::string dir_line = std::string("brush direction ") + dir_words[static_cast<int>(b.direction)];
  if (brush_line != logged_brush_) log(logged_brush_ = brush_line);
  if (dir_line != logged_direction_ && !(logged_direction_.empty() && b.direction == Brush::Direction::Stroke))
    log(logged_direction_ = dir_line);
  char line[256];
  std::snprintf(line, sizeof line, "paint %s %s %s %s %s", num(centre.x).c_str(), num(centre.y).c_str(),
                num(centre.z).c_str(), num(b.radius).c_str(), num(b.size).c_str());
  std::string l = line;
  if (b.stretch > 1 && norm2(direction) > 0)
    l += " " + num(b.stretch) + " " + num(direction.x) + " " + num(direction.y) + " " + num(direction.z);
  log(l);
  if (own) close_stroke();
}

void EditorSession::end_stroke() {
  if (!stroke_) return;
  close_stroke();
  log("stroke end");
}

void EditorSession::close_stroke() {
  if (!stroke_) return;
  if (!stroke_->vertices.empty()) {
    undo_.push_back(std::move(*stroke_));
    redo_.clear();
  }
  stroke_.reset();
}

bool EditorSession::undo() {
  if (stroke_) end_stroke();
  if (undo_.empty()) return false;
  MetricEdit e = std::move(undo_.back());
  undo_.pop_back();
  MetricField m = metric_;
  for (std::size_t i = 0; i < e.vertices.size(); ++i) m[e.vertices[i]] = e.before[i];
  if (e.settings_before != e.settings_after) base_metric_ = e.base_before ? *e.base_before : compute_metric(e.settings_before);
  const MetricSettings s = e.settings_before;
  redo_.push_back(std::move(e));
  apply_metric(std::move(m), s, true);
  log("undo");
  return true;
}

bool EditorSession::redo() {
  if (stroke_) end_stroke();
  if (redo_.empty()) return false;
  MetricEdit e = std::move(redo_.back());
  redo_.pop_back();
  MetricField m = metric_;
  for (std::size_t i = 0; i < e.vertices.size(); ++i) m[e.vertices[i]] = e.after[i];
  if (e.settings_before != e.settings_after) base_metric_ = e.base_after ? *e.base_after : compute_metric(e.settings_after);
  const MetricSettings s = e.settings_after;
  undo_.push_back(std::move(e));
  apply_metric(std::move(m), s, true);
  log("redo");
  return true;
}

// --- adaptation ---------------------------------------------------------------

void EditorSession::step() { run(1); }

void EditorSession::run(int max_passes) {
  if (!input_) throw Error("no mesh: open one first");
  if (stroke_) end_stroke();
  if (running()) return;
  poll();
  // A retired adaptation still at work holds the geometry: the new worker
  // waits for it in its own thread (Adaptation's geometry lock).
  if (!adaptation_) adaptation_ = make_adaptation();
  const std::size_t n = adaptation_->size();
  const std::size_t from = scrub_ >= 0 && static_cast<std::size_t>(scrub_) < n ? static_cast<std::size_t>(scrub_) : n - 1;
  run_start_ = from + 1;
  scrub_ = -1;
  stop_requested_.reset();
  cancelled_ = false;
  if (adaptation_->start(from, max_passes)) ++runs_started_;
  log(max_passes == 1 ? "step" : max_passes > 0 ? "run " + std::to_string(max_passes) : "run");
  changed();
}

void EditorSession::forget_input_state() {
  normals_.clear();
  curvature_.clear();
  undo_.clear();
  redo_.clear();
  stroke_.reset();
  selection_ = {};
  scrub_ = -1;
}

int EditorSession::next_cycle() {
  if (!input_) throw Error("no mesh: open one first");
  if (stroke_) end_stroke();
  wait();
  poll();
  const std::shared_ptr<const Snapshot> shown = display().snapshot;
  if (!shown || !shown->has_report) throw Error("cycle: adapt first (run), the displayed mesh is T_0");
  auto t1 = std::make_unique<SurfaceMesh>(shown->mesh);
  // The placements belong to the adaptation that made the mesh: the new T_0
  // (and its initial state) has none.
  t1->vertex_properties().remove(remesh::kPlacementProperty);
  const CompactMap map = t1->compact();
  MetricField carried(static_cast<std::size_t>(t1->vertex_capacity()));
  for (int v = 0; v < static_cast<int>(map.vertex.size()); ++v)
    if (map.vertex[v] >= 0) carried[map.vertex[v]] = shown->metric[v];
  // The settings' source evaluated on the new T_0, unless the metric comes
  // from a file of the opened mesh or was painted: then it is carried.
  MetricRecipe recipe = metric_recipe(settings_, carried);
  if (settings_.source == MetricSettings::Source::Sol || metric_painted_) {
    recipe.source = MetricRecipe::Source::Given;
    recipe.given = std::move(carried);
  }
  MetricField m = build_metric(*t1, recipe).metric;
  // The next cycles project onto the surface the first one ran on (its
  // `auto` choice), as anisurf adapt --cycles does.
  if (!geometry_mesh_ && adaptation_ && adaptation_->geometry()) {
    std::promise<std::shared_ptr<remesh::GeometrySurface>> ran_on;
    ran_on.set_value(adaptation_->geometry());
    geometry_ = ran_on.get_future().share();
  }
  retire_adaptation();
  wait_retired();
  forget_metric_jobs();  // a build reads the old T_0
  if (!geometry_mesh_) geometry_mesh_ = std::move(input_);  // geometry_ keeps reading it
  input_ = std::move(t1);
  vertex_origin_.clear();  // T_0 is no file's mesh any more
  ++cycle_;
  forget_input_state();
  base_metric_ = m;
  apply_metric(std::move(m), settings_, true);
  log("cycle");
  return input_->n_vertices();
}

void EditorSession::set_band(double lmin, double lmax) {
  if (!(lmin > 0) || !(lmax > lmin)) throw Error("the edge length band needs 0 < lmin < lmax");
  auto& op = adapt_settings_.remesh.op;
  if (op.lmin == lmin && op.lmax == lmax) return;
  if (op.lmin != lmin) log("lmin " + num(lmin));
  if (op.lmax != lmax) log("lmax " + num(lmax));
  op.lmin = lmin;
  op.lmax = lmax;
  retire_adaptation();
  changed();
}

void EditorSession::pause() {
  if (!adaptation_) return;
  if (adaptation_->running() && !stop_requested_) stop_requested_ = std::chrono::steady_clock::now();
  adaptation_->request_stop();
}

void EditorSession::cancel() {
  if (!adaptation_) return;
  if (adaptation_->running() && !stop_requested_) stop_requested_ = std::chrono::steady_clock::now();
  adaptation_->request_stop();
  cancel_pending_ = true;  // the timeline is cut once the worker is idle (poll())
  poll();
}

void EditorSession::retire_adaptation() {
  if (!adaptation_) return;
  adaptation_->request_stop();
  retired_.push_back(std::move(adaptation_));
  cancel_pending_ = false;
  cancelled_ = false;
  scrub_ = -1;
  changed_at_ = std::chrono::steady_clock::now();  // the next one is prepared once the session is still
  poll();
}

void EditorSession::wait_retired() { retired_.clear(); }  // each destructor joins its worker

void EditorSession::poll() {
  poll_metric();
  // Retired adaptations go once their worker has finished its pass.
  std::erase_if(retired_, [](const std::unique_ptr<Adaptation>& a) { return !a->working(); });
  if (cancel_pending_ && adaptation_ && !adaptation_->running()) {
    adaptation_->wait();
    adaptation_->truncate(run_start_);
    cancel_pending_ = false;
    cancelled_ = true;
    scrub_ = -1;
    ++version_;
  }
  if (input_ && !adaptation_ && !stroke_ && !metric_building() &&
      std::chrono::steady_clock::now() - changed_at_ > kPrepareDelay) {
    adaptation_ = make_adaptation();
    adaptation_->prepare();
  }
}

void EditorSession::reset() {
  retire_adaptation();
  selection_ = {};
  log("reset");
  changed();
}

void EditorSession::wait() {
  if (adaptation_) adaptation_->wait();
  wait_retired();
  poll();
}

bool EditorSession::running() const { return adaptation_ && adaptation_->running(); }

const char* run_state_name(RunState s) {
  switch (s) {
    case RunState::Idle: return "idle";
    case RunState::Running: return "running";
    case RunState::Pausing: return "pausing";
    case RunState::Cancelling: return "cancelling";
    case RunState::Paused: return "paused";
    case RunState::Converged: return "converged";
    case RunState::Cancelled: return "cancelled";
    case RunState::Failed: return "failed";
  }
  return "?";
}

RunState EditorSession::run_state() const {
  if (!adaptation_) return RunState::Idle;
  if (adaptation_->running()) {
    if (cancel_pending_) return RunState::Cancelling;
    return stop_requested_ ? RunState::Pausing : RunState::Running;
  }
  if (!adaptation_->error().empty()) return RunState::Failed;
  if (cancelled_ || cancel_pending_) return RunState::Cancelled;
  const auto tl = adaptation_->timeline();
  if (tl.size() < 2) return RunState::Idle;
  return tl.back()->schedule.phase == Schedule::Phase::Done ? RunState::Converged : RunState::Paused;
}

std::vector<std::shared_ptr<const Snapshot>> EditorSession::timeline() const {
  if (!adaptation_) return {t0_snapshot_};
  return adaptation_->timeline();
}

void EditorSession::scrub(int index) {
  const int n = static_cast<int>(adaptation_ ? adaptation_->size() : 1);
  if (index >= n) throw Error("timeline: pass " + std::to_string(index) + " does not exist (0 to " + std::to_string(n - 1) + ")");
  scrub_ = index < 0 || index == n - 1 ? -1 : index;
  ++version_;
}

std::string EditorSession::adaptation_error() const { return adaptation_ ? adaptation_->error() : std::string(); }

// --- display, analysis, selection ------------------------------------------

DisplayState EditorSession::display() const {
  DisplayState d;
  if (!input_) return d;
  if (!adaptation_) {
    d.snapshot = t0_snapshot_;
    d.version = version_ * 1000003ull;
    return d;
  }
  const auto tl = adaptation_->timeline();
  const std::size_t i = scrub_ >= 0 && static_cast<std::size_t>(scrub_) < tl.size() ? static_cast<std::size_t>(scrub_) : tl.size() - 1;
  d.snapshot = tl[i];
  d.version = version_ * 1000003ull + adaptation_->version() * 7919ull + i;
  return d;
}

void EditorSession::forget_distance() {
  if (distance_job_.valid()) distance_job_.wait();  // it reads T_G and the locator
  distance_job_ = {};
  distance_job_of_.reset();
  distance_pending_.reset();
  distance_locator_.reset();
  distance_.reset();
  distance_of_.reset();
  distance_seconds_ = 0;
  distance_error_.clear();
}

void EditorSession::start_distance(std::shared_ptr<const Snapshot> state) {
  distance_job_of_ = state;
  const SurfaceMesh* reference = &geometry_input();
  // One measure at a time: the locator is only touched by the thread that runs.
  distance_job_ = std::async(std::launch::async, [this, reference, state = std::move(state)] {
    Measured m;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (!distance_locator_) distance_locator_ = std::make_unique<Locator>(distance_locator(*reference));
      // One thread: the adaptation's worker and the drawing keep the others.
      SurfaceDistanceOptions o;
      o.threads = 1;
      m.distance = std::make_shared<const SurfaceDistance>(surface_distance(state->mesh, *distance_locator_, o));
    } catch (const std::exception& e) {
      m.error = e.what();
    }
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return m;
  });
}

void EditorSession::poll_distance() {
  if (distance_job_.valid() && distance_job_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    Measured m = distance_job_.get();
    distance_error_ = m.error;
    if (m.distance) {
      distance_ = std::move(m.distance);
      distance_of_ = distance_job_of_;
      distance_seconds_ = m.seconds;
    }
    distance_job_of_.reset();
  }
  if (!distance_job_.valid() && distance_pending_) {
    std::shared_ptr<const Snapshot> next = std::move(distance_pending_);
    distance_pending_.reset();
    if (next != distance_of_) start_distance(std::move(next));
  }
}

void EditorSession::request_distance(const std::shared_ptr<const Snapshot>& state) {
  if (!state || !input_) return;
  poll_distance();
  if (state == distance_of_ || state == distance_job_of_) {
    distance_pending_.reset();  // the latest request is served
    return;
  }
  distance_pending_ = state;
  poll_distance();
}

std::shared_ptr<const SurfaceDistance> EditorSession::ready_distance(const std::shared_ptr<const Snapshot>& state) {
  poll_distance();
  return state && state == distance_of_ ? distance_ : nullptr;
}

std::shared_ptr<const SurfaceDistance> EditorSession::distance() { return distance(display().snapshot); }

std::shared_ptr<const SurfaceDistance> EditorSession::distance(const std::shared_ptr<const Snapshot>& state) {
  if (!state || !input_) return nullptr;
  request_distance(state);
  while (state != distance_of_ && distance_job_.valid()) {
    distance_job_.wait();
    poll_distance();
  }
  if (state != distance_of_) throw Error("the distance to the input could not be measured: " + distance_error_);
  return distance_;
}

std::shared_ptr<const SurfaceDistance> EditorSession::last_distance(bool* of_displayed) const {
  if (of_displayed) *of_displayed = distance_ && distance_of_ == display().snapshot;
  return distance_;
}

void EditorSession::collect_analysis(bool wait) {
  if (!analysis_job_.valid()) return;
  if (!wait && analysis_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  analysis_ = analysis_job_.get();
  analysis_of_ = std::move(analysis_job_of_);
  analysis_job_of_.reset();
}

const Analysis* EditorSession::latest_analysis() {
  collect_analysis(false);
  const DisplayState d = display();
  if (d.snapshot && d.snapshot != analysis_of_ && !analysis_job_.valid()) {
    analysis_job_of_ = d.snapshot;
    // The snapshot is immutable and held by the job.
    analysis_job_ = std::async(std::launch::async, [snap = d.snapshot] {
      return analyze(snap->mesh, snap->metric);
    });
  }
  return analysis_of_ ? &analysis_ : nullptr;
}

const Analysis& EditorSession::analysis() {
  collect_analysis(true);
  const DisplayState d = display();
  if (d.snapshot && d.snapshot != analysis_of_) {
    analysis_ = analyze(d.snapshot->mesh, d.snapshot->metric);
    analysis_of_ = d.snapshot;
  }
  return analysis_;
}

void EditorSession::select_bin(BinKind kind, int bin) {
  const DisplayState d = display();
  if (!d.snapshot) throw Error("no mesh: open one first");
  selection_ = editor::select_bin(d.snapshot->mesh, analysis(), kind, bin);
  selection_.of = d.snapshot;
  selection_.version = ++selection_counter_;
  log(std::string("select-bin ") + bin_kind_name(kind) + " " + std::to_string(bin));
  ++version_;
}

void EditorSession::clear_selection() {
  selection_ = {};
  selection_.version = ++selection_counter_;
  ++version_;
}

namespace {

// Saving never creates directories: a mistyped path is refused, not made.
void require_existing_directory(const std::string& output) {
  const std::filesystem::path parent = std::filesystem::path(output).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  if (!std::filesystem::is_directory(parent, ec))
    throw Error("cannot save " + output + ": " +
                (std::filesystem::exists(parent, ec) ? "'" + parent.string() + "' is not a directory"
                                                     : "directory '" + parent.string() + "' does not exist") +
                ", expected an existing directory (save does not create directories)");
}

}  // namespace

void EditorSession::save(const std::string& mesh_path, const std::string& sol_path) {
  const DisplayState d = display();
  if (!d.snapshot) throw Error("no mesh: open one first");
  // The metric as a field follows the vertices through compact().
  SurfaceMesh m = d.snapshot->mesh;
  if (!sol_path.empty()) set_metric_field(m, d.snapshot->metric, "metric");
  m.compact();
  for (const std::string& p : {mesh_path, sol_path})
    if (!p.empty()) require_existing_directory(p);
  // The mesh and its metric as one set: both replaced, or neither.
  OutputSet outputs;
  save_mesh(outputs.temporary(mesh_path), m);
  if (!sol_path.empty()) write_sol(outputs.temporary(sol_path), extract_fields(m), m.n_vertices(), 3);
  outputs.commit();
  for (const std::string& p : {mesh_path, sol_path})
    if (!p.empty()) {
      const std::string a = absolute_path(p);
      if (std::find(written_.begin(), written_.end(), a) == written_.end()) written_.push_back(a);
    }
  log("save " + mesh_path + (sol_path.empty() ? "" : " " + sol_path));
  dirty_ = false;
}

std::vector<std::string> EditorSession::would_overwrite(const std::string& mesh_path, const std::string& sol_path) const {
  std::vector<std::string> out;
  for (const std::string& p : {mesh_path, sol_path}) {
    if (p.empty()) continue;
    std::error_code ec;
    const std::string a = absolute_path(p);
    if (std::filesystem::exists(p, ec) && std::find(written_.begin(), written_.end(), a) == written_.end())
      out.push_back(a);
  }
  return out;
}

std::string default_save_mesh(const std::string& opened) {
  std::filesystem::path p = absolute_path(opened);
  return (p.parent_path() / (p.stem().string() + ".adapted.mesh")).string();
}

std::string default_save_sol(const std::string& opened) {
  std::filesystem::path p = absolute_path(opened);
  return (p.parent_path() / (p.stem().string() + ".adapted.sol")).string();
}

}  // namespace anisurf::editor
