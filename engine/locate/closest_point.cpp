#include "locate/closest_point.h"

#include <algorithm>
#include <cmath>

namespace anisurf {

namespace {

double clamp01(double t) { return t < 0 ? 0 : (t > 1 ? 1 : t); }

// Signed volume of (a, b, c, d) times 6.
double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dot(cross(b - a, c - a), d - a);
}

// True when the open segment (p, q) passes through the plane of (a, b, c)
// strictly between its ends and inside the triangle. Touching cases (an end
// on the plane, the segment through an edge) are left to the distance terms,
// which are 0 there.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (!((sp > 0 && sq < 0) || (sp < 0 && sq > 0))) return false;
  const double s0 = orient3d(p, q, a, b), s1 = orient3d(p, q, b, c), s2 = orient3d(p, q, c, a);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

}  // namespace

namespace detail {

TriangleClosest closest_point_on_degenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3* v[3] = {&a, &b, &c};
  TriangleClosest best;
  best.distance2 = INFINITY;
  for (int k = 0; k < 3; ++k) {
    const Vec3& s = *v[k];
    const Vec3& e = *v[(k + 1) % 3];
    const double t = closest_parameter_on_segment(p, s, e);
    const Vec3 q = t == 0 ? s : (t == 1 ? e : s + t * (e - s));
    const double d2 = norm2(p - q);
    if (d2 < best.distance2) {
      best.point = q;
      best.distance2 = d2;
      best.bary = {0, 0, 0};
      best.bary[k] = 1 - t;
      best.bary[(k + 1) % 3] = t;
      static constexpr TriangleRegion kEdge[3] = {TriangleRegion::Edge01, TriangleRegion::Edge12,
                                                  TriangleRegion::Edge20};
      static constexpr TriangleRegion kVertex[3] = {TriangleRegion::Vertex0, TriangleRegion::Vertex1,
                                                    TriangleRegion::Vertex2};
      best.region = t == 0 ? kVertex[k] : (t == 1 ? kVertex[(k + 1) % 3] : kEdge[k]);
    }
  }
  return best;
}

TriangleClosest closest_point_on_thin_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleClosest best = closest_point_on_degenerate_triangle(p, a, b, c);
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Vec3 n = cross(ab, ac);
  const double nn = norm2(n);
  if (!(nn > 0)) return best;
  // Barycentrics of the projection of p onto the plane, from the cross products.
  const double v = dot(n, cross(ap, ac)) / nn, w = dot(n, cross(ab, ap)) / nn;
  if (!(v >= 0 && w >= 0 && v + w <= 1)) return best;
  const Vec3 q = a + v * ab + w * ac;
  const double d2 = norm2(p - q);
  if (d2 < best.distance2) best = make_closest(p, q, 1 - v - w, v, w, TriangleRegion::Face);
  return best;
}

}  // namespace detail

double closest_parameter_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double den = norm2(ab);
  if (!(den > 0)) return 0;
  const double num = dot(p - a, ab);
  if (num <= 0) return 0;
  if (num >= den) return 1;
  return num / den;
}

double point_segment_distance2(const Vec3& p, const Vec3& a, const Vec3& b) {
  const double t = closest_parameter_on_segment(p, a, b);
  const Vec3 q = t == 0 ? a : (t == 1 ? b : a + t * (b - a));
  return norm2(p - q);
}

double segment_segment_distance2(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // Minimise |p0 + s d1 - (q0 + t d2)|^2 over [0,1]^2 (Ericson 5.1.9).
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = norm2(d1), e = norm2(d2), f = dot(d2, r);
  double s = 0, t = 0;
  if (!(a > 0) && !(e > 0)) {
    return norm2(r);
  } else if (!(a > 0)) {
    t = clamp01(f / e);
  } else {
    const double c = dot(d1, r);
    if (!(e > 0)) {
      s = clamp01(-c / a);
    } else {
      const double b = dot(d1, d2);
      const double den = a * e - b * b;  // >= 0; 0 for parallel segments
      s = den > 0 ? clamp01((b * f - c * e) / den) : 0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = clamp01(-c / a);
      } else if (t > 1) {
        t = 1;
        s = clamp01((b - c) / a);
      }
    }
  }
  return norm2((p0 + s * d1) - (q0 + t * d2));
}

double segment_triangle_distance2(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (segment_crosses_triangle(p, q, a, b, c)) return 0;
  // Otherwise a closest pair has its segment point at an end or its triangle
  // point on an edge.
  double d = std::min(point_triangle_distance2(p, a, b, c), point_triangle_distance2(q, a, b, c));
  d = std::min(d, segment_segment_distance2(p, q, a, b));
  d = std::min(d, segment_segment_distance2(p, q, b, c));
  d = std::min(d, segment_segment_distance2(p, q, c, a));
  return d;
}

double triangle_triangle_distance2(const std::array<Vec3, 3>& s, const std::array<Vec3, 3>& t) {
  // Intersecting triangles have an edge of one crossing the other. Otherwise a
  // closest pair has a vertex of one triangle, or a point on an edge of each.
  for (int k = 0; k < 3; ++k)
    if (segment_crosses_triangle(s[k], s[(k + 1) % 3], t[0], t[1], t[2]) ||
        segment_crosses_triangle(t[k], t[(k + 1) % 3], s[0], s[1], s[2]))
      return 0;
  double d = INFINITY;
  for (int k = 0; k < 3; ++k) {
    d = std::min(d, point_triangle_distance2(s[k], t[0], t[1], t[2]));
    d = std::min(d, point_triangle_distance2(t[k], s[0], s[1], s[2]));
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      d = std::min(d, segment_segment_distance2(s[i], s[(i + 1) % 3], t[j], t[(j + 1) % 3]));
  return d;
}

}  // namespace anisurf
