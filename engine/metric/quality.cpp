#include "metric/quality.h"

#include <cmath>

namespace anisurf {

double quality_from_lengths(double l1, double l2, double l3) {
  const double p = 0.5 * (l1 + l2 + l3);
  if (!(p > 0)) return 0.0;
  const double a = p - l1, b = p - l2, c = p - l3;
  if (!(a > 0 && b > 0 && c > 0)) return 0.0;
  return 27.0 * a * b * c / (p * p * p);
}

double triangle_quality(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M, LengthFormula formula) {
  std::array<double, 3> l;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    l[i] = edge_length(M[i], M[j], p[j] - p[i], formula);
  }
  return quality_from_lengths(l[0], l[1], l[2]);
}

double triangle_quality_in(const std::array<Vec3, 3>& p, const SymTensor3& M) {
  return quality_from_lengths(metric_length(M, p[1] - p[0]), metric_length(M, p[2] - p[1]),
                              metric_length(M, p[0] - p[2]));
}

double mean_ratio_in(const std::array<Vec3, 3>& p, const SymTensor3& M) {
  const Vec3 a = p[1] - p[0], b = p[2] - p[0], c = p[2] - p[1];
  const double aa = quad(M, a), bb = quad(M, b), ab = bilinear(M, a, b);
  const double sum = aa + bb + quad(M, c);
  if (!(sum > 0)) return 0.0;
  const double area = 0.5 * std::sqrt(max_of(aa * bb - ab * ab, 0.0));
  return 4.0 * std::sqrt(3.0) * area / sum;
}

}  // namespace anisurf
