#include "render/outline.h"

#include <imgui.h>

#include <algorithm>

#include "render/pick.h"

namespace anisurf::render {

float ScreenTriangle::extent() const {
  return std::max({glm::length(corner[1] - corner[0]), glm::length(corner[2] - corner[1]),
                   glm::length(corner[0] - corner[2])});
}

std::vector<ScreenTriangle> project_triangles(const Camera& camera, std::span<const WorldTriangle> triangles, int width,
                                              int height) {
  std::vector<ScreenTriangle> out;
  out.reserve(triangles.size());
  for (const WorldTriangle& t : triangles) {
    ScreenTriangle s;
    bool visible = true;
    for (int k = 0; k < 3 && visible; ++k) {
      const auto p = project_to_pixel(camera, t[static_cast<std::size_t>(k)], width, height);
      if (p) s.corner[static_cast<std::size_t>(k)] = *p;
      visible = p.has_value();
    }
    if (visible) out.push_back(s);
  }
  return out;
}

std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t cap) {
  std::vector<std::size_t> keep;
  if (cap == 0 || count == 0) return keep;
  const std::size_t n = std::min(count, cap);
  keep.reserve(n);
  // Index i * count / n: the gaps differ by at most one item.
  for (std::size_t i = 0; i < n; ++i) keep.push_back(i * count / n);
  return keep;
}

namespace {

ImVec2 im(const glm::vec2& p) { return ImVec2(p.x, p.y); }

}  // namespace

void draw_outlines(std::span<const ScreenTriangle> triangles, const OutlineStyle& style) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const ImU32 halo = IM_COL32(15, 15, 20, 235);
  const ImU32 line = ImGui::ColorConvertFloat4ToU32(ImVec4(style.color.r, style.color.g, style.color.b, 1.0f));
  for (int pass = 0; pass < 2; ++pass) {
    const ImU32 c = pass == 0 ? halo : line;
    const float w = pass == 0 ? style.width_px + 2.5f : style.width_px;
    for (const ScreenTriangle& t : triangles) {
      const ImVec2 pts[3] = {im(t.corner[0]), im(t.corner[1]), im(t.corner[2])};
      dl->AddPolyline(pts, 3, c, ImDrawFlags_Closed, w);
      if (t.extent() < style.ring_below_px) dl->AddCircle(im(t.centroid()), style.ring_below_px, c, 24, w);
    }
  }
}

}  // namespace anisurf::render
