#include "editor/editor_view.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "geometry/normals.h"
#include "render/point_sampling.h"

namespace anisurf::editor {

namespace {

const char* kMeshName = "mesh";
const char* kBezierName = "G1 surface";
const char* kPlacementName = "vertex placement";

std::string quantity_of(const std::string& color) {
  namespace q = render::quantity;
  if (color == "size") return q::kSize;
  if (color == "aniso") return q::kAniso;
  if (color == "length") return q::kLength;
  if (color == "quality") return q::kQuality;
  if (color == "ref") return q::kReference;
  if (color == "deviation") return q::kDeviation;
  if (color == "distance") return q::kDistance;
  if (color == "fallback") return kPlacementName;
  return "";
}

// The colours of the placements: the G1 surface neutral (the surface's own
// grey), the input fallback red, off the surface green.
glm::vec3 placement_color(VertexPlacement p) {
  switch (p) {
    case VertexPlacement::Pulled: return {0.88f, 0.12f, 0.10f};
    case VertexPlacement::OffSurface: return {0.10f, 0.62f, 0.25f};
    case VertexPlacement::OnSurface:
    case VertexPlacement::None: break;
  }
  return {0.80f, 0.81f, 0.84f};
}

// "pulled to the input: 312 vertices (2.1%)".
std::string placement_row(const PlacementCounts& c, VertexPlacement p) {
  char buf[96];
  const int n = c.count(p);
  std::snprintf(buf, sizeof buf, "%s: %d %s (%.1f%%)", placement_name(p), n, n == 1 ? "vertex" : "vertices", c.percent(p));
  return buf;
}

// The "fallback" colours of a state: each vertex by its placement (the
// engine's, recorded in the snapshot's mesh), the counts in the legend. A
// state without placements (the initial mesh) is drawn neutral, and the
// legend says why.
render::VertexCategories placement_categories(const render::MeshStructure& ms, const Snapshot& snap) {
  render::VertexCategories q;
  q.name = kPlacementName;
  std::vector<VertexPlacement> per_slot;
  count_placements(snap.mesh, &per_slot);
  const PlacementCounts& c = snap.placement;
  q.values.assign(ms.structure.geometry.positions.size(), 0);
  if (!c.known) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "input vertices: %d", c.vertices);
    q.categories.push_back({buf, placement_color(VertexPlacement::None)});
    q.note = snap.has_report ? "this state records no placements"
                             : "the initial mesh: its vertices are the input's; the passes place the vertices they make or move.";
    return q;
  }
  const VertexPlacement order[] = {VertexPlacement::OnSurface, VertexPlacement::Pulled, VertexPlacement::OffSurface};
  for (VertexPlacement p : order) q.categories.push_back({placement_row(c, p), placement_color(p)});
  for (std::size_t v = 0; v < per_slot.size() && v < ms.draw_vertex.size(); ++v) {
    const int g = ms.draw_vertex[v];
    if (g < 0 || static_cast<std::size_t>(g) >= q.values.size()) continue;
    const VertexPlacement p = per_slot[v];
    q.values[static_cast<std::size_t>(g)] = p == VertexPlacement::Pulled ? 1 : p == VertexPlacement::OffSurface ? 2 : 0;
  }
  q.note = "pulled: the G1 surface strayed beyond the input bound there, the vertex was pulled back towards the "
           "input. Off: a split at the straight midpoint, or a hausd split part of the way to the input.";
  return q;
}

glm::vec3 to_glm(const Vec3& p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }

// The legend's lines under the distance colours: what is coloured, and the
// largest distance over every kind of sample (the colours show the vertices).
std::string distance_note(const SurfaceDistance& d) {
  const DistanceSample w = d.worst_sample();
  char buf[160];
  std::snprintf(buf, sizeof buf, "T_1 to the input T_G at the vertices\nmax %.3g (%.3g%%) at %s %s", d.max(),
                d.percent(d.max()), w == DistanceSample::Midpoint ? "an" : "a", distance_sample_name(w));
  return buf;
}

// The top of the distance colours: the 98th percentile of the vertex
// distances, so that a few far vertices do not leave the rest dark (the
// farthest ones saturate; the note gives the maximum); the largest distance
// when that percentile is 0, a thousandth of the diagonal when all are 0.
float distance_range_top(const render::ScalarQuantity& q, const SurfaceDistance& d) {
  std::vector<float> v;
  v.reserve(q.values.size());
  for (float x : q.values)
    if (std::isfinite(x)) v.push_back(x);
  float top = 0.0f;
  if (!v.empty()) {
    const auto k = static_cast<std::size_t>(0.98 * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    top = v[k];
  }
  if (!(top > 0.0f)) top = static_cast<float>(d.vertices.max);
  if (!(top > 0.0f)) top = static_cast<float>(1e-3 * d.reference_diagonal);
  return top > 0.0f ? top : 1.0f;
}

}  // namespace

bool EditorView::has_distance() const {
  for (const auto& q : mesh_.structure.scalars)
    if (q.name == render::quantity::kDistance) return true;
  return false;
}

namespace {

// The "distance to input" quantity of a mesh structure.
void add_distance_to(render::MeshStructure& ms, const SurfaceDistance& d) {
  render::ScalarQuantity q = render::vertex_quantity(ms, render::quantity::kDistance, d.vertex);
  q.colormap = render::Colormap::Viridis;
  q.range_min = 0.0f;
  q.range_max = distance_range_top(q, d);
  q.percent_of = static_cast<float>(d.reference_diagonal);
  q.note = distance_note(d);
  ms.structure.scalars.push_back(std::move(q));
}

// The touched vertices' markers: at most EditorView::kMaxTouchedMarkers
// drawn, spread over the touched region (render::spread_sample); `counts`
// receives how many are drawn of how many.
render::Markers touched_markers(const render::MeshStructure& ms, const std::vector<int>& touched, bool enabled,
                                EditorView::MarkerCounts& counts) {
  std::vector<glm::vec3> all;
  std::vector<char> seen(ms.draw_vertex.size(), 0);
  for (int v : touched)
    if (v >= 0 && v < static_cast<int>(ms.draw_vertex.size()) && ms.draw_vertex[v] >= 0 && !seen[v]) {
      seen[v] = 1;
      all.push_back(ms.structure.geometry.positions[static_cast<std::size_t>(ms.draw_vertex[v])]);
    }
  render::Markers mk{EditorView::kTouchedName, {}, {1.0f, 0.55f, 0.0f}, 3.0f, enabled};
  for (std::size_t i : render::spread_sample(all, EditorView::kMaxTouchedMarkers)) mk.positions.push_back(all[i]);
  counts = {static_cast<int>(mk.positions.size()), static_cast<int>(all.size())};
  return mk;
}

// The structure of a state (the body of a mesh build, in its thread): the
// mesh with its metric's quantities, the colour ranges `kept` (by quantity
// name), the placements, the touched vertices and the distance to T_G.
render::MeshStructure build_mesh(const Snapshot& snap, const SurfaceDistance* distance,
                                 const std::vector<std::pair<std::string, std::array<float, 2>>>& kept, bool show_touched,
                                 EditorView::MarkerCounts& touched) {
  SurfaceMesh m = snap.mesh;
  set_metric_field(m, snap.metric, "metric");
  render::MeshStructureOptions o;
  o.metric_field = "metric";
  render::MeshStructure ms = render::make_mesh_structure(m, kMeshName, o);
  for (auto& q : ms.structure.scalars)
    for (const auto& [name, r] : kept)
      if (q.name == name) {
        // Widened to the new values' own range: painted sizes beyond the
        // kept ends move the legend's ends instead of saturating.
        q.range_min = std::min(r[0], q.range_min);
        q.range_max = std::max(r[1], q.range_max);
      }
  ms.structure.categories.push_back(placement_categories(ms, snap));
  // The vertices the displayed pass created, kept or moved.
  touched = {};
  if (snap.has_report && !snap.report.touched.empty())
    ms.structure.markers.push_back(touched_markers(ms, snap.report.touched, show_touched, touched));
  if (distance) add_distance_to(ms, *distance);
  return ms;
}

}  // namespace

void EditorView::add_distance(const SurfaceDistance& d) {
  add_distance_to(mesh_, d);
  mesh_.structure.version = ++counter_;
}

EditorView::NextState EditorView::next_to_show(EditorSession& session, const ViewState& view,
                                               const std::shared_ptr<const Snapshot>& displayed) {
  if (view.color != "distance") return {displayed, nullptr};
  session.request_distance(displayed);
  if (auto d = session.ready_distance(displayed)) return {displayed, d};
  // Not measured yet: a new mesh (or a failed measure) is shown at once, without
  // colours; otherwise the shown state stays, or during a run the latest pass
  // measured is shown, so that the colours always belong to the mesh drawn.
  if (!shown_ || shown_opened_ != session.opened() || !session.distance_error().empty()) return {displayed, nullptr};
  const auto measured = session.last_measured();
  if (session.running() && measured && measured != shown_)
    for (const auto& s : session.timeline())
      if (s == measured) return {measured, session.ready_distance(measured)};
  return {shown_, nullptr};
}

EditorView::~EditorView() {
  if (bezier_job_.valid()) bezier_job_.wait();
  if (mesh_job_.valid()) mesh_job_.wait();
}

bool EditorView::settled(const EditorSession& session, const ViewState& view) const {
  const auto displayed = session.display().snapshot;
  if (displayed && (shown_ != displayed || mesh_job_.valid())) return false;
  if (view.bezier > 0 && displayed && !bezier_current(view)) return false;
  if (view.color != "distance" || !displayed || !session.distance_error().empty()) return true;
  return shown_ == displayed && has_distance();
}

bool EditorView::bezier_current(const ViewState& view) const {
  return bezier_ && bezier_k_ == view.bezier && bezier_of_ == shown_ && bezier_epoch_ == net_epoch_;
}

double EditorView::bezier_build_seconds() const {
  if (!bezier_job_.valid()) return 0;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - bezier_job_start_).count();
}

void EditorView::start_mesh(const ViewState& view, const EditorSession& session, const NextState& next) {
  // Metric edits on the same input keep the colour ranges of the settings'
  // own metric (base_ranges_), widened to cover the new values (so painting
  // changes the colours only where it changes the metric, the legend spans
  // what was painted, and undoing every edit gives the first picture back);
  // another mesh, a pass or a new file take the ranges of their data.
  const bool keep = kept_for_ == session.opened() && !next.snapshot->has_report && kept_initial_ &&
                    kept_settings_ == session.settings();
  std::vector<std::pair<std::string, std::array<float, 2>>> kept;
  if (keep) kept = base_ranges_;
  mesh_job_keeps_ = keep;
  mesh_job_of_ = next.snapshot;
  mesh_job_opened_ = session.opened();
  mesh_job_settings_ = session.settings();
  mesh_job_ = std::async(std::launch::async, [snap = next.snapshot, distance = next.distance, kept = std::move(kept),
                                              touched = view.show_touched] {
    // At the window's priority: the pass is on screen once it is built.
    const auto t0 = std::chrono::steady_clock::now();
    MeshBuilt b;
    b.structure = build_mesh(*snap, distance.get(), kept, touched, b.touched);
    b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return b;
  });
}

bool EditorView::collect_mesh() {
  if (!mesh_job_.valid() || mesh_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  MeshBuilt b = mesh_job_.get();
  mesh_ = std::move(b.structure);
  mesh_.structure.version = ++counter_;
  build_seconds_ = b.seconds;
  touched_counts_ = b.touched;
  if (!mesh_job_keeps_) {
    base_ranges_.clear();
    for (const auto& q : mesh_.structure.scalars) base_ranges_.push_back({q.name, {q.range_min, q.range_max}});
  }
  shown_ = std::move(mesh_job_of_);
  mesh_job_of_.reset();
  shown_opened_ = mesh_job_opened_;
  kept_for_ = mesh_job_opened_;
  kept_initial_ = !shown_->has_report;
  kept_settings_ = mesh_job_settings_;
  return true;
}

int EditorView::bezier_samples(int requested, int triangles) {
  int k = std::max(requested, 1);
  while (k > 1 && static_cast<long long>(k) * k * triangles > kBezierMaxTriangles) --k;
  return k;
}

void EditorView::start_bezier(const ViewState& view, const render::Scene& scene) {
  bezier_job_of_ = shown_;
  bezier_job_k_ = view.bezier;
  bezier_job_sampled_k_ = bezier_samples(view.bezier, shown_->mesh.n_triangles());
  bezier_job_epoch_ = net_epoch_;
  bezier_job_start_ = std::chrono::steady_clock::now();
  render::BezierStructureOptions bo;
  bo.k = bezier_job_sampled_k_;
  bo.control_net = view.control_net;
  // The wireframe toggle shows them (not the sub-triangles); sampled once per
  // triangle, the sub-triangles are the patches and the shader draws them.
  bo.patch_edges = bezier_job_sampled_k_ > 1;
  bo.net_max_patches = kNetMaxPatches;
  // The net around the point of the mesh at the centre of the view (what
  // the user looks at), else (the mesh's buffers still being built) around
  // the eye: the patches nearest to it face the camera, where the camera's
  // target (the middle of a closed surface) is as far from every patch.
  bo.net_centre = scene.camera.eye();
  if (const auto hit = render::pick(mesh_.structure.geometry, render::pixel_ray(scene.camera, 0.0f, 0.0f, 1, 1)))
    bo.net_centre = hit->point;
  // The snapshot is immutable and kept alive by the job.
  bezier_job_ = std::async(std::launch::async, [of = shown_, bo] {
    // Below the window's thread: it keeps drawing. Best effort.
    setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 5);
    const SurfaceMesh& m = of->mesh;  // tags as T_1 carries them
    const BezierSurface surface(m, compute_frames(m));
    BezierBuilt b;
    b.structure = render::make_bezier_structure(m, surface, kBezierName, bo, &b.net);
    return b;
  });
}

bool EditorView::collect_bezier(const ViewState& view) {
  if (!bezier_job_.valid() || bezier_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  BezierBuilt b = bezier_job_.get();
  std::shared_ptr<const Snapshot> of = std::move(bezier_job_of_);
  bezier_job_of_.reset();
  // A surface of an earlier state of the same mesh (a run went on
  // meanwhile) is still shown until the current one is built; another
  // sampling, a hidden surface or another opened mesh is dropped.
  if (view.bezier != bezier_job_k_ || shown_opened_ != bezier_job_opened_) return false;
  bezier_ = std::move(b.structure);
  bezier_->version = ++counter_;
  bezier_k_ = bezier_job_k_;
  bezier_sampled_k_ = bezier_job_sampled_k_;
  bezier_of_ = std::move(of);
  bezier_epoch_ = bezier_job_epoch_;
  net_info_ = b.net;
  return true;
}

void EditorView::update(EditorSession& session, ViewState& view, render::Scene& scene, float aspect, float reserve_left,
                        float reserve_right) {
  const DisplayState d = session.display();
  bool structures_changed = false;
  if (!d.snapshot) {
    if (!scene.surfaces.empty()) scene.surfaces.clear();
    shown_.reset();
    return;
  }
  // While the adaptation runs, a new pass is shown at most every 0.4 s (the
  // structure is rebuilt on this thread; the rest of the time goes to the
  // worker and to drawing).
  const auto now = std::chrono::steady_clock::now();
  const bool throttled = session.running() && shown_ && now - last_rebuild_ < std::chrono::milliseconds(400);
  if (session.opened() != opened_seen_) {  // a new mesh: the iso view (front for a planar one)
    opened_seen_ = session.opened();
    if (!view.view_request)
      view.view_request = session.input().dimension() == 2 ? render::NamedView::Front : render::NamedView::Iso;
  }
  // With the distance colours, a state is shown once its distance to T_G is
  // measured (in the session's measuring thread; see next_to_show()). Its
  // structure is built in a thread of its own, one at a time: the state
  // shown so far stays until it is ready.
  structures_changed |= collect_mesh();
  if (d.snapshot != shown_ && !throttled && !mesh_job_.valid()) {
    const NextState next = next_to_show(session, view, d.snapshot);
    if (next.snapshot != shown_) {
      last_rebuild_ = now;
      start_mesh(view, session, next);
      if (synchronous_) {
        mesh_job_.wait();
        structures_changed |= collect_mesh();
      }
    }
  }
  if (!shown_) return;  // the first structure is being built
  // The distance colours chosen while a state is shown: added once measured.
  if (view.color == "distance" && shown_ && !has_distance()) {
    session.request_distance(shown_);
    if (const auto dist = session.ready_distance(shown_)) {
      add_distance(*dist);
      structures_changed = true;
    }
  }
  if (session.selection().version != selection_version_ || structures_changed) {
    selection_version_ = session.selection().version;
    mesh_.structure.highlight_triangles.clear();
    const Selection& sel = session.selection();
    if (sel.active && sel.of == shown_)
      for (int t : sel.triangles)
        if (t >= 0 && t < static_cast<int>(mesh_.draw_triangle.size()) && mesh_.draw_triangle[t] >= 0)
          mesh_.structure.highlight_triangles.push_back(static_cast<std::uint32_t>(mesh_.draw_triangle[t]));
    mesh_.structure.version = ++counter_;
    structures_changed = true;
  }
  const bool want_bezier = view.bezier > 0;
  if (want_bezier) {
    structures_changed |= collect_bezier(view);
    // A build is started for the state shown, once its structure is, and
    // once the camera is where it is going (the net is built around the
    // view's centre: not before the fit of a mesh just opened).
    const bool camera_settled = !view.fit_request && !view.view_request;
    if (!bezier_current(view) && !bezier_job_.valid() && camera_settled) {
      start_bezier(view, scene);
      bezier_job_opened_ = shown_opened_;
      if (synchronous_) {
        bezier_job_.wait();
        structures_changed |= collect_bezier(view);
      }
    }
  } else {
    collect_bezier(view);  // a build in progress is dropped once done
    if (bezier_) {
      bezier_.reset();
      bezier_of_.reset();
      structures_changed = true;
    }
  }

  // Scene: the G1 surface (when shown) replaces the mesh's faces; the mesh
  // stays for its wireframe-free quantities otherwise.
  if (structures_changed || scene.surfaces.empty()) {
    scene.surfaces.clear();
    if (bezier_) {
      // The metric glyphs and the touched vertices over the G1 surface too.
      render::SurfaceStructure b = *bezier_;
      b.glyphs = mesh_.structure.glyphs;
      for (const auto& mk : mesh_.structure.markers)
        if (mk.name == kTouchedName) b.markers.push_back(mk);
      b.version = ++counter_;
      scene.surfaces.push_back(std::move(b));
    }
    scene.surfaces.push_back(mesh_.structure);
  }
  // Toggles (cheap: no rebuild).
  for (auto& s : scene.surfaces) {
    if (s.name == kMeshName) {
      s.enabled = !bezier_;
      s.activate(view.color == "deviation" ? "" : quantity_of(view.color));
      for (auto& g : s.glyphs) g.enabled = view.glyphs;
      for (auto& c : s.curves) c.enabled = view.features;
      for (auto& mk : s.markers) mk.enabled = mk.name == kTouchedName ? view.show_touched : view.features;
    } else if (s.name == kBezierName) {
      s.activate(view.color == "deviation" ? render::quantity::kDeviation : "");
      // Sampled once per triangle, the sub-triangles are the patches: the
      // shader's wireframe draws their edges (far cheaper than as curves).
      for (auto& c : s.curves)
        c.enabled = c.name == "patch edges" ? view.wireframe && bezier_sampled_k_ > 1 : view.control_net;
      for (auto& mk : s.markers) mk.enabled = mk.name == kTouchedName ? view.show_touched : view.control_net;
      for (auto& g : s.glyphs) g.enabled = view.glyphs;
    }
  }
  scene.display.wireframe = view.wireframe && (!bezier_ || bezier_sampled_k_ == 1);

  // Camera requests wait for the opened mesh's structure (a fit needs it).
  if (shown_opened_ != session.opened()) return;
  if (view.view_request) {
    scene.camera.set_view(*view.view_request);
    view.view_request.reset();
    view.fit_request = true;
  }
  if (view.fit_request) {
    scene.fit_camera(aspect, reserve_left, reserve_right);
    view.fit_request = false;
  }
  if (view.frame_selection) {
    view.frame_selection = false;
    const Selection& sel = session.selection();
    if (sel.active && sel.of == shown_) frame_triangle(sel.worst_triangle, scene, aspect, reserve_left, reserve_right);
  }
  if (view.frame_element) {
    frame_triangle(*view.frame_element, scene, aspect, reserve_left, reserve_right);
    view.frame_element.reset();
  }
}

namespace {

// The unit normal of triangle t (counter-clockwise seen from outside); for
// a triangle too thin to have a reliable one, the area-weighted normal of
// its fan (it and its edge neighbours).
Vec3 facing_normal(const SurfaceMesh& m, Triangle t) {
  auto area_normal = [&](Triangle u) {
    const Vec3 a = m.position(m.vertex(u, 0)), b = m.position(m.vertex(u, 1)), c = m.position(m.vertex(u, 2));
    return cross(b - a, c - a);
  };
  Vec3 n = area_normal(t);
  double longest = 0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, norm2(m.position(m.vertex(t, (k + 1) % 3)) - m.position(m.vertex(t, k))));
  if (norm(n) < 1e-3 * longest)
    for (int k = 0; k < 3; ++k) {
      const Corner o = m.opposite(SurfaceMesh::corner(t, k));
      if (o.is_valid()) n += area_normal(SurfaceMesh::triangle(o));
    }
  const double len = norm(n);
  return len > 0 ? n / len : Vec3(0, 0, 1);
}

}  // namespace

void EditorView::frame_triangle(int slot, render::Scene& scene, float aspect, float reserve_left,
                                float reserve_right) const {
  if (!shown_) return;
  const SurfaceMesh& m = shown_->mesh;
  const Triangle t(slot);
  if (slot < 0 || slot >= m.triangle_capacity() || m.is_deleted(t)) return;
  Vec3 c;
  for (int k = 0; k < 3; ++k) c += m.position(m.vertex(t, k)) / 3.0;
  const BBox box = m.bbox();
  const double diagonal = norm(box.hi - box.lo);
  // Looking at the element's front along its normal; its corners pushed
  // away from its centroid by 1 / kFrameFill, and their mirror images
  // through it, are fitted: the centroid at the centre of the free part of
  // the view, the element spanning about kFrameFill of it (not less than
  // 10^-4 of the diagonal around it).
  scene.camera.look_along(-to_glm(facing_normal(m, t)));
  std::vector<glm::vec3> pts;
  for (int k = 0; k < 3; ++k) {
    const Vec3 out = (m.position(m.vertex(t, k)) - c) / kFrameFill;
    pts.push_back(to_glm(c + out));
    pts.push_back(to_glm(c - out));  // symmetric: the centroid at the centre
  }
  const glm::vec3 e = to_glm(Vec3(1, 1, 1) * (1e-4 * diagonal));
  pts.push_back(to_glm(c) - e);
  pts.push_back(to_glm(c) + e);
  scene.camera.fit(pts, aspect, 0.0f, reserve_left, reserve_right);
  // The near and far planes keep the whole mesh (fit() set them around the
  // element alone): the surroundings stay visible when zooming out.
  scene.camera.scene_radius = std::max(scene.camera.scene_radius, static_cast<float>(0.5 * diagonal));
}

std::vector<render::WorldTriangle> EditorView::triangle_corners(std::span<const int> slots) const {
  std::vector<render::WorldTriangle> out;
  if (!shown_) return out;
  const SurfaceMesh& m = shown_->mesh;
  out.reserve(slots.size());
  for (int slot : slots) {
    if (slot < 0 || slot >= m.triangle_capacity() || m.is_deleted(Triangle(slot))) continue;
    render::WorldTriangle w;
    for (int k = 0; k < 3; ++k) w[static_cast<std::size_t>(k)] = to_glm(m.position(m.vertex(Triangle(slot), k)));
    out.push_back(w);
  }
  return out;
}

void EditorView::size_markers(render::Scene& scene, int width, int height) const {
  for (auto& s : scene.surfaces)
    for (auto& mk : s.markers) {
      if (mk.name != kTouchedName || !mk.enabled || mk.positions.empty()) continue;
      int inside = 0;
      for (const glm::vec3& p : mk.positions)
        if (const auto px = render::project_to_pixel(scene.camera, p, width, height))
          inside += px->x >= 0 && px->y >= 0 && px->x < static_cast<float>(width) && px->y < static_cast<float>(height);
      // Discs covering about 3% of the view together.
      const float area = 0.03f * static_cast<float>(width) * static_cast<float>(height) / static_cast<float>(std::max(inside, 1));
      mk.radius_px = std::clamp(std::sqrt(area / 3.14159265f), 1.5f, 4.5f);
    }
}

std::optional<HoverInfo> EditorView::hover(const render::Scene& scene, float x, float y, int width, int height) const {
  if (!shown_ || scene.surfaces.empty()) return std::nullopt;
  const render::SurfaceStructure* s = nullptr;
  for (const auto& st : scene.surfaces)
    if (st.name == kMeshName) s = &st;
  if (!s) return std::nullopt;
  const auto hit = render::pick(s->geometry, render::pixel_ray(scene.camera, x, y, width, height));
  if (!hit) return std::nullopt;
  HoverInfo h;
  h.point = Vec3(hit->point.x, hit->point.y, hit->point.z);
  for (std::size_t t = 0; t < mesh_.draw_triangle.size(); ++t)
    if (mesh_.draw_triangle[t] == static_cast<int>(hit->triangle)) {
      h.triangle = static_cast<int>(t);
      break;
    }
  if (h.triangle < 0) return std::nullopt;
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (hit->barycentric[i] > hit->barycentric[k]) k = i;
  h.vertex = shown_->mesh.vertex(Triangle(h.triangle), k).idx;
  return h;
}

}  // namespace anisurf::editor
