// Turns an engine SurfaceMesh (and its fields) into a drawable structure
// (render/scene.h): the live triangles, feature curves and corners from the
// mesh tags, and the colour quantities the `shot --color` modes and the
// viewer's panel offer. Metric lengths and qualities come from the engine's
// metric module; only the tangent-plane ellipse of the glyphs (and the sizes
// read from it) are computed here.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "mesh/surface_mesh.h"
#include "metric/length.h"
#include "metric/metric.h"
#include "metric/metric_field.h"
#include "render/scene.h"

namespace anisurf::render {

// Names of the quantities made by make_mesh_structure().
namespace quantity {
inline constexpr const char* kQuality = "quality";        // triangle, eq. 17 in the metric (or Euclidean)
inline constexpr const char* kLength = "edge length";     // edge, metric length (or Euclidean)
inline constexpr const char* kSize = "size";              // vertex, sqrt(h1 h2) of the tangent metric
inline constexpr const char* kAniso = "anisotropy";       // vertex, h_max / h_min of the tangent metric
inline constexpr const char* kReference = "reference";    // triangle labels
inline constexpr const char* kDistance = "distance to input";  // vertex, to the input surface (the editor adds it)
}  // namespace quantity

struct MeshStructureOptions {
  // Display only: smooth normals are also split where the dihedral angle
  // exceeds this (besides ridge and boundary edges), so CAD parts without
  // ridge tags still look sharp. 180 disables it.
  double crease_angle_deg = 50.0;
  // Field used as the metric: "" picks the first tensor field, else the first
  // scalar field (an isotropic size map), as metric_from_field() does. An
  // unusable automatic choice is recorded in MeshStructure::metric_problem
  // and the mesh is drawn without a metric; a named one throws.
  std::string metric_field;
  // BuildReport::vertex_origin, so that messages number vertices as the file.
  std::vector<int> vertex_origin;
  LengthFormula length_formula = LengthFormula::LinearMetric;  // eq. 6
  // Fraction of the metric glyphs drawn (0: automatic, about 2500 glyphs) and
  // their scale relative to the unit ellipse (0: automatic, so that the median
  // glyph spans 0.45 of the mean distance between the drawn ones: they nearly
  // touch; 0.45 on a mesh adapted to the metric with every glyph drawn).
  float glyph_density = 0.0f;
  float glyph_scale = 0.0f;
};

struct MeshStructure {
  SurfaceStructure structure;
  std::string metric_field;           // field used as the metric ("" if none)
  std::string metric_problem;         // why there is no metric despite fields ("" otherwise)
  std::vector<int> draw_triangle;     // mesh triangle index -> geometry index (-1 if deleted)
  std::vector<int> draw_vertex;       // mesh vertex index -> geometry index (-1 if deleted)
};

// Builds everything; throws Error if options.metric_field names a field that
// is absent or not usable as a metric (its message lists the fields).
MeshStructure make_mesh_structure(const SurfaceMesh& mesh, const std::string& name,
                                  const MeshStructureOptions& options = {});

// A vertex quantity of `s` from one value per vertex slot of the mesh `s`
// was made from (NaN or a missing slot: drawn grey). Range: that of the data.
ScalarQuantity vertex_quantity(const MeshStructure& s, const std::string& name, const std::vector<double>& per_slot);

// Highlights mesh triangles (and draws mesh vertices as markers), ids 0-based
// in the mesh's numbering. Throws Error naming the first id out of range
// (1-based in the message, as users type them).
void highlight(MeshStructure& s, const std::vector<int>& triangles, const std::vector<int>& vertices);

// The unit ellipse of metric M in the plane orthogonal to the unit normal n:
// semi-axes (largest first), as vectors of length h = lambda^-1/2. Empty if
// the restricted tensor is not positive definite.
struct TangentEllipse {
  Vec3 major, minor;
};
std::optional<TangentEllipse> tangent_ellipse(const SymTensor3& M, const Vec3& n);

// An order of the points such that every prefix is spread evenly over them
// (coarse-to-fine grid sampling), deterministic.
std::vector<int> spread_order(const std::vector<Vec3>& points);

}  // namespace anisurf::render
