#include "geometry/normals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "geometry/pivoted_qr.h"
#include "geometry/symmetric_cg.h"

namespace anisurf {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Orthonormal (t1, t2) with t1 x t2 = n for a unit n.
void frame_of(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 a = std::fabs(n.x) < 0.6 ? Vec3(1, 0, 0) : (std::fabs(n.y) < 0.6 ? Vec3(0, 1, 0) : Vec3(0, 0, 1));
  t1 = normalized(cross(a, n));
  t2 = cross(n, t1);
}

double corner_angle(const SurfaceMesh& mesh, Corner c) {
  const Vec3& p = mesh.position(mesh.vertex(c));
  const Vec3 a = mesh.position(mesh.vertex(SurfaceMesh::next(c))) - p;
  const Vec3 b = mesh.position(mesh.vertex(SurfaceMesh::prev(c))) - p;
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

// Least-squares height-function fit; returns false when ill-posed.
class LocalFit {
 public:
  explicit LocalFit(const SurfaceMesh& mesh)
      : mesh_(mesh), tri_mark_(mesh.triangle_capacity(), 0), vert_mark_(mesh.vertex_capacity(), 0) {}

  // Points of the sector's neighbourhood (relative to the vertex).
  const std::vector<Vec3>& gather(Vertex v, const std::vector<Corner>& sector) {
    points_.clear();
    tris_.clear();
    ring1_.clear();
    // ring 1: vertices of the sector's triangles
    for (Corner c : sector) visit_tri(SurfaceMesh::triangle(c));
    for (Triangle t : tris_)
      for (int k = 0; k < 3; ++k) mark_vertex(mesh_.vertex(t, k), v, &ring1_);
    // ring 2: triangles around ring-1 vertices reached without crossing a
    // feature edge (a flood over their fans from the sector)
    std::size_t head = 0;
    while (head < tris_.size()) {
      const Triangle t = tris_[head++];
      for (int k = 0; k < 3; ++k) {
        const Corner c = SurfaceMesh::corner(t, k);
        if (is_feature_edge(mesh_, c)) continue;
        const Triangle n = SurfaceMesh::triangle(mesh_.opposite(c));
        if (tri_mark_[n.idx]) continue;
        bool near = false;
        for (int j = 0; j < 3 && !near; ++j) {
          const Vertex w = mesh_.vertex(n, j);
          near = w == v || ring1_mark(w);
        }
        if (near) visit_tri(n);
      }
    }
    for (Triangle t : tris_)
      for (int k = 0; k < 3; ++k) mark_vertex(mesh_.vertex(t, k), v, nullptr);
    // reset marks
    for (Triangle t : tris_) tri_mark_[t.idx] = 0;
    for (Vertex w : verts_) vert_mark_[w.idx] = 0;
    verts_.clear();
    return points_;
  }

  // Normal of the height function fitted in the frame of n0 through the
  // origin, or zero if ill-posed (rank below the unknowns' count: a pivot of
  // the least-squares QR at most 1e-8 of the largest).
  Vec3 fit(const std::vector<Vec3>& pts, const Vec3& n0, int degree) {
    const int m = static_cast<int>(pts.size());
    const int k = degree == 3 ? 9 : 5;
    if (m < k) return {};
    Vec3 t1, t2;
    frame_of(n0, t1, t2);
    double h = 0;
    for (const Vec3& p : pts) h += norm(p);
    h /= m;
    if (!(h > 0)) return {};
    // The system by columns: A(i, j) at a_[j * m + i].
    a_.assign(static_cast<std::size_t>(m) * k, 0.0);
    z_.resize(static_cast<std::size_t>(m));
    auto A = [&](int i, int j) -> double& { return a_[static_cast<std::size_t>(j) * m + i]; };
    for (int i = 0; i < m; ++i) {
      const double x = dot(pts[i], t1) / h, y = dot(pts[i], t2) / h;
      z_[static_cast<std::size_t>(i)] = dot(pts[i], n0) / h;
      A(i, 0) = x;
      A(i, 1) = y;
      A(i, 2) = x * x;
      A(i, 3) = x * y;
      A(i, 4) = y * y;
      if (k == 9) {
        A(i, 5) = x * x * x;
        A(i, 6) = x * x * y;
        A(i, 7) = x * y * y;
        A(i, 8) = y * y * y;
      }
    }
    std::array<double, PivotedQR::kMaxColumns> c{};
    if (!solve_full_rank_least_squares(qr_, a_.data(), m, k, z_.data(), c.data(), 1e-8)) return {};
    // z = c0 x + c1 y + ... : the normal is (-c0, -c1, 1) in the frame
    return normalized(n0 - c[0] * t1 - c[1] * t2);
  }

 private:
  void visit_tri(Triangle t) {
    if (tri_mark_[t.idx]) return;
    tri_mark_[t.idx] = 1;
    tris_.push_back(t);
  }
  bool ring1_mark(Vertex w) const { return (vert_mark_[w.idx] & 2) != 0; }
  void mark_vertex(Vertex w, Vertex center, std::vector<Vertex>* ring1) {
    if (w == center) return;
    if (ring1) {
      if (vert_mark_[w.idx] & 2) return;
      if (!vert_mark_[w.idx]) verts_.push_back(w);
      vert_mark_[w.idx] |= 2;
      ring1->push_back(w);
      return;
    }
    if (vert_mark_[w.idx] & 1) return;
    if (!vert_mark_[w.idx]) verts_.push_back(w);
    vert_mark_[w.idx] |= 1;
    points_.push_back(mesh_.position(w) - mesh_.position(center));
  }

  const SurfaceMesh& mesh_;
  std::vector<char> tri_mark_, vert_mark_;
  std::vector<Triangle> tris_;
  std::vector<Vertex> ring1_, verts_;
  std::vector<Vec3> points_;
  // The least-squares system of fit(), reused from one fit to the next.
  std::vector<double> a_, z_;
  PivotedQR qr_;
};

// Tangent line at a regular curve vertex v between curve neighbours a and b,
// oriented towards b. curve_tangent (the circle tangent, or the turn shared
// by the edges' lengths where they are very unequal) turns the chord v->b by alpha and
// v->a by beta = turn - alpha, in the plane of the chords; turning a chord
// past a thin triangle beside it would fold the patch there. So alpha is
// kept where, for every triangle (v, w, x) beside either curve edge, the
// turned direction stays on x's side of the chord by at least `room` times
// the chord's own margin (measured in the triangle's plane): the feasible
// alpha nearest to the circle's, or the circle's when none fits.
Vec3 safe_curve_tangent(const SurfaceMesh& mesh, Vertex v, const FeatureEdgeAt& ea, const FeatureEdgeAt& eb,
                        const NormalOptions& options) {
  const double room = options.tangent_room;
  const Vec3& p = mesh.position(v);
  const Vec3 ua = normalized(mesh.position(ea.other) - p), ub = normalized(mesh.position(eb.other) - p);
  const Vec3 t = curve_tangent(mesh.position(ea.other), p, mesh.position(eb.other), options.tangent_circle_ratio,
                               options.tangent_even_ratio);
  const double turn = std::numbers::pi - vector_angle(ua, ub);
  if (turn < 1e-9) return t;
  const Vec3 wb = normalized(-ua - dot(-ua, ub) * ub);  // ub turns towards wb
  const Vec3 wa = normalized(-ub - dot(-ub, ua) * ua);  // ua turns towards wa
  // direction turned from u by angle g towards w, for the triangles beside
  // the edge: cos g + sin g D_w / D_u >= room, D_q = det[q, x - v, n_T]
  struct Side {
    double ratio;  // D_w / D_u
  };
  auto sides = [&](const FeatureEdgeAt& e, const Vec3& u, const Vec3& w) {
    std::vector<Side> out;
    for (Corner c : {e.edge, mesh.opposite(e.edge)}) {
      if (!c.is_valid()) continue;
      const Triangle tri = SurfaceMesh::triangle(c);
      const Vec3 nt = normalized(mesh.triangle_normal(tri));
      const Vec3 x = mesh.position(mesh.vertex(c)) - p;  // c is opposite the edge: its vertex is the third one
      const double du = dot(cross(u, x), nt), dw = dot(cross(w, x), nt);
      if (du == 0) continue;
      out.push_back({dw / du});
    }
    return out;
  };
  const auto sb = sides(eb, ub, wb), sa = sides(ea, ua, wa);
  auto ok = [&](double alpha) {
    const double beta = turn - alpha;
    for (const Side& s : sb)
      if (std::cos(alpha) + std::sin(alpha) * s.ratio < room) return false;
    for (const Side& s : sa)
      if (std::cos(beta) + std::sin(beta) * s.ratio < room) return false;
    return true;
  };
  const double alpha_c = vector_angle(t, ub);
  if (ok(alpha_c)) return t;
  const int steps = 64;
  double best = -1;
  for (int i = 0; i <= steps; ++i) {
    const double alpha = turn * i / steps;
    if (ok(alpha) && (best < 0 || std::fabs(alpha - alpha_c) < std::fabs(best - alpha_c))) best = alpha;
  }
  // no turn fits (the curve bends out of the surface beside slivers): keep
  // curve_tangent's; the sector planes turn about it instead (step 3c)
  if (best < 0) return t;
  return normalized(std::cos(best) * ub + std::sin(best) * wb);
}

// The unit normal nearest to n whose plane contains the unit tangents ts
// (two independent ones fix it; one leaves a turn about it), oriented like n.
Vec3 plane_containing(const std::vector<Vec3>& ts, const Vec3& n) {
  Vec3 best;
  for (std::size_t i = 0; i < ts.size(); ++i)
    for (std::size_t j = i + 1; j < ts.size(); ++j) {
      const Vec3 c = cross(ts[i], ts[j]);
      if (norm(c) > norm(best)) best = c;
    }
  if (norm(best) > std::sin(10 * kDeg)) return normalized(dot(best, n) >= 0 ? best : -best);
  Vec3 m = n;
  for (const Vec3& t : ts) m = m - dot(m, t) * t;
  return norm(m) > 0 ? normalized(m) : n;
}

// A sector's normal as step 2 of compute_frames estimates it, and where it
// came from.
struct SectorEstimate {
  enum class Source : char { AngleWeighted, Fitted, File };
  Vec3 n;
  Source source = Source::AngleWeighted;
};

// Step 2 for one sector of v: the angle-weighted normal of its triangles;
// the file's normal `file` (oriented like it) when given; else the local
// fit's normal when it is within max_fit_deviation_deg of it.
SectorEstimate estimate_sector_normal(const SurfaceMesh& mesh, Vertex v, const std::vector<Corner>& sector,
                                      const Vec3* file, const NormalOptions& options, LocalFit& fitter) {
  Vec3 n;
  for (Corner c : sector) n += corner_angle(mesh, c) * normalized(mesh.triangle_normal(SurfaceMesh::triangle(c)));
  n = normalized(n);
  if (file) {
    const Vec3 fn = normalized(*file);
    return {dot(fn, n) >= 0 ? fn : -fn, SectorEstimate::Source::File};
  }
  if (options.method == NormalOptions::Method::LocalFit && norm(n) > 0) {
    const std::vector<Vec3>& pts = fitter.gather(v, sector);
    const int degree = (options.cubic_min_points > 0 && static_cast<int>(pts.size()) >= options.cubic_min_points) ? 3 : 2;
    Vec3 fit = n;
    for (int it = 0; it <= options.fit_iterations; ++it) {
      const Vec3 next = fitter.fit(pts, fit, degree);
      if (norm(next) == 0) {
        fit = Vec3();
        break;
      }
      fit = next;
    }
    if (norm(fit) > 0 && vector_angle(fit, n) < options.max_fit_deviation_deg * kDeg) return {fit, SectorEstimate::Source::Fitted};
  }
  return {n, SectorEstimate::Source::AngleWeighted};
}

// One edge of a triangle, from corner cv to corner cw (the next one), as
// the mirror system (compute_frames, step 3) sees it.
struct MirrorEdge {
  Corner cv, cw;
};

// The edges of the triangles of a sector's corners that end at its vertex:
// each corner's next edge and its previous one.
template <class Visit>
void for_sector_edges(const std::vector<Corner>& sector, Visit visit) {
  for (Corner c : sector) {
    visit(MirrorEdge{c, SurfaceMesh::next(c)});
    visit(MirrorEdge{SurfaceMesh::prev(c), c});
  }
}

// The mirror system's unknowns and the structure of its matrix: the
// unknowns of the sectors at both ends of every edge of positive length are
// coupled (explicit zeros included), one column per unknown with sorted
// rows. Columns are built and filled per sector in parallel: a sector's
// columns gather the edges of its own corners, so no two chunks write the
// same value.
class MirrorSystem {
 public:
  MirrorSystem(const SurfaceMesh& mesh, const std::vector<int>& corner_sector, const std::vector<int>& movable,
               const std::vector<std::vector<Corner>>& members, int n_sectors, const std::vector<Vec3>& axis)
      : first_unknown(n_sectors, -1), n_unknowns(n_sectors, 0) {
    int nu = 0;
    for (std::size_t i = 0; i < movable.size(); ++i) {
      const int s = movable[i];
      first_unknown[s] = nu;
      n_unknowns[s] = norm(axis[i]) > 0 ? 1 : 2;
      nu += n_unknowns[s];
    }
    A.n = nu;
    A.outer.assign(static_cast<std::size_t>(nu) + 1, 0);
    const int nm = static_cast<int>(movable.size());
    const int chunks = chunk_count(nm, 4096);
    // rows per column, then the running sum, then the rows themselves
    run_chunks(nm, chunks, [&](int, int begin, int end) {
      std::vector<int> coupled;
      for (int i = begin; i < end; ++i) {
        coupled_sectors(mesh, corner_sector, members[i], coupled);
        int rows = 0;
        for (int t : coupled) rows += n_unknowns[t];
        const int s = movable[i];
        for (int k = 0; k < n_unknowns[s]; ++k) A.outer[first_unknown[s] + k + 1] = rows;
      }
    });
    for (int u = 0; u < nu; ++u) A.outer[u + 1] += A.outer[u];
    A.inner.resize(static_cast<std::size_t>(A.outer[nu]));
    A.value.assign(A.inner.size(), -0.0);
    run_chunks(nm, chunks, [&](int, int begin, int end) {
      std::vector<int> coupled;
      for (int i = begin; i < end; ++i) {
        coupled_sectors(mesh, corner_sector, members[i], coupled);
        const int s = movable[i];
        for (int k = 0; k < n_unknowns[s]; ++k) {
          int* row = A.inner.data() + A.outer[first_unknown[s] + k];
          for (int t : coupled)
            for (int m = 0; m < n_unknowns[t]; ++m) *row++ = first_unknown[t] + m;
        }
      }
    });
  }

  std::vector<int> first_unknown, n_unknowns;  // per sector (-1, 0: none)
  SymmetricColumns A;

 private:
  // The sorted sectors with unknowns coupled to the sector of `sector`'s
  // corners (itself included when one of its edges has positive length).
  void coupled_sectors(const SurfaceMesh& mesh, const std::vector<int>& corner_sector,
                       const std::vector<Corner>& sector, std::vector<int>& out) const {
    out.clear();
    for_sector_edges(sector, [&](const MirrorEdge& e) {
      const Vec3 d = mesh.position(mesh.vertex(e.cw)) - mesh.position(mesh.vertex(e.cv));
      if (!(norm2(d) > 0)) return;
      for (Corner c : {e.cv, e.cw})
        if (first_unknown[corner_sector[c.idx]] >= 0) out.push_back(corner_sector[c.idx]);
    });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
};

}  // namespace

Vec3 circle_tangent(const Vec3& a, const Vec3& v, const Vec3& b) {
  // With e1 = v - a, e2 = b - v: t ~ |e2|/|e1| e1 + |e1|/|e2| e2 (the
  // tangent makes the inscribed angles with both chords).
  const Vec3 e1 = v - a, e2 = b - v;
  const double l1 = norm(e1), l2 = norm(e2);
  if (!(l1 > 0) || !(l2 > 0)) return normalized(b - a);
  return normalized(e1 * (l2 / l1) + e2 * (l1 / l2));
}

Vec3 curve_tangent(const Vec3& a, const Vec3& v, const Vec3& b, double circle_ratio, double even_ratio) {
  // t ~ w1 e1 / l1 + w2 e2 / l2 turns off edge i by about turn x w_j / (w1 + w2):
  // the circle's weights (w1, w2) = (l2, l1) turn it off each edge in
  // proportion to that edge's length, (l1, l2) in inverse proportion;
  // w1 = l1^s l2^(1-s), w2 = l2^s l1^(1-s) blends them (s from 0 to 1).
  const Vec3 e1 = v - a, e2 = b - v;
  const double l1 = norm(e1), l2 = norm(e2);
  if (!(l1 > 0) || !(l2 > 0)) return normalized(b - a);
  const double ratio = std::max(l1, l2) / std::min(l1, l2);
  const double s = even_ratio > circle_ratio
                       ? std::clamp((ratio - circle_ratio) / (even_ratio - circle_ratio), 0.0, 1.0)
                       : (ratio > circle_ratio ? 1.0 : 0.0);
  if (s == 0) return circle_tangent(a, v, b);
  const double w1 = std::pow(l1, s) * std::pow(l2, 1 - s), w2 = std::pow(l2, s) * std::pow(l1, 1 - s);
  return normalized(e1 * (w1 / l1) + e2 * (w2 / l2));
}

SurfaceFrames compute_frames(const SurfaceMesh& mesh, const NormalOptions& options) {
  SurfaceFrames f;
  const int nc = mesh.corner_capacity();
  f.corner_sector_.assign(nc, -1);
  f.tangent_slot_.assign(nc, -1);
  for (Triangle t : mesh.triangles())
    for (int q = 0; q < 3; ++q) {
      const Corner c = SurfaceMesh::corner(t, q);
      if (!is_feature_edge(mesh, c)) continue;
      f.tangent_slot_[c.idx] = static_cast<int>(f.tangent_.size());
      f.tangent_.push_back({Vec3(), Vec3()});
    }

  // 1. feature-curve tangents. Regular curve vertices (exactly two feature
  // edges, not corners) get the circle tangent through their two curve
  // neighbours; an end at a corner reflects the tangent of the other end
  // about the chord (the same circle arc), or takes the chord itself.
  std::vector<Vec3> line(mesh.vertex_capacity());
  std::vector<char> regular(mesh.vertex_capacity(), 0);
  for (Vertex vh : mesh.vertices()) {
    if (mesh.is_isolated(vh) || mesh.has_tag(vh, kCorner)) continue;
    const auto fe = feature_edges_at(mesh, vh);
    if (fe.size() != 2) continue;
    const Vec3 t = safe_curve_tangent(mesh, vh, fe[0], fe[1], options);
    regular[vh.idx] = 1;
    line[vh.idx] = t;
  }
  auto end_tangent = [&](Vertex a, Vertex b) {
    const Vec3 chord = normalized(mesh.position(b) - mesh.position(a));
    if (regular[a.idx]) return dot(line[a.idx], chord) >= 0 ? line[a.idx] : -line[a.idx];
    if (regular[b.idx]) {
      const Vec3 tb = dot(line[b.idx], chord) >= 0 ? line[b.idx] : -line[b.idx];
      return normalized(2.0 * dot(tb, chord) * chord - tb);
    }
    return chord;
  };
  // the two end tangents of the feature edge of corner e
  auto set_feature_tangents = [&](Corner e) {
    const Vertex a = mesh.edge_from(e), b = mesh.edge_to(e);
    const Corner o = mesh.opposite(e);
    if (o.is_valid() && o < e) {
      // the same curve seen from the other side: reuse it (exactly equal)
      f.tangent(e.idx, 0) = f.tangent(o.idx, 1);
      f.tangent(e.idx, 1) = f.tangent(o.idx, 0);
      return;
    }
    f.tangent(e.idx, 0) = end_tangent(a, b);
    f.tangent(e.idx, 1) = end_tangent(b, a);
  };
  for (Triangle t : mesh.triangles())
    for (int q = 0; q < 3; ++q) {
      const Corner e = SurfaceMesh::corner(t, q);
      if (is_feature_edge(mesh, e)) set_feature_tangents(e);
    }

  // 2. sector normals
  auto file_normal = mesh.get_vertex_property<Vec3>("normal");
  auto has_file_normal = mesh.get_vertex_property<std::uint8_t>("has_normal");
  const bool file_normals = options.use_file_normals && file_normal && has_file_normal;
  // sectors whose normal may still turn about a curve tangent
  std::vector<int> movable;
  std::vector<Vec3> axis, estimate;
  std::vector<std::vector<Corner>> members;

  // The estimates (every one from its own sector: vertices in parallel
  // chunks), then the sectors in vertex order.
  const int nv = mesh.vertex_capacity();
  const int chunks = chunk_count(nv, 4096);
  std::vector<std::vector<SectorEstimate>> estimates(static_cast<std::size_t>(chunks));
  run_chunks(nv, chunks, [&](int c, int begin, int end) {
    LocalFit fitter(mesh);
    std::vector<SectorEstimate>& out = estimates[static_cast<std::size_t>(c)];
    for (int i = begin; i < end; ++i) {
      const Vertex vh(i);
      if (mesh.is_deleted(vh) || mesh.is_isolated(vh)) continue;
      const auto sectors = smooth_sectors(mesh, vh);
      const Vec3* file = file_normals && sectors.size() == 1 && has_file_normal[vh] && norm(file_normal[vh]) > 0
                             ? &file_normal[vh]
                             : nullptr;
      for (const auto& sector : sectors) out.push_back(estimate_sector_normal(mesh, vh, sector, file, options, fitter));
    }
  });
  std::size_t next_estimate = 0;
  int estimate_chunk = 0;
  for (Vertex vh : mesh.vertices()) {
    if (mesh.is_isolated(vh)) continue;
    const auto sectors = smooth_sectors(mesh, vh);
    for (const auto& sector : sectors) {
      while (next_estimate == estimates[static_cast<std::size_t>(estimate_chunk)].size()) {
        ++estimate_chunk;
        next_estimate = 0;
      }
      const SectorEstimate& estimated = estimates[static_cast<std::size_t>(estimate_chunk)][next_estimate++];
      Vec3 n = estimated.n;
      const bool file = estimated.source == SectorEstimate::Source::File;
      switch (estimated.source) {
        case SectorEstimate::Source::File: ++f.from_file; break;
        case SectorEstimate::Source::Fitted: ++f.fitted; break;
        case SectorEstimate::Source::AngleWeighted: ++f.angle_weighted; break;
      }
      // on a regular curve vertex the plane contains the curve tangent; at
      // corners the tangents follow from the sector planes (step 4)
      Vec3 free_axis;
      if (regular[vh.idx]) {
        free_axis = line[vh.idx];
        n = normalized(n - dot(n, free_axis) * free_axis);
        ++f.constrained;
      }
      const int s = static_cast<int>(f.sector_normal_.size());
      if (!file) {  // the file's normals are kept as they are
        movable.push_back(s);
        axis.push_back(free_axis);
        estimate.push_back(n);
        members.push_back(sector);
      }
      f.sector_normal_.push_back(n);
      f.sector_vertex_.push_back(vh);
      for (Corner c : sector) {
        f.corner_sector_[c.idx] = s;
      }
    }
  }
  // 3. consistency: turn the sector normals (about the curve tangent on a
  // feature curve, freely elsewhere, not at all where two curve tangents fix
  // them) so that every edge (v, w) of every triangle makes the same angle
  // with the tangent planes at v and w: (n_v + n_w) . (w - v) = 0, which holds
  // exactly on planes, spheres and cylinders and to third order in the edge
  // length on any smooth surface. A global linear least-squares problem in
  // the tangent offsets, with a pull of weight mirror_anchor towards the
  // estimate; a few Gauss-Newton steps. It mostly corrects one-sided
  // (boundary) neighbourhoods, where fits are biased.
  if (options.mirror_iterations > 0 && !movable.empty()) {
    const int ns = f.n_sectors();
    MirrorSystem sys(mesh, f.corner_sector_, movable, members, ns, axis);
    const std::vector<int>& first_unknown = sys.first_unknown;
    const std::vector<int>& n_unknowns = sys.n_unknowns;
    const int nm = static_cast<int>(movable.size());
    const int chunks = chunk_count(nm, 4096);
    std::vector<Vec3> b1(ns), b2(ns);
    std::vector<double> rhs(static_cast<std::size_t>(sys.A.n)), x;
    double first_rhs_norm = 0;
    for (int it = 0; it < options.mirror_iterations; ++it) {
      for (std::size_t i = 0; i < movable.size(); ++i) {
        const int s = movable[i];
        if (n_unknowns[s] == 1) {
          b1[s] = normalized(cross(axis[i], f.sector_normal_[s]));
          b2[s] = Vec3();
        } else {
          frame_of(f.sector_normal_[s], b1[s], b2[s]);
        }
      }
      // Each sector's columns and right-hand side from the edges at its
      // vertex: residual r + sum_k J_k x_k of every edge, weighted 1/l^4,
      // and the pull towards the estimate.
      run_chunks(nm, chunks, [&](int, int begin, int end) {
        for (int i = begin; i < end; ++i) {
          const int s = movable[i];
          for (int k = 0; k < n_unknowns[s]; ++k) {
            const int u = first_unknown[s] + k;
            std::fill(sys.A.value.begin() + sys.A.outer[u], sys.A.value.begin() + sys.A.outer[u + 1], -0.0);
            rhs[u] = 0;
          }
          double scale = 0;
          for_sector_edges(members[i], [&](const MirrorEdge& edge) {
            const Vec3 e = mesh.position(mesh.vertex(edge.cw)) - mesh.position(mesh.vertex(edge.cv));
            const double l2 = norm2(e);
            if (!(l2 > 0)) return;
            const double wt = 1.0 / (l2 * l2);
            const int sv = f.corner_sector_[edge.cv.idx], sw = f.corner_sector_[edge.cw.idx];
            const double r = dot(f.sector_normal_[sv] + f.sector_normal_[sw], e);
            int idx[4];
            double J[4];
            bool own[4];
            int m = 0;
            for (int t : {sv, sw}) {
              if (first_unknown[t] < 0) continue;
              idx[m] = first_unknown[t];
              own[m] = t == s;
              J[m++] = dot(b1[t], e);
              if (n_unknowns[t] == 2) {
                idx[m] = first_unknown[t] + 1;
                own[m] = t == s;
                J[m++] = dot(b2[t], e);
              }
            }
            scale += wt * l2;
            for (int a = 0; a < m; ++a) {
              if (!own[a]) continue;
              rhs[idx[a]] -= wt * J[a] * r;
              for (int c = 0; c < m; ++c) sys.A.add(idx[c], idx[a], wt * J[a] * J[c]);
            }
          });
          const double mu = options.mirror_anchor * scale;
          if (!(mu > 0)) continue;
          const Vec3 d = estimate[i] - f.sector_normal_[s];
          sys.A.add(first_unknown[s], first_unknown[s], mu);
          rhs[first_unknown[s]] += mu * dot(d, b1[s]);
          if (n_unknowns[s] == 2) {
            sys.A.add(first_unknown[s] + 1, first_unknown[s] + 1, mu);
            rhs[first_unknown[s] + 1] += mu * dot(d, b2[s]);
          }
        }
      });
      // Residual mirror_tolerance of the first step's right-hand side: a
      // later step, whose right-hand side is already smaller, is solved to
      // the same absolute accuracy, not to a share of itself.
      const double tolerance = options.mirror_tolerance;
      double rhs_norm = 0;
      for (double v : rhs) rhs_norm += v * v;
      rhs_norm = std::sqrt(rhs_norm);
      if (it == 0) first_rhs_norm = rhs_norm;
      if (!(rhs_norm > tolerance * first_rhs_norm)) break;
      solve_conjugate_gradient(sys.A, rhs, std::min(1.0, tolerance * first_rhs_norm / rhs_norm), 2000, x);
      bool finite = true;
      for (double v : x) finite = finite && std::isfinite(v);
      if (!finite) break;
      for (std::size_t i = 0; i < movable.size(); ++i) {
        const int s = movable[i];
        const int u = first_unknown[s];
        const double x1 = std::clamp(x[u], -0.5, 0.5);
        const double x2 = n_unknowns[s] == 2 ? std::clamp(x[u + 1], -0.5, 0.5) : 0.0;
        f.sector_normal_[s] = normalized(f.sector_normal_[s] + x1 * b1[s] + x2 * b2[s]);
      }
    }
  }
  // 3a. the consistency holds to third order in the edge length: where the
  // mesh is coarse for its curvature (a scan's fans turning by tens of
  // degrees) it asks for turns the surface does not have. A sector normal
  // stays within max_mirror_turn_deg of its estimate.
  if (options.mirror_iterations > 0) {
    const double cap = options.max_mirror_turn_deg * kDeg;
    for (std::size_t i = 0; i < movable.size(); ++i) {
      Vec3& n = f.sector_normal_[movable[i]];
      const Vec3& e = estimate[i];
      if (!(vector_angle(e, n) > cap)) continue;
      const Vec3 away = n - dot(n, e) * e;  // in the plane of e and n: normal to a curve axis when both are
      if (!(norm(away) > 0)) continue;
      n = normalized(std::cos(cap) * e + std::sin(cap) * normalized(away));
      ++f.mirror_capped;
    }
  }
  // 3b. a sector normal must see every triangle of its sector (else the patch
  // folds there): on noisy fans, tilt it towards the triangles it sees worst.
  const double min_cos = std::cos(options.max_tilt_deg * kDeg);
  for (std::size_t i = 0; i < movable.size(); ++i) {
    const int s = movable[i];
    auto worst = [&](const Vec3& n, Vec3* wn) {
      double m = 2;
      for (Corner c : members[i]) {
        const Vec3 tn = normalized(mesh.triangle_normal(SurfaceMesh::triangle(c)));
        if (dot(n, tn) < m) {
          m = dot(n, tn);
          if (wn) *wn = tn;
        }
      }
      return m;
    };
    Vec3 n = f.sector_normal_[s];
    if (worst(n, nullptr) >= min_cos) continue;
    for (int it = 0; it < 100 && worst(n, nullptr) < min_cos; ++it) {
      Vec3 wn;
      worst(n, &wn);
      n = normalized(n + 0.1 * wn);
      if (norm(axis[i]) > 0) n = normalized(n - dot(n, axis[i]) * axis[i]);
    }
    if (worst(n, nullptr) > worst(f.sector_normal_[s], nullptr)) {
      f.sector_normal_[s] = n;
      ++f.tilted;
    }
  }

  // 3c. on a regular curve vertex, a triangle beside the curve folds when its
  // other edge, seen in the sector plane, crosses the curve tangent (thin
  // triangles): turn the sector normal about the tangent to the nearest
  // direction that keeps every such triangle unfolded with a margin, or
  // failing that, to the direction that unfolds them best.
  const double margin = std::sin(options.unfold_margin_deg * kDeg);
  for (std::size_t i = 0; i < movable.size(); ++i) {
    const Vec3& t = axis[i];
    if (norm(t) == 0) continue;
    const int s = movable[i];
    const Vec3& p = mesh.position(f.sector_vertex_[s]);
    // conditions n . g > 0: det[handle towards next, handle towards prev, n] > 0
    std::vector<Vec3> gs;
    for (Corner c : members[i]) {
      const bool fa = is_feature_edge(mesh, SurfaceMesh::prev(c)), fb = is_feature_edge(mesh, SurfaceMesh::next(c));
      if (fa == fb) continue;  // none, or both along the curve (nothing to choose)
      const Vec3 a = mesh.position(mesh.vertex(SurfaceMesh::next(c))) - p;
      const Vec3 b = mesh.position(mesh.vertex(SurfaceMesh::prev(c))) - p;
      const Vec3 g = fa ? cross(dot(t, a) >= 0 ? t : -t, b) : cross(a, dot(t, b) >= 0 ? t : -t);
      if (norm(g) > 0) gs.push_back(normalized(g - dot(g, t) * t));
    }
    if (gs.empty()) continue;
    const Vec3 e1 = f.sector_normal_[s], e2 = cross(t, e1);
    auto worst = [&](double th) {
      const Vec3 n = std::cos(th) * e1 + std::sin(th) * e2;
      double w = 2;
      for (const Vec3& g : gs) w = min_of(w, dot(n, g));
      return w;
    };
    if (worst(0) >= margin) continue;
    const int steps = 720;
    double best = 0, best_worst = worst(0);
    bool feasible = false;
    for (int k = 1; k <= steps / 2; ++k)
      for (double th : {2 * std::numbers::pi * k / steps, -2 * std::numbers::pi * k / steps}) {
        const double w = worst(th);
        if (!feasible && w >= margin) {
          feasible = true;
          best = th;
        } else if (!feasible && w > best_worst) {
          best_worst = w;
          best = th;
        }
      }
    f.sector_normal_[s] = normalized(std::cos(best) * e1 + std::sin(best) * e2);
    ++f.unfolded;
  }

  // 4. corners: sectors joined by a feature edge along which their planes
  // differ by less than corner_merge_angle_deg share their mean plane; then
  // each curve end at a corner takes the intersection line of the planes of
  // its two sectors, or (one sector, or one shared plane) the projection of
  // its estimate onto that plane. Every sector plane then contains the
  // tangents of its bounding curves (proposition 1 holds in every sector).
  const double merge_angle = options.corner_merge_angle_deg * kDeg;
  const double max_corner_turn = options.corner_tangent_tolerance_deg * kDeg;
  for (Vertex vh : mesh.vertices()) {
    if (mesh.is_isolated(vh) || regular[vh.idx]) continue;
    const auto fe = feature_edges_at(mesh, vh);
    if (fe.empty()) continue;
    // the sectors on both sides of each feature edge at v
    struct End {
      Corner e;   // the feature edge (a corner of it inside v's fan)
      bool from;  // v == edge_from(e)
      int s1, s2; // sectors beside it (s2 = -1 on a boundary)
    };
    std::vector<End> ends;
    for (const auto& x : fe) {
      End en{x.edge, mesh.edge_from(x.edge) == vh, -1, -1};
      const Corner cv = en.from ? SurfaceMesh::next(x.edge) : SurfaceMesh::prev(x.edge);
      en.s1 = f.corner_sector_[cv.idx];
      const Corner o = mesh.opposite(x.edge);
      if (o.is_valid()) {
        const Corner ov = en.from ? SurfaceMesh::prev(o) : SurfaceMesh::next(o);
        en.s2 = f.corner_sector_[ov.idx];
      }
      ends.push_back(en);
    }
    // merge nearly coplanar neighbours (union-find over v's sectors)
    std::vector<int> ids;
    for (const End& en : ends)
      for (int s : {en.s1, en.s2})
        if (s >= 0 && std::find(ids.begin(), ids.end(), s) == ids.end()) ids.push_back(s);
    std::vector<int> parent(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) parent[i] = static_cast<int>(i);
    auto local = [&](int s) { return static_cast<int>(std::find(ids.begin(), ids.end(), s) - ids.begin()); };
    auto root = [&](int i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (const End& en : ends)
      if (en.s2 >= 0 && en.s1 != en.s2 && vector_angle(f.sector_normal_[en.s1], f.sector_normal_[en.s2]) < merge_angle)
        parent[root(local(en.s1))] = root(local(en.s2));
    std::vector<Vec3> group(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) group[root(static_cast<int>(i))] += f.sector_normal_[ids[i]];
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Vec3 g = normalized(group[root(static_cast<int>(i))]);
      if (norm(g) > 0) f.sector_normal_[ids[i]] = g;
    }
    // each end's tangent from the planes of its two sectors
    std::vector<Vec3> from_planes(ends.size());
    bool curves_first = false;
    for (std::size_t i = 0; i < ends.size(); ++i) {
      const End& en = ends[i];
      const Vec3& n1 = f.sector_normal_[en.s1];
      const Vec3& t = f.tangent(en.e.idx, en.from ? 0 : 1);
      const Vec3 chord = mesh.position(en.from ? mesh.edge_to(en.e) : mesh.edge_from(en.e)) - mesh.position(vh);
      Vec3 nt;
      if (en.s2 >= 0 && root(local(en.s1)) != root(local(en.s2))) {
        nt = normalized(cross(n1, f.sector_normal_[en.s2]));
      } else {
        nt = normalized(t - dot(t, n1) * n1);
        if (norm(nt) == 0) nt = normalized(chord - dot(chord, n1) * n1);
      }
      if (norm(nt) == 0) continue;
      if (dot(nt, t) < 0 || (dot(t, t) == 0 && dot(nt, chord) < 0)) nt = -nt;
      from_planes[i] = nt;
      if (norm(t) > 0 && vector_angle(nt, t) > max_corner_turn) curves_first = true;
    }
    if (curves_first) {
      // A sector plane that would turn a curve far from its own course (a
      // sector averaged over strips narrower than its triangles): the curves
      // keep the tangents of step 1 and each sector plane is made to contain
      // the tangents of its bounding curves instead, if every sector then
      // still sees all its triangles.
      std::vector<Vec3> planes(ids.size());
      bool all_see = true;
      for (std::size_t i = 0; i < ids.size() && all_see; ++i) {
        const int s = ids[i];
        std::vector<Vec3> ts;
        for (const End& en : ends)
          if (en.s1 == s || en.s2 == s) ts.push_back(f.tangent(en.e.idx, en.from ? 0 : 1));
        planes[i] = plane_containing(ts, f.sector_normal_[s]);
        // Nearly collinear tangents leave the plane to the estimate, which
        // then holds them only approximately: the tangents follow the planes.
        for (const Vec3& t : ts)
          if (std::fabs(dot(planes[i], t)) > 1e-9) all_see = false;
        for (Corner c : mesh.fan_corners(vh))
          if (f.corner_sector_[c.idx] == s &&
              dot(planes[i], normalized(mesh.triangle_normal(SurfaceMesh::triangle(c)))) < min_cos)
            all_see = false;
      }
      if (all_see) {
        for (std::size_t i = 0; i < ids.size(); ++i) f.sector_normal_[ids[i]] = planes[i];
        f.constrained += static_cast<int>(ids.size());
        continue;
      }
    }
    for (std::size_t i = 0; i < ends.size(); ++i) {
      const End& en = ends[i];
      const Vec3& nt = from_planes[i];
      if (norm(nt) == 0) continue;
      f.tangent(en.e.idx, en.from ? 0 : 1) = nt;
      const Corner o = mesh.opposite(en.e);
      if (o.is_valid()) f.tangent(o.idx, en.from ? 1 : 0) = nt;
      ++f.constrained;
    }
  }
  return f;
}

}  // namespace anisurf
