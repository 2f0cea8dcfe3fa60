#include "editor/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cfloat>
#include <cstdio>
#include <filesystem>
#include <span>

#include "core/error.h"
#include "editor/autosave.h"
#include "editor/keys.h"
#include "editor/script.h"
#include "render/outline.h"
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

// An indeterminate progress: a turning bar.
const char* spinner() {
  static const char* phases[] = {"|", "/", "-", "\\"};
  return phases[static_cast<int>(ImGui::GetTime() * 8.0) % 4];
}

// An error in red, wrapped to the window's width.
void error_text(const std::string& text) {
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.8f, 0.1f, 0.1f, 1));
  ImGui::TextWrapped("%s", text.c_str());
  ImGui::PopStyleColor();
}

// --- File -----------------------------------------------------------------------
void perform(EditorSession& s, ViewState& v, PanelState& p, const PanelState::Pending& a) {
  switch (a.action) {
    case PanelState::Action::None: break;
    case PanelState::Action::Open:
      act(p, "opened " + a.mesh, [&] {
        s.open(a.mesh, a.sol);
        remember_recent(p, a.mesh + (a.sol.empty() ? "" : "|" + a.sol));
        p.open_path = a.mesh;
        p.open_sol = a.sol;
        v.fit_request = true;
        p.draft.valid = false;
      });
      break;
    case PanelState::Action::Restore: {
      int skipped = 0;
      act(p, "restored " + a.mesh, [&] {
        skipped = restore_autosave(a.mesh, s, v);
        v.fit_request = true;
        p.draft.valid = false;
      });
      if (!p.message_is_error && skipped > 0)
        p.message += " (" + std::to_string(skipped) + " save / screenshot lines not replayed: no file written)";
      if (s.has_mesh()) {
        p.open_path = s.mesh_path();
        p.open_sol.clear();
      }
      break;
    }
    case PanelState::Action::Quit: p.quit_confirmed = true; break;
  }
}

// Saves to the panel's paths; asks first when that would overwrite a file
// the session did not write. Returns true when the files were written.
bool save_checked(EditorSession& s, PanelState& p, bool continue_pending) {
  if (p.save_mesh.empty()) {
    p.message = "save: no mesh path";
    p.message_is_error = true;
    return false;
  }
  p.overwrite = s.would_overwrite(p.save_mesh, p.save_sol);
  if (!p.overwrite.empty()) {
    p.ask_overwrite = true;
    p.continue_pending = continue_pending;
    return false;
  }
  const std::string what = absolute_path(p.save_mesh) + (p.save_sol.empty() ? "" : " and " + absolute_path(p.save_sol));
  act(p, "saved " + what, [&] { s.save(p.save_mesh, p.save_sol); });
  return !p.message_is_error;
}

// The files a save writes, in full.
void save_targets(const PanelState& p) {
  ImGui::TextDisabled("writes %s", p.save_mesh.empty() ? "(no path)" : absolute_path(p.save_mesh).c_str());
  if (!p.save_sol.empty()) ImGui::TextDisabled("   and %s", absolute_path(p.save_sol).c_str());
}

void autosave_section(EditorSession& s, ViewState& v, PanelState& p) {
  if (!p.autosave_error.empty()) {
    ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "autosave: failed (the error is shown in the status bar)");
  } else if (!p.autosave_path.empty()) {
    ImGui::TextDisabled("autosave: %s", std::filesystem::path(p.autosave_path).filename().string().c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.autosave_path.c_str());
  } else {
    ImGui::TextDisabled("autosave: written after the first edit");
  }
  if (p.autosaves.empty()) return;
  if (ImGui::TreeNode("autosaved sessions", "autosaved sessions (%zu)", p.autosaves.size())) {
    for (std::size_t i = 0; i < p.autosaves.size() && i < 12; ++i) {
      const AutosaveEntry& e = p.autosaves[i];
      ImGui::PushID(static_cast<int>(i));
      if (ImGui::SmallButton("Restore")) request(s, v, p, {PanelState::Action::Restore, e.path, {}});
      ImGui::PopID();
      const std::string tip = e.describe() + "\n" + e.path + "\nRestore replays its edits, not its saves (no file is written)";
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip.c_str());
      // One short row: the input, the start (month-day hour:minute), the edits.
      const std::string input = std::filesystem::path(e.input.empty() ? e.path : e.input).filename().string();
      std::string row = input + (e.started.size() >= 16 ? " " + e.started.substr(5, 11) : std::string()) + ", " +
                        std::to_string(e.edits) + (e.edits == 1 ? " edit" : " edits") + (e.unsaved == 0 ? ", saved" : "");
      ImGui::SameLine();
      ImGui::TextUnformatted(row.c_str());
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip.c_str());
    }
    ImGui::TreePop();
  }
}

void file_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("File")) return;
  input_text("mesh##open", p.open_path);
  input_text("sol (optional)##open", p.open_sol);
  if (ImGui::Button("Open")) request(s, v, p, {PanelState::Action::Open, p.open_path, p.open_sol});
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
  autosave_section(s, v, p);
  ImGui::Separator();
  input_text("save mesh", p.save_mesh);
  input_text("save metric", p.save_sol);
  ImGui::BeginDisabled(!s.has_mesh());
  if (ImGui::Button("Save")) save_checked(s, p, false);
  ImGui::SameLine();
  if (ImGui::Button("Save as...")) {
    p.save_as_mesh = p.save_mesh;
    p.save_as_sol = p.save_sol;
    p.ask_save_as = true;
  }
  ImGui::EndDisabled();
  save_targets(p);
  input_text("screenshot", p.shot_path);
  if (ImGui::Button("Screenshot") && p.screenshot)
    act(p, "wrote " + p.shot_path, [&] { p.screenshot(p.shot_path); });
}

// --- Metric ---------------------------------------------------------------------
void metric_panel(EditorSession& s, PanelState& p) {
  if (!ImGui::CollapsingHeader("Metric", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (p.draft.follow(s.settings())) p.preview_due.reset();
  MetricSettings& e = p.draft.edit;
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
  const bool hgrad_moved = ImGui::SliderFloat("hgrad (1: off)", &hgrad, 1.0f, 3.0f, "%.2f");
  track(hgrad_moved);
  // Only a moved slider sets the ratio (to the two decimals shown): the
  // float would otherwise turn 1.3 into 1.29999995, a change of settings.
  if (hgrad_moved) e.hgrad = std::round(static_cast<double>(hgrad) * 100.0) / 100.0;
  if (e.source != MetricSettings::Source::Curvature) {
    ImGui::SetNextItemWidth(200);
    track(ImGui::InputDouble("hausd (0: auto)", &e.hausd_bound, 0, 0, "%.4g"));
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("chordal deviation bound: the metric is intersected with the curvature metric of it and\n"
                        "the output stays within it. 0: diagonal/1000 for a Hessian metric (the geometry\n"
                        "protection of anisurf adapt), none for a loaded metric or a size");
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
  // The preview once the fields are still; the commit at once. Both build
  // in the background: the view keeps showing the current metric.
  const auto now = std::chrono::steady_clock::now();
  if (changed) p.preview_due = now + PanelState::kPreviewDelay;
  if (s.has_mesh() && p.preview_due && now >= *p.preview_due) {
    p.preview_due.reset();
    s.request_metric(e, false);  // throws only without a mesh
  }
  if (commit && s.has_mesh() && !(e == s.settings())) {
    p.preview_due.reset();
    s.request_metric(e, true);  // the line below says it builds; an error shows under the fields
  }
  // One line, building or not (the headers below do not move).
  const std::string error = s.has_mesh() ? s.metric_error(e) : std::string();
  if (s.metric_building()) {
    // An indeterminate progress: the engine reports none while it builds.
    ImGui::TextColored(ImVec4(0.15f, 0.35f, 0.75f, 1), "%s building the metric (%s%s)... %.1f s", spinner(),
                       source_name(s.metric_build_of().source), s.metric_build_applies() ? "" : ", preview",
                       s.metric_build_seconds());
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("The metric is built in the background; the view shows the current one until it is ready.\n"
                        "A newer edit supersedes it (its result is then not installed).");
  } else if (const auto predicted = s.has_mesh() ? s.preview(e) : std::optional<double>()) {
    ImGui::Text("predicted vertices: %.0f", *predicted);
  } else {
    ImGui::TextDisabled("predicted vertices: %s", error.empty() ? "(building)" : "(none)");
  }
  if (!error.empty()) error_text(error);
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
// Where the vertices of the shown pass lie: pulled back to the input (the
// fallback where the G1 surface strayed beyond the input bound) and off the
// surface, with a button for the colours that show where.
void placement_lines(const PlacementCounts& c, ViewState& v) {
  if (!c.known) {
    ImGui::TextDisabled("this state records no vertex placements");
    return;
  }
  const ImVec4 red(0.80f, 0.10f, 0.08f, 1), green(0.08f, 0.50f, 0.20f, 1);
  ImGui::TextColored(c.pulled > 0 ? red : ImGui::GetStyle().Colors[ImGuiCol_TextDisabled],
                     "pulled to the input: %d vertices (%.1f%%)", c.pulled, c.percent(VertexPlacement::Pulled));
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Where the G1 surface strayed farther from the input than the input bound allows,\n"
                      "the vertex was pulled back towards the polyhedral input (the fallback).");
  if (v.color != "fallback") {
    ImGui::SameLine();
    if (ImGui::SmallButton("colour by it")) {
      v.color = "fallback";
      v.bezier = 0;  // the colours are on the mesh
    }
  }
  ImGui::TextColored(c.off_surface > 0 ? green : ImGui::GetStyle().Colors[ImGuiCol_TextDisabled],
                     "off the surface: %d vertices (%.1f%%)", c.off_surface, c.percent(VertexPlacement::OffSurface));
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Splits at the straight midpoint (projection refused), or the final pass's\n"
                      "hausd splits placed part of the way to the input.");
  ImGui::TextDisabled("on the G1 surface: %d vertices (%.1f%%)", c.on_surface, c.percent(VertexPlacement::OnSurface));
}

void adaptation_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("Adaptation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const bool running = s.running();
  // The buttons' tooltips, shown once out of the disabled scopes (a tooltip
  // opened inside one would be drawn faded as the disabled buttons).
  const char* hovered_tip = nullptr;
  auto tip = [&](const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) hovered_tip = text;
  };
  ImGui::BeginDisabled(running || !s.has_mesh());
  if (ImGui::Button("Step")) act(p, "step: one pass", [&] { s.step(); });
  tip("One pass of the adaptation (Space), from the pass shown.");
  ImGui::SameLine();
  if (ImGui::Button("Run")) act(p, "run: passes until converged", [&] { s.run(); });
  tip("Passes until the adaptation converges (R), from the pass shown.");
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(!running);
  if (ImGui::Button("Pause")) act(p, "pause: the run stops after the pass in progress, its passes kept", [&] { s.pause(); });
  tip("Stops after the pass in progress and KEEPS every pass of the run:\n"
      "the timeline stays, Run or Step goes on from there (R).");
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) act(p, "cancel: the run is dropped once the pass in progress ends", [&] { s.cancel(); });
  tip("Stops after the pass in progress and REVERTS the whole run:\n"
      "its passes are dropped, the timeline goes back to where Run (or Step) was pressed.");
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Reset")) act(p, "reset: back to the initial mesh", [&] { s.reset(); });
  tip("Back to the initial mesh T_0: the whole timeline is dropped (the metric stays).");
  if (hovered_tip) ImGui::SetTooltip("%s", hovered_tip);
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
  {
    float band[2] = {static_cast<float>(s.adapt_settings().remesh.op.lmin),
                     static_cast<float>(s.adapt_settings().remesh.op.lmax)};
    ImGui::SetNextItemWidth(200);
    ImGui::InputFloat2("lmin, lmax", band, "%.3g");
    if (ImGui::IsItemDeactivatedAfterEdit()) act(p, "band set", [&] { s.set_band(band[0], band[1]); });
  }
  if (const std::string err = s.adaptation_error(); !err.empty()) error_text("error: " + err);
  const auto tl = s.timeline();
  const int n = static_cast<int>(tl.size());
  int shown = s.scrubbed() >= 0 ? s.scrubbed() : n - 1;
  if (const std::size_t dropped = s.dropped_passes(); dropped > 0)
    ImGui::TextDisabled("%zu earlier passes left the timeline (a run keeps its last %zu: memory)", dropped, kMaxRunSnapshots);
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
    const ImGuiTableFlags tf = ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_ScrollX |
                               ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingFixedFit;
    if (ImGui::BeginTable("##passes", 7, tf, ImVec2(std::min(360.0f, ImGui::GetContentRegionAvail().x), 160))) {
      ImGui::TableSetupScrollFreeze(0, 1);
      for (const char* h : {"#", "pass", "changes", "V", "in band", "q min", "pulled"}) ImGui::TableSetupColumn(h);
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
        ImGui::TableNextColumn();  // vertices pulled to the input (the fallback)
        if (sn->placement.known) ImGui::Text("%d", sn->placement.pulled);
      }
      ImGui::EndTable();
    }
    ImGui::TreePop();
  }
  ImGui::Checkbox("mark the vertices the pass touched", &v.show_touched);
  if (p.view && v.show_touched) {
    const EditorView::MarkerCounts mc = p.view->touched_markers();
    if (mc.shown < mc.total) {
      ImGui::SameLine();
      ImGui::TextDisabled("(%d of %d shown)", mc.shown, mc.total);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("At most %zu markers are drawn, spread evenly over the touched region.",
                          EditorView::kMaxTouchedMarkers);
    }
  }
  const auto& snap = tl[static_cast<std::size_t>(std::clamp(shown, 0, n - 1))];
  if (!snap->has_report) {
    ImGui::TextDisabled("initial mesh: %d vertices, %d triangles", snap->mesh.n_vertices(), snap->mesh.n_triangles());
    ImGui::TextDisabled("its vertices are the input's: no placements yet");
    return;
  }
  const remesh::PassReport& r = snap->report;
  ImGui::Text("pass %d of %d: %s", shown, n - 1, snap->label.c_str());
  ImGui::Text("split %d  collapse %d  swap %d  move %d  removed %d", r.splits, r.collapses, r.swaps, r.moves,
              r.removed_vertices);
  if (r.bound_splits > 0 || r.beyond_bound > 0)
    ImGui::Text("hausd bound: %d splits onto the input, %d points still beyond", r.bound_splits, r.beyond_bound);
  if (r.crease_splits > 0) ImGui::Text("creases: %d splits towards creases of the input", r.crease_splits);
  placement_lines(snap->placement, v);
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
  if (!s.distance_error().empty()) error_text(s.distance_error());
  if (const auto last = s.last_distance())
    ImGui::TextDisabled("(an earlier state: max %.3g, %.3g%%)", last->max(), last->percent(last->max()));
}

void analysis_panel(EditorSession& s, ViewState& v, PanelState& p) {
  if (!s.has_mesh()) return;
  const Analysis* latest = s.latest_analysis();
  if (!latest) return;
  const Analysis& a = *latest;
  if (!s.analysis_current()) ImGui::TextDisabled("(an earlier state: the one shown is being analysed)");
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

void bezier_panel(ViewState& v, PanelState& p) {
  if (!ImGui::CollapsingHeader("G1 surface")) return;
  bool show = v.bezier > 0;
  if (ImGui::Checkbox("show the G1 Bezier surface", &show)) {
    v.bezier = show ? 4 : 0;
    if (show && colors_mesh_only(v.color)) v.color = "size";  // the G1 surface hides the mesh they colour
  }
  if (show) {
    ImGui::SetNextItemWidth(160);
    ImGui::SliderInt("samples per edge", &v.bezier, 1, 12);
    ImGui::Checkbox("control net", &v.control_net);
    bool dev = v.color == "deviation";
    if (ImGui::Checkbox("colour by deviation mesh - surface", &dev)) v.color = dev ? "deviation" : "size";
    if (p.view && p.view->bezier_building()) {
      ImGui::TextColored(ImVec4(0.15f, 0.35f, 0.75f, 1), "%s building the G1 surface... %.1f s", spinner(),
                         p.view->bezier_build_seconds());
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Built in the background; the view shows what it showed before until it is ready.");
    }
    if (p.view && p.view->bezier_k() > 0 && p.view->bezier_k() < v.bezier) {
      ImGui::TextDisabled("drawn with k = %d (at most %d sub-triangles)", p.view->bezier_k(), EditorView::kBezierMaxTriangles);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("At most %d sub-triangles are drawn (k^2 per triangle), so that the surface draws\n"
                          "about as fast as the mesh: k is lowered on a mesh this large.",
                          EditorView::kBezierMaxTriangles);
    }
    if (p.view && v.control_net && p.view->bezier_k() > 0) {
      const render::BezierNetInfo& n = p.view->net_info();
      if (n.shown < n.patches) {
        ImGui::TextDisabled("control net of %d of %d patches", n.shown, n.patches);
        if (ImGui::IsItemHovered())
          ImGui::SetTooltip("The net of every patch would be about %d lines: it is drawn for the %d patches\n"
                            "around the point at the centre of the view when the surface was built.",
                            static_cast<int>(render::control_net_edges().size()) * n.patches, n.shown);
        ImGui::SameLine();
        if (ImGui::SmallButton("re-centre")) p.view->recentre_net();
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Build the net again around the point at the centre of the view");
      } else {
        ImGui::TextDisabled("control net of all %d patches", n.patches);
      }
    }
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
    if (colors_mesh_only(kColorModes[current])) v.bezier = 0;  // they colour the mesh
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

// Whether `h` names a live triangle of `snap`.
bool names_triangle(const Snapshot& snap, const HoverInfo& h) {
  const SurfaceMesh& m = snap.mesh;
  return h.triangle >= 0 && h.triangle < m.triangle_capacity() && !m.is_deleted(Triangle(h.triangle)) && h.vertex >= 0 &&
         h.vertex < m.vertex_capacity();
}

// What is known of a triangle and its closest vertex in state `snap`: its
// quality, edges (metric lengths, tags), the vertex's tags, position,
// distance to the input (when measured for that state), placement, sizes
// and directions of its metric. Pre: names_triangle(snap, h).
void element_info(EditorSession& s, const Snapshot& snap, const HoverInfo& h) {
  const SurfaceMesh& m = snap.mesh;
  const Triangle T(h.triangle);
  std::array<Vec3, 3> pos;
  std::array<SymTensor3, 3> M;
  for (int k = 0; k < 3; ++k) {
    pos[k] = m.position(m.vertex(T, k));
    M[k] = snap.metric[m.vertex(T, k).idx];
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
  const SizesDirections sd = sizes_and_directions(snap.metric[V.idx]);
  ImGui::Separator();
  ImGui::Text("vertex %d  tags: %s", V.idx + 1, tags(m.vertex_tags(V)).c_str());
  const Vec3& x = m.position(V);
  ImGui::Text("at (%.4g, %.4g, %.4g)", x.x, x.y, x.z);
  bool current = false;
  if (const auto dist = s.last_distance(&current);
      dist && current && s.display().snapshot.get() == &snap && V.idx < static_cast<int>(dist->vertex.size()))
    ImGui::Text("distance to the input %.4g (%.3g%% of the diagonal)", dist->vertex[static_cast<std::size_t>(V.idx)],
                dist->percent(dist->vertex[static_cast<std::size_t>(V.idx)]));
  if (const VertexPlacement pl = vertex_placement(m, V); pl != VertexPlacement::None)
    ImGui::Text("placed %s", placement_name(pl));
  for (int i = 0; i < 3; ++i)
    ImGui::Text("size %.4g along (%.3f, %.3f, %.3f)", sd.sizes[i], sd.directions[i].x, sd.directions[i].y,
                sd.directions[i].z);
}

void hover_tooltip(EditorSession& s, const PanelState& p) {
  if (!p.hover || ImGui::GetIO().WantCaptureMouse || !p.view || !p.view->shown()) return;
  const Snapshot& snap = *p.view->shown();
  if (!names_triangle(snap, *p.hover)) return;
  ImGui::BeginTooltip();
  element_info(s, snap, *p.hover);
  ImGui::TextDisabled("click to pin");
  ImGui::EndTooltip();
}

// A click without drag: pins the element under it (unpins on empty space).
void pin_clicked(const render::Scene& scene, PanelState& p, int width, int height) {
  if (!p.click) return;
  const glm::vec2 at = *p.click;
  p.click.reset();
  if (!p.view) return;
  if (const auto h = p.view->hover(scene, at.x, at.y, width, height))
    p.pinned = PanelState::Pinned{*h, p.view->shown_state()};
  else
    p.pinned.reset();
}

// The pinned element's window (closed by its X, Unpin or Esc).
void pinned_window(EditorSession& s, ViewState& v, PanelState& p) {
  if (!p.pinned || !p.pinned->of || !names_triangle(*p.pinned->of, p.pinned->element)) {
    p.pinned.reset();
    return;
  }
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(p.main_rect.x + p.main_rect.w + 8.0f, vp->Pos.y + 8.0f), ImGuiCond_Appearing);
  ImGui::SetNextWindowBgAlpha(0.94f);
  bool open = true;
  if (ImGui::Begin("Pinned element", &open,
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing)) {
    element_info(s, *p.pinned->of, p.pinned->element);
    if (s.display().snapshot != p.pinned->of)
      ImGui::TextDisabled("(of the state shown when it was pinned, not the one shown now)");
    if (p.view && p.pinned->of == p.view->shown_state()) {
      if (ImGui::SmallButton("Frame it")) v.frame_element = p.pinned->element.triangle;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Look at it along its normal and zoom on it (F fits the mesh again)");
      ImGui::SameLine();
    }
    if (ImGui::SmallButton("Unpin")) open = false;
    ImGui::SameLine();
    ImGui::TextDisabled("(Esc; a click elsewhere pins another)");
  }
  ImGui::End();
  if (!open) p.pinned.reset();
}

// The Keys window (F1, ?): the key table and the mouse.
void keys_window(PanelState& p) {
  if (!p.show_keys) return;
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (ImGui::Begin("Keys", &p.show_keys, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
    if (ImGui::BeginTable("##keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
      auto row = [](const char* keys, const char* what) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(keys);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(what);
      };
      for (const KeyBinding& b : key_bindings()) row(b.keys, b.action);
      for (const MouseBinding& m : mouse_bindings()) row(m.gesture, m.action);
      ImGui::EndTable();
    }
    ImGui::TextDisabled("Keys act when no text field has the focus.");
  }
  ImGui::End();
}

// The state's colour in the status bar.
ImVec4 run_state_color(RunState st) {
  switch (st) {
    case RunState::Running: return ImVec4(0.10f, 0.50f, 0.10f, 1);
    case RunState::Pausing:
    case RunState::Cancelling: return ImVec4(0.75f, 0.45f, 0.00f, 1);
    case RunState::Paused: return ImVec4(0.15f, 0.35f, 0.75f, 1);
    case RunState::Converged: return ImVec4(0.05f, 0.45f, 0.45f, 1);
    case RunState::Cancelled: return ImVec4(0.55f, 0.30f, 0.10f, 1);
    case RunState::Failed: return ImVec4(0.80f, 0.10f, 0.10f, 1);
    case RunState::Idle: break;
  }
  return ImVec4(0.40f, 0.40f, 0.40f, 1);
}

// What runs in the background, for the status bar ("" when nothing does).
std::string background_work(EditorSession& s, const PanelState& p) {
  std::string w;
  auto add = [&](const std::string& x) { w += (w.empty() ? "" : ", ") + x; };
  char buf[64];
  if (s.metric_building()) {
    std::snprintf(buf, sizeof buf, "building the metric %.1f s", s.metric_build_seconds());
    add(buf);
  }
  if (p.view && p.view->bezier_building()) {
    std::snprintf(buf, sizeof buf, "building the G1 surface %.1f s", p.view->bezier_build_seconds());
    add(buf);
  }
  if (s.measuring()) add("measuring the distance");
  return w;
}

// The bar at the bottom of the window: the adaptation's state (its tooltip
// says what it means), background work, timings, the Keys button; under
// them the last message and the autosave's error, wrapped (a line kept for
// them when there are none). It grows upwards with a message of several
// lines; the panels end above it.
void status_bar(EditorSession& s, PanelState& p, int width, int height) {
  const float w = static_cast<float>(width);
  ImGui::SetNextWindowPos(ImVec2(0, static_cast<float>(height)), ImGuiCond_Always, ImVec2(0, 1));
  ImGui::SetNextWindowSizeConstraints(ImVec2(w, 0), ImVec2(w, 0.5f * static_cast<float>(height)));
  ImGui::SetNextWindowBgAlpha(0.95f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus;
  if (ImGui::Begin("##status", nullptr, flags)) {
    const RunState st = s.has_mesh() ? s.run_state() : RunState::Idle;
    const std::string state = st == RunState::Running ? std::string(spinner()) + " running" : run_state_name(st);
    ImGui::TextColored(run_state_color(st), "%s", state.c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", run_state_tooltip(st, s.adaptation_error()).c_str());
    if (s.has_mesh()) {
      const auto tl = s.timeline();
      ImGui::SameLine(0, 16);
      const int shown = s.scrubbed() >= 0 ? s.scrubbed() : static_cast<int>(tl.size()) - 1;
      const auto& snap = tl[static_cast<std::size_t>(std::clamp(shown, 0, static_cast<int>(tl.size()) - 1))];
      if (snap->has_report)
        ImGui::TextDisabled("pass %d of %zu: %.2f s", shown, tl.size() - 1, snap->report.seconds);
      else
        ImGui::TextDisabled("initial mesh");
      if (s.last_metric_seconds() > 0) {
        ImGui::SameLine(0, 16);
        ImGui::TextDisabled("metric built in %.2f s", s.last_metric_seconds());
      }
    }
    if (const std::string work = background_work(s, p); !work.empty()) {
      ImGui::SameLine(0, 16);
      ImGui::TextColored(ImVec4(0.15f, 0.35f, 0.75f, 1), "%s %s", spinner(), work.c_str());
    }
    const float right = w - ImGui::GetStyle().WindowPadding.x;
    const float keys_w = ImGui::CalcTextSize("Keys (F1)").x + 2 * ImGui::GetStyle().FramePadding.x;
    if (p.fps > 0) {
      char fps[32];
      std::snprintf(fps, sizeof fps, "%.0f fps", p.fps);
      ImGui::SameLine(std::max(ImGui::GetCursorPosX(), right - keys_w - ImGui::CalcTextSize(fps).x - 16));
      ImGui::TextDisabled("%s", fps);
    }
    ImGui::SameLine(std::max(ImGui::GetCursorPosX(), right - keys_w));
    if (ImGui::SmallButton("Keys (F1)")) p.show_keys = !p.show_keys;
    ImGui::PushTextWrapPos(right);
    if (!p.autosave_error.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.8f, 0.1f, 0.1f, 1));
      ImGui::TextWrapped("autosave: %s", p.autosave_error.c_str());
      ImGui::PopStyleColor();
    }
    if (!p.message.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, p.message_is_error ? ImVec4(0.8f, 0.1f, 0.1f, 1) : ImVec4(0.2f, 0.4f, 0.2f, 1));
      ImGui::TextWrapped("%s", p.message.c_str());
      ImGui::PopStyleColor();
    }
    // The message's line is kept when there is none: the bar (and the
    // legend above it) only moves for a message of several lines.
    if (p.message.empty() && p.autosave_error.empty()) ImGui::TextUnformatted("");
    ImGui::PopTextWrapPos();
    p.status_rect = {ImGui::GetWindowPos().x, ImGui::GetWindowPos().y, ImGui::GetWindowWidth(), ImGui::GetWindowHeight()};
  }
  ImGui::End();
}

// The outlines over the scene: the selection (at most kMaxOutlined of its
// triangles, spread over it), the pinned element and the hovered one.
void draw_element_outlines(EditorSession& s, const PanelState& p, const render::Scene& scene, int width, int height) {
  if (!p.view || !p.view->shown()) return;
  const EditorView& ev = *p.view;
  auto outline = [&](std::span<const int> slots, const glm::vec3& color, float width_px) {
    const auto world = ev.triangle_corners(slots);
    render::OutlineStyle style;
    style.color = color;
    style.width_px = width_px;
    render::draw_outlines(render::project_triangles(scene.camera, world, width, height), style);
  };
  const Selection& sel = s.selection();
  if (sel.active && sel.of == ev.shown_state()) {
    constexpr std::size_t kMaxOutlined = 4000;
    std::vector<int> slots;
    for (std::size_t i : render::evenly_spaced(sel.triangles.size(), kMaxOutlined)) slots.push_back(sel.triangles[i]);
    outline(slots, scene.display.highlight_color, 2.0f);
    if (sel.worst_triangle >= 0) {
      const int worst[] = {sel.worst_triangle};
      outline(worst, {1.0f, 1.0f, 1.0f}, 3.0f);
    }
  }
  if (p.pinned && p.pinned->of == ev.shown_state()) {
    const int pinned[] = {p.pinned->element.triangle};
    outline(pinned, {0.1f, 0.85f, 1.0f}, 3.0f);
  }
  if (p.hover && !ImGui::GetIO().WantCaptureMouse) {
    const int hovered[] = {p.hover->triangle};
    outline(hovered, {1.0f, 0.9f, 0.1f}, 2.5f);
  }
}

const char* action_words(const PanelState::Pending& a) {
  switch (a.action) {
    case PanelState::Action::Open: return "Open";
    case PanelState::Action::Restore: return "Restore";
    case PanelState::Action::Quit: return "Quit";
    case PanelState::Action::None: break;
  }
  return "";
}

// "Unsaved changes": Save (then the action), Discard (the action), Cancel.
void unsaved_dialog(EditorSession& s, ViewState& v, PanelState& p) {
  if (p.ask_unsaved) {
    ImGui::OpenPopup("Unsaved changes");
    p.ask_unsaved = false;
  }
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  const PanelState::Pending& a = p.pending;
  ImGui::Text("The session on %s has unsaved changes.", s.has_mesh() ? s.mesh_path().c_str() : "(no mesh)");
  switch (a.action) {
    case PanelState::Action::Open: ImGui::Text("Open %s replaces it.", a.mesh.c_str()); break;
    case PanelState::Action::Restore: ImGui::Text("Restoring %s replaces it.", a.mesh.c_str()); break;
    case PanelState::Action::Quit: ImGui::TextUnformatted("Quitting closes it."); break;
    case PanelState::Action::None: break;
  }
  ImGui::Spacing();
  ImGui::TextUnformatted("Save first writes the mesh shown and its metric:");
  save_targets(p);
  ImGui::TextDisabled("(the autosave keeps the edits either way: File > autosaved sessions)");
  ImGui::Spacing();
  const std::string save_label = std::string("Save, then ") + action_words(a);
  if (ImGui::Button(save_label.c_str())) {
    ImGui::CloseCurrentPopup();
    if (save_checked(s, p, true)) {
      const PanelState::Pending go = p.pending;
      p.pending = {};
      perform(s, v, p, go);
    }
  }
  ImGui::SameLine();
  const std::string discard_label = std::string("Discard, then ") + action_words(a);
  if (ImGui::Button(discard_label.c_str())) {
    ImGui::CloseCurrentPopup();
    const PanelState::Pending go = p.pending;
    p.pending = {};
    perform(s, v, p, go);
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    ImGui::CloseCurrentPopup();
    p.pending = {};
  }
  ImGui::EndPopup();
}

// "Overwrite?": the files a save would replace; Overwrite saves (then the
// pending action when the save came from "Unsaved changes").
void overwrite_dialog(EditorSession& s, ViewState& v, PanelState& p) {
  if (p.ask_overwrite) {
    ImGui::OpenPopup("Overwrite?");
    p.ask_overwrite = false;
  }
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (!ImGui::BeginPopupModal("Overwrite?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::TextUnformatted(p.overwrite.size() == 1 ? "This file exists and would be replaced:"
                                                 : "These files exist and would be replaced:");
  for (const auto& f : p.overwrite) ImGui::BulletText("%s", f.c_str());
  if (ImGui::Button("Overwrite")) {
    ImGui::CloseCurrentPopup();
    const std::string what = absolute_path(p.save_mesh) + (p.save_sol.empty() ? "" : " and " + absolute_path(p.save_sol));
    act(p, "saved " + what, [&] { s.save(p.save_mesh, p.save_sol); });
    p.overwrite.clear();
    if (!p.message_is_error && p.continue_pending) {
      const PanelState::Pending go = p.pending;
      p.pending = {};
      perform(s, v, p, go);
    }
    p.continue_pending = false;
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    ImGui::CloseCurrentPopup();
    p.overwrite.clear();
    if (p.continue_pending) p.pending = {};
    p.continue_pending = false;
    p.message = "not saved";
    p.message_is_error = false;
  }
  ImGui::EndPopup();
}

// "Save as": the two paths; Save goes through the overwrite check.
void save_as_dialog(EditorSession& s, PanelState& p) {
  if (p.ask_save_as) {
    ImGui::OpenPopup("Save as");
    p.ask_save_as = false;
  }
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (!ImGui::BeginPopupModal("Save as", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  input_text("mesh##saveas", p.save_as_mesh, 460);
  input_text("metric (empty: none)##saveas", p.save_as_sol, 460);
  ImGui::TextDisabled("existing directories only; a file that exists is replaced after a confirmation");
  if (ImGui::Button("Save")) {
    ImGui::CloseCurrentPopup();
    p.save_mesh = p.save_as_mesh;
    p.save_sol = p.save_as_sol;
    save_checked(s, p, false);
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
  ImGui::EndPopup();
}

// The newest autosave of another launch, offered at start (not modal: the
// view stays usable).
void offer_window(EditorSession& s, ViewState& v, PanelState& p) {
  if (!p.offer) return;
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->GetCenter().x, vp->Pos.y + 40), ImGuiCond_Appearing, ImVec2(0.5f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.96f);
  bool open = true;
  if (ImGui::Begin("Restore an earlier session?", &open,
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse)) {
    ImGui::TextUnformatted("An earlier launch autosaved its session:");
    ImGui::BulletText("%s", p.offer->describe().c_str());
    ImGui::TextDisabled("%s", p.offer->path.c_str());
    ImGui::TextDisabled("Restore replays its edits, not its saves (no file is written).");
    if (ImGui::Button("Restore")) {
      request(s, v, p, {PanelState::Action::Restore, p.offer->path, {}});
      open = false;
    }
    ImGui::SameLine();
    if (ImGui::Button("Not now")) open = false;
    ImGui::SameLine();
    ImGui::TextDisabled("(File > autosaved sessions lists them all)");
  }
  ImGui::End();
  if (!open) p.offer.reset();
}

}  // namespace

bool SettingsDraft::follow(const MetricSettings& session) {
  if (valid && session == base) return false;
  edit = base = session;
  valid = true;
  return true;
}

void request(EditorSession& session, ViewState& view, PanelState& panels, PanelState::Pending action) {
  if (session.has_mesh() && session.dirty()) {
    panels.pending = std::move(action);
    panels.ask_unsaved = true;
    return;
  }
  perform(session, view, panels, action);
}

void remember_recent(PanelState& p, const std::string& path) {
  p.recent.erase(std::remove(p.recent.begin(), p.recent.end(), path), p.recent.end());
  p.recent.insert(p.recent.begin(), path);
  if (p.recent.size() > 8) p.recent.resize(8);
}

std::string run_state_tooltip(RunState state, const std::string& error) {
  switch (state) {
    case RunState::Idle:
      return "No pass since the mesh, the metric or the band last changed.\n"
             "Step runs one pass (Space), Run runs passes until converged (R).";
    case RunState::Running:
      return "Passes run in the background; the view follows them.\n"
             "Pause stops after the pass in progress and keeps every pass;\n"
             "Cancel stops after it and drops the whole run.";
    case RunState::Pausing:
      return "Pause asked: the pass in progress finishes, then the run stops.\n"
             "Its passes are kept.";
    case RunState::Cancelling:
      return "Cancel asked: the pass in progress finishes, then the whole run is dropped\n"
             "(the timeline goes back to where the run started).";
    case RunState::Paused:
      return "Stopped before the adaptation converged (Pause, Step, or run N passes).\n"
             "The passes are kept: Run or Step goes on from the pass shown.";
    case RunState::Converged:
      return "The adaptation converged: its last round changed (almost) nothing\n"
             "(at most 1% of the vertices split or collapsed, its splits and collapses\n"
             "undid each other, or the rounds stopped gaining).\n"
             "Run again does nothing: change the metric or the band, or Reset.";
    case RunState::Cancelled:
      return "The last run was cancelled: its passes were dropped and the timeline\n"
             "is back where that run started. Run or Step starts again from there.";
    case RunState::Failed: return "The last pass failed:\n" + error;
  }
  return "";
}

void draw_panels(EditorSession& session, ViewState& view, PanelState& panels, render::Scene& scene,
                 render::UiState& ui, int width, int height) {
  pin_clicked(scene, panels, width, height);
  // The status bar first: the panels and the legend end above it.
  status_bar(session, panels, width, height);
  const float bottom = panels.status_rect.h;
  // The legend (colour bar, curves, glyph key) from the renderer's UI.
  ui.show_panel = false;
  ui.bottom_margin = bottom;
  render::draw_ui(scene, ui, width, height);
  // The save paths follow the opened file (beside it, with its name).
  if (session.has_mesh() && session.opened() != panels.opened_seen) {
    panels.opened_seen = session.opened();
    panels.save_mesh = default_save_mesh(session.mesh_path());
    panels.save_sol = default_save_sol(session.mesh_path());
  }
  // The main panel on the left, from the top to the status bar (its width
  // the user's: the height and the place follow the window).
  const float margin = 8.0f;
  const float main_width = panels.main_rect.w > 0 ? panels.main_rect.w : 380.0f;
  ImGui::SetNextWindowPos(ImVec2(margin, margin), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(std::min(main_width, 0.6f * static_cast<float>(width)),
                                  std::max(static_cast<float>(height) - bottom - 2 * margin, 100.0f)),
                           ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.90f);
  if (ImGui::Begin("anisurf editor", nullptr, ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove)) {
    if (session.has_mesh()) {
      ImGui::TextUnformatted(session.mesh_path().c_str());
      const DisplayState d = session.display();
      ImGui::TextDisabled("%d vertices, %d triangles%s", d.snapshot->mesh.n_vertices(), d.snapshot->mesh.n_triangles(),
                          session.dirty() ? "  (modified)" : "");
    }
    if (session.has_mesh()) {
      const FeatureReport& f = session.features();
      ImGui::TextDisabled("features: %d edges, %d corners (%s)", f.feature_edges, f.corners,
                          session.features_from_file() ? "as listed in the file" : "detected");
    }
    file_panel(session, view, panels);
    metric_panel(session, panels);
    brush_panel(session, view, panels);
    adaptation_panel(session, view, panels);
    bezier_panel(view, panels);
    display_panel(view, scene);
    panels.main_rect = {ImGui::GetWindowPos().x, ImGui::GetWindowPos().y, ImGui::GetWindowWidth(), ImGui::GetWindowHeight()};
    ui.panel_width = ImGui::GetWindowPos().x + ImGui::GetWindowWidth() + margin;
  }
  ImGui::End();
  // The analysis at the right edge, from the top down to the legend.
  panels.analysis_rect = {};
  if (session.has_mesh() && session.latest_analysis()) {
    const float max_h = static_cast<float>(height) - bottom - ui.legend_height - 3 * margin;
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(width) - margin, margin), ImGuiCond_Always, ImVec2(1.0f, 0.0f));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(FLT_MAX, std::max(max_h, 120.0f)));
    ImGui::SetNextWindowBgAlpha(0.90f);
    if (ImGui::Begin("Analysis", nullptr,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove)) {
      ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 280.0f);
      analysis_panel(session, view, panels);
      ImGui::PopTextWrapPos();
      const float w = static_cast<float>(width) - ImGui::GetWindowPos().x + margin;
      if (!ImGui::IsWindowCollapsed()) ui.legend_width = std::max(ui.legend_width, w);
      panels.analysis_rect = {ImGui::GetWindowPos().x, ImGui::GetWindowPos().y, ImGui::GetWindowWidth(),
                              ImGui::GetWindowHeight()};
    }
    ImGui::End();
  }
  draw_element_outlines(session, panels, scene, width, height);
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
  if (!view.paint_tool) hover_tooltip(session, panels);
  pinned_window(session, view, panels);
  keys_window(panels);
  offer_window(session, view, panels);
  unsaved_dialog(session, view, panels);
  overwrite_dialog(session, view, panels);
  save_as_dialog(session, panels);
}

}  // namespace anisurf::editor
