#include "render/lod.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace anisurf::render {

namespace {

constexpr std::uint32_t kNone = ~0u;

struct Grid {
  glm::vec3 origin{0};
  float cell = 1;

  // The cell holding p, packed into 60 bits (20 bits per axis).
  std::uint64_t key(const glm::vec3& p) const {
    auto axis = [&](float x, float lo) {
      return static_cast<std::uint64_t>(std::max(0.0f, std::floor((x - lo) / cell))) & 0xfffffu;
    };
    return axis(p.x, origin.x) | (axis(p.y, origin.y) << 20) | (axis(p.z, origin.z) << 40);
  }
};

// Which of the six directions +-x, +-y, +-z a normal is closest to (0-5).
std::uint64_t facing(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return static_cast<std::uint64_t>(2 * axis + (n[axis] < 0 ? 1 : 0));
}

// Area-weighted normals at the vertices.
std::vector<glm::vec3> vertex_normals(const TriangleSet& g) {
  std::vector<glm::vec3> n(g.positions.size(), glm::vec3(0));
  for (const glm::uvec3& t : g.triangles) {
    const glm::vec3 fn = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
    for (int k = 0; k < 3; ++k) n[t[k]] += fn;
  }
  return n;
}

glm::vec3 lowest_corner(const std::vector<glm::vec3>& points) {
  glm::vec3 lo(INFINITY);
  for (const auto& p : points) lo = glm::min(lo, p);
  return points.empty() ? glm::vec3(0) : lo;
}

double surface_area(const TriangleSet& g) {
  double area = 0;
  for (const glm::uvec3& t : g.triangles)
    area += 0.5 * glm::length(glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]));
  return area;
}

// Cluster index of every full vertex; fills the proxy's source vertices.
// The vertices of a cell are split by the direction they face, so that the
// two sides of a plate thinner than a cell stay apart.
std::vector<std::uint32_t> assign_clusters(const TriangleSet& full, const std::vector<glm::vec3>& normals,
                                           const Grid& grid, ProxyMesh& proxy) {
  std::unordered_map<std::uint64_t, std::uint32_t> cluster_of_cell;
  cluster_of_cell.reserve(full.positions.size() / 4 + 16);
  std::vector<std::uint32_t> cluster(full.positions.size());
  for (std::size_t v = 0; v < full.positions.size(); ++v) {
    const std::uint64_t key = grid.key(full.positions[v]) | (facing(normals[v]) << 60);
    auto [it, added] = cluster_of_cell.try_emplace(key, static_cast<std::uint32_t>(proxy.source_vertex.size()));
    if (added) proxy.source_vertex.push_back(static_cast<std::uint32_t>(v));
    cluster[v] = it->second;
  }
  return cluster;
}

// Mean position of the full vertices used by a triangle, per cluster.
std::vector<glm::vec3> cluster_means(const TriangleSet& full, const std::vector<std::uint32_t>& cluster,
                                     std::size_t n_clusters) {
  std::vector<glm::dvec3> sum(n_clusters, glm::dvec3(0));
  std::vector<std::uint32_t> count(n_clusters, 0);
  for (std::size_t v = 0; v < full.positions.size(); ++v) {
    sum[cluster[v]] += glm::dvec3(full.positions[v]);
    ++count[cluster[v]];
  }
  std::vector<glm::vec3> mean(n_clusters);
  for (std::size_t c = 0; c < n_clusters; ++c) mean[c] = glm::vec3(sum[c] / static_cast<double>(count[c]));
  return mean;
}

// Area-weighted normal of the full triangles around each cluster.
std::vector<glm::vec3> cluster_normals(const std::vector<glm::vec3>& at_vertex, const std::vector<std::uint32_t>& cluster,
                                       std::size_t n_clusters) {
  std::vector<glm::vec3> n(n_clusters, glm::vec3(0));
  for (std::size_t v = 0; v < at_vertex.size(); ++v) n[cluster[v]] += at_vertex[v];
  return n;
}

std::array<std::uint32_t, 3> sorted(std::array<std::uint32_t, 3> a) {
  std::sort(a.begin(), a.end());
  return a;
}

struct TripleHash {
  std::size_t operator()(const std::array<std::uint32_t, 3>& a) const {
    std::uint64_t h = a[0];
    h = h * 0x9e3779b97f4a7c15ull ^ a[1];
    h = h * 0x9e3779b97f4a7c15ull ^ a[2];
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// Unit normal of a proxy corner: the cluster's, else the proxy face's.
glm::vec3 corner_normal(const glm::vec3& cluster_normal, const glm::vec3& face_normal) {
  const float l = glm::length(cluster_normal);
  if (l > 0) return cluster_normal / l;
  const float f = glm::length(face_normal);
  return f > 0 ? face_normal / f : glm::vec3(0, 0, 1);
}

}  // namespace

ProxyMesh cluster_vertices(const TriangleSet& full, float cell_size) {
  ProxyMesh proxy;
  proxy.cell_size = cell_size;
  const Grid grid{lowest_corner(full.positions), cell_size};
  const std::vector<glm::vec3> at_vertex = vertex_normals(full);
  const std::vector<std::uint32_t> cluster = assign_clusters(full, at_vertex, grid, proxy);
  const std::size_t n_clusters = proxy.source_vertex.size();
  proxy.geometry.positions = cluster_means(full, cluster, n_clusters);
  const std::vector<glm::vec3> normals = cluster_normals(at_vertex, cluster, n_clusters);

  std::unordered_set<std::array<std::uint32_t, 3>, TripleHash> kept;
  for (std::size_t t = 0; t < full.triangles.size(); ++t) {
    const glm::uvec3& ft = full.triangles[t];
    const std::array<std::uint32_t, 3> c = {cluster[ft.x], cluster[ft.y], cluster[ft.z]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    if (!kept.insert(sorted(c)).second) continue;
    proxy.geometry.triangles.emplace_back(c[0], c[1], c[2]);
    proxy.source_triangle.push_back(static_cast<std::uint32_t>(t));
  }
  const auto& p = proxy.geometry.positions;
  proxy.geometry.corner_normals.reserve(3 * proxy.geometry.triangles.size());
  for (const glm::uvec3& t : proxy.geometry.triangles) {
    const glm::vec3 face = glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]);
    for (int k = 0; k < 3; ++k) proxy.geometry.corner_normals.push_back(corner_normal(normals[t[k]], face));
  }
  return proxy;
}

ProxyMesh make_proxy(const TriangleSet& full, std::size_t max_triangles) {
  const double area = surface_area(full);
  const double cells = std::max(1.0, static_cast<double>(max_triangles) / 2.0);
  float cell = static_cast<float>(std::sqrt(std::max(area, 1e-30) / cells));
  for (int attempt = 0;; ++attempt) {
    ProxyMesh proxy = cluster_vertices(full, cell);
    const std::size_t n = proxy.geometry.triangles.size();
    if (n <= max_triangles || attempt == 8) return proxy;
    cell *= static_cast<float>(std::sqrt(static_cast<double>(n) / static_cast<double>(max_triangles)) * 1.05);
  }
}

SurfaceStructure proxy_structure(const SurfaceStructure& full, const ProxyMesh& proxy) {
  SurfaceStructure s;
  s.name = full.name;
  s.geometry = proxy.geometry;
  s.color = full.color;
  s.enabled = full.enabled;
  s.active = full.active;
  s.version = full.version;
  const auto& src_t = proxy.source_triangle;
  const auto& src_v = proxy.source_vertex;
  auto value = [](const std::vector<float>& v, std::size_t i) { return i < v.size() ? v[i] : NAN; };
  for (const ScalarQuantity& q : full.scalars) {
    ScalarQuantity r = q;
    r.values.clear();
    if (q.location == ScalarLocation::Vertex) {
      for (std::uint32_t v : src_v) r.values.push_back(value(q.values, v));
    } else if (q.location == ScalarLocation::Triangle) {
      for (std::uint32_t t : src_t) r.values.push_back(value(q.values, t));
    } else {
      for (std::uint32_t t : src_t)
        for (std::size_t k = 0; k < 3; ++k) r.values.push_back(value(q.values, 3 * std::size_t{t} + k));
    }
    s.scalars.push_back(std::move(r));
  }
  for (const LabelQuantity& l : full.labels) {
    LabelQuantity r{l.name, {}};
    for (std::uint32_t t : src_t) r.triangle_labels.push_back(t < l.triangle_labels.size() ? l.triangle_labels[t] : 0);
    s.labels.push_back(std::move(r));
  }
  for (const VertexCategories& c : full.categories) {
    VertexCategories r = c;
    r.values.clear();
    for (std::uint32_t v : src_v) r.values.push_back(v < c.values.size() ? c.values[v] : -1);
    s.categories.push_back(std::move(r));
  }
  if (!full.highlight_triangles.empty()) {
    std::unordered_set<std::uint32_t> lit(full.highlight_triangles.begin(), full.highlight_triangles.end());
    for (std::size_t t = 0; t < src_t.size(); ++t)
      if (lit.count(src_t[t])) s.highlight_triangles.push_back(static_cast<std::uint32_t>(t));
  }
  return s;
}

}  // namespace anisurf::render
