// Conjugate gradients for the symmetric positive (semi-)definite sparse
// systems of the setup steps (compute_frames' mirror system), run by a team
// of threads whose sums are taken over fixed blocks in a fixed order: the
// solution is the same for any number of threads.
#pragma once
#include <vector>

namespace anisurf {

// A symmetric n x n matrix in compressed columns, both triangles stored:
// column u holds the rows inner[outer[u] .. outer[u + 1]) (sorted) and their
// values; column u is also row u.
struct SymmetricColumns {
  int n = 0;
  std::vector<int> outer{0}, inner;
  std::vector<double> value;
  // A(r, c) += v; pre: r is in column c's rows.
  void add(int r, int c, double v);
};

struct CgReport {
  int iterations = 0;
  double relative_residual = 0;  // |b - A x| / |b| at the end
  bool converged = true;
};

// x with A x = b to |b - A x| <= tolerance |b| (at most max_iterations
// steps, from x = 0), by conjugate gradients with the Jacobi (diagonal)
// preconditioner; a zero diagonal entry preconditions with 1. Uses up to
// available_threads() threads when n is large enough to pay for them.
CgReport solve_conjugate_gradient(const SymmetricColumns& A, const std::vector<double>& b, double tolerance,
                                  int max_iterations, std::vector<double>& x);

}  // namespace anisurf
