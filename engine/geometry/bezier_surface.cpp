#include "geometry/bezier_surface.h"

#include <algorithm>
#include <cmath>

#include "geometry/features.h"

namespace anisurf {

namespace {

// --- triangular Bezier index arithmetic (the one place for it) --------------
// A degree-n triangle's control points (i, j, l), i + j + l = n, are stored by
// rows of constant l, j increasing: index = row_offset(n, l) + j.
constexpr int row_offset(int n, int l) { return l * (n + 1) - l * (l - 1) / 2; }
constexpr int tri_index(int n, int j, int l) { return row_offset(n, l) + j; }

// Global index (0..30) of the quartic control point (i, j, l) of subtriangle k
// (local vertices A = v_{k+1}, B = v_{k+2}, G = centre); see the header.
constexpr int global_index(int k, int i, int j, int l) {
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  if (i == 4) return a;
  if (j == 4) return b;
  if (l == 4) return 3;
  if (l == 0) return 4 + 3 * k + (j - 1);
  if (j == 0) return 13 + 3 * a + (l - 1);
  if (i == 0) return 13 + 3 * b + (l - 1);
  if (l == 1) return 22 + 2 * k + (j - 1);  // (2,1,1) -> d1, (1,2,1) -> d2
  return 28 + k;                            // (1,1,2)
}

struct SubTable {
  int idx[3][15];
  constexpr SubTable() : idx{} {
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l <= 4; ++l)
        for (int j = 0; j <= 4 - l; ++j) idx[k][tri_index(4, j, l)] = global_index(k, 4 - j - l, j, l);
  }
};
constexpr SubTable kSub;

// Indices of named points.
constexpr int edge_point(int k, int m) { return 4 + 3 * k + m; }  // macro edge opposite v_k, from v_{k+1}
constexpr int inner_point(int j, int m) { return 13 + 3 * j + m; }  // inner edge v_j -> centre
constexpr int d1_point(int k) { return 22 + 2 * k; }
constexpr int d2_point(int k) { return 23 + 2 * k; }
constexpr int e_point(int k) { return 28 + k; }

// One de Casteljau step of a degree-n triangle (n+1)(n+2)/2 points -> n(n+1)/2.
template <int N>
inline void casteljau_step(const Vec3* in, Vec3* out, double a, double b, double g) {
  // out(i,j,l) = a in(i+1,j,l) + b in(i,j+1,l) + g in(i,j,l+1), degree N-1
  int o = 0;
  for (int l = 0; l <= N - 1; ++l) {
    const int r0 = row_offset(N, l), r1 = row_offset(N, l + 1);
    for (int j = 0; j <= N - 1 - l; ++j) {
      const Vec3& pa = in[r0 + j];
      const Vec3& pb = in[r0 + j + 1];
      const Vec3& pg = in[r1 + j];
      out[o].x = a * pa.x + b * pb.x + g * pg.x;
      out[o].y = a * pa.y + b * pb.y + g * pg.y;
      out[o].z = a * pa.z + b * pb.z + g * pg.z;
      ++o;
    }
  }
}

struct Local {
  int k;             // subtriangle
  double mu[3];      // its barycentric coordinates (A, B, G)
};

inline Local locate_sub(const Bary& b) {
  int k = 0;
  if (b[1] < b[k]) k = 1;
  if (b[2] < b[k]) k = 2;
  const int a = (k + 1) % 3, c = (k + 2) % 3;
  return {k, {b[a] - b[k], b[c] - b[k], 3.0 * b[k]}};
}

// De Casteljau down to the 3 points of degree 1 (the blossom f(x,x,x,e_m)).
inline void reduce_to_linear(const BezierSurface::Patch& P, const Local& s, Vec3 lin[3]) {
  Vec3 q4[15], q3[10], q2[6];
  const int* idx = kSub.idx[s.k];
  for (int i = 0; i < 15; ++i) q4[i] = P[idx[i]];
  casteljau_step<4>(q4, q3, s.mu[0], s.mu[1], s.mu[2]);
  casteljau_step<3>(q3, q2, s.mu[0], s.mu[1], s.mu[2]);
  casteljau_step<2>(q2, lin, s.mu[0], s.mu[1], s.mu[2]);
}

// --- construction helpers ---------------------------------------------------

// Offset of an edge control point from its vertex: along `dir` (unit, in the
// tangent plane or along the curve tangent), for the chord `chord`.
Vec3 handle(const Vec3& chord, const Vec3& dir, BezierOptions::Handle mode) {
  const double L = norm(chord);
  if (!(L > 0)) return {};
  const double c = std::clamp(dot(dir, chord) / L, 0.0, 1.0);
  if (mode == BezierOptions::Handle::Projection) return dir * (L * c / 3.0);
  return dir * (2.0 * L / (3.0 * (1.0 + c)));
}

// Multi-index (i0, i1, i2), |I| = 3, of the macro cubic -> index 0..9.
constexpr int cubic_index(int i1, int i2) { return tri_index(3, i1, i2); }

// Blossom of the macro cubic at barycentric points x, y, z.
Vec3 blossom3(const Vec3 b[10], const double x[3], const double y[3], const double z[3]) {
  Vec3 r;
  for (int p = 0; p < 3; ++p) {
    if (x[p] == 0) continue;
    for (int q = 0; q < 3; ++q) {
      if (y[q] == 0) continue;
      for (int s = 0; s < 3; ++s) {
        if (z[s] == 0) continue;
        int e[3] = {0, 0, 0};
        ++e[p];
        ++e[q];
        ++e[s];
        r += (x[p] * y[q] * z[s]) * b[cubic_index(e[1], e[2])];
      }
    }
  }
  return r;
}

}  // namespace

BezierSurface::BezierSurface(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options) {
  const int nt = mesh.triangle_capacity();
  patches_.assign(nt, Patch{});

  // 1. cubic edge control points, once per edge (canonical corner): [0] next to
  // edge_from, [1] next to edge_to.
  std::vector<std::array<Vec3, 2>> edge_ctrl(3 * static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    if (mesh.is_deleted(Triangle(t))) continue;
    for (int k = 0; k < 3; ++k) {
      const Corner e = SurfaceMesh::corner(Triangle(t), k);
      if (mesh.canonical(e) != e) continue;
      const Vec3& a = mesh.position(mesh.edge_from(e));
      const Vec3& b = mesh.position(mesh.edge_to(e));
      Vec3 da, db;
      if (is_feature_edge(mesh, e)) {
        da = frames.tangent_from(e);
        db = frames.tangent_to(e);
      } else {
        const Vec3& na = frames.normal(SurfaceMesh::next(e));
        const Vec3& nb = frames.normal(SurfaceMesh::prev(e));
        const Vec3 ab = b - a;
        da = normalized(ab - dot(ab, na) * na);
        db = normalized(-ab + dot(ab, nb) * nb);
      }
      edge_ctrl[e.idx] = {a + handle(b - a, da, options.handle), b + handle(a - b, db, options.handle)};
    }
  }
  // cubic points of the edge opposite corner c, from edge_from(c) to edge_to(c)
  auto edge_cubic = [&](Corner c, Vec3& p1, Vec3& p2) {
    const Corner e = mesh.canonical(c);
    if (e == c) {
      p1 = edge_ctrl[e.idx][0];
      p2 = edge_ctrl[e.idx][1];
    } else {
      p1 = edge_ctrl[e.idx][1];
      p2 = edge_ctrl[e.idx][0];
    }
  };

  // 2. per triangle: cubic patch, centre point, split, elevation
  const double g3[3] = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  for (int t = 0; t < nt; ++t) {
    const Triangle tri(t);
    if (mesh.is_deleted(tri)) continue;
    Patch& P = patches_[t];
    Vec3 b[10];
    Vec3 v[3];
    for (int k = 0; k < 3; ++k) v[k] = mesh.position(mesh.vertex(tri, k));
    b[cubic_index(0, 0)] = v[0];
    b[cubic_index(3, 0)] = v[1];
    b[cubic_index(0, 3)] = v[2];
    Vec3 sum_edges;
    Vec3 E[3][2];
    for (int k = 0; k < 3; ++k) {
      edge_cubic(SurfaceMesh::corner(tri, k), E[k][0], E[k][1]);
      sum_edges += E[k][0] + E[k][1];
    }
    // (i1, i2) = powers of v1, v2; E[k] runs from v_{k+1} to v_{k+2}
    b[cubic_index(2, 1)] = E[0][0];  // (0,2,1): next to v1 towards v2
    b[cubic_index(1, 2)] = E[0][1];  // (0,1,2): next to v2 towards v1
    b[cubic_index(0, 2)] = E[1][0];  // (1,0,2): next to v2 towards v0
    b[cubic_index(0, 1)] = E[1][1];  // (2,0,1): next to v0 towards v2
    b[cubic_index(1, 0)] = E[2][0];  // (2,1,0): next to v0 towards v1
    b[cubic_index(2, 0)] = E[2][1];  // (1,2,0): next to v1 towards v0
    // centre: 1/4 sum of the edge points - 1/6 sum of the vertices
    b[cubic_index(1, 1)] = sum_edges * 0.25 - (v[0] + v[1] + v[2]) * (1.0 / 6.0);

    // shared points straight from the edge data (bitwise equal on both sides)
    for (int k = 0; k < 3; ++k) {
      P[k] = v[k];
      const Vec3& A = v[(k + 1) % 3];
      const Vec3& B = v[(k + 2) % 3];
      P[edge_point(k, 0)] = (A + 3.0 * E[k][0]) * 0.25;
      P[edge_point(k, 1)] = (E[k][0] + E[k][1]) * 0.5;
      P[edge_point(k, 2)] = (3.0 * E[k][1] + B) * 0.25;
    }
    // the other points: elevated blossoms of the cubic over each subtriangle
    for (int k = 0; k < 3; ++k) {
      double A[3] = {0, 0, 0}, B[3] = {0, 0, 0};
      A[(k + 1) % 3] = 1;
      B[(k + 2) % 3] = 1;
      const double* pts[3] = {A, B, g3};
      // cubic subpatch c3(i, j, l) = f(A^i, B^j, G^l)
      Vec3 c3[10];
      for (int l = 0; l <= 3; ++l)
        for (int j = 0; j <= 3 - l; ++j) {
          const int i = 3 - j - l;
          const double* args[3];
          int n = 0;
          for (int r = 0; r < i; ++r) args[n++] = pts[0];
          for (int r = 0; r < j; ++r) args[n++] = pts[1];
          for (int r = 0; r < l; ++r) args[n++] = pts[2];
          c3[tri_index(3, j, l)] = blossom3(b, args[0], args[1], args[2]);
        }
      // degree elevation: c4(I) = sum_m I_m / 4 c3(I - e_m)
      for (int l = 0; l <= 4; ++l)
        for (int j = 0; j <= 4 - l; ++j) {
          const int i = 4 - j - l;
          if (l == 0) continue;  // macro edge row: set above
          if (i == 4 || j == 4) continue;
          Vec3 q;
          if (i > 0) q += (i / 4.0) * c3[tri_index(3, j, l)];
          if (j > 0) q += (j / 4.0) * c3[tri_index(3, j - 1, l)];
          if (l > 0) q += (l / 4.0) * c3[tri_index(3, j, l - 1)];
          P[global_index(k, i, j, l)] = q;
        }
    }
  }

  if (!options.g1_corrections) return;

  // 3. G1 corrections across interior non-feature edges
  std::vector<std::array<Vec3, 6>> delta(nt);  // per triangle: d1, d2 of subtriangles 0..2
  std::vector<char> touched(nt, 0);
  for (int t = 0; t < nt; ++t) {
    if (mesh.is_deleted(Triangle(t))) continue;
    for (int k1 = 0; k1 < 3; ++k1) {
      const Corner e = SurfaceMesh::corner(Triangle(t), k1);
      const Corner o = mesh.opposite(e);
      if (!o.is_valid() || o < e || is_feature_edge(mesh, e)) continue;
      const int t2 = SurfaceMesh::triangle(o).idx;
      const int k2 = SurfaceMesh::local_index(o);
      Patch& PA = patches_[t];
      Patch& PB = patches_[t2];
      // boundary curve, canonical direction P -> Q
      const Vec3 b0 = PA[(k1 + 1) % 3], b3 = PA[(k1 + 2) % 3];
      Vec3 b1, b2;
      edge_cubic(e, b1, b2);
      const Vec3 c[5] = {b0, PA[edge_point(k1, 0)], PA[edge_point(k1, 1)], PA[edge_point(k1, 2)], b3};
      const Vec3 g0 = 3.0 * (b1 - b0), g1 = 3.0 * (b2 - b1), g2 = 3.0 * (b3 - b2);
      const Vec3& nP = frames.normal(SurfaceMesh::next(e));
      const Vec3& nQ = frames.normal(SurfaceMesh::prev(e));
      const Vec3 W0 = normalized(cross(nP, g0)), W1 = normalized(cross(nQ, g2));
      const double gg0 = norm2(g0), gg2 = norm2(g2);
      if (!(gg0 > 0) || !(gg2 > 0) || norm(W0) == 0 || norm(W1) == 0) continue;
      // rows next to the edge, in the canonical direction
      Vec3* rowA[4] = {&PA[inner_point((k1 + 1) % 3, 0)], &PA[d1_point(k1)], &PA[d2_point(k1)],
                       &PA[inner_point((k1 + 2) % 3, 0)]};
      Vec3* rowB[4] = {&PB[inner_point((k2 + 2) % 3, 0)], &PB[d2_point(k2)], &PB[d1_point(k2)],
                       &PB[inner_point((k2 + 1) % 3, 0)]};
      auto correct = [&](Vec3* row[4], Vec3& delta1, Vec3& delta2) {
        // cross-boundary vectors X_i = row_i - (c_i + c_{i+1}) / 2
        const Vec3 X0 = *row[0] - 0.5 * (c[0] + c[1]);
        const Vec3 X3 = *row[3] - 0.5 * (c[3] + c[4]);
        const double k0 = dot(X0, W0), h0 = dot(X0, g0) / gg0;
        const double k1v = dot(X3, W1), h1 = dot(X3, g2) / gg2;
        // D(t) = k(t) W(t) + h(t) Gamma'(t), k, h, W linear
        const Vec3 w0 = k0 * W0, w1 = 0.5 * (k0 * W1 + k1v * W0), w2 = k1v * W1;
        const Vec3 X1 = (w0 + 2.0 * w1) / 3.0 + (2.0 * h0 * g1 + h1 * g0) / 3.0;
        const Vec3 X2 = (2.0 * w1 + w2) / 3.0 + (h0 * g2 + 2.0 * h1 * g1) / 3.0;
        const Vec3 r1 = X1 + 0.5 * (c[1] + c[2]);
        const Vec3 r2 = X2 + 0.5 * (c[2] + c[3]);
        delta1 += r1 - *row[1];
        delta2 += r2 - *row[2];
        *row[1] = r1;
        *row[2] = r2;
      };
      correct(rowA, delta[t][2 * k1], delta[t][2 * k1 + 1]);
      correct(rowB, delta[t2][2 * k2 + 1], delta[t2][2 * k2]);
      touched[t] = touched[t2] = 1;
    }
  }

  // 4. inner points of the split from the Clough-Tocher C1 conditions across
  // the inner edges v_j -> centre (diamonds: the edge point nearer the centre
  // is the mean of its neighbour nearer v_j and the two points beside it).
  const double w = options.inner_correction_weight;
  for (int t = 0; t < nt; ++t) {
    if (!touched[t]) continue;
    Patch& P = patches_[t];
    for (int k = 0; k < 3; ++k) P[e_point(k)] += w * (delta[t][2 * k] + delta[t][2 * k + 1]);
    for (int j = 0; j < 3; ++j)
      P[inner_point(j, 1)] = (P[d1_point((j + 2) % 3)] + P[d2_point((j + 1) % 3)] + P[inner_point(j, 0)]) / 3.0;
    for (int j = 0; j < 3; ++j)
      P[inner_point(j, 2)] = (P[e_point((j + 2) % 3)] + P[e_point((j + 1) % 3)] + P[inner_point(j, 1)]) / 3.0;
    P[3] = (P[inner_point(0, 2)] + P[inner_point(1, 2)] + P[inner_point(2, 2)]) / 3.0;
  }
}

Vec3 BezierSurface::position(Triangle t, const Bary& b) const {
  const Local s = locate_sub(b);
  Vec3 lin[3];
  reduce_to_linear(patches_[t.idx], s, lin);
  return s.mu[0] * lin[0] + s.mu[1] * lin[1] + s.mu[2] * lin[2];
}

SurfacePoint BezierSurface::evaluate(Triangle t, const Bary& b) const {
  const Local s = locate_sub(b);
  Vec3 lin[3];
  reduce_to_linear(patches_[t.idx], s, lin);
  SurfacePoint r;
  r.position = s.mu[0] * lin[0] + s.mu[1] * lin[1] + s.mu[2] * lin[2];
  // macro directions (-1, 1, 0) and (-1, 0, 1) in the subtriangle's coordinates
  const int k = s.k, a = (k + 1) % 3, c = (k + 2) % 3;
  auto sub_dir = [&](const double dl[3]) {
    const double da = dl[a] - dl[k], db = dl[c] - dl[k], dg = 3.0 * dl[k];
    return 4.0 * (da * lin[0] + db * lin[1] + dg * lin[2]);
  };
  const double dir1[3] = {-1, 1, 0}, dir2[3] = {-1, 0, 1};
  r.d1 = sub_dir(dir1);
  r.d2 = sub_dir(dir2);
  r.normal = normalized(cross(r.d1, r.d2));
  return r;
}

}  // namespace anisurf
