// Metrics from expressions typed by a user (muParser syntax, variables x, y, z,
// constants pi and e): a size h(x, y, z) (eq. 3), the six tensor components,
// or a scalar field whose Hessian drives the metric (see hessian.h).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
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

}  // namespace anisurf
