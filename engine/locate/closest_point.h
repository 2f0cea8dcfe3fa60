// Exact-as-floating-point closest points and distances between points,
// segments and triangles (the kernels of point location, section 4).
//
// The point/triangle routine classifies the query against the Voronoi regions
// of the triangle's vertices, edges and face with dot products only (the
// region tests of Ericson, "Real-Time Collision Detection", 5.1.5), so that
// the returned point always lies in the closed triangle and its barycentric
// coordinates are in [0, 1]. Degenerate triangles (repeated or collinear
// positions) fall back to their edges instead of dividing by zero.
#pragma once
#include <array>
#include <cmath>

#include "core/vec3.h"

namespace anisurf {

// Where on a triangle the closest point lies.
enum class TriangleRegion : unsigned char { Vertex0, Vertex1, Vertex2, Edge01, Edge12, Edge20, Face };

struct TriangleClosest {
  Vec3 point;                  // closest point, in the closed triangle
  std::array<double, 3> bary{};  // barycentric coordinates of `point` (>= 0, sum 1)
  double distance2 = 0;        // squared distance from the query
  TriangleRegion region = TriangleRegion::Face;
};

// Closest point of triangle (a, b, c) to p. Inline: it is the inner loop of
// every search.
inline TriangleClosest closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Squared distance from p to triangle (a, b, c): closest_point_on_triangle().distance2.
inline double point_triangle_distance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return closest_point_on_triangle(p, a, b, c).distance2;
}

// Closest point of segment [a, b] to p: parameter t in [0, 1] (point a + t (b - a),
// exactly a at t = 0 and b at t = 1). A zero-length segment gives t = 0.
double closest_parameter_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);
// Squared distance from p to segment [a, b].
double point_segment_distance2(const Vec3& p, const Vec3& a, const Vec3& b);

// Squared distance between segments [p0, p1] and [q0, q1] (parallel and
// zero-length segments included).
double segment_segment_distance2(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// Squared distance between segment [p, q] and triangle (a, b, c): 0 when the
// segment crosses the triangle.
double segment_triangle_distance2(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// Squared distance between two triangles (0 when they intersect).
double triangle_triangle_distance2(const std::array<Vec3, 3>& s, const std::array<Vec3, 3>& t);

// Twice the signed area of the planar triangle (a, b, p) in the xy plane:
// positive when p is to the left of the directed line a -> b.
inline double orient2d(const Vec3& a, const Vec3& b, const Vec3& p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}


namespace detail {
// Closest point of a degenerate triangle: the best of its three edges.
TriangleClosest closest_point_on_degenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// Closest point of a thin triangle (angle at a near 0 or pi): the best of its
// edges and of the orthogonal projection onto its plane when that falls inside.
TriangleClosest closest_point_on_thin_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
inline TriangleClosest make_closest(const Vec3& p, const Vec3& q, double u, double v, double w, TriangleRegion r) {
  TriangleClosest out;
  out.point = q;
  out.bary = {u, v, w};
  out.distance2 = norm2(p - q);
  out.region = r;
  return out;
}
}  // namespace detail

inline TriangleClosest closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  using detail::make_closest;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return make_closest(p, a, 1, 0, 0, TriangleRegion::Vertex0);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return make_closest(p, b, 0, 1, 0, TriangleRegion::Vertex1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double den = d1 - d3;  // |ab|^2
    if (!(den > 0)) return detail::closest_point_on_degenerate_triangle(p, a, b, c);
    const double t = d1 / den;
    return make_closest(p, a + t * ab, 1 - t, t, 0, TriangleRegion::Edge01);
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return make_closest(p, c, 0, 0, 1, TriangleRegion::Vertex2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double den = d2 - d6;  // |ac|^2
    if (!(den > 0)) return detail::closest_point_on_degenerate_triangle(p, a, b, c);
    const double t = d2 / den;
    return make_closest(p, a + t * ac, 1 - t, 0, t, TriangleRegion::Edge20);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double den = (d4 - d3) + (d5 - d6);  // |bc|^2
    if (!(den > 0)) return detail::closest_point_on_degenerate_triangle(p, a, b, c);
    const double t = (d4 - d3) / den;
    return make_closest(p, b + t * (c - b), 0, 1 - t, t, TriangleRegion::Edge12);
  }
  // Face region. va, vb, vc are positive multiples of the barycentric
  // coordinates, accurate when the angle at a is not close to 0 or pi;
  // thinner triangles are handled apart (their sum cancels).
  const double nn = norm2(cross(ab, ac));
  if (!(nn > 1e-6 * norm2(ab) * norm2(ac))) return detail::closest_point_on_thin_triangle(p, a, b, c);
  const double sa = va > 0 ? va : 0, sb = vb > 0 ? vb : 0, sc = vc > 0 ? vc : 0;
  const double sum = sa + sb + sc;
  const double u = sa / sum, v = sb / sum, w = sc / sum;
  return make_closest(p, a + v * ab + w * ac, u, v, w, TriangleRegion::Face);
}

}  // namespace anisurf
