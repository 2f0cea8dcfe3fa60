#include "metric/expression.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh/operators.h"
#include "metric/surface_metric.h"

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

// Directions and steps of the finite differences at v: the principal axes
// (t1, t2) of v's one-ring edges projected onto the tangent plane of n, each
// step the longest projection of an edge on its axis (the local edge length
// along that direction, so that a difference reaches the neighbours and sees
// what the P1 field on the mesh sees). Steps below `floor` take the other
// step, then `floor`.
struct DifferenceStencil {
  std::array<Vec3, 2> t;
  std::array<double, 2> step{};
};
DifferenceStencil difference_stencil(const SurfaceMesh& mesh, Vertex v, const Vec3& n, double floor) {
  const std::array<Vec3, 2> fr = tangent_frame(n);
  const Vec3 p0 = mesh.position(v);
  std::vector<std::array<double, 2>> edges;
  SymTensor2 spread;
  for (Vertex w : mesh.ring_vertices(v)) {
    const Vec3 e = mesh.position(w) - p0;
    const double a = dot(e, fr[0]), b = dot(e, fr[1]);
    edges.push_back({a, b});
    spread += SymTensor2(a * a, a * b, b * b);
  }
  const double angle = eigen_decompose(spread).angle;
  const double c = std::cos(angle), s = std::sin(angle);
  DifferenceStencil d;
  d.t = {c * fr[0] + s * fr[1], -s * fr[0] + c * fr[1]};
  for (const auto& e : edges) {
    d.step[0] = std::max(d.step[0], std::fabs(c * e[0] + s * e[1]));
    d.step[1] = std::max(d.step[1], std::fabs(-s * e[0] + c * e[1]));
  }
  for (int k = 0; k < 2; ++k)
    if (!(d.step[k] >= floor)) d.step[k] = std::max(d.step[1 - k], floor);
  return d;
}

// Second derivatives of f along the stencil's axes by central differences
// (3 points per axis for the diagonal terms, 4 corners at half steps for the
// mixed one), and the normal derivative by a central difference of the
// smaller step. All exact for quadratics. False if a value is not finite.
struct DifferenceResult {
  SymTensor2 hessian;  // in the basis t1, t2
  double normal_derivative = 0;
};
bool central_differences(const Expression& e, const Vec3& p, const Vec3& n, const DifferenceStencil& d, double f0,
                         DifferenceResult& out) {
  bool finite = true;
  auto f = [&](const Vec3& q) {
    const double r = e.evaluate(q)[0];
    finite = finite && std::isfinite(r);
    return r;
  };
  const Vec3 a = d.step[0] * d.t[0], b = d.step[1] * d.t[1];
  const double h11 = (f(p + a) - 2 * f0 + f(p - a)) / (d.step[0] * d.step[0]);
  const double h22 = (f(p + b) - 2 * f0 + f(p - b)) / (d.step[1] * d.step[1]);
  // The corners at half steps stay within the reach of the axial points.
  const Vec3 a2 = 0.5 * a, b2 = 0.5 * b;
  const double h12 = (f(p + a2 + b2) - f(p + a2 - b2) - f(p - a2 + b2) + f(p - a2 - b2)) / (d.step[0] * d.step[1]);
  const double sn = std::min(d.step[0], d.step[1]);
  out.normal_derivative = (f(p + sn * n) - f(p - sn * n)) / (2 * sn);
  out.hessian = SymTensor2(h11, h12, h22);
  return finite;
}

// The vertices within `rings` edges of the seeds (seeds included).
std::vector<int> within_rings(const SurfaceMesh& mesh, const std::vector<int>& seeds, int rings) {
  std::vector<char> in(mesh.vertex_capacity(), 0);
  std::vector<int> out = seeds, front = seeds;
  for (int i : seeds) in[i] = 1;
  for (int r = 0; r < rings; ++r) {
    std::vector<int> next;
    for (int i : front)
      for (Vertex w : mesh.ring_vertices(Vertex(i)))
        if (!in[w.idx]) {
          in[w.idx] = 1;
          next.push_back(w.idx);
        }
    out.insert(out.end(), next.begin(), next.end());
    front.swap(next);
  }
  return out;
}

// Whether the second differences at a step and at half of it agree (within
// 10 %, or within the rounding of the half-step differences): f is smooth at
// the scale of the edges. A jump or a kink within the stencil, or features
// smaller than the edges, make them disagree.
bool resolved_by_differences(const SymTensor2& full, const SymTensor2& half, double f0, double half_step) {
  double difference = 0, size = 0;
  for (int k = 0; k < 3; ++k) {
    difference = std::max(difference, std::fabs(full.m[k] - half.m[k]));
    size = std::max({size, std::fabs(full.m[k]), std::fabs(half.m[k])});
  }
  const double rounding = 1e-12 * (std::fabs(f0) + 1.0) / (half_step * half_step);
  return difference <= 0.1 * size + rounding;
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

std::vector<SymTensor3> hessian_of_expression(const SurfaceMesh& mesh, const std::string& expression,
                                              const std::vector<int>& vertex_origin,
                                              const HessianRecoveryOptions& options) {
  const Expression e(expression);
  if (e.results() != 1)
    throw ExpressionError("the expression '" + expression + "' has " + std::to_string(e.results()) +
                          " comma-separated results, expected one value");
  const std::vector<double> f0 = evaluate_at_vertices(mesh, expression, vertex_origin);
  const std::vector<Vec3> normal = fitted_normals(mesh, options);
  const std::vector<SymTensor3> II = recover_curvature(mesh, options);
  const double floor = 1e-9 * std::max(mesh.bbox().diagonal(), 1e-300);
  std::vector<SymTensor3> H(mesh.vertex_capacity(), SymTensor3());
  std::vector<int> unresolved;
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    if (mesh.is_isolated(v)) continue;
    DifferenceStencil d = difference_stencil(mesh, v, normal[i], floor);
    DifferenceResult r, half;
    DifferenceStencil d_half = d;
    // A value outside the domain of a function (sqrt of a negative number just
    // beyond a boundary): shorter steps, down to 2^-20 of the edge length.
    for (int halvings = 0;; ++halvings) {
      d_half.step = {0.5 * d.step[0], 0.5 * d.step[1]};
      if (central_differences(e, mesh.position(v), normal[i], d, f0[i], r) &&
          central_differences(e, mesh.position(v), normal[i], d_half, f0[i], half))
        break;
      if (halvings == 20)
        throw ExpressionError("the expression '" + expression + "' is not finite next to " +
                              describe_vertex(mesh, i, vertex_origin) +
                              " (finite differences for its Hessian): outside the domain of a function?");
      d.step = d_half.step;
    }
    if (!resolved_by_differences(r.hessian, half.hessian, f0[i], std::min(d_half.step[0], d_half.step[1]))) {
      unresolved.push_back(i);
      continue;
    }
    // Hessian over the tangent-plane parametrisation: the tangent part of the
    // 3D Hessian minus (grad f . n) times the second fundamental form.
    SymTensor2 T = half.hessian;
    T += -half.normal_derivative * restrict_to_tangent(II[i], d.t[0], d.t[1]);
    H[i] = extend_from_tangent(T, d.t[0], d.t[1], 0.0);
  }
  if (!unresolved.empty()) {
    const RecoveredDerivatives recovered = recover_derivatives(mesh, f0, options);
    for (int i : within_rings(mesh, unresolved, options.rings)) H[i] = recovered.hessian[i];
  }
  return H;
}

}  // namespace anisurf
