#include "metric/hessian.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "geometry/pivoted_qr.h"
#include "mesh/operators.h"
#include "metric/surface_metric.h"

namespace anisurf {

namespace {

// Vertices within `rings` edges of v (v excluded), grown until min_points.
// With the feature flags set (set_features), the neighbourhood stays on one
// side of the feature curves: it starts from the triangles of one smooth
// sector of v (set_sector; the whole fan when none) and, at a vertex on a
// feature curve, enters only the sectors it already reached there, so that no
// point beyond a ridge, a boundary or a reference interface is collected
// (away from the features: the same rings, in the same order).
class RingCollector {
 public:
  explicit RingCollector(const SurfaceMesh& mesh) : mesh_(mesh), seen_(mesh.vertex_capacity(), 0) {}

  // Per vertex slot: 1 on a feature edge. Null: plain rings.
  void set_features(const std::vector<char>* on_feature) {
    clear_collection();
    on_feature_ = on_feature;
    if (on_feature_) triangle_seen_.assign(static_cast<std::size_t>(mesh_.triangle_capacity()), 0);
  }
  // The corners of v's fan the next collections start from (null: all), and
  // whether they may meet the feature curves at all (false: plain rings,
  // without the bookkeeping of the sides).
  void set_sector(const std::vector<Corner>* sector, bool near_features = true) {
    sector_ = sector;
    near_features_ = near_features;
    clear_collection();
  }

  // The points of rings 1..R around v: R at least `rings`, and more (up to
  // 4) while there are fewer than min_points. The requests at one vertex and
  // sector (the fits try rings 1 to 4, for the normal, then the curvature,
  // at two degrees) extend one collection ring by ring and are answered by
  // its prefixes: a ring's points depend only on the rings inside it.
  std::span<const int> collect(Vertex v, int rings, int min_points) {
    if (v.idx != centre_) start(v);
    int r = 1;
    for (;;) {
      if (r > collected_) extend();
      if (!(r < kMaxRings && (r < rings || ends_[r] < min_points))) break;
      ++r;
    }
    met_features_ = met_[r];
    return {out_.data(), static_cast<std::size_t>(ends_[r])};
  }

  // True when the last collection passed a vertex on a feature curve (its
  // points are then one-sided there).
  bool met_features() const { return met_features_; }

 private:
  static constexpr int kMaxRings = 4;

  // The marks of the current collection cleared; none current.
  void clear_collection() {
    if (centre_ >= 0) seen_[static_cast<std::size_t>(centre_)] = 0;
    for (int w : out_) seen_[static_cast<std::size_t>(w)] = 0;
    for (int t : triangles_) triangle_seen_[static_cast<std::size_t>(t)] = 0;
    out_.clear();
    triangles_.clear();
    centre_ = -1;
  }
  // A new collection at v, ring 1 taken.
  void start(Vertex v) {
    clear_collection();
    centre_ = v.idx;
    seen_[v.idx] = 1;
    met_features_ = false;
    add_ring_of(v, true);
    ends_[0] = 0;
    ends_[1] = static_cast<int>(out_.size());
    met_[1] = met_features_;
    collected_ = 1;
  }
  // The next ring: the neighbours of the outermost one.
  void extend() {
    const int k = collected_;
    for (int i = ends_[k - 1]; i < ends_[k]; ++i) add_ring_of(Vertex(out_[static_cast<std::size_t>(i)]), false);
    ends_[k + 1] = static_cast<int>(out_.size());
    met_[k + 1] = met_features_;
    collected_ = k + 1;
  }

  void add_ring_of(Vertex u, bool centre) {
    if (!sided()) {
      for (Corner c : mesh_.fan_corners(u)) add_triangle_of(c);
      return;
    }
    if ((*on_feature_)[u.idx]) met_features_ = true;
    if (!(*on_feature_)[u.idx] && !(centre && sector_)) {
      for (Corner c : mesh_.fan_corners(u)) add_triangle_of(c);
      return;
    }
    fan_ = mesh_.fan(u);
    const int n = static_cast<int>(fan_.size());
    allowed_.assign(fan_.size(), 0);
    for (int i = 0; i < n; ++i)
      allowed_[i] = centre ? (!sector_ || std::find(sector_->begin(), sector_->end(), fan_[i]) != sector_->end())
                           : triangle_seen_[SurfaceMesh::triangle(fan_[i]).idx];
    // Spread over the edges between consecutive fan triangles that are not
    // feature edges: whole sectors (closed fans wrap around).
    const bool closed = !mesh_.is_boundary(u);
    auto joined = [&](int i) { return (closed || i + 1 < n) && !is_feature_edge(mesh_, SurfaceMesh::next(fan_[i])); };
    for (int k = 0; k < 2 * n; ++k) {
      const int i = k % n;
      if (allowed_[i] && joined(i)) allowed_[(i + 1) % n] = 1;
    }
    for (int k = 2 * n - 1; k >= 0; --k) {
      const int i = k % n;
      if (allowed_[(i + 1) % n] && joined(i)) allowed_[i] = 1;
    }
    for (int i = 0; i < n; ++i)
      if (allowed_[i]) add_triangle_of(fan_[i]);
  }

  bool sided() const { return on_feature_ && near_features_; }

  void add_triangle_of(Corner c) {
    if (sided()) {
      const int t = SurfaceMesh::triangle(c).idx;
      if (!triangle_seen_[t]) {
        triangle_seen_[t] = 1;
        triangles_.push_back(t);
      }
    }
    for (Vertex w : {mesh_.vertex(SurfaceMesh::next(c)), mesh_.vertex(SurfaceMesh::prev(c))})
      if (!seen_[w.idx]) {
        seen_[w.idx] = 1;
        out_.push_back(w.idx);
      }
  }

  const SurfaceMesh& mesh_;
  std::vector<char> seen_;
  std::vector<int> out_;
  const std::vector<char>* on_feature_ = nullptr;
  const std::vector<Corner>* sector_ = nullptr;
  std::vector<char> triangle_seen_, allowed_;
  std::vector<int> triangles_;
  std::vector<Corner> fan_;
  int centre_ = -1;     // the vertex of the current collection (-1: none)
  int collected_ = 0;   // its rings so far
  std::array<int, kMaxRings + 1> ends_{};   // out_'s size after each ring
  std::array<bool, kMaxRings + 1> met_{};   // met_features_ after each ring
  bool met_features_ = false;
  bool near_features_ = true;
};

// How a vertex's derivatives were obtained.
enum class FitKind { None, Full, Reduced };

// The columns of the local polynomial at the ring points, in the tangent frame
// of n, coordinates scaled by s (the RMS distance to v): x, y, x^2/2, xy,
// y^2/2 [, x^3, x^2 y, x y^2, y^3], lowest order first; b holds value(w) - value(v).
// One is filled again and again (its storage reused).
struct LocalSystem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  std::array<Vec3, 2> frame;
  double s = 1;
};

template <class Value>
const LocalSystem& local_system(const SurfaceMesh& mesh, Vertex v, std::span<const int> ring, const Vec3& n,
                                int degree, Value value, LocalSystem& ls) {
  ls.frame = tangent_frame(n);
  const Vec3 p0 = mesh.position(v);
  const int m = static_cast<int>(ring.size());
  const int unknowns = degree >= 3 ? 9 : 5;
  double s2 = 0;
  for (int w : ring) s2 += norm2(mesh.position(Vertex(w)) - p0);
  ls.s = m > 0 && s2 > 0 ? std::sqrt(s2 / m) : 1.0;
  ls.A.resize(m, unknowns);
  ls.b.resize(m);
  const double f0 = value(v);
  for (int i = 0; i < m; ++i) {
    const Vec3 d = (mesh.position(Vertex(ring[i])) - p0) / ls.s;
    const double x = dot(d, ls.frame[0]), y = dot(d, ls.frame[1]);
    ls.A(i, 0) = x;
    ls.A(i, 1) = y;
    ls.A(i, 2) = 0.5 * x * x;
    ls.A(i, 3) = x * y;
    ls.A(i, 4) = 0.5 * y * y;
    if (unknowns == 9) {
      ls.A(i, 5) = x * x * x;
      ls.A(i, 6) = x * x * y;
      ls.A(i, 7) = x * y * y;
      ls.A(i, 8) = y * y * y;
    }
    ls.b(i) = value(Vertex(ring[i])) - f0;
  }
  return ls;
}

// Gradient (tangent 3D vector) and Hessian (tangent 3D tensor) from the
// coefficients of the scaled local polynomial.
void write_derivatives(const LocalSystem& ls, const double* a, Vec3& gradient, SymTensor3& hessian) {
  const double s = ls.s;
  gradient = (a[0] / s) * ls.frame[0] + (a[1] / s) * ls.frame[1];
  hessian = extend_from_tangent(SymTensor2(a[2] / (s * s), a[3] / (s * s), a[4] / (s * s)), ls.frame[0], ls.frame[1],
                                0.0);
}

// Least-squares fit of the full polynomial. False (writing nothing) when the
// points do not determine it.
bool solve_full(const LocalSystem& ls, PivotedQR& qr, double rank_threshold, Vec3& gradient, SymTensor3& hessian) {
  if (ls.A.rows() < ls.A.cols()) return false;
  std::array<double, PivotedQR::kMaxColumns> a{};
  if (!solve_full_rank_least_squares(qr, ls.A.data(), static_cast<int>(ls.A.rows()), static_cast<int>(ls.A.cols()),
                                     ls.b.data(), a.data(), rank_threshold))
    return false;
  write_derivatives(ls, a.data(), gradient, hessian);
  return true;
}

// Minimum-norm least-squares solutions of M x = r, singular values below
// `tolerance` * `reference` counted as zero: M's singular value
// decomposition once, for every right-hand side. `range()` is an orthonormal
// basis of the resolved part of M's range.
class MinNormSolver {
 public:
  MinNormSolver(const Eigen::MatrixXd& M, double tolerance, double reference) : cols_(M.cols()) {
    range_.resize(M.rows(), 0);
    if (M.cols() == 0 || !(reference > 0)) return;
    svd_.compute(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd_.singularValues();
    while (rank_ < sigma.size() && sigma(rank_) > tolerance * reference) ++rank_;
    range_ = svd_.matrixU().leftCols(rank_);
  }
  const Eigen::MatrixXd& range() const { return range_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(cols_);
    if (rank_ == 0) return x;
    const Eigen::VectorXd coefficients = range_.transpose() * r;
    for (int k = 0; k < rank_; ++k) x += (coefficients(k) / svd_.singularValues()(k)) * svd_.matrixV().col(k);
    return x;
  }

 private:
  Eigen::Index cols_ = 0;
  int rank_ = 0;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd_;
  Eigen::MatrixXd range_;
};

// v minus its projection on the orthonormal columns of U.
Eigen::MatrixXd project_out(const Eigen::MatrixXd& U, const Eigen::MatrixXd& v) {
  return U.cols() == 0 ? v : Eigen::MatrixXd(v - U * (U.transpose() * v));
}

// Least-squares fit for points that do not determine the full polynomial
// (strips one triangle wide, aligned points): among the best fits, the one
// whose cubic part is smallest, then whose quadratic part is smallest, in
// the rotation-invariant norms of the derivative tensors (|H|_F for the
// Hessian), the gradient free. Points on two parallel lines then give the
// gradient, the curvature along the lines and the twist, and zero curvature
// across them (which they cannot show), whatever the tangent frame. Needs a
// resolved second-order term and two more points than resolved terms (an
// interpolating fit has no redundancy to trust): returns the number of
// resolved terms then, 0 otherwise (writing nothing).
int solve_reduced(const LocalSystem& ls, Vec3& gradient, SymTensor3& hessian) {
  constexpr double kTolerance = 1e-6;
  const int m = static_cast<int>(ls.A.rows());
  const bool cubic = ls.A.cols() == 9;
  // Columns scaled so that the Euclidean norm of the unknowns is the tensor norm.
  const Eigen::MatrixXd G = ls.A.leftCols(2);
  Eigen::MatrixXd Q = ls.A.middleCols(2, 3);
  Q.col(1) /= std::sqrt(2.0);
  Eigen::MatrixXd C = cubic ? Eigen::MatrixXd(ls.A.rightCols(4)) : Eigen::MatrixXd(m, 0);
  if (cubic) {
    C.col(0) /= std::sqrt(3.0);
    C.col(3) /= std::sqrt(3.0);
  }
  // The ranges of the gradient, then of the quadratic terms beyond it.
  const MinNormSolver g_fit(G, kTolerance, G.norm());
  const Eigen::MatrixXd Qp = project_out(g_fit.range(), Q);
  const MinNormSolver q_fit(Qp, kTolerance, Q.norm());
  // Cubic terms: what neither the gradient nor the quadratic terms explain.
  const Eigen::MatrixXd Cp =
      cubic ? project_out(q_fit.range(), project_out(g_fit.range(), C)) : Eigen::MatrixXd(m, 0);
  const MinNormSolver c_fit(Cp, kTolerance, cubic ? C.norm() : 0.0);
  const int resolved = static_cast<int>(g_fit.range().cols() + q_fit.range().cols() + c_fit.range().cols());
  if (q_fit.range().cols() == 0 || m < resolved + 2) return 0;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(C.cols());
  if (cubic) c = c_fit.solve(project_out(q_fit.range(), project_out(g_fit.range(), ls.b)));
  const Eigen::VectorXd r = ls.b - C * c;
  const Eigen::VectorXd qs = q_fit.solve(project_out(g_fit.range(), r));
  const Eigen::VectorXd gs = g_fit.solve(r - Q * qs);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(ls.A.cols());
  a.head(2) = gs;
  a(2) = qs(0);
  a(3) = qs(1) / std::sqrt(2.0);
  a(4) = qs(2);
  write_derivatives(ls, a.data(), gradient, hessian);
  return resolved;
}

constexpr double kFullRankThreshold = 1e-10;

// What the fits at one vertex after another reuse.
struct FitWorkspace {
  explicit FitWorkspace(const SurfaceMesh& mesh) : rings(mesh) {}
  RingCollector rings;
  LocalSystem system;
  PivotedQR qr;
  // A pivot of the full fit at most this times the largest one means the
  // points do not determine the polynomial (the reduced fit takes over).
  double rank_threshold = kFullRankThreshold;
};

int min_points(const HessianRecoveryOptions& o) { return std::max(o.min_points, o.degree >= 3 ? 12 : 6); }

// The fit at v: the requested degree on the requested rings, more rings (up
// to 4) when the points do not determine it (grid corners, small meshes),
// then degree 2 (FitKind::Full). Where nothing determines the full quadratic
// (strips of boundary vertices, aligned points), the reduced fit that
// resolves the most terms over those neighbourhoods (FitKind::Reduced). None
// when not even that (a vertex of a tiny component): the caller fills it in
// (fill_unfitted).
template <class Value>
FitKind fit_at(const SurfaceMesh& mesh, Vertex v, FitWorkspace& work, const Vec3& n,
               const HessianRecoveryOptions& o, Value value, Vec3& gradient, SymTensor3& hessian) {
  const int top = std::min(std::max(o.degree, 2), 3);
  const int widest = std::max(o.rings, 4);
  // A wider request answered by the same points (the rings stop growing at
  // features, at a sector's sides, or were already widened to min_points)
  // is the same system: its fit is not tried again.
  for (int degree = top; degree >= 2; --degree) {
    std::size_t tried = 0;
    for (int r = o.rings; r <= widest; ++r) {
      const std::span<const int> points = work.rings.collect(v, r, min_points(o));
      if (points.size() == tried) continue;
      tried = points.size();
      if (solve_full(local_system(mesh, v, points, n, degree, value, work.system), work.qr, work.rank_threshold,
                     gradient, hessian))
        return FitKind::Full;
    }
  }
  int best = 0;
  for (int degree = top; degree >= 2 && best == 0; --degree) {
    std::size_t tried = 0;
    for (int r = o.rings; r <= widest; ++r) {
      const std::span<const int> points = work.rings.collect(v, r, min_points(o));
      if (points.size() == tried) continue;
      tried = points.size();
      Vec3 g;
      SymTensor3 H;
      const int k = solve_reduced(local_system(mesh, v, points, n, degree, value, work.system), g, H);
      if (k > best) {
        best = k;
        gradient = g;
        hessian = H;
      }
    }
  }
  return best > 0 ? FitKind::Reduced : FitKind::None;
}

// Vertices without a fit take the mean of their fitted (or already filled)
// neighbours, sweep after sweep; those with none in reach keep `fallback`.
// Returns how many vertices had no fit.
template <class T>
int fill_unfitted(const SurfaceMesh& mesh, std::vector<T>& values, std::vector<char>& fitted, const T& fallback) {
  int missing = 0;
  for (Vertex v : mesh.vertices())
    if (!fitted[v.idx] && !mesh.is_isolated(v)) ++missing;
  for (int sweep = 0, left = missing; left > 0 && sweep < 8; ++sweep) {
    std::vector<int> filled;
    for (Vertex v : mesh.vertices()) {
      const int i = v.idx;
      if (fitted[i] || mesh.is_isolated(v)) continue;
      T sum{};
      int n = 0;
      for (Vertex w : mesh.ring_vertices(v))
        if (fitted[w.idx]) {
          sum = sum + values[w.idx];
          ++n;
        }
      if (n == 0) continue;
      values[i] = (1.0 / n) * sum;
      filled.push_back(i);
    }
    if (filled.empty()) break;
    for (int i : filled) fitted[i] = 1;
    left -= static_cast<int>(filled.size());
  }
  for (Vertex v : mesh.vertices())
    if (!fitted[v.idx] && !mesh.is_isolated(v)) values[v.idx] = fallback;
  return missing;
}

double default_hmax(const SurfaceMesh& mesh, double hmax) {
  return std::isfinite(hmax) ? hmax : mesh.bbox().diagonal();
}

// Area of the surface around each vertex (a third of its triangles).
std::vector<double> vertex_areas(const SurfaceMesh& mesh) {
  std::vector<double> a(mesh.vertex_capacity(), 0.0);
  for (Triangle t : mesh.triangles()) {
    const double at = mesh.triangle_area(t) / 3.0;
    for (int k = 0; k < 3; ++k) a[mesh.vertex(t, k).idx] += at;
  }
  return a;
}

// |H| in the tangent frame of n, eigenvalues floored at `floor`.
struct TangentAbs {
  std::array<double, 2> values;
  double angle;
  std::array<Vec3, 2> frame;
};
TangentAbs tangent_abs(const SymTensor3& H, const Vec3& n, double floor) {
  TangentAbs t;
  t.frame = tangent_frame(n);
  const SymEigen2 e = eigen_decompose(restrict_to_tangent(H, t.frame[0], t.frame[1]));
  t.values = {max_of(std::fabs(e.values[0]), floor), max_of(std::fabs(e.values[1]), floor)};
  t.angle = e.angle;
  return t;
}

SymTensor3 tangent_metric(const TangentAbs& t, double scale) {
  const SymTensor2 T = compose({scale * t.values[0], scale * t.values[1]}, t.angle);
  // The normal direction gets the largest tangent size (smallest eigenvalue).
  return extend_from_tangent(T, t.frame[0], t.frame[1], scale * std::min(t.values[0], t.values[1]));
}

// recover_curvature with the normals already fitted.
std::vector<SymTensor3> second_fundamental_form(const SurfaceMesh& mesh, const std::vector<Vec3>& normal,
                                                const HessianRecoveryOptions& options, int* unfitted) {
  std::vector<SymTensor3> out(mesh.vertex_capacity());
  FitWorkspace work(mesh);
  std::vector<char> fitted(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    if (mesh.is_isolated(v)) continue;
    const Vec3 p0 = mesh.position(v), n = normal[i];
    Vec3 g;
    // Depth below the tangent plane: a sphere with outward normals has
    // curvature +1 / R.
    fitted[i] = fit_at(mesh, v, work, n, options, [&](Vertex w) { return -dot(mesh.position(w) - p0, n); }, g,
                       out[i]) != FitKind::None;
  }
  const int missing = fill_unfitted(mesh, out, fitted, SymTensor3());
  if (unfitted) *unfitted = missing;
  return out;
}

// Per vertex slot: 1 within `rings` edges of a vertex on a feature curve
// (the ring collections that can reach the curves: RingCollector expands up
// to its third ring).
std::vector<char> within_rings_of_features(const SurfaceMesh& mesh, const std::vector<char>& on_feature, int rings) {
  std::vector<char> near = on_feature;
  std::vector<int> front;
  for (Vertex v : mesh.vertices())
    if (on_feature[v.idx]) front.push_back(v.idx);
  for (int r = 0; r < rings && !front.empty(); ++r) {
    std::vector<int> next;
    for (int u : front)
      for (Vertex w : mesh.ring_vertices(Vertex(u)))
        if (!near[w.idx]) {
          near[w.idx] = 1;
          next.push_back(w.idx);
        }
    front.swap(next);
  }
  return near;
}

// The largest curvature of a circle tangent to the plane of n at v through
// one of the points: 2 |depth| / distance^2. A quadric fitted on the points
// bends no more than that in the directions they sample.
double largest_point_curvature(const SurfaceMesh& mesh, Vertex v, const Vec3& n, std::span<const int> points) {
  const Vec3& p0 = mesh.position(v);
  double largest = 0;
  for (int w : points) {
    const Vec3 d = mesh.position(Vertex(w)) - p0;
    const double d2 = norm2(d);
    if (d2 > 0) largest = max_of(largest, 2.0 * std::fabs(dot(d, n)) / d2);
  }
  return largest;
}

// The tangent form with its eigenvalues clamped to [-cap, cap].
SymTensor3 cap_curvature(const SymTensor3& form, const Vec3& n, double cap) {
  const auto frame = tangent_frame(n);
  SymEigen2 e = eigen_decompose(restrict_to_tangent(form, frame[0], frame[1]));
  if (std::fabs(e.values[0]) <= cap && std::fabs(e.values[1]) <= cap) return form;
  for (double& k : e.values) k = std::clamp(k, -cap, cap);
  return extend_from_tangent(compose(e.values, e.angle), frame[0], frame[1], 0.0);
}

// Vertices off the features whose neighbours do not determine a fit take
// the mean of their neighbours' forms (fill_unfitted; a vertex on a feature
// curve lends its first fitted sector). Sectors of vertices on feature
// curves without a fit stay flat: they are narrower than any neighbourhood
// on their side (a strip or a single triangle between feature curves), whose
// bending the curves' own curvature carries.
void fill_unfitted_single_sectors(const SurfaceMesh& mesh, SectorCurvatures& sc, const std::vector<char>& fitted) {
  std::vector<SymTensor3> value(static_cast<std::size_t>(mesh.vertex_capacity()));
  std::vector<char> known(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  bool any_missing = false;
  for (Vertex v : mesh.vertices())
    for (int s = sc.first[v.idx]; s < sc.first[v.idx + 1]; ++s)
      if (fitted[s] && !known[v.idx]) {
        value[v.idx] = sc.form[s];
        known[v.idx] = 1;
      } else if (!fitted[s] && !sc.on_feature[v.idx]) {
        any_missing = true;
      }
  if (!any_missing) return;
  for (Vertex v : mesh.vertices())
    if (sc.on_feature[v.idx]) known[v.idx] = 1;  // not filled: their unfitted sectors stay flat
  sc.unfitted = fill_unfitted(mesh, value, known, SymTensor3());
  for (Vertex v : mesh.vertices())
    if (!sc.on_feature[v.idx] && sc.first[v.idx + 1] > sc.first[v.idx]) sc.form[sc.first[v.idx]] = value[v.idx];
}

}  // namespace

std::vector<Vec3> fitted_normals(const SurfaceMesh& mesh, const HessianRecoveryOptions& options) {
  std::vector<Vec3> normal = vertex_normals(mesh);
  FitWorkspace work(mesh);
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    if (mesh.is_isolated(v)) continue;
    const Vec3 p0 = mesh.position(v), n = normal[i];
    // Heights z = (p - p0).n ~ a1 x + a2 y + ...: the surface's tangent plane
    // is spanned by (1, 0, a1), (0, 1, a2), its normal by (-a1, -a2, 1).
    Vec3 slope;
    SymTensor3 unused;
    // Without a fit the area-weighted normal stays.
    if (fit_at(mesh, v, work, n, options, [&](Vertex w) { return dot(mesh.position(w) - p0, n); }, slope, unused) !=
        FitKind::None)
      normal[i] = normalized(n - slope);
  }
  return normal;
}

RecoveredDerivatives recover_derivatives(const SurfaceMesh& mesh, const std::vector<double>& f,
                                         const HessianRecoveryOptions& options) {
  if (static_cast<int>(f.size()) != mesh.vertex_capacity())
    throw MetricError("Hessian recovery: " + std::to_string(f.size()) + " values for " +
                      std::to_string(mesh.vertex_capacity()) + " vertices");
  for (Vertex v : mesh.vertices())
    if (!std::isfinite(f[v.idx]))
      throw MetricError("Hessian recovery: value at vertex " + std::to_string(v.idx + 1) + " is " +
                        std::to_string(f[v.idx]));
  RecoveredDerivatives out;
  out.normal = fitted_normals(mesh, options);
  out.gradient.assign(mesh.vertex_capacity(), Vec3());
  out.hessian.assign(mesh.vertex_capacity(), SymTensor3());
  FitWorkspace work(mesh);
  std::vector<char> fitted(static_cast<std::size_t>(mesh.vertex_capacity()), 0);
  for (Vertex v : mesh.vertices()) {
    const int i = v.idx;
    if (mesh.is_isolated(v)) continue;
    const FitKind kind = fit_at(mesh, v, work, out.normal[i], options, [&](Vertex w) { return f[w.idx]; },
                                out.gradient[i], out.hessian[i]);
    fitted[i] = kind != FitKind::None;
    out.reduced += kind == FitKind::Reduced;
  }
  std::vector<char> fitted_g = fitted;
  out.unfitted = fill_unfitted(mesh, out.hessian, fitted, SymTensor3());
  fill_unfitted(mesh, out.gradient, fitted_g, Vec3());
  return out;
}

std::vector<SymTensor3> recover_curvature(const SurfaceMesh& mesh, const HessianRecoveryOptions& options,
                                          int* unfitted) {
  return second_fundamental_form(mesh, fitted_normals(mesh, options), options, unfitted);
}

HessianMetricOptions cycle_metric_defaults() {
  HessianMetricOptions o;
  o.p = 2;
  o.error_constant = 2.0 / 9.0;
  return o;
}

MetricField hessian_metric(const SurfaceMesh& mesh, const std::vector<SymTensor3>& hessian,
                           const HessianMetricOptions& o) {
  const bool by_error = o.error > 0, by_count = o.target_vertices > 0;
  if (by_error == by_count)
    throw MetricError("Hessian metric: give exactly one target, an error > 0 or a vertex count > 0");
  if (!(o.p >= 1)) throw MetricError("Hessian metric: the norm exponent p must be >= 1 or infinity");
  if (!(o.error_constant > 0)) throw MetricError("Hessian metric: the error constant must be > 0");
  MetricBounds bounds = o.bounds;
  bounds.hmax = default_hmax(mesh, bounds.hmax);
  const std::vector<Vec3> normal = vertex_normals(mesh);
  const int nv = mesh.vertex_capacity();
  const double c = o.error_constant;

  // Floor of |lambda|: in error mode the size hmax (c/eps lambda = hmax^-2); by
  // count a tiny fraction of the largest curvature of f.
  double lmax = 0;
  for (int i = 0; i < nv; ++i)
    if (!mesh.is_deleted(Vertex(i))) lmax = max_of(lmax, frobenius_norm(hessian[i]));
  const double floor = by_error ? o.error / (c * bounds.hmax * bounds.hmax) : max_of(1e-12 * lmax, 1e-300);

  const bool finite_p = std::isfinite(o.p);
  const double det_power = finite_p ? -1.0 / (2.0 * o.p + 2.0) : 0.0;
  std::vector<TangentAbs> abs(nv);
  std::vector<double> local(nv, 1.0);  // det(|H|)^(-1/(2p+2))
  for (int i = 0; i < nv; ++i) {
    if (mesh.is_deleted(Vertex(i))) continue;
    abs[i] = tangent_abs(hessian[i], normal[i], floor);
    if (finite_p) local[i] = std::pow(abs[i].values[0] * abs[i].values[1], det_power);
  }
  auto build = [&](double D) {
    MetricField M(nv, SymTensor3::identity());
    for (int i = 0; i < nv; ++i)
      if (!mesh.is_deleted(Vertex(i))) M[i] = clamp_metric(tangent_metric(abs[i], D * local[i]), bounds);
    return M;
  };

  if (by_error) {
    double D = c / o.error;
    if (finite_p) {
      const std::vector<double> area = vertex_areas(mesh);
      double integral = 0;
      for (int i = 0; i < nv; ++i)
        if (!mesh.is_deleted(Vertex(i)))
          integral += area[i] * std::pow(abs[i].values[0] * abs[i].values[1], o.p / (2.0 * o.p + 2.0));
      D *= std::pow(integral, 1.0 / o.p);
    }
    return build(D);
  }
  // By vertex count: predicted_vertex_count(build(D)) grows with D; bisect on log D.
  const double target = o.target_vertices;
  auto count = [&](double D) { return predicted_vertex_count(metric_complexity(mesh, build(D))); };
  double lo = 1.0, hi = 1.0;
  while (count(lo) > target && lo > 1e-300) lo *= 1e-3;
  while (count(hi) < target && hi < 1e300) hi *= 1e3;
  const double n_lo = count(lo), n_hi = count(hi);
  if (n_lo > target || n_hi < target)
    throw MetricError("Hessian metric: " + std::to_string(target) + " vertices is out of reach within hmin/hmax (" +
                      std::to_string(n_lo) + " .. " + std::to_string(n_hi) + ")");
  for (int it = 0; it < 100 && hi / lo > 1 + 1e-12; ++it) {
    const double mid = std::sqrt(lo * hi);
    (count(mid) < target ? lo : hi) = mid;
  }
  return build(std::sqrt(lo * hi));
}

SymTensor3 absolute_tangent_metric(const SymTensor3& H, const Vec3& unit_normal, double floor, double scale) {
  return tangent_metric(tangent_abs(H, unit_normal, floor), scale);
}

namespace {

// The sector fits of a range of vertex slots (recover_sector_curvature's
// work on one chunk): per slot the index of its first sector in this chunk's
// lists, and per sector its normal, form and whether it was fitted.
struct SectorChunk {
  std::vector<int> first;
  std::vector<Vec3> normal;
  std::vector<SymTensor3> form;
  std::vector<char> fitted;
};

// Fits every smooth sector of the vertices in [begin, end): the tangent
// plane from the fitted heights (as fitted_normals), then the depth below it
// (as recover_curvature), on the same points.
SectorChunk fit_sectors(const SurfaceMesh& mesh, const HessianRecoveryOptions& options,
                        const std::vector<char>& on_feature, const std::vector<char>& near, int begin, int end) {
  SectorChunk out;
  out.first.reserve(static_cast<std::size_t>(end - begin));
  out.normal.reserve(static_cast<std::size_t>(end - begin));
  out.form.reserve(static_cast<std::size_t>(end - begin));
  out.fitted.reserve(static_cast<std::size_t>(end - begin));
  FitWorkspace work(mesh);
  work.rings.set_features(&on_feature);
  const std::vector<std::vector<Corner>> whole_fan(1);  // one sector, the whole fan
  std::vector<std::vector<Corner>> split_sectors;
  for (int i = begin; i < end; ++i) {
    out.first.push_back(static_cast<int>(out.form.size()));
    const Vertex v(i);
    if (mesh.is_deleted(v) || mesh.is_isolated(v)) continue;
    if (on_feature[i]) split_sectors = smooth_sectors(mesh, v);
    const std::vector<std::vector<Corner>>& sectors = on_feature[i] ? split_sectors : whole_fan;
    const Vec3 p0 = mesh.position(v);
    for (const std::vector<Corner>& sector : sectors) {
      const bool whole = sector.empty();
      work.rings.set_sector(whole ? nullptr : &sector, near[i] != 0);
      // Points on one side of a feature curve: the stricter rank test and the cap.
      work.rings.collect(v, options.rings, min_points(options));
      const bool one_sided = work.rings.met_features();
      work.rank_threshold = one_sided ? options.sector_rank_threshold : kFullRankThreshold;
      Vec3 n;
      if (whole)
        for (Corner c : mesh.fan_corners(v)) n += mesh.triangle_normal(SurfaceMesh::triangle(c));
      else
        for (Corner c : sector) n += mesh.triangle_normal(SurfaceMesh::triangle(c));
      n = normalized(n);
      Vec3 slope;
      SymTensor3 form;
      if (fit_at(mesh, v, work, n, options, [&](Vertex w) { return dot(mesh.position(w) - p0, n); }, slope, form) !=
          FitKind::None)
        n = normalized(n - slope);
      form = SymTensor3();
      Vec3 g;
      const bool ok = fit_at(mesh, v, work, n, options, [&](Vertex w) { return -dot(mesh.position(w) - p0, n); }, g,
                             form) != FitKind::None;
      if (ok && one_sided)
        form = cap_curvature(form, n,
                             largest_point_curvature(mesh, v, n, work.rings.collect(v, options.rings, min_points(options))));
      out.normal.push_back(n);
      out.form.push_back(ok ? form : SymTensor3());
      out.fitted.push_back(ok);
    }
  }
  return out;
}

}  // namespace

// The vertices are fitted in chunks on parallel threads (every fit depends on
// its vertex alone), joined in vertex order.
SectorCurvatures recover_sector_curvature(const SurfaceMesh& mesh, const HessianRecoveryOptions& options) {
  SectorCurvatures out;
  const int nv = mesh.vertex_capacity();
  out.on_feature.assign(static_cast<std::size_t>(nv), 0);
  for (Corner c : mesh.edges())
    if (is_feature_edge(mesh, c)) out.on_feature[mesh.edge_from(c).idx] = out.on_feature[mesh.edge_to(c).idx] = 1;
  const std::vector<char> near = within_rings_of_features(mesh, out.on_feature, 3);
  const int chunks = chunk_count(nv, 512);
  std::vector<SectorChunk> parts(static_cast<std::size_t>(chunks));
  run_chunks(nv, chunks, [&](int c, int begin, int end) {
    parts[static_cast<std::size_t>(c)] = fit_sectors(mesh, options, out.on_feature, near, begin, end);
  });
  out.first.reserve(static_cast<std::size_t>(nv) + 1);
  std::vector<char> fitted;
  for (const SectorChunk& part : parts) {
    const int offset = static_cast<int>(out.form.size());
    for (int f : part.first) out.first.push_back(offset + f);
    out.normal.insert(out.normal.end(), part.normal.begin(), part.normal.end());
    out.form.insert(out.form.end(), part.form.begin(), part.form.end());
    fitted.insert(fitted.end(), part.fitted.begin(), part.fitted.end());
  }
  out.first.push_back(static_cast<int>(out.form.size()));
  fill_unfitted_single_sectors(mesh, out, fitted);
  return out;
}

}  // namespace anisurf
