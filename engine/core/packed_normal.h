// Unit vectors in 4 bytes: the octahedral map (the unit sphere onto the
// octahedron |x| + |y| + |z| = 1, unfolded onto the square [-1, 1]^2), 16
// bits a coordinate. A decoded vector is within 1e-4 radian of the encoded
// one; the zero vector stays zero.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/vec3.h"

namespace anisurf {

struct PackedNormal {
  // Outside the range of encoded coordinates ([-32767, 32767]): the zero vector.
  static constexpr std::int16_t kZero = std::numeric_limits<std::int16_t>::min();
  std::int16_t u = kZero, v = kZero;
};

namespace detail {
inline double sign_not_zero(double x) { return x >= 0 ? 1.0 : -1.0; }
inline std::int16_t quantize_unit(double x) {
  return static_cast<std::int16_t>(std::lround(std::fmax(-1.0, std::fmin(1.0, x)) * 32767.0));
}
}  // namespace detail

// Pre: n is unit or zero (anything else is stored normalised).
inline PackedNormal pack_normal(const Vec3& n) {
  const double l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  if (!(l1 > 0) || !std::isfinite(l1)) return {};
  double px = n.x / l1, py = n.y / l1;
  if (n.z < 0) {
    const double fx = (1.0 - std::fabs(py)) * detail::sign_not_zero(px);
    const double fy = (1.0 - std::fabs(px)) * detail::sign_not_zero(py);
    px = fx;
    py = fy;
  }
  return {detail::quantize_unit(px), detail::quantize_unit(py)};
}

inline Vec3 unpack_normal(PackedNormal p) {
  if (p.u == PackedNormal::kZero) return {};
  double x = p.u / 32767.0, y = p.v / 32767.0;
  const double z = 1.0 - std::fabs(x) - std::fabs(y);
  if (z < 0) {
    const double fx = (1.0 - std::fabs(y)) * detail::sign_not_zero(x);
    const double fy = (1.0 - std::fabs(x)) * detail::sign_not_zero(y);
    x = fx;
    y = fy;
  }
  const double l = std::sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}

}  // namespace anisurf
