#include "render/bezier_structure.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.h"

namespace anisurf::render {

namespace {

glm::vec3 to_glm(const Vec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

// Index (0..30) of quartic point (i, j, l) of Clough-Tocher subtriangle k
// (local vertices A = v_{k+1}, B = v_{k+2}, G = centre), following the layout
// documented in geometry/bezier_surface.h: 0-2 vertices, 3 centre, 4+3k+m
// outer edge opposite v_k from v_{k+1}, 13+3j+m inner edge v_j -> centre,
// 22+2k+{0,1} and 28+k the inner points of subtriangle k.
int patch_index(int k, int i, int j, int l) {
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  if (i == 4) return a;
  if (j == 4) return b;
  if (l == 4) return 3;
  if (l == 0) return 4 + 3 * k + (j - 1);
  if (j == 0) return 13 + 3 * a + (l - 1);
  if (i == 0) return 13 + 3 * b + (l - 1);
  if (l == 1) return 22 + 2 * k + (j - 1);
  return 28 + k;
}

}  // namespace

const std::vector<std::array<int, 2>>& control_net_edges() {
  static const std::vector<std::array<int, 2>> edges = [] {
    std::set<std::array<int, 2>> s;
    auto add = [&](int p, int q) { s.insert({std::min(p, q), std::max(p, q)}); };
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l <= 4; ++l)
        for (int j = 0; j <= 4 - l; ++j) {
          const int i = 4 - j - l;
          const int p = patch_index(k, i, j, l);
          if (i > 0) add(p, patch_index(k, i - 1, j + 1, l));  // along A -> B
          if (i > 0) add(p, patch_index(k, i - 1, j, l + 1));  // along A -> G
          if (j > 0) add(p, patch_index(k, i, j - 1, l + 1));  // along B -> G
        }
    return std::vector<std::array<int, 2>>(s.begin(), s.end());
  }();
  return edges;
}

namespace {

// The triangles whose control net is drawn (bezier_structure.h: at most
// o.net_max_patches, the nearest to o.net_centre or every n-th), as a flag
// per triangle slot.
std::vector<char> net_patches(const SurfaceMesh& mesh, const BezierStructureOptions& o) {
  std::vector<char> on(static_cast<std::size_t>(mesh.triangle_capacity()), 0);
  std::vector<int> all;
  for (Triangle T : mesh.triangles()) all.push_back(T.idx);
  const auto n = static_cast<std::size_t>(o.net_max_patches);
  if (o.net_max_patches <= 0 || all.size() <= n) {
    for (int t : all) on[static_cast<std::size_t>(t)] = 1;
    return on;
  }
  if (o.net_centre) {
    const Vec3 c(o.net_centre->x, o.net_centre->y, o.net_centre->z);
    std::vector<std::pair<double, int>> d;
    d.reserve(all.size());
    for (int t : all) {
      Vec3 g;
      for (int k = 0; k < 3; ++k) g += mesh.position(mesh.vertex(Triangle(t), k)) / 3.0;
      d.push_back({norm2(g - c), t});
    }
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(n), d.end());
    for (std::size_t i = 0; i < n; ++i) on[static_cast<std::size_t>(d[i].second)] = 1;
  } else {
    const double stride = static_cast<double>(all.size()) / static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) on[static_cast<std::size_t>(all[static_cast<std::size_t>(i * stride)])] = 1;
  }
  return on;
}

}  // namespace

SurfaceStructure make_bezier_structure(const SurfaceMesh& mesh, const BezierSurface& surface, const std::string& name,
                                       const BezierStructureOptions& o, BezierNetInfo* info) {
  if (o.k < 1) throw Error("the Bezier sampling needs k >= 1, got " + std::to_string(o.k));
  if (surface.size() != mesh.triangle_capacity())
    throw Error("the Bezier surface was built over another mesh (" + std::to_string(surface.size()) +
                " triangle slots, the mesh has " + std::to_string(mesh.triangle_capacity()) + ")");
  SurfaceStructure s;
  s.name = name;
  s.color = {0.80f, 0.78f, 0.70f};
  TriangleSet& g = s.geometry;
  ScalarQuantity dev{quantity::kDeviation, ScalarLocation::Vertex};
  const int k = o.k;
  const int per_tri = (k + 1) * (k + 2) / 2;
  // Grid point (a, b) of a triangle: barycentric ((k - a - b), a, b) / k.
  auto grid = [k](int a, int b) { return b * (k + 1) - b * (b - 1) / 2 + a; };
  Curves patch{"patch edges", {}, {0.25f, 0.25f, 0.30f}, 1.0f, o.patch_edges};
  Curves net{"control net", {}, {0.10f, 0.45f, 0.15f}, 1.2f, o.control_net};
  Markers points{"control points", {}, {0.10f, 0.55f, 0.15f}, 2.5f, o.control_net};
  std::vector<glm::vec3> normals;
  const std::vector<char> with_net = net_patches(mesh, o);
  BezierNetInfo net_info;
  for (Triangle T : mesh.triangles()) {
    ++net_info.patches;
    const Vec3 v[3] = {mesh.position(mesh.vertex(T, 0)), mesh.position(mesh.vertex(T, 1)),
                       mesh.position(mesh.vertex(T, 2))};
    const auto base = static_cast<std::uint32_t>(g.positions.size());
    normals.resize(g.positions.size() + per_tri);
    for (int b = 0; b <= k; ++b)
      for (int a = 0; a <= k - b; ++a) {
        const Bary w = {static_cast<double>(k - a - b) / k, static_cast<double>(a) / k, static_cast<double>(b) / k};
        const SurfacePoint sp = surface.evaluate(T, w);
        const Vec3 flat = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        g.positions.push_back(to_glm(sp.position));
        normals[base + grid(a, b)] = to_glm(sp.normal);
        dev.values.push_back(static_cast<float>(norm(sp.position - flat)));
      }
    for (int b = 0; b < k; ++b)
      for (int a = 0; a < k - b; ++a) {
        const std::uint32_t p = base + grid(a, b), q = base + grid(a + 1, b), r = base + grid(a, b + 1);
        g.triangles.emplace_back(p, q, r);
        if (a + b < k - 1) g.triangles.emplace_back(q, base + grid(a + 1, b + 1), r);
      }
    if (o.patch_edges) {
      // The three edges, each once (from the canonical corner).
      for (int e = 0; e < 3; ++e) {
        const Corner c = SurfaceMesh::corner(T, e);
        if (mesh.canonical(c) != c) continue;
        // Edge opposite vertex e: from vertex e+1 to vertex e+2.
        for (int i = 0; i < k; ++i) {
          auto at = [&](int s) {
            Bary w{};
            w[(e + 1) % 3] = static_cast<double>(k - s) / k;
            w[(e + 2) % 3] = static_cast<double>(s) / k;
            return to_glm(surface.position(T, w));
          };
          patch.points.push_back(at(i));
          patch.points.push_back(at(i + 1));
        }
      }
    }
    if (!with_net[static_cast<std::size_t>(T.idx)]) continue;
    ++net_info.shown;
    const BezierSurface::Patch& P = surface.patch(T);
    for (const auto& [p, q] : control_net_edges()) {
      net.points.push_back(to_glm(P[p]));
      net.points.push_back(to_glm(P[q]));
    }
    for (int i = 3; i < BezierSurface::kControlPoints; ++i) points.positions.push_back(to_glm(P[i]));
  }
  g.corner_normals.reserve(3 * g.triangles.size());
  for (const auto& t : g.triangles)
    for (int c = 0; c < 3; ++c) g.corner_normals.push_back(normals[t[c]]);
  dev.colormap = Colormap::Viridis;
  // Range: 0 to the 98th percentile, so a few large deviations (at sharp
  // corners) do not darken the rest.
  std::vector<float> sorted = dev.values;
  std::sort(sorted.begin(), sorted.end());
  dev.range_min = 0.0f;
  dev.range_max = sorted.empty() ? 1.0f : sorted[static_cast<std::size_t>(0.98 * static_cast<double>(sorted.size() - 1))];
  if (!(dev.range_max > 0.0f)) dev.range_max = sorted.empty() || !(sorted.back() > 0) ? 1.0f : sorted.back();
  dev.note = "distance mesh - G1 surface (k = " + std::to_string(k) + ")";
  s.scalars.push_back(std::move(dev));
  if (!patch.points.empty()) s.curves.push_back(std::move(patch));
  s.curves.push_back(std::move(net));
  s.markers.push_back(std::move(points));
  s.version = 1;
  if (info) *info = net_info;
  return s;
}

}  // namespace anisurf::render
