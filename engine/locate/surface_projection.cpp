#include "locate/surface_projection.h"

#include <cmath>
#include <vector>

namespace anisurf {

namespace {

using Bary = std::array<double, 3>;

// Derivative of the surface along the barycentric direction db (sum 0).
Vec3 directional(const ParametricPoint& p, const Bary& db) { return db[1] * p.d1 + db[2] * p.d2; }

struct State {
  Triangle t;
  Bary b;
  ParametricPoint p;
  double f = INFINITY;  // |S - x|^2
  double g = INFINITY;  // |gradient of f / 2| in the parameters
};

// A step is taken when it lowers the distance or, once the distance no longer
// changes beyond its rounding (the last digits of a minimiser: |S - x|^2
// carries the rounding of S, about eps |S| |S - x|), the gradient.
bool better(const State& c, const State& s) {
  if (c.f < s.f) return true;
  const double noise = 1e-13 * s.f + 1e-15 * norm(s.p.position) * std::sqrt(s.f);
  return c.f <= s.f + noise && c.g < s.g;
}

// Parameter walking on the mesh: moves the parameter point (t, b) by the
// barycentric displacement d, crossing edges into the neighbouring triangle
// (the rest of the displacement unfolded about the shared edge), sliding
// along boundary edges.
class ParameterWalker {
 public:
  explicit ParameterWalker(const SurfaceMesh& m) : m_(m) {}

  void move(Triangle& t, Bary& b, Bary d) const {
    for (int crossing = 0; crossing < 64; ++crossing) {
      double a = 1;
      int k = -1;
      for (int i = 0; i < 3; ++i)
        if (d[i] < 0 && b[i] + d[i] < 0) {
          const double ai = b[i] / -d[i];
          if (ai < a) a = ai, k = i;
        }
      if (k < 0) {
        for (int i = 0; i < 3; ++i) b[i] = std::max(0.0, b[i] + d[i]);
        normalise(b);
        return;
      }
      for (int i = 0; i < 3; ++i) b[i] = std::max(0.0, b[i] + a * d[i]);
      b[k] = 0;
      normalise(b);
      for (double& v : d) v *= (1 - a);
      const Corner c = SurfaceMesh::corner(t, k);
      const int i = SurfaceMesh::local_index(SurfaceMesh::next(c)), j = SurfaceMesh::local_index(SurfaceMesh::prev(c));
      const Corner o = m_.opposite(c);
      if (!o.is_valid()) {
        // Boundary: keep the part of the displacement along the edge.
        const double along = 0.5 * (d[j] - d[i]);
        d = {0, 0, 0};
        d[i] = -along;
        d[j] = along;
        d[k] = 0;
        if (std::fabs(along) < 1e-300) return;
        continue;
      }
      // Into the neighbour: the edge point keeps its weights, the rest of the
      // displacement is rotated about the edge into the neighbour's plane.
      const Triangle u = SurfaceMesh::triangle(o);
      const int oi = SurfaceMesh::local_index(SurfaceMesh::prev(o));  // vertex of c's next
      const int oj = SurfaceMesh::local_index(SurfaceMesh::next(o));  // vertex of c's prev
      const Vec3 dp = displacement(t, d);
      const Vec3 e = normalized(m_.position(m_.vertex(t, j)) - m_.position(m_.vertex(t, i)));
      const Vec3 out_t = cross(e, unit_normal(t));  // leaves t across the edge
      const Vec3 in_u = cross(e, unit_normal(u));   // enters u across the edge
      const Vec3 dq = dot(dp, e) * e + dot(dp, out_t) * in_u;
      Bary nb{};
      nb[oi] = b[i];
      nb[oj] = b[j];
      nb[SurfaceMesh::local_index(o)] = 0;
      t = u;
      b = nb;
      d = barycentric_of(t, dq);
    }
  }

 private:
  static void normalise(Bary& b) {
    const double s = b[0] + b[1] + b[2];
    for (double& v : b) v /= s;
  }
  Vec3 unit_normal(Triangle t) const { return normalized(m_.triangle_normal(t)); }
  Vec3 displacement(Triangle t, const Bary& d) const {
    return d[0] * m_.position(m_.vertex(t, 0)) + d[1] * m_.position(m_.vertex(t, 1)) + d[2] * m_.position(m_.vertex(t, 2));
  }
  // Barycentric displacement (sum 0) of t closest to the vector v.
  Bary barycentric_of(Triangle t, const Vec3& v) const {
    const Vec3 p0 = m_.position(m_.vertex(t, 0));
    const Vec3 e1 = m_.position(m_.vertex(t, 1)) - p0, e2 = m_.position(m_.vertex(t, 2)) - p0;
    const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), r1 = dot(e1, v), r2 = dot(e2, v);
    const double det = a * c - b * b;
    if (!(det > 0)) return {0, 0, 0};
    const double x1 = (c * r1 - b * r2) / det, x2 = (a * r2 - b * r1) / det;
    return {-x1 - x2, x1, x2};
  }
  const SurfaceMesh& m_;
};

State evaluate(const SurfaceEvaluator& eval, const Vec3& x, Triangle t, const Bary& b) {
  State s{t, b, eval(t, b)};
  const Vec3 r = s.p.position - x;
  s.f = norm2(r);
  s.g = std::hypot(dot(s.p.d1, r), dot(s.p.d2, r));
  return s;
}

// The same along a feature edge: the gradient along the edge direction db.
State evaluate_on_edge(const SurfaceEvaluator& eval, const Vec3& x, Triangle t, const Bary& b, const Bary& db) {
  State s{t, b, eval(t, b)};
  const Vec3 r = s.p.position - x;
  s.f = norm2(r);
  s.g = std::fabs(dot(directional(s.p, db), r));
  return s;
}

SurfaceProjection finish(const State& s, const Vec3& x, const Location& poly, int it, bool converged) {
  SurfaceProjection r;
  r.location = poly;
  r.location.triangle = s.t;
  r.location.bary = s.b;
  r.location.point = s.p.position;
  r.location.distance = std::sqrt(s.f);
  r.point = s.p.position;
  r.distance = std::sqrt(s.f);
  r.polyhedral = poly;
  r.iterations = it;
  r.converged = converged;
  return r;
}

SurfaceProjection free_projection(const SurfaceMesh& m, const SurfaceEvaluator& eval, const Vec3& x,
                                  const Location& poly, const SurfaceProjectionOptions& o) {
  const ParameterWalker walker(m);
  State s = evaluate(eval, x, poly.triangle, poly.bary);
  for (int it = 0; it < o.max_iterations; ++it) {
    // Gauss-Newton step in (b1, b2).
    const Vec3 r = s.p.position - x;
    const double a11 = dot(s.p.d1, s.p.d1), a12 = dot(s.p.d1, s.p.d2), a22 = dot(s.p.d2, s.p.d2);
    const double g1 = dot(s.p.d1, r), g2 = dot(s.p.d2, r);
    const double det = a11 * a22 - a12 * a12;
    if (!(det > 0)) return finish(s, x, poly, it, false);
    if (std::hypot(g1, g2) <= o.tolerance * std::sqrt(s.f) * std::sqrt(a11 + a22)) return finish(s, x, poly, it, true);
    const double x1 = -(a22 * g1 - a12 * g2) / det, x2 = -(a11 * g2 - a12 * g1) / det;
    if (std::hypot(x1, x2) < o.tolerance) return finish(s, x, poly, it, true);
    auto try_step = [&](double step) {
      Triangle t = s.t;
      Bary b = s.b;
      walker.move(t, b, {-step * (x1 + x2), step * x1, step * x2});
      return evaluate(eval, x, t, b);
    };
    // Gauss-Newton ignores the curvature term (S - x).S'': far from the
    // surface its step overshoots or falls short. The secant of the
    // directional derivative between the start and the full step corrects
    // the length (when both lie in the same triangle, one chart).
    State c = try_step(1);
    if (c.t == s.t) {
      const double d0 = dot(x1 * s.p.d1 + x2 * s.p.d2, s.p.position - x);
      const double d1 = dot(x1 * c.p.d1 + x2 * c.p.d2, c.p.position - x);
      if (d1 > d0 && d0 < 0) {
        const double a = std::min(100.0, d0 / (d0 - d1));
        if (std::fabs(a - 1) > 1e-3) {
          const State ca = try_step(a);
          if (better(ca, c)) c = ca;
        }
      }
    }
    // Backtracking along the step; the walker crosses edges.
    bool moved = false;
    for (double step = 0.5; !better(c, s) && step > 1e-12; step *= 0.5) c = try_step(step);
    if (better(c, s)) {
      s = c;
      moved = true;
    }
    if (!moved) return finish(s, x, poly, it, true);  // stationary up to rounding
  }
  return finish(s, x, poly, o.max_iterations, false);
}

// The feature edges at vertex v (one corner each).
std::vector<Corner> feature_edges_at(const SurfaceMesh& m, Vertex v, std::uint8_t tags) {
  std::vector<Corner> out;
  auto add = [&](Corner c) {
    if (!(m.edge_tags(c) & tags)) return;
    const Corner k = m.canonical(c);
    for (Corner e : out)
      if (e == k) return;
    out.push_back(k);
  };
  for (Corner c : m.fan_corners(v)) {
    add(SurfaceMesh::next(c));
    add(SurfaceMesh::prev(c));
  }
  return out;
}

SurfaceProjection feature_projection(const Locator& loc, const SurfaceEvaluator& eval, const Vec3& x,
                                     const Location& poly, const SurfaceProjectionOptions& o) {
  const SurfaceMesh& m = loc.mesh();
  Corner c = poly.edge;
  auto bary_of = [](Corner e, double s) {
    Bary b{};
    b[SurfaceMesh::local_index(SurfaceMesh::next(e))] = 1 - s;
    b[SurfaceMesh::local_index(SurfaceMesh::prev(e))] = s;
    return b;
  };
  auto length = [&](Corner e) { return norm(m.position(m.edge_to(e)) - m.position(m.edge_from(e))); };
  // Moves along the curve by ds (in units of edge e's parameter), going on
  // into the next edge at a vertex where the curve continues.
  auto move = [&](Corner e, double s, double ds, Corner& out_e, double& out_s) {
    for (int hop = 0; hop < 64; ++hop) {
      const double t = s + ds;
      if (t >= 0 && t <= 1) {
        out_e = e, out_s = t;
        return;
      }
      const Vertex end = t > 1 ? m.edge_to(e) : m.edge_from(e);
      const std::vector<Corner> at = feature_edges_at(m, end, loc.options().feature_tags);
      const bool goes_on = at.size() == 2 && !(m.vertex_tags(end) & loc.options().corner_tags);
      if (!goes_on) {
        out_e = e, out_s = t > 1 ? 1 : 0;
        return;
      }
      const Corner next = at[0] == m.canonical(e) ? at[1] : at[0];
      const double rest = (t > 1 ? t - 1 : -t) * length(e) / length(next);  // length left, in next's units
      if (m.edge_from(next) == end) {
        s = 0, ds = rest;
      } else {
        s = 1, ds = -rest;
      }
      e = next;
    }
    out_e = e, out_s = std::clamp(s, 0.0, 1.0);
  };
  // Direction of the edge parameter in barycentric coordinates: to - from.
  auto direction = [](Corner e) {
    Bary db{};
    db[SurfaceMesh::local_index(SurfaceMesh::next(e))] = -1;
    db[SurfaceMesh::local_index(SurfaceMesh::prev(e))] = 1;
    return db;
  };
  double s = poly.bary[SurfaceMesh::local_index(SurfaceMesh::prev(c))];
  State st = evaluate_on_edge(eval, x, SurfaceMesh::triangle(c), bary_of(c, s), direction(c));
  for (int it = 0; it < o.max_iterations; ++it) {
    const Vec3 T = directional(st.p, direction(c));
    const Vec3 r = st.p.position - x;
    const double tt = dot(T, T), g = dot(T, r);
    if (!(tt > 0)) break;
    if (std::fabs(g) <= o.tolerance * std::sqrt(st.f * tt)) {
      SurfaceProjection out = finish(st, x, poly, it, true);
      out.location.edge = c;
      return out;
    }
    const double ds = -g / tt;
    if (std::fabs(ds) < o.tolerance) {
      SurfaceProjection out = finish(st, x, poly, it, true);
      out.location.edge = c;
      return out;
    }
    struct Candidate {
      State st;
      Corner e;
      double s;
    };
    auto try_step = [&](double step) {
      Candidate k;
      move(c, s, step * ds, k.e, k.s);
      k.st = evaluate_on_edge(eval, x, SurfaceMesh::triangle(k.e), bary_of(k.e, k.s), direction(k.e));
      // Gradients in different edges' parameters: compare per unit length.
      k.st.g *= length(c) / length(k.e);
      return k;
    };
    // Secant correction of the Gauss-Newton length, as in the free case.
    Candidate k = try_step(1);
    if (k.e == c) {
      const double d0 = g * ds;
      const double d1 = dot(directional(k.st.p, direction(c)), k.st.p.position - x) * ds;
      if (d1 > d0 && d0 < 0) {
        const double a = std::min(100.0, d0 / (d0 - d1));
        if (std::fabs(a - 1) > 1e-3) {
          const Candidate ka = try_step(a);
          if (better(ka.st, k.st)) k = ka;
        }
      }
    }
    bool moved = false;
    for (double step = 0.5; !better(k.st, st) && step > 1e-12; step *= 0.5) k = try_step(step);
    if (better(k.st, st)) {
      k.st.g *= length(k.e) / length(c);
      st = k.st, c = k.e, s = k.s, moved = true;
    }
    if (!moved) {
      SurfaceProjection out = finish(st, x, poly, it, true);
      out.location.edge = c;
      return out;
    }
  }
  SurfaceProjection out = finish(st, x, poly, o.max_iterations, false);
  out.location.edge = c;
  return out;
}

}  // namespace

SurfaceProjection project_onto_surface(Locator& locator, const SurfaceEvaluator& eval, const Vec3& x,
                                       std::span<const Hint> hints, Constraint constraint,
                                       const SurfaceProjectionOptions& options) {
  const Location poly = locator.project(x, hints, constraint);
  if (!poly.is_valid()) {
    SurfaceProjection r;
    r.polyhedral = r.location = poly;
    r.point = x;
    r.distance = INFINITY;
    return r;
  }
  switch (poly.constraint) {
    case Constraint::Fixed: {
      // The surface interpolates the vertices of its mesh.
      const State s = evaluate(eval, x, poly.triangle, poly.bary);
      SurfaceProjection r = finish(s, x, poly, 0, true);
      r.location.vertex = poly.vertex;
      return r;
    }
    case Constraint::OnFeature:
      return feature_projection(locator, eval, x, poly, options);
    case Constraint::Free:
      break;
  }
  return free_projection(locator.mesh(), eval, x, poly, options);
}

}  // namespace anisurf
