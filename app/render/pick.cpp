#include "render/pick.h"

#include <cmath>
#include <limits>

namespace anisurf::render {

Ray pixel_ray(const Camera& camera, float x, float y, int width, int height) {
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const glm::mat4 inv = glm::inverse(camera.projection(aspect) * camera.view());
  const float nx = 2.0f * (x + 0.5f) / static_cast<float>(width) - 1.0f;
  const float ny = 1.0f - 2.0f * (y + 0.5f) / static_cast<float>(height);
  glm::vec4 a = inv * glm::vec4(nx, ny, -1.0f, 1.0f), b = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
  const glm::vec3 p0 = glm::vec3(a) / a.w, p1 = glm::vec3(b) / b.w;
  return {p0, glm::normalize(p1 - p0)};
}

std::optional<PickHit> pick(const TriangleSet& g, const Ray& ray) {
  std::optional<PickHit> best;
  float best_t = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < g.triangles.size(); ++i) {
    const glm::uvec3& t = g.triangles[i];
    const glm::vec3 &a = g.positions[t.x], &b = g.positions[t.y], &c = g.positions[t.z];
    // Moller-Trumbore.
    const glm::vec3 e1 = b - a, e2 = c - a;
    const glm::vec3 p = glm::cross(ray.direction, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-20f) continue;
    const float inv = 1.0f / det;
    const glm::vec3 s = ray.origin - a;
    const float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) continue;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(ray.direction, q) * inv;
    if (v < 0.0f || u + v > 1.0f) continue;
    const float d = glm::dot(e2, q) * inv;
    if (d <= 0.0f || d >= best_t) continue;
    best_t = d;
    best = PickHit{static_cast<std::uint32_t>(i), glm::vec3(1 - u - v, u, v), ray.origin + d * ray.direction, d};
  }
  return best;
}

std::optional<glm::vec2> project_to_pixel(const Camera& camera, const glm::vec3& p, int width, int height) {
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const glm::vec4 c = camera.projection(aspect) * camera.view() * glm::vec4(p, 1.0f);
  if (c.w <= 0) return std::nullopt;
  const glm::vec3 n = glm::vec3(c) / c.w;
  return glm::vec2((n.x + 1.0f) * 0.5f * static_cast<float>(width), (1.0f - n.y) * 0.5f * static_cast<float>(height));
}

}  // namespace anisurf::render
