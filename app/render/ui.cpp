#include "render/ui.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace anisurf::render {

namespace {

ImU32 to_imgui(const glm::vec3& c, float alpha = 1.0f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, alpha));
}

std::string format_value(float v) {
  char buf[32];
  float a = std::abs(v);
  if (v == 0.0f || (a >= 1e-3f && a < 1e5f))
    std::snprintf(buf, sizeof buf, "%.4g", v);
  else
    std::snprintf(buf, sizeof buf, "%.2e", v);
  return buf;
}

const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

SurfaceStructure* first_enabled(Scene& scene) {
  for (auto& s : scene.surfaces)
    if (s.enabled) return &s;
  return nullptr;
}

void legend_window(Scene& scene, UiState& ui, int width, int height) {
  ui.legend_width = 0;
  ui.legend_height = 0;
  SurfaceStructure* s = first_enabled(scene);
  if (!s) return;
  const ScalarQuantity* q = s->active_scalar();
  const LabelQuantity* l = s->active_label();
  const VertexCategories* vc = s->active_categories();
  bool any_curves = false;
  for (const auto& c : s->curves) any_curves |= c.enabled && !c.points.empty();
  for (const auto& m : s->markers) any_curves |= m.enabled && !m.positions.empty();
  any_curves |= !s->highlight_triangles.empty();
  const EllipseGlyphs* glyphs = nullptr;
  for (const auto& g : s->glyphs)
    if (g.enabled && !g.centers.empty()) glyphs = &g;
  if (!q && !l && !vc && !any_curves && !glyphs) return;

  const float pad = 12.0f;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(width) - pad, static_cast<float>(height) - pad - ui.bottom_margin),
                          ImGuiCond_Always,
                          ImVec2(1.0f, 1.0f));
  ImGui::SetNextWindowBgAlpha(0.82f);
  ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                           ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                           ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove;
  if (!ImGui::Begin("##legend", nullptr, flags)) {
    ImGui::End();
    return;
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float line = ImGui::GetTextLineHeight();
  if (q) {
    ImGui::TextUnformatted(q->name.c_str());
    // Vertical bar, high values on top, ticks on its right.
    const float bar_w = 16.0f, bar_h = std::clamp(static_cast<float>(height) * 0.25f, 80.0f, 240.0f);
    ImVec2 p0 = ImGui::GetCursorScreenPos();
    p0.y += 0.5f * line;
    const int n = 48;
    auto tmap = [&](float v) {
      float a = q->log_scale ? std::log(std::max(v, 1e-30f)) : v;
      float lo = q->log_scale ? std::log(std::max(q->range_min, 1e-30f)) : q->range_min;
      float hi = q->log_scale ? std::log(std::max(q->range_max, 1e-30f)) : q->range_max;
      return hi > lo ? (a - lo) / (hi - lo) : 0.5f;
    };
    for (int i = 0; i < n; ++i) {
      float t0 = static_cast<float>(i) / n, t1 = static_cast<float>(i + 1) / n;
      ImU32 c0 = to_imgui(colormap_color(q->colormap, t0)), c1 = to_imgui(colormap_color(q->colormap, t1));
      float y0 = p0.y + bar_h * (1.0f - t0), y1 = p0.y + bar_h * (1.0f - t1);
      dl->AddRectFilledMultiColor(ImVec2(p0.x, y1), ImVec2(p0.x + bar_w, y0), c1, c1, c0, c0);
    }
    dl->AddRect(ImVec2(p0.x - 0.5f, p0.y - 0.5f), ImVec2(p0.x + bar_w + 0.5f, p0.y + bar_h + 0.5f),
                IM_COL32(60, 60, 60, 255));
    float label_w = 0;
    for (float v : legend_ticks(q->range_min, q->range_max, q->log_scale)) {
      float y = p0.y + bar_h * (1.0f - std::clamp(tmap(v), 0.0f, 1.0f));
      dl->AddLine(ImVec2(p0.x + bar_w, y), ImVec2(p0.x + bar_w + 5, y), IM_COL32(60, 60, 60, 255));
      std::string txt = format_value(v);
      if (q->percent_of > 0) txt += "  (" + format_value(100.0f * v / q->percent_of) + "%)";
      dl->AddText(ImVec2(p0.x + bar_w + 8, y - 0.5f * line), ImGui::GetColorU32(ImGuiCol_Text), txt.c_str());
      label_w = std::max(label_w, ImGui::CalcTextSize(txt.c_str()).x);
    }
    const float width = std::max(bar_w + 10 + label_w, 150.0f);
    ImGui::Dummy(ImVec2(width, bar_h + line));
    if (!q->note.empty()) {
      ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + width + 40.0f);
      ImGui::TextDisabled("%s", q->note.c_str());
      ImGui::PopTextWrapPos();
    }
  } else if (l) {
    ImGui::TextUnformatted(l->name.c_str());
    std::map<int, std::size_t> counts;
    for (int v : l->triangle_labels) ++counts[v];
    // As many rows as fit in about 70% of the height (at most 16).
    const float row = ImGui::GetFrameHeightWithSpacing();
    std::size_t rows = static_cast<std::size_t>(std::clamp((0.7f * static_cast<float>(height) - 3 * row) / row, 2.0f, 16.0f));
    if (counts.size() > rows) --rows;  // room for the "more" line
    std::size_t shown = 0;
    for (const auto& [label, count] : counts) {
      if (shown++ == rows) {
        ImGui::TextDisabled("... %zu more", counts.size() - rows);
        break;
      }
      ImVec2 p = ImGui::GetCursorScreenPos();
      dl->AddRectFilled(ImVec2(p.x, p.y + 2), ImVec2(p.x + line - 2, p.y + line), to_imgui(categorical_color(label)));
      ImGui::Dummy(ImVec2(line, line));
      ImGui::SameLine();
      ImGui::Text("%d  (%zu triangles)", label, count);
    }
  } else if (vc) {
    ImGui::TextUnformatted(vc->name.c_str());
    for (const auto& c : vc->categories) {
      ImVec2 p = ImGui::GetCursorScreenPos();
      dl->AddRectFilled(ImVec2(p.x, p.y + 2), ImVec2(p.x + line - 2, p.y + line), to_imgui(c.color));
      dl->AddRect(ImVec2(p.x, p.y + 2), ImVec2(p.x + line - 2, p.y + line), IM_COL32(60, 60, 60, 255));
      ImGui::Dummy(ImVec2(line, line));
      ImGui::SameLine();
      ImGui::TextUnformatted(c.label.c_str());
    }
    if (!vc->note.empty()) {
      float rows_w = 0;
      for (const auto& c : vc->categories) rows_w = std::max(rows_w, line + ImGui::CalcTextSize(c.label.c_str()).x);
      ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + std::max(rows_w, 260.0f));
      ImGui::TextDisabled("%s", vc->note.c_str());
      ImGui::PopTextWrapPos();
    }
  }
  if (any_curves) {
    if (q || l || vc) ImGui::Separator();
    for (const auto& c : s->curves) {
      if (!c.enabled || c.points.empty()) continue;
      ImVec2 p = ImGui::GetCursorScreenPos();
      dl->AddLine(ImVec2(p.x, p.y + 0.5f * line), ImVec2(p.x + 2 * line, p.y + 0.5f * line), to_imgui(c.color),
                  std::max(c.width_px, 1.0f));
      ImGui::Dummy(ImVec2(2 * line, line));
      ImGui::SameLine();
      ImGui::Text("%s (%zu)", c.name.c_str(), c.points.size() / 2);
    }
    if (!s->highlight_triangles.empty()) {
      ImVec2 p = ImGui::GetCursorScreenPos();
      dl->AddTriangleFilled(ImVec2(p.x + 0.4f * line, p.y + line), ImVec2(p.x + 1.6f * line, p.y + line),
                            ImVec2(p.x + line, p.y + 0.1f * line), to_imgui(scene.display.highlight_color));
      ImGui::Dummy(ImVec2(2 * line, line));
      ImGui::SameLine();
      ImGui::Text("highlighted triangles (%zu)", s->highlight_triangles.size());
    }
    for (const auto& m : s->markers) {
      if (!m.enabled || m.positions.empty()) continue;
      ImVec2 p = ImGui::GetCursorScreenPos();
      dl->AddCircleFilled(ImVec2(p.x + line, p.y + 0.5f * line), m.radius_px, to_imgui(m.color));
      dl->AddCircle(ImVec2(p.x + line, p.y + 0.5f * line), m.radius_px, to_imgui(m.color * 0.25f));
      ImGui::Dummy(ImVec2(2 * line, line));
      ImGui::SameLine();
      ImGui::Text("%s (%zu)", m.name.c_str(), m.positions.size());
    }
  }
  if (glyphs) {
    if (q || l || vc || any_curves) ImGui::Separator();
    ImVec2 p = ImGui::GetCursorScreenPos();
    ImVec2 c(p.x + line, p.y + 0.5f * line);
    for (int i = 0; i < 24; ++i) {
      float t = 6.2831853f * static_cast<float>(i) / 24.0f;
      dl->PathLineTo(ImVec2(c.x + 0.9f * line * std::cos(t), c.y + 0.4f * line * std::sin(t)));
    }
    const glm::vec3 gc = s->active.empty() ? glyphs->color : glm::vec3(0.97f);  // as the renderer draws them
    dl->PathFillConvex(to_imgui(gc, 0.4f));
    for (int i = 0; i <= 24; ++i) {
      float t = 6.2831853f * static_cast<float>(i) / 24.0f;
      dl->PathLineTo(ImVec2(c.x + 0.9f * line * std::cos(t), c.y + 0.4f * line * std::sin(t)));
    }
    dl->PathStroke(to_imgui(gc * 0.35f), 0, 1.5f);
    ImGui::Dummy(ImVec2(2 * line, line));
    ImGui::SameLine();
    ImGui::Text("unit ellipse x %.2g", glyphs->scale);
    ImGui::TextDisabled("%zu of %zu vertices", glyphs->drawn_count(), glyphs->centers.size());
  }
  ui.legend_width = ImGui::GetWindowWidth() + 2 * pad;
  ui.legend_height = ImGui::GetWindowHeight() + pad;
  ImGui::End();
}

bool combo_strings(const char* label, int* index, const std::vector<std::string>& items) {
  auto getter = [](void* data, int i, const char** out) {
    *out = (*static_cast<const std::vector<std::string>*>(data))[static_cast<std::size_t>(i)].c_str();
    return true;
  };
  return ImGui::Combo(label, index, getter, const_cast<std::vector<std::string>*>(&items),
                      static_cast<int>(items.size()));
}

void panel_window(Scene& scene, UiState& ui) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.88f);
  if (!ImGui::Begin("anisurf", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
    ImGui::End();
    return;
  }
  if (!ui.title.empty()) ImGui::TextUnformatted(ui.title.c_str());
  if (!ui.info.empty()) ImGui::TextDisabled("%s", ui.info.c_str());
  if (ui.fps > 0) ImGui::TextDisabled("%.1f fps", ui.fps);
  DisplayOptions& d = scene.display;

  for (std::size_t si = 0; si < scene.surfaces.size(); ++si) {
    SurfaceStructure& s = scene.surfaces[si];
    ImGui::PushID(static_cast<int>(si));
    ImGui::Separator();
    ImGui::Checkbox(s.name.c_str(), &s.enabled);
    // Colour: none, each scalar, label and category quantity.
    std::vector<std::string> names = {"(plain)"};
    for (const auto& q : s.scalars) names.push_back(q.name);
    for (const auto& l : s.labels) names.push_back(l.name);
    for (const auto& c : s.categories) names.push_back(c.name);
    int current = 0;
    for (std::size_t i = 1; i < names.size(); ++i)
      if (names[i] == s.active) current = static_cast<int>(i);
    ImGui::SetNextItemWidth(180);
    if (combo_strings("colour", &current, names)) s.activate(current == 0 ? "" : names[static_cast<std::size_t>(current)]);
    if (current == 0) {
      ImGui::SetNextItemWidth(180);
      ImGui::ColorEdit3("surface", &s.color.r, ImGuiColorEditFlags_NoInputs);
    }
    for (auto& q : s.scalars) {
      if (q.name != s.active) continue;
      int cm = q.colormap == Colormap::Viridis ? 0 : 1;
      const char* maps[] = {"viridis", "coolwarm"};
      ImGui::SetNextItemWidth(180);
      if (ImGui::Combo("colormap", &cm, maps, 2)) q.colormap = cm == 0 ? Colormap::Viridis : Colormap::Coolwarm;
      ImGui::SetNextItemWidth(180);
      float speed = std::max(std::abs(q.range_max - q.range_min), 1e-6f) * 0.005f;
      ImGui::DragFloatRange2("range", &q.range_min, &q.range_max, speed, 0, 0, "%.4g", "%.4g");
      ImGui::Checkbox("log scale", &q.log_scale);
      ImGui::SameLine();
      if (ImGui::Button("data range")) q.set_range_from_data();
    }
    for (auto& c : s.curves) {
      std::string label = c.name + " (" + std::to_string(c.points.size() / 2) + ")";
      ImGui::Checkbox(label.c_str(), &c.enabled);
    }
    for (auto& m : s.markers) {
      std::string label = m.name + " (" + std::to_string(m.positions.size()) + ")";
      ImGui::Checkbox(label.c_str(), &m.enabled);
    }
    for (auto& g : s.glyphs) {
      ImGui::Checkbox(g.name.c_str(), &g.enabled);
      if (g.enabled) {
        ImGui::SetNextItemWidth(180);
        ImGui::SliderFloat("density", &g.density, 0.001f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic);
        ImGui::SetNextItemWidth(180);
        ImGui::SliderFloat("scale", &g.scale, 0.05f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
      }
    }
    ImGui::PopID();
  }

  ImGui::Separator();
  int shading = d.flat ? 1 : 0;
  ImGui::RadioButton("smooth", &shading, 0);
  ImGui::SameLine();
  ImGui::RadioButton("flat", &shading, 1);
  d.flat = shading == 1;
  ImGui::Checkbox("wireframe", &d.wireframe);
  if (d.wireframe) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    ImGui::SliderFloat("width", &d.wire_width_px, 0.5f, 4.0f, "%.1f px");
  }
  ImGui::Checkbox("legend", &d.legend);

  ImGui::Separator();
  Camera& cam = scene.camera;
  if (ImGui::Checkbox("orthographic", &cam.orthographic)) ui.fit_requested = true;
  for (NamedView v : {NamedView::Iso, NamedView::Front, NamedView::Back, NamedView::Top, NamedView::Bottom,
                      NamedView::Left, NamedView::Right}) {
    if (v != NamedView::Iso && v != NamedView::Top) ImGui::SameLine();
    if (ImGui::SmallButton(view_name(v))) {
      cam.set_view(v);
      ui.fit_requested = true;
    }
  }
  if (ImGui::SmallButton("fit")) ui.fit_requested = true;
  ImGui::SameLine();
  int up = cam.up_axis == UpAxis::Y ? 0 : 1;
  ImGui::RadioButton("y up", &up, 0);
  ImGui::SameLine();
  ImGui::RadioButton("z up", &up, 1);
  UpAxis new_up = up == 0 ? UpAxis::Y : UpAxis::Z;
  if (new_up != cam.up_axis) {
    cam.up_axis = new_up;
    ui.fit_requested = true;
  }
  ImGui::SetNextItemWidth(180);
  ImGui::ColorEdit3("background", &d.background.r, ImGuiColorEditFlags_NoInputs);
  ui.panel_width = ImGui::GetWindowPos().x + ImGui::GetWindowWidth() + 8.0f;
  ImGui::End();
}

}  // namespace

ImGuiSession::ImGuiSession() {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the working directory
  io.LogFilename = nullptr;
  ImGui::StyleColorsLight();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 4.0f;
  style.FrameRounding = 3.0f;
  style.WindowBorderSize = 1.0f;
  std::error_code ec;
  if (std::filesystem::exists(kFontPath, ec)) io.Fonts->AddFontFromFileTTF(kFontPath, 15.0f);
  if (io.Fonts->Fonts.empty()) io.Fonts->AddFontDefault();
}

ImGuiSession::~ImGuiSession() { ImGui::DestroyContext(); }

void draw_ui(Scene& scene, UiState& ui, int width, int height) {
  ui.panel_width = 0;
  if (ui.show_panel) panel_window(scene, ui);
  ui.legend_width = 0;
  ui.legend_height = 0;
  if (scene.display.legend) legend_window(scene, ui, width, height);
}

float UiState::left_reserve(int width) const {
  return width > 0 ? std::min(panel_width / static_cast<float>(width), 0.45f) : 0.0f;
}

float UiState::right_reserve(int width) const {
  return width > 0 ? std::min(legend_width / static_cast<float>(width), 0.45f) : 0.0f;
}

std::vector<float> legend_ticks(float lo, float hi, bool log_scale) {
  std::vector<float> out;
  if (!(hi > lo)) return {lo};
  if (log_scale && lo > 0) {
    // 1, 2, 5 times powers of ten inside the range.
    for (int e = static_cast<int>(std::floor(std::log10(lo))); e <= static_cast<int>(std::ceil(std::log10(hi))); ++e)
      for (float m : {1.0f, 2.0f, 5.0f}) {
        float v = m * std::pow(10.0f, static_cast<float>(e));
        if (v > lo * 1.0001f && v < hi * 0.9999f) out.push_back(v);
      }
    if (out.size() > 7) {  // too many: keep powers of ten only
      std::vector<float> p;
      for (float v : out)
        if (std::abs(std::log10(v) - std::round(std::log10(v))) < 1e-4f) p.push_back(v);
      out = p;
    }
  } else {
    // A step of 1, 2 or 5 times a power of ten giving 3 to 7 ticks.
    float raw = (hi - lo) / 5.0f;
    float p10 = std::pow(10.0f, std::floor(std::log10(raw)));
    float step = p10;
    for (float m : {1.0f, 2.0f, 5.0f, 10.0f})
      if (m * p10 >= raw) {
        step = m * p10;
        break;
      }
    for (float v = std::ceil(lo / step) * step; v < hi - 1e-4f * step; v += step)
      if (v > lo + 1e-4f * step) out.push_back(std::abs(v) < 1e-6f * step ? 0.0f : v);
  }
  // The ends, dropping inner ticks that would overlap them.
  std::vector<float> ticks = {lo};
  auto pos = [&](float v) {
    return log_scale && lo > 0 ? std::log(v / lo) / std::log(hi / lo) : (v - lo) / (hi - lo);
  };
  for (float v : out)
    if (pos(v) > 0.12f && pos(v) < 0.88f) ticks.push_back(v);
  ticks.push_back(hi);
  return ticks;
}

}  // namespace anisurf::render
