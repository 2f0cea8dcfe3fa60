#include "remesh/adapted_mesh.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "locate/closest_point.h"
#include "mesh/operators.h"
#include "metric/quality.h"

namespace anisurf::remesh {

AdaptedMesh::AdaptedMesh(SurfaceMesh initial, GeometrySurface& geometry, ControlSpace& control, LengthFormula length,
                         bool project_initial, const InputBound& bound)
    : mesh_(std::move(initial)), geometry_(geometry), control_(control), length_(length), bound_(bound) {
  auto& props = mesh_.vertex_properties();
  for (const char* n : {kMetricProperty, kIsotropicMetricProperty, "remesh:normal", "remesh:on_surface", "remesh:hint_g",
                        "remesh:hint_0"})
    props.remove(n);
  // Fields of the initial mesh that are not solution fields of T_0 (its
  // metric: T_1 keeps its own in remesh:metric) would follow every new
  // vertex for nothing (48 bytes each).
  std::vector<std::string> stale;
  for (const FieldInfo& f : mesh_.fields()) {
    const auto& infos = control_.field_infos();
    if (std::none_of(infos.begin(), infos.end(), [&](const FieldInfo& g) { return g.name == f.name; }))
      stale.push_back(f.name);
  }
  for (const std::string& n : stale) mesh_.remove_field(n);
  if (control_.is_isotropic()) mesh_.add_vertex_property<double>(kIsotropicMetricProperty, 1.0);
  bind_properties();
  mark_rough_triangles();
  measure_sagitta();

  // Initial locations. T_1's vertices that are T_G's own (T_1 starts as a
  // copy of T_G) are located there, in parallel chunks when T_0 is T_G too
  // (nothing is searched). The others by propagation (section 4.3):
  // breadth-first over T_1, each vertex searched from the hints of the
  // neighbours already located. Positions are kept (T_1 starts on the
  // geometry) unless project_initial.
  const int nv = mesh_.vertex_capacity();
  std::vector<char> seen(static_cast<std::size_t>(nv), 0);
  if (!project_initial && control_.is_geometry()) {
    auto locate_input_vertices = [&] {
      run_chunks(nv, chunk_count(nv, 16384), [&](int, int begin, int end) {
        for (int i = begin; i < end; ++i) {
          const Vertex v(i);
          if (mesh_.is_deleted(v) || mesh_.is_isolated(v)) continue;
          std::optional<Placement> p = place_at_input_vertex(v, mesh_.position(v), kind(v));
          if (!p) continue;
          commit(v, *p);
          seen[v.idx] = 2;
        }
      });
    };
    committing_in_parallel_ = true;
    locate_input_vertices();
    committing_in_parallel_ = false;
    if (lost_isotropy_) {
      store_full_metric();
      locate_input_vertices();
    }
  }
  std::deque<Vertex> queue;
  for (Vertex seed : mesh_.vertices()) {
    if (mesh_.is_isolated(seed) || seen[seed.idx]) continue;
    seen[seed.idx] = 1;
    queue.push_back(seed);
    while (!queue.empty()) {
      const Vertex v = queue.front();
      queue.pop_front();
      std::vector<Vertex> near;
      for (Vertex w : mesh_.ring_vertices(v))
        if (seen[w.idx] == 2) near.push_back(w);
      const Vec3 x = mesh_.position(v);
      const VertexKind k = kind(v);
      std::optional<Placement> same = project_initial ? std::nullopt : place_at_input_vertex(v, x, k);
      Placement p = same ? std::move(*same) : place(x, k, near);
      if (!project_initial) p.position = x;
      commit(v, p);
      seen[v.idx] = 2;
      for (Vertex w : mesh_.ring_vertices(v))
        if (!seen[w.idx]) {
          seen[w.idx] = 1;
          queue.push_back(w);
        }
    }
  }
}

AdaptedMesh::AdaptedMesh(SurfaceMesh part, const AdaptedMesh& whole, GeometrySurface& geometry, ControlSpace& control)
    : mesh_(std::move(part)),
      geometry_(geometry),
      control_(control),
      length_(whole.length_),
      rough_(whole.rough_),
      bound_(whole.bound_),
      sagitta_(whole.sagitta_) {
  bind_properties();
}

bool stores_isotropic_metric(const SurfaceMesh& mesh) {
  return static_cast<bool>(mesh.get_vertex_property<double>(kIsotropicMetricProperty));
}

void widen_metric_property(SurfaceMesh& mesh) {
  const Property<double> iso = mesh.get_vertex_property<double>(kIsotropicMetricProperty);
  if (!iso) return;
  Property<PackedMetric> full = mesh.vertex_property<PackedMetric>(kMetricProperty);
  for (int i = 0; i < mesh.vertex_capacity(); ++i) full[Vertex(i)] = PackedMetric::pack(SymTensor3::identity(iso[Vertex(i)]));
  mesh.vertex_properties().remove(kIsotropicMetricProperty);
}

void AdaptedMesh::store_full_metric() {
  if (!iso_) return;
  widen_metric_property(mesh_);
  bind_properties();
}

void AdaptedMesh::set_metric(Vertex v, const SymTensor3& M) {
  if (iso_) {
    if (is_isotropic(M)) {
      metric_iso_[v] = M.m[0];
      return;
    }
    if (committing_in_parallel_) {
      lost_isotropy_ = true;
      return;
    }
    store_full_metric();
  }
  metric_[v] = PackedMetric::pack(M);
}

double AdaptedMesh::isotropic_length(Vertex a, Vertex b) const {
  const Vec3 e = mesh_.position(b) - mesh_.position(a);
  const double ee = dot(e, e), la = metric_iso_[a], lb = metric_iso_[b];
  const double l0 = std::sqrt(la * ee);
  if (la == lb) return l0;
  const double l1 = std::sqrt(lb * ee);
  return length_ == LengthFormula::LinearMetric ? length_linear_metric(l0, l1) : length_linear_size(l0, l1);
}

void AdaptedMesh::bind_properties() {
  metric_iso_ = mesh_.get_vertex_property<double>(kIsotropicMetricProperty);
  iso_ = static_cast<bool>(metric_iso_);
  metric_ = iso_ ? Property<PackedMetric>() : mesh_.vertex_property<PackedMetric>(kMetricProperty);
  normal_ = mesh_.vertex_property<PackedNormal>("remesh:normal");
  on_surface_ = mesh_.vertex_property<std::uint8_t>("remesh:on_surface", 1);
  hint_g_ = mesh_.vertex_property<Hint>("remesh:hint_g");
  // T_0 is T_G: a location on T_G is the location on T_0, its hint too.
  hint_0_ = control_.same_as_geometry() ? Property<Hint>() : mesh_.vertex_property<Hint>("remesh:hint_0");
  solution_.clear();
  for (const FieldInfo& f : control_.field_infos()) {
    Property<FieldValue> p = mesh_.get_field(f.name);
    if (!p) p = mesh_.add_field(f.name, f.kind, f.ncomp);
    solution_.push_back(p);
  }
}

Constraint AdaptedMesh::constraint(VertexKind k) const {
  switch (k) {
    case VertexKind::Free: return Constraint::Free;
    case VertexKind::Curve: return Constraint::OnFeature;
    case VertexKind::Fixed: return Constraint::Fixed;
  }
  return Constraint::Free;
}

VertexKind AdaptedMesh::kind(Vertex v) const {
  const std::uint8_t tags = mesh_.vertex_tags(v);
  if (tags & (kCorner | kRequired)) return VertexKind::Fixed;
  // Vertices on feature edges carry kRidge / kBoundary (detect_features, and
  // the split and collapse operators keep it so): the others are free.
  if (!(tags & (kRidge | kBoundary)) && !mesh_.is_boundary(v)) return VertexKind::Free;
  const std::size_t n = feature_edges_at(mesh_, v).size();
  if (n == 0) return VertexKind::Free;
  return n == 2 ? VertexKind::Curve : VertexKind::Fixed;
}

Placement AdaptedMesh::place(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near) {
  return place(x, kind, std::span<const Vertex>(near.begin(), near.size()));
}

Placement AdaptedMesh::place(const Vec3& x, VertexKind kind, std::span<const Vertex> near) {
  std::array<Hint, 8> h0{};
  std::size_t n = 0;
  const Projection pr = project_from(x, kind, near, h0, n);
  return placement_at(x, kind, pr, h0, n);
}

Vec3 AdaptedMesh::placed_position(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near) {
  if (kind == VertexKind::Fixed) return x;  // not moved (place() only locates it)
  std::array<Hint, 8> h0{};
  std::size_t n = 0;
  const Projection pr = project_from(x, kind, std::span<const Vertex>(near.begin(), near.size()), h0, n);
  return position_placed_at(x, kind, pr, h0, n);
}

Vec3 AdaptedMesh::position_placed_at(const Vec3& x, VertexKind kind, const Projection& pr,
                                     const std::array<Hint, 8>& h0, std::size_t n) {
  // pull_towards_input leaves the point where it is when it lies within the
  // least tolerance of its input triangle.
  if (!bound_.enabled || !pr.location.is_valid() ||
      !(norm(pr.point - pr.location.point) > least_input_tolerance(pr.location.triangle)))
    return pr.point;
  return placement_at(x, kind, pr, h0, n).position;
}

bool AdaptedMesh::placed_within(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near, double tol) {
  if (kind != VertexKind::Free) return norm(placed_position(x, kind, near) - x) <= tol;
  std::array<Hint, 8> hg{};
  std::array<Hint, 8> h0{};
  const std::size_t n = hints_of(std::span<const Vertex>(near.begin(), near.size()), hg, &h0);
  const std::span<const Hint> hints(hg.data(), n);
  if (geometry_.projects_onto_input()) return geometry_.input_within(x, tol, hints);
  // On the G1 surface: a surface point within tol settles it, taken at the
  // location c' of the first triangle of T_G found within tol (within the
  // deviation bound of c' by the bound alone, else evaluated; a point placed
  // there, between c' and that surface point, is as close).
  // Without a bound (the Closest projection) the placed point decides.
  Location c = geometry_.first_on_input_within(x, tol, hints);
  const double first_dev = c.is_valid() ? geometry_.deviation_bound(c.triangle) : INFINITY;
  if (!std::isfinite(first_dev)) return norm(placed_position(x, kind, near) - x) <= tol;
  if (const double first_d = norm(c.point - x); first_d < tol) {
    if (first_d + first_dev <= tol * (1 - 1e-9)) return true;
    if (norm(geometry_.at(c).point - x) <= tol) return true;
    c = geometry_.closest_on_input(x, hints);
  }
  // Else the placed point: it lies between the surface point S at x's
  // closest location c on T_G and c itself (pull_towards_input), |S - c| <=
  // dev, so within |c - x| + dev of x and no closer than |c - x| - dev:
  // only a test between the two evaluates the surface (margins for the
  // rounding).
  const double dev = c.is_valid() ? geometry_.deviation_bound(c.triangle) : INFINITY;
  if (!std::isfinite(dev)) return norm(placed_position(x, kind, near) - x) <= tol;
  const double d = norm(c.point - x);
  if (d + dev <= tol * (1 - 1e-9)) return true;
  if (d - dev > tol * (1 + 1e-9)) return false;
  return norm(position_placed_at(x, kind, geometry_.at(c), h0, n) - x) <= tol;
}

std::size_t AdaptedMesh::hints_of(std::span<const Vertex> near, std::array<Hint, 8>& hg,
                                  std::array<Hint, 8>* h0) const {
  std::size_t n = 0;
  for (Vertex v : near) {
    if (n == hg.size()) break;
    if (!hint_g_[v].is_valid()) continue;
    hg[n] = hint_g_[v];
    if (h0) (*h0)[n] = hint_0(v);
    ++n;
  }
  return n;
}

Projection AdaptedMesh::project_from(const Vec3& x, VertexKind kind, std::span<const Vertex> near,
                                     std::array<Hint, 8>& h0, std::size_t& n) {
  std::array<Hint, 8> hg{};
  n = hints_of(near, hg, &h0);
  // A fixed vertex is not moved: it is only located (as a free point).
  const Constraint c = kind == VertexKind::Fixed ? Constraint::Free : constraint(kind);
  return geometry_.project(x, std::span<const Hint>(hg.data(), n), c);
}

Placement AdaptedMesh::placement_at(const Vec3& x, VertexKind kind, const Projection& pr,
                                    const std::array<Hint, 8>& h0, std::size_t n) {
  Placement p;
  p.position = kind == VertexKind::Fixed ? x : pr.point;
  p.normal = kind == VertexKind::Free ? pr.normal : Vec3();
  p.distance = norm(pr.point - x);
  p.hint_g = pr.location.hint();
  const Location in0 = control_.locate(p.position, n ? h0[0] : Hint{}, pr.location);
  p.hint_0 = in0.hint();
  p.values = control_.values_at(in0);
  p.on_input = pr.location.is_valid() ? pr.location.point : p.position;
  if (kind != VertexKind::Fixed) pull_towards_input(p, pr.location);
  return p;
}

std::optional<Placement> AdaptedMesh::place_at_input_vertex(Vertex v, const Vec3& x, VertexKind kind) {
  const SurfaceMesh& g = geometry_.mesh();
  if (v.idx >= g.vertex_capacity() || g.is_deleted(v) || g.is_isolated(v) || !(g.position(v) == x)) return std::nullopt;
  const Corner c = g.corner(v);
  Location at;
  at.triangle = SurfaceMesh::triangle(c);
  at.bary[SurfaceMesh::local_index(c)] = 1;
  at.point = x;
  at.distance = 0;
  const Projection pr = geometry_.at(at);
  Placement p;
  p.position = x;
  p.normal = kind == VertexKind::Free ? pr.normal : Vec3();
  p.hint_g = at.hint();
  const Location in0 = control_.locate(x, Hint{}, at);
  p.hint_0 = in0.hint();
  p.values = control_.values_at(in0);
  p.on_input = x;
  return p;
}

AdaptedMesh::InputDistance AdaptedMesh::distance_to_input(const Vec3& x, std::initializer_list<Vertex> near) {
  std::array<Hint, 4> hg{};
  std::size_t n = 0;
  for (Vertex v : near)
    if (n < hg.size() && hint_g_[v].is_valid()) hg[n++] = hint_g_[v];
  const Location at = geometry_.closest_on_input(x, std::span<const Hint>(hg.data(), n));
  InputDistance out;
  out.distance = at.is_valid() ? norm(x - at.point) : 0.0;
  const Triangle t = at.triangle;
  if (bound_.enabled && t.is_valid() && static_cast<std::size_t>(t.idx) < sagitta_->size())
    out.natural = bound_.natural_factor * (*sagitta_)[static_cast<std::size_t>(t.idx)];
  return out;
}

double AdaptedMesh::distance_to_hinted_input(const Vec3& x, std::initializer_list<Vertex> near) const {
  const SurfaceMesh& g = geometry_.mesh();
  double d2 = INFINITY;
  for (Vertex v : near) {
    const Triangle t = hint_g_[v].triangle;
    if (!t.is_valid() || g.is_deleted(t)) continue;
    const int* w = g.triangle_vertices(t);
    d2 = std::min(d2, point_triangle_distance2(x, g.position(Vertex(w[0])), g.position(Vertex(w[1])), g.position(Vertex(w[2]))));
  }
  return std::sqrt(d2);
}

double AdaptedMesh::input_tolerance(Triangle t, const SymTensor3& M) const {
  const double tr = trace(M);
  const double h = tr > 0 ? std::sqrt(3.0 / tr) : INFINITY;
  const double natural =
      t.is_valid() && static_cast<std::size_t>(t.idx) < sagitta_->size() ? (*sagitta_)[static_cast<std::size_t>(t.idx)] : 0.0;
  double tol = std::max(bound_.size_fraction * h, bound_.natural_factor * natural);
  if (bound_.hausd > 0) tol = std::min(tol, bound_.hausd_fraction * bound_.hausd);
  return tol;
}

double AdaptedMesh::least_input_tolerance(Triangle t) const {
  const double natural =
      t.is_valid() && static_cast<std::size_t>(t.idx) < sagitta_->size() ? (*sagitta_)[static_cast<std::size_t>(t.idx)] : 0.0;
  double tol = bound_.natural_factor * natural;  // input_tolerance's max() is at least this
  if (bound_.hausd > 0) tol = std::min(tol, bound_.hausd_fraction * bound_.hausd);
  return tol;
}

void AdaptedMesh::pull_towards_input(Placement& p, const Location& on_geometry) const {
  if (!bound_.enabled || !on_geometry.is_valid()) return;
  const Vec3 off = p.position - on_geometry.point;
  const double d = norm(off);
  const double tol = input_tolerance(on_geometry.triangle, p.values.metric);
  if (!(d > tol)) return;
  p.position = on_geometry.point + off * (tol / d);
  p.pulled = true;
}

// Per triangle of T_G (in parallel chunks), 4/3 of |e| theta / 8 over its
// edges (InputBound): theta the dihedral angle across an edge inside a
// smooth region, or on a feature curve the angle the curve turns along the edge, |e| times its curvature
// (the mean of its ends' discrete curvatures, turn / mean length of the two
// edges there: right for a circle sampled unevenly). A corner has no
// curvature of its own (the curve may start in any direction): an edge with
// a corner at one end takes its other end's, whose circle the curve's
// tangent follows there (NormalOptions::corner_tangent_tolerance_deg), 0
// when both ends are corners.
void AdaptedMesh::measure_sagitta() {
  const SurfaceMesh& g = geometry_.mesh();
  auto sagitta = std::make_shared<std::vector<float>>(static_cast<std::size_t>(g.triangle_capacity()), 0.0f);
  // The curve's curvature at v, or -1 where v has none (corner, required, end).
  auto curvature = [&](Vertex v) {
    if (g.vertex_tags(v) & (kCorner | kRequired)) return -1.0;
    const auto fe = feature_edges_at(g, v);
    if (fe.size() != 2) return -1.0;
    const Vec3& p = g.position(v);
    const double mean_len = 0.5 * (norm(g.position(fe[0].other) - p) + norm(g.position(fe[1].other) - p));
    return mean_len > 0 ? anisurf::curve_turn(g, v, fe[0], fe[1]) / mean_len : -1.0;
  };
  auto edge_turn = [&](Vertex a, Vertex b, double len) {
    const double ka = curvature(a), kb = curvature(b);
    const double k = ka < 0 || kb < 0 ? std::max({ka, kb, 0.0}) : 0.5 * (ka + kb);
    return len * k;
  };
  const int nt_slots = g.triangle_capacity();
  run_chunks(nt_slots, chunk_count(nt_slots, 16384), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Triangle t(i);
      if (g.is_deleted(t)) continue;
      double worst = 0;
      const Vec3 nt = g.triangle_normal(t);
      for (int k = 0; k < 3; ++k) {
        const Corner c = SurfaceMesh::corner(t, k);
        const Vertex a = g.edge_from(c), b = g.edge_to(c);
        const double len = norm(g.position(b) - g.position(a));
        double theta = 0;
        if (is_feature_edge(g, c)) {
          theta = edge_turn(a, b, len);
        } else {
          const Vec3 no = g.triangle_normal(SurfaceMesh::triangle(g.opposite(c)));
          theta = vector_angle(nt, no);
        }
        worst = std::max(worst, len * theta / 8.0);
      }
      (*sagitta)[static_cast<std::size_t>(t.idx)] = static_cast<float>(4.0 / 3.0 * worst);
    }
  });
  sagitta_ = std::move(sagitta);
}

void AdaptedMesh::refresh_values() {
  for (Vertex v : mesh_.vertices()) {
    if (mesh_.is_isolated(v)) continue;
    // Located again (as a fixed point: the position does not change).
    const Placement p = place(mesh_.position(v), VertexKind::Fixed, {v});
    set_metric(v, p.values.metric);
    if (hint_0_) hint_0_[v] = p.hint_0;
    for (std::size_t f = 0; f < solution_.size() && f < p.values.fields.size(); ++f) solution_[f][v] = p.values.fields[f];
  }
}

Placement AdaptedMesh::current(Vertex v) const {
  Placement p;
  p.position = mesh_.position(v);
  p.normal = surface_normal(v);
  p.on_surface = on_surface_[v] != 0;
  p.pulled = on_surface_[v] == 2;
  p.hint_g = hint_g_[v];
  p.hint_0 = hint_0(v);
  p.values.metric = metric(v);
  for (const auto& s : solution_) p.values.fields.push_back(s[v]);
  return p;
}

void AdaptedMesh::commit(Vertex v, const Placement& p) {
  mesh_.position(v) = p.position;
  normal_[v] = pack_normal(p.normal);
  on_surface_[v] = !p.on_surface ? 0 : (p.pulled ? 2 : 1);
  hint_g_[v] = p.hint_g;
  if (hint_0_) hint_0_[v] = p.hint_0;
  set_metric(v, p.values.metric);
  for (std::size_t i = 0; i < solution_.size() && i < p.values.fields.size(); ++i) solution_[i][v] = p.values.fields[i];
}

double AdaptedMesh::quality(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M) const {
  return triangle_quality(p, M, length_);
}

double AdaptedMesh::quality(Triangle t) const {
  const Vertex a = mesh_.vertex(t, 0), b = mesh_.vertex(t, 1), c = mesh_.vertex(t, 2);
  return quality({mesh_.position(a), mesh_.position(b), mesh_.position(c)}, {metric(a), metric(b), metric(c)});
}

double AdaptedMesh::quality_in_one_metric(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M) const {
  return triangle_quality_in(p, centroid_metric(M, MetricInterpolation::Linear));
}

double AdaptedMesh::quality_in_one_metric(Triangle t) const {
  const Vertex a = mesh_.vertex(t, 0), b = mesh_.vertex(t, 1), c = mesh_.vertex(t, 2);
  return quality_in_one_metric({mesh_.position(a), mesh_.position(b), mesh_.position(c)},
                               {metric(a), metric(b), metric(c)});
}

int AdaptedMesh::count_inverted() {
  // Parallel chunks of triangle slots, each searching its own copy of the
  // surface (the first the surface itself): the searches' marks are per copy.
  const int nt = mesh_.triangle_capacity();
  const int chunks = chunk_count(nt, 32768);
  std::vector<std::unique_ptr<GeometrySurface>> copies(static_cast<std::size_t>(chunks));
  for (int k = 1; k < chunks; ++k) copies[static_cast<std::size_t>(k)] = geometry_.copy_for_thread();
  std::vector<int> counts(static_cast<std::size_t>(chunks), 0);
  run_chunks(nt, chunks, [&](int k, int begin, int end) {
    GeometrySurface& g = k == 0 ? geometry_ : *copies[static_cast<std::size_t>(k)];
    for (int i = begin; i < end; ++i)
      if (!mesh_.is_deleted(Triangle(i)) && is_inverted(Triangle(i), g)) ++counts[static_cast<std::size_t>(k)];
  });
  int n = 0;
  for (int c : counts) n += c;
  return n;
}

bool AdaptedMesh::near_feature(const Hint& h) const {
  if (!h.is_valid() || static_cast<std::size_t>(h.triangle.idx) >= rough_->size()) return true;
  return (*rough_)[static_cast<std::size_t>(h.triangle.idx)] != 0;
}

void AdaptedMesh::mark_rough_triangles() {
  const SurfaceMesh& g = geometry_.mesh();
  auto rough = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(g.triangle_capacity()), 0);
  constexpr double kFoldCosine = 0.5;           // 60 degrees
  constexpr double kConeCosine = 0.8668967489;  // cos 29.9 degrees
  const int nt = g.triangle_capacity(), nv = g.vertex_capacity();
  std::vector<Vec3> unit(static_cast<std::size_t>(nt));
  run_chunks(nt, chunk_count(nt, 16384), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i)
      if (!g.is_deleted(Triangle(i))) unit[static_cast<std::size_t>(i)] = normalized(g.triangle_normal(Triangle(i)));
  });
  // Vertex by vertex, each fan once: its triangles are all rough when v is
  // on a feature or has another sheet within a quarter of its edges (a thin
  // part, nearly touching sheets of a defective input: a point of T_1 near v
  // may be closest to that sheet); a triangle of the fan is rough when
  // another triangle of the fan turns more than 60 degrees from it. Marked
  // per corner (each corner is in one fan: no two chunks write the same
  // one), then a triangle is rough when one of its corners is.
  std::vector<std::uint8_t> rough_corner(static_cast<std::size_t>(3) * static_cast<std::size_t>(nt), 0);
  run_chunks(nv, chunk_count(nv, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Vertex v(i);
      if (g.is_deleted(v) || g.is_isolated(v)) continue;
      double longest = 0;
      for (Vertex w : g.ring_vertices(v)) longest = std::max(longest, norm(g.position(w) - g.position(v)));
      const bool rough_vertex = (g.vertex_tags(v) & (kRidge | kBoundary | kCorner | kRequired)) ||
                                geometry_.clearance(v) < 0.25 * longest;
      const FanCornerRange fan = g.fan_corners(v);
      // Every normal of the fan within 29.9 degrees of their mean: any two
      // within 59.8 degrees of each other, none turns past 60 (no pair to test).
      bool within_cone = !rough_vertex;
      if (within_cone) {
        Vec3 mean;
        for (Corner a : fan) mean += unit[static_cast<std::size_t>(SurfaceMesh::triangle(a).idx)];
        const Vec3 axis = normalized(mean);
        for (Corner a : fan)
          within_cone = within_cone && dot(unit[static_cast<std::size_t>(SurfaceMesh::triangle(a).idx)], axis) >= kConeCosine;
      }
      for (Corner a : fan) {
        const auto ta = static_cast<std::size_t>(SurfaceMesh::triangle(a).idx);
        bool r = rough_vertex;
        if (!within_cone)
          for (Corner b : fan)
            r = r || dot(unit[ta], unit[static_cast<std::size_t>(SurfaceMesh::triangle(b).idx)]) < kFoldCosine;
        rough_corner[static_cast<std::size_t>(a.idx)] = r ? 1 : 0;
      }
    }
  });
  run_chunks(nt, chunk_count(nt, 16384), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const auto c = static_cast<std::size_t>(3 * i);
      (*rough)[static_cast<std::size_t>(i)] = rough_corner[c] | rough_corner[c + 1] | rough_corner[c + 2];
    }
  });
  rough_ = std::move(rough);
}

bool AdaptedMesh::is_inverted(Triangle t) { return is_inverted(t, geometry_); }

bool AdaptedMesh::is_inverted(Triangle t, GeometrySurface& g) {
  std::array<Vec3, 3> p;
  std::array<bool, 3> free;
  std::array<Hint, 3> hints;
  for (int k = 0; k < 3; ++k) {
    const Vertex v = mesh_.vertex(t, k);
    p[k] = mesh_.position(v);
    free[k] = kind(v) == VertexKind::Free;
    hints[k] = hint_g_[v];
  }
  // Every corner free, on the surface away from features, its surface
  // normal (stored when it was placed) within 60 degrees of the triangle's:
  // the normal 1/10 of the way to the centroid, where the surface turns
  // slowly, faces the same way (no projection needed).
  const Vec3 nt = cross(p[1] - p[0], p[2] - p[0]);
  const double len = norm(nt);
  bool clear = len > 0;
  for (int k = 0; k < 3 && clear; ++k) {
    const Vertex v = mesh_.vertex(t, k);
    clear = free[k] && on_surface_[v] != 0 && !near_feature(hints[k]) && dot(nt, surface_normal(v)) > 0.5 * len;
  }
  if (clear) return false;
  return !faces_surface(p, free, hints, g);
}

bool AdaptedMesh::faces_surface(const std::array<Vec3, 3>& p, const std::array<bool, 3>& free,
                                const std::array<Hint, 3>& hints) {
  return faces_surface(p, free, hints, geometry_);
}

bool AdaptedMesh::faces_surface(const std::array<Vec3, 3>& p, const std::array<bool, 3>& free,
                                const std::array<Hint, 3>& hints, GeometrySurface& geometry) {
  const Vec3 nt = cross(p[1] - p[0], p[2] - p[0]);
  const Vec3 g = (p[0] + p[1] + p[2]) / 3.0;
  // Votes of the surface normal near the free corners (inside the
  // triangle, from the vertex's own hint, so on its sheet of a thin
  // part); at curve and fixed corners the surface has two sides, so a
  // triangle with no free corner votes once, at its centroid.
  // The majority decides: the votes stop once the rest cannot change it.
  const int votes = free[0] + free[1] + free[2];
  int cast = 0, against = 0;
  for (int k = 0; k < 3; ++k) {
    if (!free[k]) continue;
    if (2 * against > votes || 2 * (against + votes - cast) <= votes) break;
    const Projection pr = geometry.project(0.9 * p[k] + 0.1 * g, std::span<const Hint>(&hints[k], 1), Constraint::Free);
    ++cast;
    if (!(dot(nt, pr.normal) > 0)) ++against;
  }
  if (votes > 0) return 2 * against <= votes;
  // A triangle spanning a thin part between feature curves (the tip of a
  // wing or a tail: every corner on the curve where the two sheets meet)
  // lies between the sheets, its centroid about as close to the sheet it
  // faces as to the one behind it, so its closest point picks a sheet by
  // chance. When that sheet is behind the triangle and faces away, the
  // triangle is judged again from the centroid moved by that distance
  // along its normal: by the sheet it faces, when there is one in front of
  // it (a real inversion finds the same sheet again).
  const Projection first = geometry.project(g, std::span<const Hint>(&hints[0], 1), Constraint::Free);
  if (dot(nt, first.normal) > 0) return true;
  const double d = norm(first.point - g);
  const double area2 = norm(nt);
  if (d > 0 && area2 > 0 && dot(first.point - g, nt) < 0) {
    const Vec3 front = g + (d / area2) * nt;
    const Hint h1 = first.location.hint();
    const Projection second = geometry.project(front, std::span<const Hint>(&h1, 1), Constraint::Free);
    if (dot(second.point - g, nt) > 0 && dot(nt, second.normal) > 0) return true;
  }
  return false;
}

}  // namespace anisurf::remesh
