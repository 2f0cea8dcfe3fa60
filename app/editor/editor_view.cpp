#include "editor/editor_view.h"

#include <array>
#include <chrono>

#include "geometry/normals.h"
#include "render/bezier_structure.h"

namespace anisurf::editor {

namespace {

const char* kMeshName = "mesh";
const char* kBezierName = "G1 surface";

std::string quantity_of(const std::string& color) {
  namespace q = render::quantity;
  if (color == "size") return q::kSize;
  if (color == "aniso") return q::kAniso;
  if (color == "length") return q::kLength;
  if (color == "quality") return q::kQuality;
  if (color == "ref") return q::kReference;
  if (color == "deviation") return q::kDeviation;
  return "";
}

glm::vec3 to_glm(const Vec3& p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }

}  // namespace

void EditorView::rebuild_mesh(const ViewState& view, const EditorSession& session) {
  const auto t0 = std::chrono::steady_clock::now();
  SurfaceMesh m = shown_->mesh;
  set_metric_field(m, shown_->metric, "metric");
  render::MeshStructureOptions o;
  o.metric_field = "metric";
  // Metric edits on the same input keep the colour ranges (so painting
  // changes the colours only where it changes the metric); another mesh, a
  // pass or a new file take the ranges of their data.
  std::vector<std::pair<std::string, std::array<float, 2>>> kept;
  const bool keep = kept_for_ == session.opened() && !shown_->has_report && kept_initial_ &&
                    kept_settings_ == session.settings();
  if (keep)
    for (const auto& q : mesh_.structure.scalars) kept.push_back({q.name, {q.range_min, q.range_max}});
  mesh_ = render::make_mesh_structure(m, kMeshName, o);
  for (auto& q : mesh_.structure.scalars)
    for (const auto& [name, r] : kept)
      if (q.name == name) q.range_min = r[0], q.range_max = r[1];
  kept_for_ = session.opened();
  kept_initial_ = !shown_->has_report;
  kept_settings_ = session.settings();
  mesh_.structure.version = ++counter_;
  // The vertices the displayed pass created, kept or moved.
  if (shown_->has_report && !shown_->report.touched.empty()) {
    render::Markers mk{"touched by the pass", {}, {1.0f, 0.55f, 0.0f}, 3.0f, view.show_touched};
    if (shown_->report.touched.size() > 3000) mk.radius_px = 1.8f;  // dense: dots
    std::vector<char> seen(mesh_.draw_vertex.size(), 0);
    for (int v : shown_->report.touched)
      if (v >= 0 && v < static_cast<int>(mesh_.draw_vertex.size()) && mesh_.draw_vertex[v] >= 0 && !seen[v]) {
        seen[v] = 1;
        mk.positions.push_back(mesh_.structure.geometry.positions[static_cast<std::size_t>(mesh_.draw_vertex[v])]);
      }
    mesh_.structure.markers.push_back(std::move(mk));
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void EditorView::rebuild_bezier(const ViewState& view) {
  bezier_.reset();
  if (view.bezier <= 0 || !shown_) return;
  SurfaceMesh m = shown_->mesh;  // tags as T_1 carries them
  const BezierSurface surface(m, compute_frames(m));
  render::BezierStructureOptions bo;
  bo.k = view.bezier;
  bo.control_net = view.control_net;
  bo.patch_edges = true;  // the wireframe toggle shows them (not the sub-triangles)
  bezier_ = render::make_bezier_structure(m, surface, kBezierName, bo);
  bezier_->version = ++counter_;
  bezier_k_ = view.bezier;
  bezier_of_ = shown_.get();
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
  if (d.snapshot != shown_ && !throttled) {
    last_rebuild_ = now;
    shown_ = d.snapshot;
    rebuild_mesh(view, session);
    structures_changed = true;
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
  if (want_bezier && (!bezier_ || bezier_k_ != view.bezier || bezier_of_ != shown_.get())) {
    rebuild_bezier(view);
    structures_changed = true;
  }
  if (!want_bezier && bezier_) {
    bezier_.reset();
    structures_changed = true;
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
        if (mk.name == "touched by the pass") b.markers.push_back(mk);
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
      for (auto& mk : s.markers) mk.enabled = mk.name == "touched by the pass" ? view.show_touched : view.features;
    } else if (s.name == kBezierName) {
      s.activate(view.color == "deviation" ? render::quantity::kDeviation : "");
      for (auto& c : s.curves) c.enabled = c.name == "patch edges" ? view.wireframe : view.control_net;
      for (auto& mk : s.markers) mk.enabled = mk.name == "touched by the pass" ? view.show_touched : view.control_net;
      for (auto& g : s.glyphs) g.enabled = view.glyphs;
    }
  }
  scene.display.wireframe = view.wireframe && !bezier_;

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
    if (sel.active && sel.worst_triangle >= 0 && !shown_->mesh.is_deleted(Triangle(sel.worst_triangle))) {
      // Frame the worst element with some of its surroundings (8 times its size).
      const SurfaceMesh& m = shown_->mesh;
      Vec3 c;
      double r = 0;
      for (int k = 0; k < 3; ++k) c += m.position(m.vertex(Triangle(sel.worst_triangle), k)) / 3.0;
      for (int k = 0; k < 3; ++k) r = std::max(r, norm(m.position(m.vertex(Triangle(sel.worst_triangle), k)) - c));
      const BBox box = m.bbox();
      r = std::max(8 * r, 0.04 * norm(box.hi - box.lo));
      std::vector<glm::vec3> pts;
      for (int a = -1; a <= 1; a += 2)
        for (int b = -1; b <= 1; b += 2)
          for (int e = -1; e <= 1; e += 2) pts.push_back(to_glm(c + Vec3(a * r, b * r, e * r)));
      scene.camera.fit(pts, aspect, 0.06f, reserve_left, reserve_right);
    }
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
