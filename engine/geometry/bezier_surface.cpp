#include "geometry/bezier_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"

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


// The first point of the inner edge v_j -> centre, as the split computes it
// (both subtriangles beside the inner edge give the same expression): the
// elevation 3/4 f(v_j, v_j, G) + 1/4 f(v_j, v_j, v_j) of the blossom of the
// macro cubic, f(v_j, v_j, G) the mean of the cubic points (2 e_j + e_s),
// s = 0, 1, 2, summed in blossom3's order. v: the vertices, E[k]: the cubic
// points of the side opposite v_k, from v_{k+1}.
Vec3 inner_edge_start(const Vec3 v[3], const Vec3 E[3][2], int j) {
  const double g = 1.0 / 3.0;
  // cubic points 2 e_j + e_s for s = 0, 1, 2
  const Vec3* c[3][3] = {{&v[0], &E[2][0], &E[1][1]}, {&E[2][1], &v[1], &E[0][0]}, {&E[1][0], &E[0][1], &v[2]}};
  Vec3 f2g, f3;
  for (int s = 0; s < 3; ++s) f2g += (1.0 * 1.0 * g) * *c[j][s];
  f3 += (1.0 * 1.0 * 1.0) * v[j];
  Vec3 q;
  q += 0.75 * f2g;
  q += 0.25 * f3;
  return q;
}

// Global index <-> slot of the points stored per triangle (see the header).
constexpr int kStoredIdx[BezierSurface::kStoredPoints] = {22, 23, 24, 25, 26, 27, 28, 29, 30};
constexpr int kDerivedIdx[BezierSurface::kDerivedPoints] = {3, 14, 15, 17, 18, 20, 21};
constexpr int stored_slot(int g) { return g - 22; }  // pre: g in kStoredIdx

// Step 4: the centre and inner-edge points of a corrected triangle from the
// Clough-Tocher C1 conditions across the inner edges v_j -> centre (diamonds:
// the edge point nearer the centre is the mean of its neighbour nearer v_j and
// the two points beside it).
void apply_c1_conditions(BezierSurface::Patch& P) {
  for (int j = 0; j < 3; ++j)
    P[inner_point(j, 1)] = (P[d1_point((j + 2) % 3)] + P[d2_point((j + 1) % 3)] + P[inner_point(j, 0)]) / 3.0;
  for (int j = 0; j < 3; ++j)
    P[inner_point(j, 2)] = (P[e_point((j + 2) % 3)] + P[e_point((j + 1) % 3)] + P[inner_point(j, 1)]) / 3.0;
  P[3] = (P[inner_point(0, 2)] + P[inner_point(1, 2)] + P[inner_point(2, 2)]) / 3.0;
}

}  // namespace

// Section 3, storage: vertices copied, one id per edge (its canonical corner).
void BezierSurface::index_mesh(const SurfaceMesh& mesh) {
  const int nt = mesh.triangle_capacity();
  vertex_.resize(mesh.vertex_capacity());
  for (int v = 0; v < mesh.vertex_capacity(); ++v) vertex_[v] = mesh.position(Vertex(v));
  macro_.assign(nt, Macro{});
  int n_edges = 0;
  for (Corner c : mesh.edges()) macro_[SurfaceMesh::triangle(c).idx].edge[SurfaceMesh::local_index(c)] = n_edges++;
  for (Triangle t : mesh.triangles()) {
    Macro& macro = macro_[t.idx];
    for (int k = 0; k < 3; ++k) {
      macro.vertex[k] = mesh.vertex(t, k).idx;
      const Corner c = SurfaceMesh::corner(t, k), e = mesh.canonical(c);
      if (e != c) macro.edge[k] = ~macro_[SurfaceMesh::triangle(e).idx].edge[SurfaceMesh::local_index(e)];
    }
  }
  edge_.assign(n_edges, {});
}

// Section 3, step 1: the cubic edge control points, once per edge, in the
// tangent planes of the end vertices (or along the feature curve tangents).
void BezierSurface::build_edges(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options) {
  // Each edge's points on their own (parallel chunks of the edges).
  std::vector<Corner> edges;
  for (Corner e : mesh.edges()) edges.push_back(e);
  const int ne = static_cast<int>(edges.size());
  run_chunks(ne, chunk_count(ne, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Corner e = edges[static_cast<std::size_t>(i)];
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
      const int id = macro_[SurfaceMesh::triangle(e).idx].edge[SurfaceMesh::local_index(e)];
      edge_[id] = {a + handle(b - a, da, options.handle), b + handle(a - b, db, options.handle)};
    }
  });
}

// Cubic points of the side opposite vertex k, from vertex k+1 to vertex k+2.
void BezierSurface::edge_cubic(const Macro& m, int k, Vec3& p1, Vec3& p2) const {
  const int e = m.edge[k];
  if (e >= 0) {
    p1 = edge_[e][0];
    p2 = edge_[e][1];
  } else {
    p1 = edge_[~e][1];
    p2 = edge_[~e][0];
  }
}

// The shared points of a patch: vertices and the quartic points of the macro
// edges (degree elevation of the cubic edge: bitwise equal on both sides).
void BezierSurface::fill_shared(const Macro& m, Patch& P) const {
  for (int k = 0; k < 3; ++k) P[k] = vertex_[m.vertex[k]];
  Vec3 E[3][2];
  for (int k = 0; k < 3; ++k) {
    edge_cubic(m, k, E[k][0], E[k][1]);
    const Vec3& A = P[(k + 1) % 3];
    const Vec3& B = P[(k + 2) % 3];
    P[edge_point(k, 0)] = (A + 3.0 * E[k][0]) * 0.25;
    P[edge_point(k, 1)] = (E[k][0] + E[k][1]) * 0.5;
    P[edge_point(k, 2)] = (3.0 * E[k][1] + B) * 0.25;
  }
  const Vec3 v[3] = {P[0], P[1], P[2]};
  for (int j = 0; j < 3; ++j) P[inner_point(j, 0)] = inner_edge_start(v, E, j);
}

// Section 3, steps 1-2: the control net of the macro cubic (vertices, edge
// points, centre by the report's formula), from P's vertices.
void BezierSurface::cubic_net(const Macro& m, const Patch& P, Vec3 b[10]) const {
  const Vec3 v[3] = {P[0], P[1], P[2]};
  b[cubic_index(0, 0)] = v[0];
  b[cubic_index(3, 0)] = v[1];
  b[cubic_index(0, 3)] = v[2];
  Vec3 sum_edges;
  Vec3 E[3][2];
  for (int k = 0; k < 3; ++k) {
    edge_cubic(m, k, E[k][0], E[k][1]);
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
}

// Section 3, steps 2-3: the cubic patch of triangle t, split at the
// barycentre and elevated to 3 quartics (31 points).
BezierSurface::Patch BezierSurface::elevated_patch(int t) const {
  const Macro& m = macro_[t];
  Patch P{};
  fill_shared(m, P);
  const double g3[3] = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  Vec3 b[10];
  cubic_net(m, P, b);
  // The blossoms shared by the subtriangles (the same arguments in the same
  // order give the same values): f(G, G, G), f(e_j, G, G), f(e_j, e_j, G).
  const double unit[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Vec3 fGGG = blossom3(b, g3, g3, g3);
  Vec3 fEGG[3], fEEG[3];
  for (int j = 0; j < 3; ++j) {
    fEGG[j] = blossom3(b, unit[j], g3, g3);
    fEEG[j] = blossom3(b, unit[j], unit[j], g3);
  }
  // the other points: elevated blossoms of the cubic over each subtriangle
  for (int k = 0; k < 3; ++k) {
    const int ia = (k + 1) % 3, ib = (k + 2) % 3;
    const double* pts[3] = {unit[ia], unit[ib], g3};
    // cubic subpatch c3(i, j, l) = f(A^i, B^j, G^l), A = e_ia, B = e_ib
    Vec3 c3[10];
    for (int l = 0; l <= 3; ++l)
      for (int j = 0; j <= 3 - l; ++j) {
        const int i = 3 - j - l;
        Vec3& c = c3[tri_index(3, j, l)];
        if (l == 3) {
          c = fGGG;
        } else if (l == 2) {
          c = fEGG[i == 1 ? ia : ib];
        } else if (l == 1 && i != 1) {
          c = fEEG[i == 2 ? ia : ib];
        } else {
          const double* args[3] = {nullptr, nullptr, nullptr};
          int n = 0;
          for (int r = 0; r < i; ++r) args[n++] = pts[0];
          for (int r = 0; r < j; ++r) args[n++] = pts[1];
          for (int r = 0; r < l; ++r) args[n++] = pts[2];
          c = blossom3(b, args[0], args[1], args[2]);
        }
      }
    // degree elevation: c4(I) = sum_m I_m / 4 c3(I - e_m)
    for (int l = 0; l <= 4; ++l)
      for (int j = 0; j <= 4 - l; ++j) {
        const int i = 4 - j - l;
        if (l == 0) continue;  // macro edge row: shared points
        if (i == 4 || j == 4) continue;
        Vec3 q;
        if (i > 0) q += (i / 4.0) * c3[tri_index(3, j, l)];
        if (j > 0) q += (j / 4.0) * c3[tri_index(3, j - 1, l)];
        if (l > 0) q += (l / 4.0) * c3[tri_index(3, j, l - 1)];
        P[global_index(k, i, j, l)] = q;
      }
  }
  return P;
}

BezierSurface::BezierSurface(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options) {
  index_mesh(mesh);
  build_edges(mesh, frames, options);
  const int nt = mesh.triangle_capacity();
  // The elevated patches (each from its own triangle's data: in parallel
  // chunks), their stored points and, until the G1 corrections tell which
  // triangles keep them, their derived points.
  stored_.assign(nt, {});
  std::vector<std::array<Vec3, kDerivedPoints>> elevated_derived(static_cast<std::size_t>(nt));
  run_chunks(nt, chunk_count(nt, 8192), [&](int, int begin, int end) {
    for (int t = begin; t < end; ++t) {
      if (macro_[t].vertex[0] < 0) continue;
      const Patch P = elevated_patch(t);
      for (int i = 0; i < kStoredPoints; ++i) stored_[t][i] = P[kStoredIdx[i]];
      for (int i = 0; i < kDerivedPoints; ++i) elevated_derived[t][i] = P[kDerivedIdx[i]];
    }
  });
  const std::vector<char> corrected =
      options.g1_corrections ? correct_g1(mesh, frames, options) : std::vector<char>(nt, 0);
  // the triangles left as elevated keep their own centre and inner-edge points
  for (int t = 0; t < nt; ++t) {
    if (macro_[t].vertex[0] < 0 || corrected[t]) continue;
    macro_[t].derived = static_cast<int>(derived_.size());
    derived_.push_back(elevated_derived[t]);
  }
  derived_.shrink_to_fit();
}

// Section 3, step 4: G1 corrections across interior non-feature edges; the
// free inner point of each subtriangle moves by the weighted sum of the
// corrections of its two points next to the macro edge. Returns the
// triangles corrected (their centre and inner-edge points then follow from
// the C1 conditions).
std::vector<char> BezierSurface::correct_g1(const SurfaceMesh& mesh, const SurfaceFrames& frames,
                                            const BezierOptions& options) {
  const int nt = mesh.triangle_capacity();
  const double w = options.inner_correction_weight;
  // Each macro edge moves only its own points of its two triangles (d1, d2
  // and e of its side): the edges are corrected in parallel chunks, each
  // once (from its smaller corner), then the triangles of the corrected
  // ones are marked.
  std::vector<Corner> edges;
  for (Triangle tri : mesh.triangles())
    for (int k1 = 0; k1 < 3; ++k1) {
      const Corner e = SurfaceMesh::corner(tri, k1);
      const Corner o = mesh.opposite(e);
      if (o.is_valid() && e < o && !is_feature_edge(mesh, e)) edges.push_back(e);
    }
  std::vector<char> corrected(edges.size(), 0);
  const int ne = static_cast<int>(edges.size());
  run_chunks(ne, chunk_count(ne, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Corner e = edges[static_cast<std::size_t>(i)];
      const Corner o = mesh.opposite(e);
      const int t = SurfaceMesh::triangle(e).idx;
      const int k1 = SurfaceMesh::local_index(e);
      const int t2 = SurfaceMesh::triangle(o).idx;
      const int k2 = SurfaceMesh::local_index(o);
      Patch shared{}, shared2{};
      fill_shared(macro_[t], shared);
      fill_shared(macro_[t2], shared2);
      // boundary curve, canonical direction P -> Q
      const Vec3 b0 = shared[(k1 + 1) % 3], b3 = shared[(k1 + 2) % 3];
      Vec3 b1, b2;
      edge_cubic(macro_[t], k1, b1, b2);
      const Vec3 c[5] = {b0, shared[edge_point(k1, 0)], shared[edge_point(k1, 1)], shared[edge_point(k1, 2)], b3};
      const Vec3 g0 = 3.0 * (b1 - b0), g1 = 3.0 * (b2 - b1), g2 = 3.0 * (b3 - b2);
      const Vec3& nP = frames.normal(SurfaceMesh::next(e));
      const Vec3& nQ = frames.normal(SurfaceMesh::prev(e));
      const Vec3 W0 = normalized(cross(nP, g0)), W1 = normalized(cross(nQ, g2));
      const double gg0 = norm2(g0), gg2 = norm2(g2);
      if (!(gg0 > 0) || !(gg2 > 0) || norm(W0) == 0 || norm(W1) == 0) continue;
      auto& SA = stored_[t];
      auto& SB = stored_[t2];
      // rows next to the edge, in the canonical direction
      Vec3* rowA[4] = {&shared[inner_point((k1 + 1) % 3, 0)], &SA[stored_slot(d1_point(k1))],
                       &SA[stored_slot(d2_point(k1))], &shared[inner_point((k1 + 2) % 3, 0)]};
      Vec3* rowB[4] = {&shared2[inner_point((k2 + 2) % 3, 0)], &SB[stored_slot(d2_point(k2))],
                       &SB[stored_slot(d1_point(k2))], &shared2[inner_point((k2 + 1) % 3, 0)]};
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
      // each macro edge is corrected once: its free inner point moves now
      Vec3 dA1, dA2, dB1, dB2;  // corrections of points d1, d2 of each side
      correct(rowA, dA1, dA2);
      correct(rowB, dB2, dB1);
      SA[stored_slot(e_point(k1))] += w * (dA1 + dA2);
      SB[stored_slot(e_point(k2))] += w * (dB1 + dB2);
      corrected[static_cast<std::size_t>(i)] = 1;
    }
  });
  std::vector<char> touched(nt, 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!corrected[i]) continue;
    touched[SurfaceMesh::triangle(edges[i]).idx] = 1;
    touched[SurfaceMesh::triangle(mesh.opposite(edges[i])).idx] = 1;
  }
  return touched;
}

BezierSurface::Patch BezierSurface::patch(Triangle t) const {
  Patch P{};
  const Macro& m = macro_[t.idx];
  if (m.vertex[0] < 0) return P;
  fill_shared(m, P);
  const auto& S = stored_[t.idx];
  for (int i = 0; i < kStoredPoints; ++i) P[kStoredIdx[i]] = S[i];
  if (m.derived < 0) {
    apply_c1_conditions(P);
  } else {
    for (int i = 0; i < kDerivedPoints; ++i) P[kDerivedIdx[i]] = derived_[m.derived][i];
  }
  return P;
}

double BezierSurface::flat_deviation(Triangle t, const std::array<Vec3, 3>& corners) const {
  const Patch P = patch(t);
  const Vec3 centre = (corners[0] + corners[1] + corners[2]) / 3.0;
  double worst2 = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3& A = corners[(k + 1) % 3];
    const Vec3& B = corners[(k + 2) % 3];
    for (int l = 0; l <= 4; ++l)
      for (int j = 0; j <= 4 - l; ++j) {
        const int i = 4 - j - l;
        const Vec3 flat = (i * A + j * B + l * centre) * 0.25;
        worst2 = std::max(worst2, norm2(P[global_index(k, i, j, l)] - flat));
      }
  }
  // Plus the rounding of an evaluation (de Casteljau's convex combinations
  // at the corners' magnitude).
  const double magnitude = std::max({norm(corners[0]), norm(corners[1]), norm(corners[2])});
  return std::sqrt(worst2) + 64 * std::numeric_limits<double>::epsilon() * magnitude;
}

Vec3 BezierSurface::position(Triangle t, const Bary& b) const {
  const Local s = locate_sub(b);
  Vec3 lin[3];
  reduce_to_linear(patch(t), s, lin);
  return s.mu[0] * lin[0] + s.mu[1] * lin[1] + s.mu[2] * lin[2];
}

SurfacePoint BezierSurface::evaluate(Triangle t, const Bary& b) const { return evaluate(patch(t), b); }

SurfacePoint BezierSurface::evaluate(const Patch& P, const Bary& b) {
  const Local s = locate_sub(b);
  Vec3 lin[3];
  reduce_to_linear(P, s, lin);
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
