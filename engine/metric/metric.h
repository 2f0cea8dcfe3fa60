// Metric tensors: the control space of the report's section 2.
//
// A metric is a symmetric positive definite tensor M; the length of a vector u
// in M is sqrt(u^T M u) (eq. 2), an isotropic size h is M = h^-2 I (eq. 3) and
// an anisotropic one is M = R diag(h_i^-2) R^T (eq. 1). 3x3 tensors are stored
// as 6 doubles in the .sol file order m11 m12 m22 m13 m23 m33 (the layout of
// FieldValue), 2x2 ones (tangent planes, planar meshes) as m11 m12 m22.
// This header stays light (no Eigen): everything heavy lives in the .cpp.
#pragma once
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/vec3.h"

namespace anisurf {

// A metric field was refused (not finite, not positive definite ...). The
// message names the vertex (1-based, as in the .mesh/.sol files).
class MetricError : public Error {
 public:
  using Error::Error;
};

// ---------------------------------------------------------------------------
// 3x3 symmetric tensor.
struct SymTensor3 {
  std::array<double, 6> m{};  // m11 m12 m22 m13 m23 m33 (.sol order)

  constexpr SymTensor3() = default;
  constexpr SymTensor3(double m11, double m12, double m22, double m13, double m23, double m33)
      : m{m11, m12, m22, m13, m23, m33} {}
  constexpr explicit SymTensor3(const std::array<double, 6>& sol) : m(sol) {}

  double xx() const { return m[0]; }
  double xy() const { return m[1]; }
  double yy() const { return m[2]; }
  double xz() const { return m[3]; }
  double yz() const { return m[4]; }
  double zz() const { return m[5]; }
  // Entry (i, j), 0-based, either triangle.
  double operator()(int i, int j) const { return m[index(i, j)]; }
  double& operator()(int i, int j) { return m[index(i, j)]; }
  static constexpr int index(int i, int j) {
    // (0,0)->0 (0,1)->1 (1,1)->2 (0,2)->3 (1,2)->4 (2,2)->5
    return i > j ? index(j, i) : (j == 2 ? 3 + i : i + j);
  }

  static constexpr SymTensor3 diagonal(double a, double b, double c) { return {a, 0, b, 0, 0, c}; }
  static constexpr SymTensor3 identity(double s = 1.0) { return diagonal(s, s, s); }
  // u u^T.
  static SymTensor3 outer(const Vec3& u) {
    return {u.x * u.x, u.x * u.y, u.y * u.y, u.x * u.z, u.y * u.z, u.z * u.z};
  }

  SymTensor3& operator+=(const SymTensor3& o) {
    for (int i = 0; i < 6; ++i) m[i] += o.m[i];
    return *this;
  }
  SymTensor3& operator-=(const SymTensor3& o) {
    for (int i = 0; i < 6; ++i) m[i] -= o.m[i];
    return *this;
  }
  SymTensor3& operator*=(double s) {
    for (double& x : m) x *= s;
    return *this;
  }
  friend SymTensor3 operator+(SymTensor3 a, const SymTensor3& b) { return a += b; }
  friend SymTensor3 operator-(SymTensor3 a, const SymTensor3& b) { return a -= b; }
  friend SymTensor3 operator*(SymTensor3 a, double s) { return a *= s; }
  friend SymTensor3 operator*(double s, SymTensor3 a) { return a *= s; }
  friend bool operator==(const SymTensor3& a, const SymTensor3& b) { return a.m == b.m; }
  friend bool operator!=(const SymTensor3& a, const SymTensor3& b) { return a.m != b.m; }
};

// M u.
inline Vec3 operator*(const SymTensor3& M, const Vec3& u) {
  return {M.m[0] * u.x + M.m[1] * u.y + M.m[3] * u.z, M.m[1] * u.x + M.m[2] * u.y + M.m[4] * u.z,
          M.m[3] * u.x + M.m[4] * u.y + M.m[5] * u.z};
}
// u^T M u: the squared length of u in M (integrand of eq. 2).
inline double quad(const SymTensor3& M, const Vec3& u) {
  return M.m[0] * u.x * u.x + M.m[2] * u.y * u.y + M.m[5] * u.z * u.z +
         2.0 * (M.m[1] * u.x * u.y + M.m[3] * u.x * u.z + M.m[4] * u.y * u.z);
}
// u^T M v.
inline double bilinear(const SymTensor3& M, const Vec3& u, const Vec3& v) { return dot(u, M * v); }
// Length of the vector u in the constant metric M: sqrt(u^T M u).
inline double metric_length(const SymTensor3& M, const Vec3& u) { return std::sqrt(max_of(quad(M, u), 0.0)); }
inline double trace(const SymTensor3& M) { return M.m[0] + M.m[2] + M.m[5]; }
inline double det(const SymTensor3& M) {
  const auto& a = M.m;
  return a[0] * (a[2] * a[5] - a[4] * a[4]) - a[1] * (a[1] * a[5] - a[4] * a[3]) +
         a[3] * (a[1] * a[4] - a[2] * a[3]);
}
// Frobenius norm (off-diagonal entries counted twice).
inline double frobenius_norm(const SymTensor3& M) {
  const auto& a = M.m;
  return std::sqrt(a[0] * a[0] + a[2] * a[2] + a[5] * a[5] + 2.0 * (a[1] * a[1] + a[3] * a[3] + a[4] * a[4]));
}
// Inverse by the adjugate. Pre: det(M) != 0.
SymTensor3 inverse(const SymTensor3& M);
// A^T M A for a general 3x3 A given by its columns (a change of basis).
SymTensor3 congruence(const SymTensor3& M, const std::array<Vec3, 3>& columns);

// ---------------------------------------------------------------------------
// 2x2 symmetric tensor (tangent-plane metrics, planar meshes).
struct SymTensor2 {
  std::array<double, 3> m{};  // m11 m12 m22

  constexpr SymTensor2() = default;
  constexpr SymTensor2(double m11, double m12, double m22) : m{m11, m12, m22} {}
  double xx() const { return m[0]; }
  double xy() const { return m[1]; }
  double yy() const { return m[2]; }
  static constexpr SymTensor2 identity(double s = 1.0) { return {s, 0, s}; }
  SymTensor2& operator+=(const SymTensor2& o) {
    for (int i = 0; i < 3; ++i) m[i] += o.m[i];
    return *this;
  }
  SymTensor2& operator*=(double s) {
    for (double& x : m) x *= s;
    return *this;
  }
  friend SymTensor2 operator+(SymTensor2 a, const SymTensor2& b) { return a += b; }
  friend SymTensor2 operator*(SymTensor2 a, double s) { return a *= s; }
  friend SymTensor2 operator*(double s, SymTensor2 a) { return a *= s; }
};
inline double det(const SymTensor2& M) { return M.m[0] * M.m[2] - M.m[1] * M.m[1]; }
inline double trace(const SymTensor2& M) { return M.m[0] + M.m[2]; }
inline double quad(const SymTensor2& M, double x, double y) {
  return M.m[0] * x * x + 2.0 * M.m[1] * x * y + M.m[2] * y * y;
}

// ---------------------------------------------------------------------------
// Eigen-decompositions. Eigenvalues ascending, eigenvectors orthonormal:
// M = sum_i values[i] vectors[i] vectors[i]^T.
struct SymEigen3 {
  std::array<double, 3> values{};
  std::array<Vec3, 3> vectors{};
};
struct SymEigen2 {
  std::array<double, 2> values{};
  double angle = 0;  // vectors[0] = (cos, sin), vectors[1] = (-sin, cos)
};

// Cyclic Jacobi rotations on the scaled tensor: backward stable (errors of
// order 1e-16 times the largest eigenvalue, like Eigen's solver), and for
// graded tensors (diagonal-dominant, widely scaled) also relatively accurate on
// the tiny eigenvalues. Non-finite input gives NaN values.
SymEigen3 eigen_decompose(const SymTensor3& M);
// Closed form (eq. 1: angle and the two eigenvalues).
SymEigen2 eigen_decompose(const SymTensor2& M);
// sum_i values[i] v_i v_i^T.
SymTensor3 compose(const std::array<double, 3>& values, const std::array<Vec3, 3>& vectors);
SymTensor2 compose(const std::array<double, 2>& values, double angle);

// ---------------------------------------------------------------------------
// Metrics from sizes and back (eq. 1 and 3).

// Isotropic metric h^-2 I (eq. 3). Pre: h > 0.
inline SymTensor3 isotropic_metric(double h) { return SymTensor3::identity(1.0 / (h * h)); }
// True when M is lambda I (eq. 3) to the relative tolerance `rel` of its
// diagonal: off-diagonal terms and diagonal differences within rel x m11.
inline bool is_isotropic(const SymTensor3& M, double rel = 1e-12) {
  const auto& m = M.m;
  const double tol = rel * std::abs(m[0]);
  return std::abs(m[1]) <= tol && std::abs(m[3]) <= tol && std::abs(m[4]) <= tol && std::abs(m[2] - m[0]) <= tol &&
         std::abs(m[5] - m[0]) <= tol;
}
// sum_i h_i^-2 d_i d_i^T for orthonormal directions d_i (eq. 1 in 3D): the
// length of h_i d_i is 1. Directions are normalised here; pre: orthogonal, h_i > 0.
SymTensor3 metric_from_sizes(const std::array<double, 3>& sizes, const std::array<Vec3, 3>& directions);
// R(angle) diag(h1^-2, h2^-2) R^T (eq. 1).
SymTensor2 metric_from_sizes(double h1, double h2, double angle);

// Sizes h_i = lambda_i^-1/2 and the unit directions (largest size first).
struct SizesDirections {
  std::array<double, 3> sizes{};
  std::array<Vec3, 3> directions{};
};
SizesDirections sizes_and_directions(const SymTensor3& M);

// ---------------------------------------------------------------------------
// Validity.

bool is_finite(const SymTensor3& M);
// Positive definite, decided by the pivots of an LDL^T factorisation (all > 0).
bool is_spd(const SymTensor3& M);
bool is_spd(const SymTensor2& M);
// Empty if M is a valid metric (finite, SPD), else why not (for messages).
std::string metric_problem(const SymTensor3& M);
// Throws MetricError "vertex <index+1>: <problem>" if M is not a valid metric.
void check_metric(const SymTensor3& M, int vertex_index);

// ---------------------------------------------------------------------------
// Spectral functions and operations on metrics.

// f(M) = V f(Lambda) V^T for f = log, exp, power. Pre (log, power): M SPD.
SymTensor3 tensor_log(const SymTensor3& M);
SymTensor3 tensor_exp(const SymTensor3& M);
SymTensor3 tensor_power(const SymTensor3& M, double p);

// Eigenvalues (ascending) of B^-1 A, i.e. of the pencil A v = lambda B v.
// Pre: B SPD, A symmetric. The Rayleigh quotient u^T A u / u^T B u lies in
// [values[0], values[2]].
std::array<double, 3> generalized_eigenvalues(const SymTensor3& A, const SymTensor3& B);
// The largest of them (no iteration, see largest_eigenvalue); NaN unless B is SPD.
double largest_generalized_eigenvalue(const SymTensor3& A, const SymTensor3& B);
// The largest eigenvalue of M without iterations (the cubic's trigonometric
// solution, refined as a Rayleigh quotient): accurate to round-off relative
// to the largest |eigenvalue|, repeated eigenvalues included.
double largest_eigenvalue(const SymTensor3& M);
// The smallest eigenvalue of M, the same way: round-off relative to the
// largest |eigenvalue|.
double smallest_eigenvalue(const SymTensor3& M);

// Intersection by simultaneous reduction: in the basis where M1 = I and M2 =
// diag(d_i), the result is diag(max(1, d_i)): the largest ellipsoid (in that
// basis) inside the unit balls of both, so every vector is at least as long
// in the result as in M1 and in M2. Pre: M1, M2 SPD.
SymTensor3 intersect(const SymTensor3& M1, const SymTensor3& M2);

// Bounds on sizes (Mmg's -hmin -hmax) and on the size ratio of one metric.
struct MetricBounds {
  double hmin = 0.0;                                           // smallest size
  double hmax = std::numeric_limits<double>::infinity();       // largest size
  double max_anisotropy = std::numeric_limits<double>::infinity();  // largest h_max / h_min at a point
};
// Clamps the sizes of M into [hmin, hmax], then raises the small eigenvalues
// so that no size exceeds max_anisotropy times the smallest one. Keeps the
// directions. Throws MetricError unless hmin <= hmax and max_anisotropy >= 1.
SymTensor3 clamp_metric(const SymTensor3& M, const MetricBounds& bounds);

}  // namespace anisurf
