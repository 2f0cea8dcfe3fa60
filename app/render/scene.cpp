#include "render/scene.h"

#include <algorithm>
#include <cmath>

namespace anisurf::render {

void ScalarQuantity::set_range_from_data() {
  float lo = INFINITY, hi = -INFINITY;
  for (float v : values) {
    if (!std::isfinite(v) || (log_scale && v <= 0)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!(lo <= hi)) {
    lo = log_scale ? 1.0f : 0.0f;
    hi = log_scale ? 10.0f : 1.0f;
  }
  range_min = lo;
  range_max = hi;
}

std::size_t EllipseGlyphs::drawn_count() const {
  float d = std::clamp(density, 0.0f, 1.0f);
  auto n = static_cast<std::size_t>(std::ceil(d * static_cast<float>(centers.size())));
  return std::min(n, centers.size());
}

const ScalarQuantity* SurfaceStructure::active_scalar() const {
  for (const auto& s : scalars)
    if (s.name == active) return &s;
  return nullptr;
}

const LabelQuantity* SurfaceStructure::active_label() const {
  for (const auto& l : labels)
    if (l.name == active) return &l;
  return nullptr;
}

const VertexCategories* SurfaceStructure::active_categories() const {
  for (const auto& c : categories)
    if (c.name == active) return &c;
  return nullptr;
}

bool SurfaceStructure::activate(const std::string& quantity) {
  bool known = quantity.empty() || std::any_of(scalars.begin(), scalars.end(), [&](auto& s) { return s.name == quantity; }) ||
               std::any_of(labels.begin(), labels.end(), [&](auto& l) { return l.name == quantity; }) ||
               std::any_of(categories.begin(), categories.end(), [&](auto& c) { return c.name == quantity; });
  if (known) active = quantity;
  return known;
}

std::vector<glm::vec3> Scene::all_positions() const {
  std::vector<glm::vec3> out;
  for (const auto& s : surfaces)
    if (s.enabled) out.insert(out.end(), s.geometry.positions.begin(), s.geometry.positions.end());
  return out;
}

void Scene::fit_camera(float aspect, float reserve_left, float reserve_right) {
  std::vector<glm::vec3> pts = all_positions();
  camera.fit(pts, aspect, 0.06f, reserve_left, reserve_right);
}

}  // namespace anisurf::render
