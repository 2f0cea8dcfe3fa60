#include "metric/metric.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace anisurf {

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

// Where entry (i, j) of a symmetric 3 x 3 matrix is in SymTensor3::m.
constexpr int kSlot[3][3] = {{0, 1, 3}, {1, 2, 4}, {3, 4, 5}};

Mat3 to_mat(const SymTensor3& M) {
  Mat3 a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = M.m[kSlot[i][j]];
  return a;
}

// Lower-triangular Cholesky factor L (M = L L^T); false if a pivot is not
// positive (M not SPD).
bool cholesky(const SymTensor3& M, Mat3& L) {
  L = {};
  const double l00 = M.m[0];
  if (!(l00 > 0)) return false;
  L[0][0] = std::sqrt(l00);
  L[1][0] = M.m[1] / L[0][0];
  L[2][0] = M.m[3] / L[0][0];
  const double d1 = M.m[2] - L[1][0] * L[1][0];
  if (!(d1 > 0)) return false;
  L[1][1] = std::sqrt(d1);
  L[2][1] = (M.m[4] - L[2][0] * L[1][0]) / L[1][1];
  const double d2 = M.m[5] - L[2][0] * L[2][0] - L[2][1] * L[2][1];
  if (!(d2 > 0)) return false;
  L[2][2] = std::sqrt(d2);
  return true;
}

// Inverse of a lower-triangular matrix with a positive diagonal.
Mat3 lower_inverse(const Mat3& L) {
  Mat3 X{};
  X[0][0] = 1.0 / L[0][0];
  X[1][1] = 1.0 / L[1][1];
  X[2][2] = 1.0 / L[2][2];
  X[1][0] = -L[1][0] * X[0][0] / L[1][1];
  X[2][1] = -L[2][1] * X[1][1] / L[2][2];
  X[2][0] = -(L[2][0] * X[0][0] + L[2][1] * X[1][0]) / L[2][2];
  return X;
}

// X A X^T for a general X (result symmetrised).
SymTensor3 sandwich(const Mat3& X, const SymTensor3& A) {
  const Mat3 a = to_mat(A);
  Mat3 XA{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) XA[i][j] = X[i][0] * a[0][j] + X[i][1] * a[1][j] + X[i][2] * a[2][j];
  SymTensor3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      out.m[kSlot[i][j]] = XA[i][0] * X[j][0] + XA[i][1] * X[j][1] + XA[i][2] * X[j][2];
    }
  return out;
}

Vec3 mat_vec(const Mat3& X, const Vec3& u) {
  return {X[0][0] * u.x + X[0][1] * u.y + X[0][2] * u.z, X[1][0] * u.x + X[1][1] * u.y + X[1][2] * u.z,
          X[2][0] * u.x + X[2][1] * u.y + X[2][2] * u.z};
}

// f applied to the eigenvalues.
template <class F>
SymTensor3 spectral(const SymTensor3& M, F f) {
  SymEigen3 e = eigen_decompose(M);
  for (double& v : e.values) v = f(v);
  return compose(e.values, e.vectors);
}

// Among the cross products of two rows of A - lambda I, the longest: a
// vector of the null space when lambda is a simple eigenvalue of A.
Vec3 null_vector(const SymTensor3& A, double lambda) {
  const auto& a = A.m;
  const Vec3 r0(a[0] - lambda, a[1], a[3]), r1(a[1], a[2] - lambda, a[4]), r2(a[3], a[4], a[5] - lambda);
  Vec3 best = cross(r0, r1);
  for (const Vec3& c : {cross(r0, r2), cross(r1, r2)})
    if (norm2(c) > norm2(best)) best = c;
  return best;
}

// A unit vector orthogonal to the unit vector v.
Vec3 orthogonal_unit(const Vec3& v) {
  const Vec3 axis = std::fabs(v.x) <= std::fabs(v.y) && std::fabs(v.x) <= std::fabs(v.z) ? Vec3(1, 0, 0)
                    : std::fabs(v.y) <= std::fabs(v.z)                                   ? Vec3(0, 1, 0)
                                                                                         : Vec3(0, 0, 1);
  return normalized(axis - dot(axis, v) * v);
}

// Eigen-decomposition of a symmetric 3 x 3 matrix without iterations: the
// eigenvalues from the trigonometric solution of the characteristic cubic,
// the vector of the one farthest from the other two from a cross product of
// rows of M - lambda I, the other two by the Jacobi rotation of the 2 x 2
// restriction to the plane orthogonal to it; the values are the Rayleigh
// quotients of the vectors. Accurate to round-off relative to the largest
// |eigenvalue| (eigen_decompose, Jacobi, also keeps the small eigenvalues of
// SPD tensors accurate). Diagonal and non-finite matrices, and three equal
// eigenvalues, go to eigen_decompose.
SymEigen3 direct_eigen_decompose(const SymTensor3& M) {
  double scale = 0;
  for (double x : M.m) scale = max_of(scale, std::fabs(x));
  const auto& m = M.m;
  if (!(scale > 0) || !std::isfinite(scale) || m[1] * m[1] + m[3] * m[3] + m[4] * m[4] == 0) return eigen_decompose(M);
  const SymTensor3 A = M * (1.0 / scale);
  const auto& a = A.m;
  const double q = (a[0] + a[2] + a[5]) / 3.0;
  const SymTensor3 shifted(a[0] - q, a[1], a[2] - q, a[3], a[4], a[5] - q);
  const auto& b = shifted.m;
  const double p =
      std::sqrt((b[0] * b[0] + b[2] * b[2] + b[5] * b[5] + 2.0 * (b[1] * b[1] + b[3] * b[3] + b[4] * b[4])) / 6.0);
  const double phi = std::acos(std::clamp(0.5 * det(shifted) / (p * p * p), -1.0, 1.0)) / 3.0;
  const double cos_phi = std::cos(phi), sin_phi = std::sin(phi);
  const double largest = q + 2.0 * p * cos_phi;
  const double smallest = q - p * (cos_phi + std::sqrt(3.0) * sin_phi);  // q + 2 p cos(phi + 2 pi / 3)
  const double middle = 3.0 * q - largest - smallest;
  const double isolated = largest - middle >= middle - smallest ? largest : smallest;
  const Vec3 n = null_vector(A, isolated);
  if (!(norm2(n) > 0)) return eigen_decompose(M);
  SymEigen3 out;
  out.vectors[0] = normalized(n);
  const Vec3 u = orthogonal_unit(out.vectors[0]), w = cross(out.vectors[0], u);
  // The 2 x 2 restriction [[uAu, uAw], [uAw, wAw]], diagonalised by the
  // plane rotation (c, -s), (s, c) of a Jacobi step.
  const Vec3 Au = A * u;
  const double uw = dot(w, Au);
  double c = 1, s = 0;
  if (uw != 0) {
    const double tau = (quad(A, w) - dot(u, Au)) / (2.0 * uw);
    const double t = std::fabs(tau) > 1e150 ? 0.5 / tau
                                             : (tau >= 0 ? 1.0 : -1.0) / (std::fabs(tau) + std::sqrt(1.0 + tau * tau));
    c = 1.0 / std::sqrt(1.0 + t * t);
    s = t * c;
  }
  out.vectors[1] = c * u - s * w;
  out.vectors[2] = s * u + c * w;
  for (int i = 0; i < 3; ++i) out.values[i] = quad(A, out.vectors[i]);
  for (int i = 1; i < 3; ++i)
    for (int k = i; k > 0 && out.values[k] < out.values[k - 1]; --k) {
      std::swap(out.values[k], out.values[k - 1]);
      std::swap(out.vectors[k], out.vectors[k - 1]);
    }
  for (double& v : out.values) v *= scale;
  return out;
}

}  // namespace

SymTensor3 inverse(const SymTensor3& M) {
  const auto& a = M.m;
  // Cofactors of the symmetric matrix [[a0 a1 a3] [a1 a2 a4] [a3 a4 a5]].
  const double c00 = a[2] * a[5] - a[4] * a[4];
  const double c01 = a[3] * a[4] - a[1] * a[5];
  const double c02 = a[1] * a[4] - a[2] * a[3];
  const double c11 = a[0] * a[5] - a[3] * a[3];
  const double c12 = a[1] * a[3] - a[0] * a[4];
  const double c22 = a[0] * a[2] - a[1] * a[1];
  const double d = a[0] * c00 + a[1] * c01 + a[3] * c02;
  const double s = 1.0 / d;
  return {c00 * s, c01 * s, c11 * s, c02 * s, c12 * s, c22 * s};
}

SymTensor3 congruence(const SymTensor3& M, const std::array<Vec3, 3>& columns) {
  SymTensor3 out;
  for (int i = 0; i < 3; ++i) {
    const Vec3 Mi = M * columns[i];
    for (int j = 0; j <= i; ++j) out(j, i) = dot(columns[j], Mi);
  }
  return out;
}

// --------------------------------------------------------------------------
// Eigen-decompositions.

SymEigen3 eigen_decompose(const SymTensor3& M) {
  SymEigen3 out;
  double scale = 0;
  for (double x : M.m) scale = max_of(scale, std::fabs(x));
  if (!std::isfinite(scale) || !is_finite(M)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.values = {nan, nan, nan};
    out.vectors = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    return out;
  }
  if (scale == 0) {
    out.vectors = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    return out;
  }
  Mat3 a = to_mat(M * (1.0 / scale));
  Mat3 v = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  static constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 32; ++sweep) {
    bool rotated = false;
    for (const auto& pq : kPairs) {
      const int p = pq[0], q = pq[1], r = 3 - p - q;
      const double apq = a[p][q];
      // Negligible against both diagonal entries (relative test: keeps the
      // small eigenvalues of SPD tensors accurate) or below underflow.
      if (std::fabs(apq) <= 1e-18 * std::sqrt(std::fabs(a[p][p] * a[q][q])) || std::fabs(apq) < 1e-300) {
        a[p][q] = a[q][p] = 0;
        continue;
      }
      rotated = true;
      const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
      const double t = std::fabs(theta) > 1e150 ? 0.5 / theta
                                                 : std::copysign(1.0, theta) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
      const double c = 1.0 / std::sqrt(t * t + 1.0);
      const double s = t * c;
      a[p][p] -= t * apq;
      a[q][q] += t * apq;
      a[p][q] = a[q][p] = 0;
      const double arp = a[r][p], arq = a[r][q];
      a[r][p] = a[p][r] = c * arp - s * arq;
      a[r][q] = a[q][r] = s * arp + c * arq;
      for (int k = 0; k < 3; ++k) {
        const double vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
    if (!rotated) break;
  }
  // Ascending eigenvalues, equal ones in their original order.
  std::array<int, 3> order = {0, 1, 2};
  for (int i = 1; i < 3; ++i)
    for (int k = i; k > 0 && a[order[k]][order[k]] < a[order[k - 1]][order[k - 1]]; --k) std::swap(order[k], order[k - 1]);
  for (int i = 0; i < 3; ++i) {
    const int k = order[i];
    out.values[i] = a[k][k] * scale;
    out.vectors[i] = Vec3(v[0][k], v[1][k], v[2][k]);
  }
  return out;
}

SymEigen2 eigen_decompose(const SymTensor2& M) {
  SymEigen2 out;
  const double a = M.m[0], b = M.m[1], c = M.m[2];
  const double mean = 0.5 * (a + c);
  const double r = std::hypot(0.5 * (a - c), b);
  // The larger-magnitude eigenvalue from the sum, the other from the
  // determinant (no cancellation for SPD tensors with large anisotropy).
  double big = mean >= 0 ? mean + r : mean - r;
  double small = big != 0 ? (a * c - b * b) / big : 0.0;
  if (r == 0) small = big;
  out.values = {min_of(big, small), max_of(big, small)};
  // The eigenvector of the larger eigenvalue has angle 0.5 atan2(2b, a - c).
  const double phi = 0.5 * std::atan2(2.0 * b, a - c);
  out.angle = phi + 0.5 * M_PI;  // vectors[0] belongs to the smaller eigenvalue
  return out;
}

SymTensor3 compose(const std::array<double, 3>& values, const std::array<Vec3, 3>& vectors) {
  SymTensor3 out;
  for (int i = 0; i < 3; ++i) out += values[i] * SymTensor3::outer(vectors[i]);
  return out;
}

SymTensor2 compose(const std::array<double, 2>& values, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  // v0 = (c, s), v1 = (-s, c).
  return {values[0] * c * c + values[1] * s * s, (values[0] - values[1]) * c * s,
          values[0] * s * s + values[1] * c * c};
}

// --------------------------------------------------------------------------
// Sizes and directions.

SymTensor3 metric_from_sizes(const std::array<double, 3>& sizes, const std::array<Vec3, 3>& directions) {
  SymTensor3 out;
  for (int i = 0; i < 3; ++i) out += (1.0 / (sizes[i] * sizes[i])) * SymTensor3::outer(normalized(directions[i]));
  return out;
}

SymTensor2 metric_from_sizes(double h1, double h2, double angle) {
  return compose({1.0 / (h1 * h1), 1.0 / (h2 * h2)}, angle);
}

SizesDirections sizes_and_directions(const SymTensor3& M) {
  const SymEigen3 e = eigen_decompose(M);
  SizesDirections out;
  for (int i = 0; i < 3; ++i) {
    out.sizes[i] = 1.0 / std::sqrt(e.values[i]);
    out.directions[i] = e.vectors[i];
  }
  return out;
}

// --------------------------------------------------------------------------
// Validity.

bool is_finite(const SymTensor3& M) {
  for (double x : M.m)
    if (!std::isfinite(x)) return false;
  return true;
}

bool is_spd(const SymTensor3& M) {
  Mat3 L;
  return is_finite(M) && cholesky(M, L);
}

bool is_spd(const SymTensor2& M) {
  return std::isfinite(M.m[0]) && std::isfinite(M.m[1]) && std::isfinite(M.m[2]) && M.m[0] > 0 &&
         M.m[2] - M.m[1] * M.m[1] / M.m[0] > 0;
}

std::string metric_problem(const SymTensor3& M) {
  static const char* kNames[6] = {"m11", "m12", "m22", "m13", "m23", "m33"};
  char buf[200];
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(M.m[i])) {
      std::snprintf(buf, sizeof buf, "non-finite component %s = %g", kNames[i], M.m[i]);
      return buf;
    }
  if (!is_spd(M)) {
    const SymEigen3 e = eigen_decompose(M);
    std::snprintf(buf, sizeof buf,
                  "not positive definite (m11 m12 m22 m13 m23 m33 = %g %g %g %g %g %g; eigenvalues %g %g %g)",
                  M.m[0], M.m[1], M.m[2], M.m[3], M.m[4], M.m[5], e.values[0], e.values[1], e.values[2]);
    return buf;
  }
  return {};
}

void check_metric(const SymTensor3& M, int vertex_index) {
  std::string problem = metric_problem(M);
  if (!problem.empty())
    throw MetricError("metric at vertex " + std::to_string(vertex_index + 1) + " (1-based): " + problem);
}

// --------------------------------------------------------------------------
// Spectral functions and operations.

SymTensor3 tensor_log(const SymTensor3& M) {
  return spectral(M, [](double x) { return std::log(x); });
}
SymTensor3 tensor_exp(const SymTensor3& M) {
  return spectral(M, [](double x) { return std::exp(x); });
}
SymTensor3 tensor_power(const SymTensor3& M, double p) {
  return spectral(M, [p](double x) { return std::pow(x, p); });
}

std::array<double, 3> generalized_eigenvalues(const SymTensor3& A, const SymTensor3& B) {
  Mat3 L;
  if (!cholesky(B, L)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  return eigen_decompose(sandwich(lower_inverse(L), A)).values;
}

double largest_generalized_eigenvalue(const SymTensor3& A, const SymTensor3& B) {
  Mat3 L;
  if (!cholesky(B, L)) return std::numeric_limits<double>::quiet_NaN();
  return largest_eigenvalue(sandwich(lower_inverse(L), A));
}

double largest_eigenvalue(const SymTensor3& M) { return direct_eigen_decompose(M).values[2]; }

double smallest_eigenvalue(const SymTensor3& M) { return direct_eigen_decompose(M).values[0]; }

SymTensor3 intersect(const SymTensor3& M1, const SymTensor3& M2) {
  Mat3 L;
  if (!cholesky(M1, L)) return M2;
  // C = L^-1 M2 L^-T = Q D Q^T; result = L Q max(I, D) Q^T L^T
  //                                    = M1 + sum_{d_i > 1} (d_i - 1) (L q_i)(L q_i)^T.
  const SymEigen3 e = direct_eigen_decompose(sandwich(lower_inverse(L), M2));
  SymTensor3 out = M1;
  for (int i = 0; i < 3; ++i)
    if (e.values[i] > 1.0) out += (e.values[i] - 1.0) * SymTensor3::outer(mat_vec(L, e.vectors[i]));
  return out;
}

SymTensor3 clamp_metric(const SymTensor3& M, const MetricBounds& b) {
  if (!(b.hmin <= b.hmax) || !(b.max_anisotropy >= 1))
    throw MetricError("metric bounds: need 0 <= hmin <= hmax and max anisotropy >= 1 (hmin " +
                      std::to_string(b.hmin) + ", hmax " + std::to_string(b.hmax) + ", max anisotropy " +
                      std::to_string(b.max_anisotropy) + ")");
  SymEigen3 e = eigen_decompose(M);
  const double lmin = 1.0 / (b.hmax * b.hmax);  // 0 for hmax = inf
  const double lmax = b.hmin > 0 ? 1.0 / (b.hmin * b.hmin) : std::numeric_limits<double>::infinity();
  for (double& v : e.values) v = std::clamp(v, lmin, lmax);
  if (std::isfinite(b.max_anisotropy)) {
    const double floor = e.values[2] / (b.max_anisotropy * b.max_anisotropy);
    for (double& v : e.values) v = max_of(v, floor);
  }
  return compose(e.values, e.vectors);
}

}  // namespace anisurf
