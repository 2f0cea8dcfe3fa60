// What the renderer draws, independent of OpenGL and of the engine's mesh
// (Polyscope's structure / quantity split): a Scene holds surface structures;
// each has triangle geometry and named quantities that colour it (scalars on
// vertices, triangles or edges; integer labels; vertex categories), curves
// (feature lines, boundaries), point markers and ellipse glyphs.
// mesh_structure.h builds one from a SurfaceMesh; a sampled surface (e.g. the G1 Bezier surface of the
// geometry module) is drawn by adding another structure with its own
// TriangleSet.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "render/camera.h"
#include "render/colormap.h"

namespace anisurf::render {

// Triangles to draw. Orientation: counter-clockwise seen from outside.
struct TriangleSet {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
  // Optional per-corner normals (3 per triangle, e.g. split at creases).
  // Empty: smooth normals averaged at the vertices.
  std::vector<glm::vec3> corner_normals;
};

enum class ScalarLocation {
  Vertex,    // one value per position
  Triangle,  // one value per triangle
  Edge,      // three values per triangle: the edge opposite local corner k
};

// A scalar quantity coloured through a colormap. Values outside the range
// are clamped to the ends of the colormap; NaN values are drawn grey.
struct ScalarQuantity {
  ScalarQuantity() = default;
  ScalarQuantity(std::string n, ScalarLocation l) : name(std::move(n)), location(l) {}

  std::string name;         // shown in the UI and on the legend
  ScalarLocation location = ScalarLocation::Vertex;
  std::vector<float> values;
  Colormap colormap = Colormap::Viridis;
  bool log_scale = false;   // colour by log(value) (values must be > 0)
  float range_min = 0, range_max = 1;  // values at the ends of the colormap
  std::string note;         // one line under the legend ("metric from x.sol")
  // > 0: the legend's ticks also give each value as a percentage of this
  // length (a distance as a share of the model's bounding box diagonal).
  float percent_of = 0;

  // Range = [min, max] of the finite (and, on a log scale, positive) values.
  void set_range_from_data();
};

// Integer labels per triangle (references), drawn with categorical colours.
struct LabelQuantity {
  std::string name;
  std::vector<int> triangle_labels;
};

// A category per vertex (how each vertex was made, say), drawn without
// blending: each triangle shows, around each corner, the points nearer that
// corner than the other two (largest barycentric coordinate) in the colour
// of the corner's category, so that every vertex shows as a patch of its own
// category's colour. The legend lists the categories' labels as given (the
// producer writes the counts into them).
struct VertexCategories {
  struct Category {
    std::string label;  // one legend row
    glm::vec3 color{0.6f};
  };
  std::string name;                  // shown in the UI and as the legend's title
  std::vector<Category> categories;
  std::vector<int> values;           // per position: index into categories (else drawn grey)
  std::string note;                  // lines under the legend
};

// Line segments (2 points each) drawn with a constant width in pixels.
struct Curves {
  std::string name;
  std::vector<glm::vec3> points;
  glm::vec3 color{0, 0, 0};
  float width_px = 2.5f;
  bool enabled = true;
};

// Discs of constant pixel radius at points.
struct Markers {
  std::string name;
  std::vector<glm::vec3> positions;
  glm::vec3 color{1, 0, 0};
  float radius_px = 4.0f;
  bool enabled = true;
};

// Ellipses c + cos(t) u + sin(t) v (e.g. the unit ball of a metric in the
// tangent plane). The order matters: drawing a fraction `density` of them
// draws the first ones, so the producer orders them so that every prefix is
// spread evenly (see mesh_structure.h).
struct EllipseGlyphs {
  std::string name;
  std::vector<glm::vec3> centers, axes_u, axes_v;
  glm::vec3 color{0.95f, 0.45f, 0.1f};
  float density = 1.0f;  // fraction drawn, in (0, 1]
  float scale = 1.0f;    // multiplies both axes
  bool enabled = true;
  std::size_t drawn_count() const;
};

struct SurfaceStructure {
  std::string name;  // unique in a Scene (the renderer caches GPU data by name)
  TriangleSet geometry;
  glm::vec3 color{0.70f, 0.74f, 0.80f};   // when no quantity is active
  std::vector<ScalarQuantity> scalars;
  std::vector<LabelQuantity> labels;
  std::vector<VertexCategories> categories;
  std::vector<Curves> curves;
  std::vector<Markers> markers;
  std::vector<EllipseGlyphs> glyphs;
  std::vector<std::uint32_t> highlight_triangles;  // indices into geometry.triangles
  bool enabled = true;
  // Name of the scalar, label or category quantity colouring the surface ("" = none).
  std::string active;

  const ScalarQuantity* active_scalar() const;
  const LabelQuantity* active_label() const;
  const VertexCategories* active_categories() const;
  // Sets `active`; false (unchanged) if no quantity has that name.
  bool activate(const std::string& quantity);

  // Bump after changing data (not after toggles / ranges): the renderer
  // re-uploads GPU buffers when the version changed.
  std::uint64_t version = 0;
};

struct DisplayOptions {
  bool flat = false;              // flat (per triangle) or smooth shading
  bool wireframe = false;         // barycentric wireframe overlay
  float wire_width_px = 1.0f;
  glm::vec3 wire_color{0.12f, 0.12f, 0.14f};
  glm::vec3 highlight_color{1.0f, 0.15f, 0.55f};
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  int msaa_samples = 4;           // 1 disables multisampling
  bool legend = true;             // colour bar of the active quantity
};

struct Scene {
  std::vector<SurfaceStructure> surfaces;
  DisplayOptions display;
  Camera camera;

  // Positions of every enabled surface (for camera fitting), world coordinates.
  std::vector<glm::vec3> all_positions() const;
  // Fits the camera to the enabled surfaces for the current orientation,
  // keeping fractions of the width free on the left (the panel) and on the
  // right (the legend).
  void fit_camera(float aspect, float reserve_left = 0.0f, float reserve_right = 0.0f);
};

}  // namespace anisurf::render
