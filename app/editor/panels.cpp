#include "editor/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <filesystem>

#include "core/error.h"
#include "editor/editor_app.h"
#include "editor/script.h"
#include "render/pick.h"
#include "metric/length.h"
#include "metric/quality.h"
#include "remesh/operators.h"

namespace anisurf::editor {

namespace {

bool input_text(const char* label, std::string& s, float width = 260.0f) {
  char buf[1024];
  std::snprintf(buf, sizeof buf, "%s", s.c_str());
  ImGui::SetNextItemWidth(width);
  const bool enter = ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue);
  s = buf;
  return enter;
}

// Runs an action, reporting its error in the panel instead of throwing.
template <class F>
void act(PanelState& p, const std::string& ok, F&& f) {
  try {
    f();
    p.message = ok;
    p.message_is_error = false;
  } catch (const std::exception& e) {
    p.message = e.what();
    p.message_is_error = true;
  }
}

// --- File -----------------------------------------------------------------------
void file_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("File")) return;
  input_text("mesh##open", p.open_path);
  input_text("sol (optional)##open", p.open_sol);
  if (ImGui::Button("Open")) {
    act(p, "opened " + p.open_path, [&] {
      if (s.dirty()) s.log("# unsaved work replaced by open");
      s.open(p.open_path, p.open_sol);
      remember_recent(p, p.open_path + (p.open_sol.empty() ? "" : "|" + p.open_sol));
      v.fit_request = true;
      p.edit_valid = false;
    });
  }
  ImGui::SameLine();
  ImGui::TextDisabled("(or drop a file on the window)");
  if (!p.recent.empty()) {
    ImGui::SetNextItemWidth(260);
    if (ImGui::BeginCombo("recent", "choose...")) {
      for (const auto& r : p.recent)
        if (ImGui::Selectable(r.c_str())) {
          const auto bar = r.find('|');
          p.open_path = r.substr(0, bar);
          p.open_sol = bar == std::string::npos ? "" : r.substr(bar + 1);
        }
      ImGui::EndCombo();
    }
  }
  const std::string autosave = autosave_path();
  std::error_code ec;
  if (std::filesystem::exists(autosave, ec) && ImGui::Button("Restore the autosaved session")) {
    act(p, "restored " + autosave, [&] {
      s.reset();
      for (const auto& line : read_script(autosave)) {
        execute(line, s, v, {});
        s.wait();
      }
      p.edit_valid = false;
    });
  }
  ImGui::Separator();
  input_text("save mesh", p.save_mesh);
  input_text("save metric", p.save_sol);
  if (ImGui::Button("Save mesh + metric"))
    act(p, "saved " + p.save_mesh, [&] { s.save(p.save_mesh, p.save_sol); });
  ImGui::SameLine();
  if (ImGui::Button("Save mesh")) act(p, "saved " + p.save_mesh, [&] { s.save(p.save_mesh); });
  input_text("screenshot", p.shot_path);
  if (ImGui::Button("Screenshot") && p.screenshot)
    act(p, "wrote " + p.shot_path, [&] { p.screenshot(p.shot_path); });
}

// --- Metric ---------------------------------------------------------------------
void metric_panel(EditorSession& s, PanelState& p) {
  if (!ImGui::CollapsingHeader("Metric", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (!p.edit_valid || (!ImGui::IsAnyItemActive() && !(p.edit == s.settings()) && p.preview_error.empty())) {
    p.edit = s.settings();
    p.edit_valid = true;
    p.preview_vertices = s.predicted_vertices();
  }
  MetricSettings& e = p.edit;
  bool changed = false, commit = false;
  int src = static_cast<int>(e.source);
  const char* names[] = {"iso size", "size expression", "Hessian", "curvature", "loaded .sol"};
  for (int i = 0; i < 5; ++i) {
    if (i == 4 && s.settings().sol_path.empty() && e.sol_path.empty()) continue;
    if (ImGui::RadioButton(names[i], &src, i)) commit = true;
    if (i % 3 != 2 && i != 4) ImGui::SameLine();
  }
  ImGui::NewLine();
  e.source = static_cast<MetricSettings::Source>(src);
  auto track = [&](bool ch) {
    changed |= ch;
    commit |= ImGui::IsItemDeactivatedAfterEdit();
  };
  ImGui::SetNextItemWidth(200);
  switch (e.source) {
    case MetricSettings::Source::Iso:
      track(ImGui::InputDouble("h", &e.iso, 0, 0, "%.4g"));
      break;
    case MetricSettings::Source::Size:
      commit |= input_text("h(x,y,z)", e.size_expr);
      commit |= ImGui::IsItemDeactivatedAfterEdit();
      break;
    case MetricSettings::Source::Hessian:
      commit |= input_text("f(x,y,z)", e.hessian_expr);
      commit |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::SetNextItemWidth(200);
      track(ImGui::InputDouble("error", &e.hessian_error, 0, 0, "%.4g"));
      break;
    case MetricSettings::Source::Curvature:
      track(ImGui::InputDouble("hausd", &e.hausd, 0, 0, "%.4g"));
      break;
    case MetricSettings::Source::Sol:
      commit |= input_text("file", e.sol_path);
      commit |= ImGui::IsItemDeactivatedAfterEdit();
      break;
  }
  float hgrad = static_cast<float>(e.hgrad);
  ImGui::SetNextItemWidth(200);
  track(ImGui::SliderFloat("hgrad (1: off)", &hgrad, 1.0f, 3.0f, "%.2f"));
  e.hgrad = hgrad;
  if (e.source != MetricSettings::Source::Curvature) {
    ImGui::SetNextItemWidth(200);
    track(ImGui::InputDouble("hausd bound (0: diagonal/1000 for a .sol or a Hessian)", &e.hausd_bound, 0, 0, "%.4g"));
  }
  ImGui::SetNextItemWidth(200);
  track(ImGui::InputDouble("hmin", &e.hmin, 0, 0, "%.4g"));
  double hmax = std::isinf(e.hmax) ? 0.0 : e.hmax, aniso = std::isinf(e.max_aniso) ? 0.0 : e.max_aniso;
  ImGui::SetNextItemWidth(200);
  track(ImGui::InputDouble("hmax (0: none)", &hmax, 0, 0, "%.4g"));
  ImGui::SetNextItemWidth(200);
  track(ImGui::InputDouble("max anisotropy (0: none)", &aniso, 0, 0, "%.4g"));
  e.hmax = hmax > 0 ? hmax : INFINITY;
  e.max_aniso = aniso >= 1 ? aniso : INFINITY;
  const bool small = s.has_mesh() && s.input().n_vertices() < 50000;
  if (changed && small) {  // live preview of the vertex count
    try {
      p.preview_vertices = s.predict_vertices(e);
      p.preview_error.clear();
    } catch (const std::exception& ex) {
      p.preview_error = ex.what();
    }
  }
  if (commit && s.has_mesh() && !(e == s.settings())) {
    act(p, "metric updated", [&] { s.set_settings(e); });
    p.preview_vertices = s.predicted_vertices();
    p.preview_error = p.message_is_error ? p.message : "";
  }
  if (!p.preview_error.empty())
    ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", p.preview_error.c_str());
  ImGui::Text("predicted vertices: %.0f", e == s.settings() ? s.predicted_vertices() : p.preview_vertices);
  if (s.has_mesh()) ImGui::TextDisabled("(input: %d vertices)", s.input().n_vertices());
}

// --- Brush ----------------------------------------------------------------------
void brush_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("Metric brush")) return;
  ImGui::Checkbox("paint with the left button (B)", &v.paint_tool);
  Brush& b = s.brush();
  int mode = static_cast<int>(b.mode);
  ImGui::RadioButton("set", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("smooth", &mode, 1);
  ImGui::SameLine();
  ImGui::RadioButton("erase", &mode, 2);
  b.mode = static_cast<Brush::Mode>(mode);
  float radius = static_cast<float>(b.radius), size = static_cast<float>(b.size), stretch = static_cast<float>(b.stretch),
        strength = static_cast<float>(b.strength);
  const float diag = s.has_mesh() ? static_cast<float>(norm(s.input().bbox().hi - s.input().bbox().lo)) : 1.0f;
  ImGui::SetNextItemWidth(200);
  ImGui::SliderFloat("radius", &radius, 0.005f * diag, 0.5f * diag, "%.4g", ImGuiSliderFlags_Logarithmic);
  ImGui::SetNextItemWidth(200);
  ImGui::SliderFloat("target size", &size, 0.001f * diag, 0.2f * diag, "%.4g", ImGuiSliderFlags_Logarithmic);
  ImGui::SetNextItemWidth(200);
  ImGui::SliderFloat("stretch", &stretch, 1.0f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
  ImGui::SetNextItemWidth(200);
  ImGui::SliderFloat("strength", &strength, 0.05f, 1.0f, "%.2f");
  b.radius = radius, b.size = size, b.stretch = stretch, b.strength = strength;
  int dir = static_cast<int>(b.direction);
  ImGui::TextUnformatted("direction:");
  ImGui::SameLine();
  ImGui::RadioButton("stroke", &dir, 0);
  ImGui::SameLine();
  ImGui::RadioButton("max curv.", &dir, 1);
  ImGui::SameLine();
  ImGui::RadioButton("min curv.", &dir, 2);
  b.direction = static_cast<Brush::Direction>(dir);
  ImGui::BeginDisabled(!s.can_undo());
  if (ImGui::Button("Undo")) act(p, "undone", [&] { s.undo(); });
  ImGui::EndDisabled();
  if (s.can_undo()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", s.undo_label().c_str());
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(!s.can_redo());
  if (ImGui::Button("Redo")) act(p, "redone", [&] { s.redo(); });
  ImGui::EndDisabled();
  if (s.can_redo()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", s.redo_label().c_str());
  }
}

// --- Adaptation -----------------------------------------------------------------
void adaptation_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("Adaptation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const bool running = s.running();
  ImGui::BeginDisabled(running || !s.has_mesh());
  if (ImGui::Button("Step")) act(p, "step", [&] { s.step(); });
  ImGui::SameLine();
  if (ImGui::Button("Run")) act(p, "running", [&] { s.run(); });
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(!running);
  if (ImGui::Button("Pause")) s.pause();
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) s.cancel();
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Reset")) s.reset();
  // Section 7.1's loop: the adapted mesh shown becomes T_0, its metric derived again.
  ImGui::BeginDisabled(running || !s.has_mesh() || s.timeline().size() < 2);
  if (ImGui::Button("Next cycle")) {
    int vertices = 0;
    act(p, "cycle", [&] { vertices = s.next_cycle(); });
    if (!p.message_is_error)
      p.message = "cycle " + std::to_string(s.cycle() + 1) + ": T_0 has " + std::to_string(vertices) +
                  " vertices, the metric derived again; Run adapts";
  }
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("The adapted mesh becomes the input (T_0) and the metric is derived again on it\n"
                      "(Hessian, size, curvature); a loaded or painted metric is carried over.\n"
                      "The surface stays the opened mesh's. Then Run adapts again.");
  if (s.cycle() > 0) {
    ImGui::SameLine();
    ImGui::Text("cycle %d", s.cycle() + 1);
  }
  if (running) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.1f, 0.5f, 0.1f, 1), "running...");
  }
  {
    float band[2] = {static_cast<float>(s.adapt_settings().remesh.op.lmin),
                     static_cast<float>(s.adapt_settings().remesh.op.lmax)};
    ImGui::SetNextItemWidth(200);
    ImGui::InputFloat2("lmin, lmax", band, "%.3g");
    if (ImGui::IsItemDeactivatedAfterEdit()) act(p, "band set", [&] { s.set_band(band[0], band[1]); });
  }
  if (const std::string err = s.adaptation_error(); !err.empty())
    ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "error: %s", err.c_str());
  const auto tl = s.timeline();
  const int n = static_cast<int>(tl.size());
  int shown = s.scrubbed() >= 0 ? s.scrubbed() : n - 1;
  if (n > 1) {
    ImGui::SetNextItemWidth(260);
    const std::string fmt_label = "%d: " + tl[static_cast<std::size_t>(shown)]->label;  // labels hold no '%'
    if (ImGui::SliderInt("timeline", &shown, 0, n - 1, fmt_label.c_str()))
      s.scrub(shown);
    // In-band share over the passes.
    std::vector<float> band;
    for (const auto& snap : tl)
      if (snap->has_report) band.push_back(static_cast<float>(100.0 * snap->report.in_band_share));
    if (!band.empty()) {
      char overlay[64];
      std::snprintf(overlay, sizeof overlay, "%.1f%%", band.back());
      ImGui::PlotLines("edges in\nband", band.data(), static_cast<int>(band.size()), 0, overlay, 0.0f, 100.0f,
                       ImVec2(260, 45));
    }
  }
  // The passes side by side (click a row to show that pass).
  if (n > 1 && ImGui::TreeNodeEx("passes", ImGuiTreeNodeFlags_DefaultOpen)) {
    const ImGuiTableFlags tf = ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_ScrollY |
                               ImGuiTableFlags_SizingFixedFit;
    if (ImGui::BeginTable("##passes", 6, tf, ImVec2(340, 160))) {
      ImGui::TableSetupScrollFreeze(0, 1);
      for (const char* h : {"#", "pass", "changes", "V", "in band", "q min"}) ImGui::TableSetupColumn(h);
      ImGui::TableHeadersRow();
      for (int i = 0; i < n; ++i) {
        const auto& sn = tl[static_cast<std::size_t>(i)];
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        char id[16];
        std::snprintf(id, sizeof id, "%d", i);
        if (ImGui::Selectable(id, i == shown, ImGuiSelectableFlags_SpanAllColumns)) s.scrub(i);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(sn->label.c_str());
        ImGui::TableNextColumn();
        ImGui::Text("%d", sn->has_report ? sn->report.changes() : 0);
        ImGui::TableNextColumn();
        ImGui::Text("%d", sn->mesh.n_vertices());
        ImGui::TableNextColumn();
        if (sn->has_report) ImGui::Text("%.1f%%", 100 * sn->report.in_band_share);
        ImGui::TableNextColumn();
        if (sn->has_report) ImGui::Text("%.3f", sn->report.q_min);
      }
      ImGui::EndTable();
    }
    ImGui::TreePop();
  }
  ImGui::Checkbox("mark the vertices the pass touched", &v.show_touched);
  const auto& snap = tl[static_cast<std::size_t>(std::clamp(shown, 0, n - 1))];
  if (!snap->has_report) {
    ImGui::TextDisabled("initial mesh: %d vertices, %d triangles", snap->mesh.n_vertices(), snap->mesh.n_triangles());
    return;
  }
  const remesh::PassReport& r = snap->report;
  ImGui::Text("pass %d of %d: %s", shown, n - 1, snap->label.c_str());
  ImGui::Text("split %d  collapse %d  swap %d  move %d  removed %d", r.splits, r.collapses, r.swaps, r.moves,
              r.removed_vertices);
  if (r.bound_splits > 0 || r.beyond_bound > 0)
    ImGui::Text("hausd bound: %d splits onto the input, %d points still beyond", r.bound_splits, r.beyond_bound);
  std::string rej;
  for (int i = 1; i < remesh::kRejectionCount; ++i)
    if (r.rejected[i])
      rej += std::string(rej.empty() ? "" : ", ") + std::string(remesh::rejection_name(static_cast<remesh::Rejection>(i))) +
             " " + std::to_string(r.rejected[i]);
  ImGui::TextWrapped("refused: %s", rej.empty() ? "none" : rej.c_str());
  ImGui::Text("V %d  T %d  in band %.1f%%  q min %.3f mean %.3f", r.vertices, r.triangles, 100 * r.in_band_share,
              r.q_min, r.q_mean);
  ImGui::TextDisabled("%.3f s, %zu vertices touched", r.seconds, r.touched.size());
}

// A clickable histogram (bars drawn with the draw list); returns the clicked bin or -1.
int histogram(const char* id, const std::vector<int>& counts, BinKind kind, int selected, ImU32 color) {
  const float w = 260, h = 70;
  ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton(id, ImVec2(w, h));
  const bool hovered = ImGui::IsItemHovered();
  const bool clicked = ImGui::IsItemClicked();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, ImVec2(p0.x + w, p0.y + h), IM_COL32(245, 245, 245, 255));
  const int nb = static_cast<int>(counts.size());
  const int maxc = std::max(1, *std::max_element(counts.begin(), counts.end()));
  const float bw = w / static_cast<float>(nb);
  int hover_bin = -1;
  if (hovered) hover_bin = std::clamp(static_cast<int>((ImGui::GetIO().MousePos.x - p0.x) / bw), 0, nb - 1);
  for (int i = 0; i < nb; ++i) {
    const float bh = counts[i] > 0 ? std::max(2.0f, (h - 4) * static_cast<float>(counts[i]) / static_cast<float>(maxc)) : 0.0f;
    const ImVec2 a(p0.x + i * bw + 1, p0.y + h - bh), b(p0.x + (i + 1) * bw - 1, p0.y + h);
    ImU32 c = i == selected ? IM_COL32(255, 40, 140, 255) : i == hover_bin ? IM_COL32(90, 90, 90, 255) : color;
    dl->AddRectFilled(a, b, c);
  }
  dl->AddRect(p0, ImVec2(p0.x + w, p0.y + h), IM_COL32(120, 120, 120, 255));
  if (hover_bin >= 0)
    ImGui::SetTooltip("%s %s: %d (click to select)", bin_kind_name(kind), bin_label(kind, hover_bin).c_str(),
                      counts[hover_bin]);
  return clicked ? hover_bin : -1;
}

// The distance of the displayed mesh to the input surface T_G: measured by
// the "distance" colours, or here on demand.
void distance_section(EditorSession& s, ViewState& v, PanelState& p) {
  ImGui::TextUnformatted("distance to the input T_G");
  const auto displayed = s.display().snapshot;
  if (const auto d = s.ready_distance(displayed)) {
    ImGui::TextDisabled("max %.4g = %.3g%% of the diagonal", d->max(), d->percent(d->max()));
    const DistanceSample w = d->worst_sample();
    ImGui::TextDisabled("at %s %s; measured in %.2f s", w == DistanceSample::Midpoint ? "an" : "a",
                        distance_sample_name(w), s.last_distance_seconds());
    const std::pair<const char*, const DistanceStats*> rows[] = {
        {"vertex", &d->vertices}, {"midpoint", &d->midpoints}, {"centroid", &d->centroids}};
    for (const auto& [name, st] : rows)
      if (st->count > 0) ImGui::TextDisabled("%-9s max %-9.3g mean %.3g", name, st->max, st->mean);
    return;
  }
  if (s.measuring()) {
    ImGui::TextDisabled("measuring ...");
  } else {
    if (ImGui::SmallButton("measure")) act(p, "measuring the distance to the input", [&] { s.request_distance(displayed); });
    ImGui::SameLine();
    if (ImGui::SmallButton("colour by it")) {
      v.color = "distance";
      v.bezier = 0;
    }
  }
  if (!s.distance_error().empty()) ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", s.distance_error().c_str());
  if (const auto last = s.last_distance())
    ImGui::TextDisabled("(an earlier state: max %.3g, %.3g%%)", last->max(), last->percent(last->max()));
}

void analysis_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!s.has_mesh()) return;
  const Analysis& a = s.analysis();
  const Selection& sel = s.selection();
  ImGui::TextUnformatted("edge length in the metric");
  ImGui::TextDisabled("min %.3f  mean %.3f  max %.3f", a.length_min, a.length_mean, a.length_max);
  ImGui::TextDisabled("in [0.71, 1.41]: %.1f%% of %zu edges", 100 * a.in_band_share, a.edges.size());
  std::vector<int> lc(a.length_histogram.begin(), a.length_histogram.end());
  int clicked = histogram("##length", lc, BinKind::Length, sel.active && sel.kind == BinKind::Length ? sel.bin : -1,
                          IM_COL32(60, 110, 200, 255));
  if (clicked >= 0) act(p, "selected", [&] { s.select_bin(BinKind::Length, clicked); v.frame_selection = true; });
  ImGui::TextUnformatted("triangle quality (eq. 17)");
  ImGui::TextDisabled("min %.3f  mean %.3f  >= 0.5: %.1f%%", a.quality_min, a.quality_mean, 100 * a.good_quality_share);
  std::vector<int> qc(a.quality_histogram.begin(), a.quality_histogram.end());
  clicked = histogram("##quality", qc, BinKind::Quality, sel.active && sel.kind == BinKind::Quality ? sel.bin : -1,
                      IM_COL32(60, 160, 90, 255));
  if (clicked >= 0) act(p, "selected", [&] { s.select_bin(BinKind::Quality, clicked); v.frame_selection = true; });
  distance_section(s, v, p);
  if (sel.active) {
    ImGui::Text("selected: %s %s", bin_kind_name(sel.kind), bin_label(sel.kind, sel.bin).c_str());
    ImGui::TextDisabled("%zu triangles, worst %.3f", sel.triangles.size(), sel.worst_value);
    if (ImGui::SmallButton("frame worst")) v.frame_selection = true;
    ImGui::SameLine();
    if (ImGui::SmallButton("clear")) s.clear_selection();
  }
}

void bezier_panel(ViewState& v) {
  if (!ImGui::CollapsingHeader("G1 surface")) return;
  bool show = v.bezier > 0;
  if (ImGui::Checkbox("show the G1 Bezier surface", &show)) {
    v.bezier = show ? 4 : 0;
    if (show && v.color == "distance") v.color = "size";  // the G1 surface hides the mesh it colours
  }
  if (show) {
    ImGui::SetNextItemWidth(160);
    ImGui::SliderInt("samples per edge", &v.bezier, 1, 12);
    ImGui::Checkbox("control net", &v.control_net);
    bool dev = v.color == "deviation";
    if (ImGui::Checkbox("colour by deviation mesh - surface", &dev)) v.color = dev ? "deviation" : "size";
  } else if (v.color == "deviation") {
    v.color = "size";
  }
}

void display_panel(ViewState& v, render::Scene& scene) {
  if (!ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int current = 0;
  const int n = static_cast<int>(std::size(kColorModes));
  for (int i = 0; i < n; ++i)
    if (v.color == kColorModes[i]) current = i;
  ImGui::SetNextItemWidth(160);
  if (ImGui::Combo("colour", &current, kColorModes, n)) {
    if (std::string(kColorModes[current]) == "deviation" && v.bezier == 0) v.bezier = 4;
    if (std::string(kColorModes[current]) == "distance") v.bezier = 0;  // it colours the mesh
    v.color = kColorModes[current];
  }
  ImGui::Checkbox("glyphs (G)", &v.glyphs);
  ImGui::SameLine();
  ImGui::Checkbox("wireframe (W)", &v.wireframe);
  ImGui::SameLine();
  ImGui::Checkbox("features", &v.features);
  for (render::NamedView nv : {render::NamedView::Iso, render::NamedView::Front, render::NamedView::Back,
                               render::NamedView::Top, render::NamedView::Bottom, render::NamedView::Left,
                               render::NamedView::Right}) {
    if (nv != render::NamedView::Iso) ImGui::SameLine();
    if (ImGui::SmallButton(render::view_name(nv))) v.view_request = nv;
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("fit")) v.fit_request = true;
  for (auto& s : scene.surfaces)
    for (auto& q : s.scalars)
      if (q.name == s.active && s.enabled) {
        ImGui::SetNextItemWidth(200);
        float speed = std::max(std::abs(q.range_max - q.range_min), 1e-6f) * 0.005f;
        ImGui::DragFloatRange2("range", &q.range_min, &q.range_max, speed, 0, 0, "%.4g", "%.4g");
      }
}

void hover_tooltip(EditorSession& s, EditorView* view, PanelState& p) {
  if (!p.hover || ImGui::GetIO().WantCaptureMouse) return;
  const DisplayState d = s.display();
  if (!d.snapshot) return;
  const SurfaceMesh& m = d.snapshot->mesh;
  const HoverInfo& h = *p.hover;
  if (h.triangle < 0 || h.triangle >= m.triangle_capacity() || m.is_deleted(Triangle(h.triangle))) return;
  ImGui::BeginTooltip();
  const Triangle T(h.triangle);
  std::array<Vec3, 3> pos;
  std::array<SymTensor3, 3> M;
  for (int k = 0; k < 3; ++k) {
    pos[k] = m.position(m.vertex(T, k));
    M[k] = d.snapshot->metric[m.vertex(T, k).idx];
  }
  auto tags = [](std::uint8_t t) {
    std::string s;
    if (t & kBoundary) s += "boundary ";
    if (t & kRidge) s += "ridge ";
    if (t & kCorner) s += "corner ";
    if (t & kRequired) s += "required ";
    return s.empty() ? std::string("none") : s;
  };
  ImGui::Text("triangle %d  ref %d  quality %.3f", h.triangle + 1, m.triangle_ref(T),
              triangle_quality(pos, M, LengthFormula::LinearMetric));
  ImGui::Text("triangle tags: %s", tags(m.triangle_tags(T)).c_str());
  ImGui::Text("edges (length in the metric, tags):");
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    ImGui::Text("  %d-%d  %.3f  %s", m.vertex(T, a).idx + 1, m.vertex(T, b).idx + 1,
                edge_length(M[a], M[b], pos[b] - pos[a], LengthFormula::LinearMetric),
                tags(m.edge_tags(SurfaceMesh::corner(T, k))).c_str());
  }
  const Vertex V(h.vertex);
  const SizesDirections sd = sizes_and_directions(d.snapshot->metric[V.idx]);
  ImGui::Separator();
  ImGui::Text("vertex %d  tags: %s", V.idx + 1, tags(m.vertex_tags(V)).c_str());
  const Vec3& x = m.position(V);
  ImGui::Text("at (%.4g, %.4g, %.4g)", x.x, x.y, x.z);
  bool current = false;
  if (const auto dist = s.last_distance(&current); dist && current && V.idx < static_cast<int>(dist->vertex.size()))
    ImGui::Text("distance to the input %.4g (%.3g%% of the diagonal)", dist->vertex[static_cast<std::size_t>(V.idx)],
                dist->percent(dist->vertex[static_cast<std::size_t>(V.idx)]));
  for (int i = 0; i < 3; ++i)
    ImGui::Text("size %.4g along (%.3f, %.3f, %.3f)", sd.sizes[i], sd.directions[i].x, sd.directions[i].y,
                sd.directions[i].z);
  ImGui::EndTooltip();
  (void)view;
}

void quit_dialog(EditorSession& s, PanelState& p) {
  if (p.quit_requested) {
    ImGui::OpenPopup("Quit?");
    p.quit_requested = false;
  }
  if (ImGui::BeginPopupModal("Quit?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted("The session has unsaved changes (the autosave keeps them).");
    if (ImGui::Button("Save and quit")) {
      act(p, "saved", [&] { s.save(p.save_mesh, p.save_sol); });
      if (!p.message_is_error) p.quit_confirmed = true;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Quit without saving")) {
      p.quit_confirmed = true;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
}

}  // namespace

void remember_recent(PanelState& p, const std::string& path) {
  p.recent.erase(std::remove(p.recent.begin(), p.recent.end(), path), p.recent.end());
  p.recent.insert(p.recent.begin(), path);
  if (p.recent.size() > 8) p.recent.resize(8);
}

void draw_panels(EditorSession& session, ViewState& view, PanelState& panels, render::Scene& scene,
                 render::UiState& ui, int width, int height) {
  // The legend (colour bar, curves, glyph key) from the renderer's UI.
  ui.show_panel = false;
  render::draw_ui(scene, ui, width, height);
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, static_cast<float>(height) - 16), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.90f);
  if (ImGui::Begin("anisurf editor", nullptr, ImGuiWindowFlags_NoSavedSettings)) {
    if (session.has_mesh()) {
      ImGui::TextUnformatted(session.mesh_path().c_str());
      const DisplayState d = session.display();
      ImGui::TextDisabled("%d vertices, %d triangles%s", d.snapshot->mesh.n_vertices(), d.snapshot->mesh.n_triangles(),
                          session.dirty() ? "  (modified)" : "");
    }
    if (panels.fps > 0) ImGui::TextDisabled("%.0f fps", panels.fps);
    if (!panels.message.empty())
      ImGui::TextColored(panels.message_is_error ? ImVec4(0.8f, 0.1f, 0.1f, 1) : ImVec4(0.2f, 0.4f, 0.2f, 1), "%s",
                         panels.message.c_str());
    file_panel(session, view, panels);
    metric_panel(session, panels);
    brush_panel(session, view, panels);
    adaptation_panel(session, view, panels);
    bezier_panel(view);
    display_panel(view, scene);
    ui.panel_width = ImGui::GetWindowPos().x + ImGui::GetWindowWidth() + 8.0f;
  }
  ImGui::End();
  // The analysis on the right, above the legend.
  if (session.has_mesh()) {
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(width) - 8.0f, 8.0f), ImGuiCond_FirstUseEver, ImVec2(1.0f, 0.0f));
    ImGui::SetNextWindowBgAlpha(0.90f);
    if (ImGui::Begin("Analysis", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
      analysis_panel(session, view, panels);
      const float w = static_cast<float>(width) - ImGui::GetWindowPos().x + 8.0f;
      if (!ImGui::IsWindowCollapsed()) ui.legend_width = std::max(ui.legend_width, w);
    }
    ImGui::End();
  }
  // The brush's footprint under the mouse (a circle of its radius, in the
  // view plane) while the paint tool is on.
  if (view.paint_tool && panels.hover && session.has_mesh()) {
    const Vec3& c = panels.hover->point;
    const glm::vec3 cw(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z));
    const glm::vec3 ew = cw + scene.camera.right() * static_cast<float>(session.brush().radius);
    const auto pc = render::project_to_pixel(scene.camera, cw, width, height);
    const auto pe = render::project_to_pixel(scene.camera, ew, width, height);
    if (pc && pe) {
      const float r = glm::length(*pe - *pc);
      ImDrawList* dl = ImGui::GetForegroundDrawList();
      dl->AddCircle(ImVec2(pc->x, pc->y), r, IM_COL32(255, 255, 255, 220), 48, 3.0f);
      dl->AddCircle(ImVec2(pc->x, pc->y), r, IM_COL32(20, 20, 20, 255), 48, 1.5f);
    }
  }
  if (!view.paint_tool) hover_tooltip(session, nullptr, panels);
  quit_dialog(session, panels);
}

}  // namespace anisurf::editor
