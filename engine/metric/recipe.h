// The metric of an adaptation as one value: a source (a given field, an
// isotropic size, expressions, the Hessian of a function or of a solution
// field, the curvature for a chordal deviation), the size bounds, the
// chordal-deviation intersection (Mmg's -hausd) and the size gradation, in
// the order of Mmg's pipeline (analysis -> size map -> gradation). The same
// recipe applied to another mesh of the surface gives that mesh's metric:
// the adaptation cycles of the report's section 7.1 re-derive it on each
// adapted mesh.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "metric/hessian.h"
#include "metric/metric_field.h"

namespace anisurf {

struct MetricRecipe {
  enum class Source {
    Given,          // `given`: one tensor per vertex slot (a .sol, a painted field)
    Iso,            // the isotropic size `iso`
    Size,           // isotropic size h(x,y,z) = `expression` (eq. 3)
    Tensor,         // six components 'm11, m12, m22, m13, m23, m33' = `expression`
    Hessian,        // Hessian of the function `expression` (hessian_of_expression: exact where smooth)
    HessianField,   // Hessian of the scalar solution field `field` of the mesh (recovered)
    Curvature,      // principal curvatures for the chordal deviation `hausd`
  };
  Source source = Source::Iso;
  MetricField given;
  double iso = 0;
  std::string expression;
  std::string field;

  // Hessian sources: exactly one target (> 0): the interpolation error, the
  // complexity C or the vertex count N = 2 C / sqrt 3. A complexity or a
  // vertex count is met by the final metric, after bounds and gradation.
  double error = 0;
  double complexity = 0;
  double vertices = 0;
  // Norm of the interpolation error (L^p, p >= 1 or infinity). L^2, the
  // norm the report's section 7.1 measures: the metric equidistributes the
  // error, and at a jump the sizes shrink as det^(-1/6) only, so that the
  // adapt -> re-derive -> adapt cycles settle (cycle_metric_defaults()).
  double lp = cycle_metric_defaults().p;
  double error_constant = cycle_metric_defaults().error_constant;  // BAMG's 2/9

  MetricBounds bounds;
  // Chordal deviation: the metric is intersected with the curvature metric
  // of `hausd` (> 0; with the Curvature source it is that metric's deviation).
  double hausd = 0;
  // The curvatures of that intersection when the source is not Curvature: a
  // bound on what another metric may ask, fitted as Mmg's -hausd fits them
  // (a quadric over each vertex's ring, the neighbourhood grown where it
  // does not determine one), where the Curvature source, whose sizes are
  // the metric, fits cubics over two rings (HessianRecoveryOptions{}).
  HessianRecoveryOptions deviation_fit = ring_quadric_fit();
  // Size gradation ratio (Mmg's -hgrad); <= 1: none.
  double hgrad = 1.3;
  GradationSpace hgrad_space = GradationSpace::Metric;

  bool is_hessian() const { return source == Source::Hessian || source == Source::HessianField; }
  bool has_vertex_target() const { return is_hessian() && (complexity > 0 || vertices > 0); }
};

// What build_metric made.
struct MetricResult {
  MetricField metric;          // one SPD tensor per vertex slot
  std::string description;     // "Hessian of 100*x^2, error 0.01, graded 1.3" ...
  double complexity = 0;       // of the final metric on the mesh
  double predicted_vertices = 0;
  int scaling_steps = 0;       // rescalings to meet a vertex target
  GradationReport gradation;   // of the last gradation (none: 0 updates)
  std::vector<SymTensor3> hessian;  // Hessian sources: the tangent Hessians used
};

// The recipe's metric on `mesh` (its vertex slots): the source, then the
// bounds, the hausd intersection and the gradation; with a vertex target,
// the whole chain again with the Hessian metric rescaled until the final
// metric predicts the target within 1% (at most 12 rescalings). Throws
// MetricError / ExpressionError with a message naming the vertex
// (`vertex_origin`: 1-based file numbering, see BuildReport).
// The recipe is taken by value: a given metric is moved into the result
// (std::move the recipe when it is not needed after).
MetricResult build_metric(const SurfaceMesh& mesh, MetricRecipe recipe, const std::vector<int>& vertex_origin = {});

// Checks the recipe's values without a mesh (targets, bounds, sizes); throws
// MetricError with what is wrong.
void check_recipe(const MetricRecipe& recipe);

// The tangent Hessian of the recipe's function on `mesh`: of the expression
// (Source::Hessian: hessian_of_expression, exact where the function is smooth
// at the edges' scale, even on two triangles) or recovered from the scalar
// field's vertex values (Source::HessianField: recover_derivatives).
std::vector<SymTensor3> recipe_hessian(const SurfaceMesh& mesh, const MetricRecipe& recipe,
                                       const std::vector<int>& vertex_origin = {});

// Estimated P1 interpolation error of the recipe's function on `mesh`, from
// the tangent Hessians at the vertices: on each triangle the largest
// |e^T H e| / 8 over its edges e (H averaged over the triangle's vertices),
// combined in the recipe's L^p norm (the maximum for p = infinity,
// (sum |K| e_K^p)^(1/p) otherwise).
double estimated_interpolation_error(const SurfaceMesh& mesh, const std::vector<SymTensor3>& hessian, double lp);

}  // namespace anisurf
