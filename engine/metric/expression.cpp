#include "metric/expression.h"

#include <cmath>
#include <cstdio>

#ifdef ANISURF_HAVE_MUPARSER
#include <muParser.h>
#endif

namespace anisurf {

struct Expression::Impl {
  std::string text;
  int results = 1;
#ifdef ANISURF_HAVE_MUPARSER
  mu::Parser parser;
  // The parser holds the addresses of these.
  double x = 0, y = 0, z = 0;
#endif
};

namespace {

#ifdef ANISURF_HAVE_MUPARSER
std::string parse_error_message(const std::string& text, const mu::Parser::exception_type& e) {
  std::string msg = "cannot read the expression '" + text + "': " + e.GetMsg();
  const int pos = e.GetPos();
  if (pos >= 0 && pos <= static_cast<int>(text.size())) {
    msg += "\n  " + text + "\n  " + std::string(pos, ' ') + "^";
  }
  return msg;
}
#endif

std::string describe_vertex(const SurfaceMesh& mesh, int v, const std::vector<int>& vertex_origin) {
  const int file = v < static_cast<int>(vertex_origin.size()) && vertex_origin[v] >= 0 ? vertex_origin[v] : v;
  const Vec3 p = mesh.position(Vertex(v));
  char buf[160];
  std::snprintf(buf, sizeof buf, "vertex %d (1-based) at (x, y, z) = (%.9g, %.9g, %.9g)", file + 1, p.x, p.y, p.z);
  return buf;
}

// Evaluates at every live vertex, checking the number of results and finiteness.
template <class Use>
void for_each_vertex_value(const SurfaceMesh& mesh, const Expression& e, const std::vector<int>& vertex_origin,
                           Use use) {
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    const std::vector<double> r = e.evaluate(mesh.position(v));
    for (std::size_t k = 0; k < r.size(); ++k)
      if (!std::isfinite(r[k]))
        throw ExpressionError("the expression '" + e.text() + "'" +
                              (r.size() > 1 ? " (result " + std::to_string(k + 1) + ")" : std::string()) + " is " +
                              std::to_string(r[k]) + " at " + describe_vertex(mesh, i, vertex_origin) +
                              (std::isinf(r[k]) ? ": a division by zero?" : ": outside the domain of a function?"));
    use(i, r);
  }
}

}  // namespace

Expression::Expression(const std::string& text) : impl_(std::make_unique<Impl>()) {
  impl_->text = text;
#ifdef ANISURF_HAVE_MUPARSER
  try {
    impl_->parser.DefineVar("x", &impl_->x);
    impl_->parser.DefineVar("y", &impl_->y);
    impl_->parser.DefineVar("z", &impl_->z);
    impl_->parser.DefineConst("pi", M_PI);
    impl_->parser.DefineConst("e", M_E);
    impl_->parser.SetExpr(text);
    int n = 0;
    impl_->parser.Eval(n);  // parses now, so that errors show before any vertex
    impl_->results = n;
  } catch (const mu::Parser::exception_type& e) {
    throw ExpressionError(parse_error_message(text, e));
  }
#else
  throw ExpressionError("cannot read the expression '" + text + "': this build has no expression parser (muParser)");
#endif
}

Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

int Expression::results() const { return impl_->results; }
const std::string& Expression::text() const { return impl_->text; }

std::vector<double> Expression::evaluate(const Vec3& p) const {
#ifdef ANISURF_HAVE_MUPARSER
  impl_->x = p.x;
  impl_->y = p.y;
  impl_->z = p.z;
  try {
    int n = 0;
    const double* r = impl_->parser.Eval(n);
    return std::vector<double>(r, r + n);
  } catch (const mu::Parser::exception_type& e) {
    throw ExpressionError(parse_error_message(impl_->text, e));
  }
#else
  return {};
#endif
}

std::vector<double> evaluate_at_vertices(const SurfaceMesh& mesh, const std::string& expression,
                                         const std::vector<int>& vertex_origin) {
  const Expression e(expression);
  if (e.results() != 1)
    throw ExpressionError("the expression '" + expression + "' has " + std::to_string(e.results()) +
                          " comma-separated results, expected one value");
  std::vector<double> out(mesh.vertex_capacity(), 0.0);
  for_each_vertex_value(mesh, e, vertex_origin, [&](int i, const std::vector<double>& r) { out[i] = r[0]; });
  return out;
}

MetricField metric_from_size_expression(const SurfaceMesh& mesh, const std::string& expression,
                                        const std::vector<int>& vertex_origin) {
  const std::vector<double> h = evaluate_at_vertices(mesh, expression, vertex_origin);
  MetricField M(mesh.vertex_capacity(), SymTensor3::identity());
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    if (!(h[i] > 0))
      throw ExpressionError("the size '" + expression + "' is " + std::to_string(h[i]) + " at " +
                            describe_vertex(mesh, i, vertex_origin) + ", expected h > 0");
    M[i] = isotropic_metric(h[i]);
  }
  return M;
}

MetricField metric_from_tensor_expression(const SurfaceMesh& mesh, const std::string& expression,
                                          const std::vector<int>& vertex_origin) {
  const Expression e(expression);
  const bool planar = mesh.dimension() == 2;
  if (e.results() != 6 && !(planar && e.results() == 3))
    throw ExpressionError("the tensor '" + expression + "' has " + std::to_string(e.results()) +
                          " comma-separated components, expected 6: m11, m12, m22, m13, m23, m33" +
                          (planar ? " (or 3 for this planar mesh: m11, m12, m22)" : ""));
  MetricField M(mesh.vertex_capacity(), SymTensor3::identity());
  for_each_vertex_value(mesh, e, vertex_origin, [&](int i, const std::vector<double>& r) {
    M[i] = r.size() == 6 ? SymTensor3(r[0], r[1], r[2], r[3], r[4], r[5]) : SymTensor3(r[0], r[1], r[2], 0, 0, 1);
    const std::string problem = metric_problem(M[i]);
    if (!problem.empty())
      throw ExpressionError("the tensor '" + expression + "' at " + describe_vertex(mesh, i, vertex_origin) + ": " +
                            problem);
  });
  return M;
}

}  // namespace anisurf
