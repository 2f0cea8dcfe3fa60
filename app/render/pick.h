// Picking: the triangle of a TriangleSet under a pixel (a ray from the
// camera through the pixel, the closest hit). CPU, brute force over the
// triangles (about 1 ms per 100k triangles), independent of the GL backend.
#pragma once
#include <glm/glm.hpp>

#include <optional>

#include "render/camera.h"
#include "render/scene.h"

namespace anisurf::render {

struct PickHit {
  std::uint32_t triangle = 0;  // index into geometry.triangles
  glm::vec3 barycentric{0};    // weights of the triangle's 3 vertices
  glm::vec3 point{0};
  float distance = 0;          // along the ray
};

// The ray through pixel (x, y) (pixels from the top-left of a width x height
// view) in world coordinates.
struct Ray {
  glm::vec3 origin, direction;  // direction unit
};
Ray pixel_ray(const Camera& camera, float x, float y, int width, int height);

// Closest triangle hit by the ray (both sides), if any.
std::optional<PickHit> pick(const TriangleSet& geometry, const Ray& ray);

// Pixel (top-left origin) of a world point; nullopt behind the camera.
std::optional<glm::vec2> project_to_pixel(const Camera& camera, const glm::vec3& p, int width, int height);

}  // namespace anisurf::render
