// Metrics from expressions typed by a user (muParser syntax, variables x, y, z,
// constants pi and e): a size h(x, y, z) (eq. 3), the six tensor components,
// or a scalar field whose Hessian drives the metric (see hessian.h).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "metric/hessian.h"
#include "metric/metric_field.h"

namespace anisurf {

// An expression was refused: a parse error (the message quotes the expression
// and marks the position) or a non-finite value at a vertex (the message names
// the vertex and its coordinates).
class ExpressionError : public Error {
 public:
  using Error::Error;
};

// A compiled expression of x, y, z with one or more comma-separated results
// ("1/x^2, 0, 1"). Throws ExpressionError on a parse error, or if the engine
// was built without muParser.
class Expression {
 public:
  explicit Expression(const std::string& text);
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  int results() const;
  const std::string& text() const;
  // The results at p (results() of them; may be non-finite).
  std::vector<double> evaluate(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The values of a one-result expression at the vertices (by slot). Throws
// ExpressionError for a non-finite value, naming the vertex (1-based file
// numbering through `vertex_origin` if given) and its position.
std::vector<double> evaluate_at_vertices(const SurfaceMesh& mesh, const std::string& expression,
                                         const std::vector<int>& vertex_origin = {});
// Isotropic metric of the size h(x, y, z) > 0 (eq. 3).
MetricField metric_from_size_expression(const SurfaceMesh& mesh, const std::string& expression,
                                        const std::vector<int>& vertex_origin = {});
// Metric from 6 comma-separated components in the .sol order m11, m12, m22,
// m13, m23, m33 (3 for a planar mesh: m11, m12, m22, with m33 = 1); every
// vertex metric must be SPD.
MetricField metric_from_tensor_expression(const SurfaceMesh& mesh, const std::string& expression,
                                          const std::vector<int>& vertex_origin = {});

// The Hessian of a one-result expression f(x, y, z) as a field on the
// surface, per vertex slot, in the form recover_derivatives gives (a tangent
// 3D tensor, zero along the normal): the Hessian over the tangent-plane
// parametrisation, P H3 P - (grad f . n) II, with H3 and grad f . n by
// central finite differences of f and II, n the fitted second fundamental
// form and normals (recover_curvature, fitted_normals with `options`).
// Use it for the metric of an expression (the report's section 7.1 cases):
// it is exact for quadratics whatever the mesh (two triangles of the unit
// square and f = 100 x^2 give H = diag(200, 0)), where a recovery from the
// vertex values only sees the P1 field (a linear one there). Use
// recover_derivatives for a field known by its vertex values only.
// The differences run along the principal axes of each vertex's one-ring
// edges, the step the longest edge projection on its axis, and again at half
// that step. Where the two disagree (by more than 10 %: a jump or a kink of f
// within the stencil, or features smaller than the edges), and within
// options.rings rings of there, the Hessian is the one recovered from the
// vertex values (recover_derivatives). A jump then gives jump / h^2 with h
// the local mesh size, spread over the fit's rings as on a field: finite,
// growing as the mesh refines there, and the L^p metric with finite p
// (cycle_metric_defaults) reaches a fixed point in the cycles. (Differences
// alone give a value that depends on where the jump falls in a one-ring
// stencil, and an abrupt change to the exact Hessian one ring further: the
// vertex counts of the cycles then oscillate by a factor 2.)
// Where f is not finite at a difference point (a function's domain ends
// there) the steps are halved, up to 20 times. Throws ExpressionError for a
// parse error, more than one result, or a non-finite value at or next to a
// vertex (named, 1-based through `vertex_origin`).
std::vector<SymTensor3> hessian_of_expression(const SurfaceMesh& mesh, const std::string& expression,
                                              const std::vector<int>& vertex_origin = {},
                                              const HessianRecoveryOptions& options = {});

}  // namespace anisurf
