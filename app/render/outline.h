// Outlines of chosen triangles (a selection, the element under the mouse,
// a pinned one) drawn over the rendered scene with no depth test: projected
// to pixels and stroked as 2D lines on Dear ImGui's background draw list
// (above the 3D picture, below the panels), a dark halo under a bright line
// so that they show on any colour. A triangle too small on screen to be
// seen (a sliver seen from afar) also gets a ring around it.
#pragma once
#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "render/camera.h"

namespace anisurf::render {

using WorldTriangle = std::array<glm::vec3, 3>;

// A triangle's corners in pixels (top-left origin).
struct ScreenTriangle {
  std::array<glm::vec2, 3> corner;
  glm::vec2 centroid() const { return (corner[0] + corner[1] + corner[2]) / 3.0f; }
  // The largest distance between two corners, in pixels.
  float extent() const;
};

// The triangles projected into a width x height view; those with a corner
// behind the eye are left out.
std::vector<ScreenTriangle> project_triangles(const Camera& camera, std::span<const WorldTriangle> triangles, int width,
                                              int height);

// At most `cap` of `count` items, spread evenly over them (every k-th):
// the indices to keep, in order.
std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t cap);

struct OutlineStyle {
  glm::vec3 color{1.0f, 0.9f, 0.1f};
  float width_px = 2.5f;       // the bright line; the halo is 2.5 px wider
  float ring_below_px = 8.0f;  // triangles smaller than this on screen get a ring of this radius
};

// Strokes the outlines on the background draw list of the current ImGui
// frame (between ImGui::NewFrame() and ImGui::Render()).
void draw_outlines(std::span<const ScreenTriangle> triangles, const OutlineStyle& style);

}  // namespace anisurf::render
