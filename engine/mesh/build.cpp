#include "mesh/build.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <span>
#include <unordered_map>

#include "core/error.h"
#include "core/huge_pages.h"

namespace anisurf {

namespace {

using Tri = std::array<int, 3>;

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

void check_input(const MeshData& d, const std::string& source) {
  if (d.triangles.empty()) throw TopologyError(source + ": the mesh has no triangle (nothing to build)");
  const int nv = static_cast<int>(d.vertices.size());
  // Squared lengths and the bounding box diagonal must stay finite: a
  // coordinate beyond kMaxCoordinate would overflow them (welding, metric
  // lengths, areas) and turn every measure into inf or NaN.
  constexpr double kMaxCoordinate = 1e150;
  for (std::size_t i = 0; i < d.vertices.size(); ++i) {
    const Vec3& p = d.vertices[i];
    if (!is_finite(p))
      throw TopologyError(source + ": vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
    if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > kMaxCoordinate) {
      char msg[160];
      std::snprintf(msg, sizeof msg, ": vertex %zu has a coordinate beyond +-1e150 (%g %g %g): lengths would overflow; "
                    "rescale the mesh", i + 1, p.x, p.y, p.z);
      throw TopologyError(source + msg);
    }
  }
  for (std::size_t t = 0; t < d.triangles.size(); ++t)
    for (int v : d.triangles[t])
      if (v < 0 || v >= nv)
        throw TopologyError(source + ": triangle " + std::to_string(t + 1) + " uses vertex " + std::to_string(v + 1) +
                            ", expected 1.." + std::to_string(nv));
  auto check_ids = [&](const std::vector<int>& ids, int n, const char* what) {
    for (int id : ids)
      if (id < 0 || id >= n)
        throw TopologyError(source + ": " + what + " id " + std::to_string(id + 1) + " out of range 1.." +
                            std::to_string(n));
  };
  check_ids(d.corners, nv, "corner vertex");
  check_ids(d.required_vertices, nv, "required vertex");
  check_ids(d.ridges, static_cast<int>(d.edges.size()), "ridge edge");
  check_ids(d.required_edges, static_cast<int>(d.edges.size()), "required edge");
  check_ids(d.required_triangles, static_cast<int>(d.triangles.size()), "required triangle");
  for (const auto& e : d.edges)
    for (int v : e)
      if (v < 0 || v >= nv)
        throw TopologyError(source + ": edge uses vertex " + std::to_string(v + 1) + ", expected 1.." +
                            std::to_string(nv));
  for (const auto& f : d.fields)
    if (f.info.ncomp < 1 || f.info.ncomp > 6 || f.values.size() != d.vertices.size() * f.info.ncomp)
      throw TopologyError(source + ": field '" + f.info.name + "' has " + std::to_string(f.values.size()) +
                          " values, expected " + std::to_string(d.vertices.size()) + " x " +
                          std::to_string(f.info.ncomp));
}

// Integer coordinates of a cell of the welding grid.
using GridCell = std::array<std::int64_t, 3>;

// Cells at least 2 tol wide (a point's neighbours within tol lie in the 27
// cells around it) and at least 2^-60 of the largest coordinate: a cell index
// then stays within +-2^60 for any finite coordinates, however small tol is
// (such a cell is still only a few hundred doubles wide).
double weld_cell_size(const std::vector<Vec3>& p, double tol) {
  double largest = 0;
  for (const Vec3& q : p) largest = std::max({largest, std::abs(q.x), std::abs(q.y), std::abs(q.z)});
  const double cell = std::max(2 * tol, std::ldexp(largest, -60));
  return std::isfinite(cell) ? cell : std::numeric_limits<double>::max();
}

GridCell grid_cell(const Vec3& q, double cell) {
  return {static_cast<std::int64_t>(std::floor(q.x / cell)), static_cast<std::int64_t>(std::floor(q.y / cell)),
          static_cast<std::int64_t>(std::floor(q.z / cell))};
}

// Spatial hash of a cell, in unsigned (wrapping) arithmetic.
std::uint64_t cell_hash(const GridCell& c) {
  return (static_cast<std::uint64_t>(c[0]) * 73856093u) ^ (static_cast<std::uint64_t>(c[1]) * 19349663u) ^
         (static_cast<std::uint64_t>(c[2]) * 83492791u);
}

// A hash of a position by the bits of its coordinates (+0.0 for -0.0: they
// compare equal).
std::size_t position_hash(const Vec3& x) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (double c : {x.x + 0.0, x.y + 0.0, x.z + 0.0}) {
    std::uint64_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xbf58476d1ce4e5b9ull;
    h ^= h >> 31;
  }
  return static_cast<std::size_t>(h);
}

// Representative of each vertex after merging coincident positions: exact
// equality when tol == 0, else within tol (grid hashing, 27 neighbour cells).
std::vector<int> merge_positions(const std::vector<Vec3>& p, double tol) {
  const int n = static_cast<int>(p.size());
  std::vector<int> rep(n);
  std::iota(rep.begin(), rep.end(), 0);
  if (tol <= 0) {
    // Equal positions: each vertex meets the first of its position in a hash
    // table (open addressing, at most half full).
    std::size_t size = 16;
    while (size < 2 * static_cast<std::size_t>(n)) size *= 2;
    std::vector<int> table(size, -1);
    for (int v = 0; v < n; ++v) {
      std::size_t i = position_hash(p[v]) & (size - 1);
      while (table[i] >= 0 && !(p[table[i]] == p[v])) i = (i + 1) & (size - 1);
      if (table[i] >= 0) rep[v] = table[i];
      else table[i] = v;
    }
    return rep;
  }
  const double cell = weld_cell_size(p, tol);
  std::unordered_multimap<std::uint64_t, int> grid;
  grid.reserve(static_cast<std::size_t>(n) * 2);
  const double tol2 = tol * tol;
  for (int v = 0; v < n; ++v) {
    const GridCell c = grid_cell(p[v], cell);
    int found = -1;
    for (std::int64_t di = -1; di <= 1 && found < 0; ++di)
      for (std::int64_t dj = -1; dj <= 1 && found < 0; ++dj)
        for (std::int64_t dk = -1; dk <= 1 && found < 0; ++dk) {
          auto range = grid.equal_range(cell_hash({c[0] + di, c[1] + dj, c[2] + dk}));
          for (auto it = range.first; it != range.second; ++it)
            if (norm2(p[it->second] - p[v]) <= tol2) {
              found = it->second;
              break;
            }
        }
    if (found >= 0) {
      rep[v] = found;
    } else {
      grid.emplace(cell_hash(c), v);
    }
  }
  return rep;
}

// Triangle incidences of one undirected edge, grouped by sorting.
struct EdgeUse {
  std::uint64_t key;
  int tri;
  int local;  // corner opposite the edge
};

// Indices 0..n-1 ordered by (first(i), then by `less` within equal firsts),
// first(i) in [0, buckets): a counting sort on first, then each bucket
// (a vertex's few edges or triangles) sorted in place.
template <class First, class Less>
std::vector<int> bucket_order(int n, int buckets, First first, Less less) {
  std::vector<int> start(static_cast<std::size_t>(buckets) + 1, 0);
  for (int i = 0; i < n; ++i) ++start[static_cast<std::size_t>(first(i)) + 1];
  for (int b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<int> order;
  reserve_huge(order, static_cast<std::size_t>(n));
  order.resize(static_cast<std::size_t>(n));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(fill[first(i)]++)] = i;
  for (int b = 0; b < buckets; ++b) std::sort(order.begin() + start[b], order.begin() + start[b + 1], less);
  return order;
}

int vertex_bound(const std::vector<Tri>& tris) {
  int n = 0;
  for (const Tri& t : tris) n = std::max({n, t[0] + 1, t[1] + 1, t[2] + 1});
  return n;
}

// The uses of every edge (key, triangle, opposite corner), ordered by key,
// then triangle, then corner: made in (triangle, corner) order (twice: to
// count, then to place, with no array of them in input order), placed
// stably by the key's first vertex (a counting sort), then each vertex's few
// uses sorted stably on the key (insertion).
std::vector<EdgeUse> sorted_edge_uses(const std::vector<Tri>& tris) {
  const int nt = static_cast<int>(tris.size());
  auto use = [&](int t, int k) { return EdgeUse{edge_key(tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]), t, k}; };
  const auto buckets = static_cast<std::size_t>(vertex_bound(tris));
  std::vector<int> start(buckets + 1, 0);
  auto first_vertex = [](const EdgeUse& u) { return static_cast<std::size_t>(u.key >> 32); };
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) ++start[first_vertex(use(t, k)) + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<EdgeUse> sorted;
  reserve_huge(sorted, tris.size() * 3);
  sorted.resize(tris.size() * 3);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const EdgeUse u = use(t, k);
        sorted[static_cast<std::size_t>(fill[first_vertex(u)]++)] = u;
      }
  }
  for (std::size_t b = 0; b < buckets; ++b)
    for (int i = start[b] + 1; i < start[b + 1]; ++i) {
      const EdgeUse u = sorted[static_cast<std::size_t>(i)];
      int j = i;
      for (; j > start[b] && sorted[static_cast<std::size_t>(j) - 1].key > u.key; --j)
        sorted[static_cast<std::size_t>(j)] = sorted[static_cast<std::size_t>(j) - 1];
      sorted[static_cast<std::size_t>(j)] = u;
    }
  return sorted;
}

// True when the edge opposite corner `local` of t runs in the same direction
// in both triangles (so one of them must be flipped).
bool same_direction(const Tri& a, int la, const Tri& b, int lb) {
  return a[(la + 1) % 3] == b[(lb + 1) % 3];
}

}  // namespace

bool BuildReport::repaired() const {
  return merged_vertices || unreferenced_vertices || degenerate_triangles || duplicate_triangles ||
         flipped_triangles || non_manifold_edges || non_manifold_vertices || non_orientable_components ||
         dropped_edges;
}

std::vector<std::string> BuildReport::repair_messages() const {
  std::vector<std::string> m;
  auto add = [&](int n, const std::string& what) {
    if (n > 0) m.push_back(std::to_string(n) + " " + what);
  };
  add(merged_vertices, "coincident vertices merged");
  add(unreferenced_vertices, "unreferenced vertices dropped");
  add(degenerate_triangles, "degenerate triangles (repeated vertex) dropped");
  add(duplicate_triangles, "duplicated triangles dropped");
  add(flipped_triangles, "triangles flipped to orient their component consistently");
  add(non_manifold_edges, "non-manifold edges (more than 2 triangles) cut apart");
  add(non_manifold_vertices, "non-manifold vertices split into one copy per fan");
  add(non_orientable_components, "edges cut to orient non-orientable components");
  add(dropped_edges, "listed edges dropped (not an edge of any triangle)");
  add(zero_area_triangles, "zero-area triangles kept (reported only)");
  return m;
}

BuildReport build_mesh(const MeshData& d, SurfaceMesh& mesh, const BuildOptions& opt, const std::string& source) {
  check_input(d, source);
  BuildReport rep;
  rep.input_vertices = static_cast<int>(d.vertices.size());
  rep.input_triangles = static_cast<int>(d.triangles.size());
  rep.warnings = d.warnings;
  const int nv_in = rep.input_vertices;

  // 1. merge coincident positions
  std::vector<int> rep_of(nv_in);
  std::iota(rep_of.begin(), rep_of.end(), 0);
  {
    BBox b;
    for (const auto& p : d.vertices) b.add(p);
    const bool merge = opt.merge == BuildOptions::Merge::Always ||
                       (opt.merge == BuildOptions::Merge::Auto && (d.split_vertices || opt.merge_tolerance > 0));
    std::vector<int> same = merge_positions(d.vertices, merge ? opt.merge_tolerance * b.diagonal() : 0.0);
    rep.unique_positions = 0;
    for (int v = 0; v < nv_in; ++v) rep.unique_positions += same[v] == v;
    if (merge) rep_of = std::move(same);
  }

  // 2. triangles: drop degenerate and duplicated ones
  std::vector<Tri> tris;
  std::vector<int> tri_origin;
  reserve_huge(tris, d.triangles.size());
  reserve_huge(tri_origin, d.triangles.size());
  for (int t = 0; t < static_cast<int>(d.triangles.size()); ++t) {
    Tri tr{rep_of[d.triangles[t][0]], rep_of[d.triangles[t][1]], rep_of[d.triangles[t][2]]};
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2]) {
      ++rep.degenerate_triangles;
      continue;
    }
    tris.push_back(tr);
    tri_origin.push_back(t);
  }
  if (opt.drop_duplicate_triangles) {
    std::vector<int> order;
    auto sorted = [&](int t) {
      Tri s = tris[t];
      std::sort(s.begin(), s.end());
      return s;
    };
    std::vector<Tri> keys(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) keys[t] = sorted(static_cast<int>(t));
    order = bucket_order(static_cast<int>(tris.size()), vertex_bound(tris), [&](int t) { return keys[t][0]; },
                         [&](int a, int b) { return keys[a] != keys[b] ? keys[a] < keys[b] : a < b; });
    std::vector<char> drop(tris.size(), 0);
    for (std::size_t i = 1; i < order.size(); ++i)
      if (keys[order[i]] == keys[order[i - 1]]) drop[order[i]] = 1;
    std::size_t w = 0;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      if (drop[t]) {
        ++rep.duplicate_triangles;
        continue;
      }
      tris[w] = tris[t];
      tri_origin[w] = tri_origin[t];
      ++w;
    }
    tris.resize(w);
    tri_origin.resize(w);
  }
  if (tris.empty()) throw TopologyError(source + ": every triangle is degenerate or duplicated (nothing to build)");
  const int nt = static_cast<int>(tris.size());

  // 3. pair triangles across manifold edges; cut non-manifold ones
  std::vector<EdgeUse> uses = sorted_edge_uses(tris);
  struct Pair {
    int t0, l0, t1, l1;
    std::uint64_t key;
  };
  std::vector<Pair> pairs;
  reserve_huge(pairs, uses.size() / 2);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 2) {
      pairs.push_back({uses[i].tri, uses[i].local, uses[i + 1].tri, uses[i + 1].local, uses[i].key});
    } else if (j - i > 2) {
      ++rep.non_manifold_edges;
    }
    i = j;
  }

  // 4. orient each component by a breadth-first walk over the pairs
  // The pairs of each triangle (one per edge at most: three slots, -1 when
  // unused), in pair order.
  std::vector<char> cut(pairs.size(), 0);
  // Consistently oriented pairs throughout (most inputs): the walk would
  // flip nothing and cut nothing.
  bool consistent = true;
  for (const Pair& pr : pairs)
    if (same_direction(tris[pr.t0], pr.l0, tris[pr.t1], pr.l1)) {
      consistent = false;
      break;
    }
  if (opt.orient && !consistent) {
    std::vector<std::array<int, 3>> tri_pairs(static_cast<std::size_t>(nt), {-1, -1, -1});
    auto add_pair = [&](int t, int p) {
      for (int& slot : tri_pairs[static_cast<std::size_t>(t)])
        if (slot < 0) {
          slot = p;
          return;
        }
    };
    for (int p = 0; p < static_cast<int>(pairs.size()); ++p) {
      add_pair(pairs[p].t0, p);
      add_pair(pairs[p].t1, p);
    }
    std::vector<int> flip(nt, -1);
    std::vector<int> queue;
    queue.reserve(nt);
    for (int seed = 0; seed < nt; ++seed) {
      if (flip[seed] >= 0) continue;
      flip[seed] = 0;
      queue.assign(1, seed);
      bool cut_here = false;
      for (std::size_t qi = 0; qi < queue.size(); ++qi) {
        int t = queue[qi];
        for (int p : tri_pairs[t]) {
          if (p < 0) break;
          const Pair& pr = pairs[p];
          int u = pr.t0 == t ? pr.t1 : pr.t0;
          bool same = same_direction(tris[pr.t0], pr.l0, tris[pr.t1], pr.l1);
          int want = flip[t] ^ (same ? 1 : 0);
          if (flip[u] < 0) {
            flip[u] = want;
            queue.push_back(u);
          } else if (flip[u] != want && !cut[p]) {
            cut[p] = 1;
            cut_here = true;
          }
        }
      }
      if (cut_here) ++rep.non_orientable_components;
    }
    for (int t = 0; t < nt; ++t)
      if (flip[t] == 1) {
        std::swap(tris[t][1], tris[t][2]);
        ++rep.flipped_triangles;
      }
  }
  // Local corner indices move with a flip (1 <-> 2): recompute them by vertex.
  const bool flipped = rep.flipped_triangles > 0;
  auto corner_opposite = [&](int t, std::uint64_t key) {
    for (int k = 0; k < 3; ++k)
      if (edge_key(tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]) == key) return k;
    return -1;
  };

  // 5. fill the mesh (vertex ids still in input numbering; compacted below)
  mesh.clear();
  mesh.set_dimension(d.dimension);
  mesh.reserve(nv_in, nt);
  mesh.append_vertices(d.vertices);
  mesh.append_triangles(tris);
  for (int p = 0; p < static_cast<int>(pairs.size()); ++p) {
    if (cut[p]) continue;
    const Pair& pr = pairs[p];
    const std::uint64_t key = pr.key;
    int l0 = flipped ? corner_opposite(pr.t0, key) : pr.l0;
    int l1 = flipped ? corner_opposite(pr.t1, key) : pr.l1;
    Corner c0 = SurfaceMesh::corner(Triangle(pr.t0), l0), c1 = SurfaceMesh::corner(Triangle(pr.t1), l1);
    // Without orientation, an inconsistent pair cannot be linked.
    if (!opt.orient && same_direction(tris[pr.t0], l0, tris[pr.t1], l1)) continue;
    mesh.link(c0, c1);
  }
  {
    // Tag the cut edges (corner indices recomputed after flips).
    for (std::size_t i = 0; i < uses.size();) {
      std::size_t j = i;
      while (j < uses.size() && uses[j].key == uses[i].key) ++j;
      if (j - i > 2)
        for (std::size_t k = i; k < j; ++k) {
          int l = flipped ? corner_opposite(uses[k].tri, uses[k].key) : uses[k].local;
          mesh.add_edge_tag(SurfaceMesh::corner(Triangle(uses[k].tri), l), kNonManifold);
        }
      i = j;
    }
  }

  // 6. vertex fans: assign incident corners; split non-manifold vertices
  // corners of each vertex, in corner order: corner_list[corner_start[v] ..
  // corner_start[v + 1])
  std::vector<int> corner_start(static_cast<std::size_t>(nv_in) + 1, 0), corner_list(3 * static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) ++corner_start[tris[t][k] + 1];
  for (int v = 0; v < nv_in; ++v) corner_start[v + 1] += corner_start[v];
  {
    std::vector<int> fill(corner_start.begin(), corner_start.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) corner_list[fill[tris[t][k]]++] = 3 * t + k;
  }
  auto corners_of = [&](int v) {
    return std::span<const int>(corner_list.data() + corner_start[v], corner_list.data() + corner_start[v + 1]);
  };
  std::vector<int> origin(nv_in);
  std::iota(origin.begin(), origin.end(), 0);
  std::vector<char> seen(3 * static_cast<std::size_t>(nt), 0);
  for (int v = 0; v < nv_in; ++v) {
    if (corners_of(v).empty()) continue;
    bool first_fan = true;
    for (int c0 : corners_of(v)) {
      if (seen[c0]) continue;
      // Collect this fan: walk clockwise to its start, then counter-clockwise.
      Corner start(c0);
      for (std::size_t guard = 0; guard <= corners_of(v).size(); ++guard) {
        Corner n = mesh.swing_cw(start);
        if (!n.is_valid() || n.idx == c0) break;
        start = n;
      }
      Vertex target(v);
      if (!first_fan) {
        target = mesh.add_vertex(d.vertices[v]);
        origin.push_back(v);
        ++rep.non_manifold_vertices;
      }
      Corner c = start;
      for (std::size_t guard = 0; guard <= corners_of(v).size(); ++guard) {
        seen[c.idx] = 1;
        mesh.set_corner_vertex(c, target);
        c = mesh.swing_ccw(c);
        if (!c.is_valid() || c == start) break;
      }
      mesh.set_vertex_corner(target, start);
      first_fan = false;
    }
  }

  // 7. tags, references and attached data (in input numbering; the mesh
  // vertices [0, nv_in) are the file's vertices, later ones are split copies)
  const bool has_vref = d.vertex_refs.size() == d.vertices.size();
  for (Vertex v : mesh.vertices())
    if (has_vref) mesh.set_vertex_ref(v, d.vertex_refs[origin[v.idx]]);
  if (d.triangle_refs.size() == d.triangles.size())
    for (int t = 0; t < nt; ++t) mesh.set_triangle_ref(Triangle(t), d.triangle_refs[tri_origin[t]]);
  // vertex lists: also apply to merged representatives and split copies
  std::vector<std::uint8_t> file_vtags(nv_in, 0);
  for (int v : d.corners) file_vtags[v] |= kCorner;
  for (int v : d.required_vertices) file_vtags[v] |= kRequired;
  for (int v = 0; v < nv_in; ++v)
    if (rep_of[v] != v) file_vtags[rep_of[v]] |= file_vtags[v];
  for (Vertex v : mesh.vertices()) mesh.set_vertex_tags(v, file_vtags[origin[v.idx]]);
  {
    std::vector<char> req_tri(d.triangles.size(), 0);
    for (int t : d.required_triangles) req_tri[t] = 1;
    for (int t = 0; t < nt; ++t)
      if (req_tri[tri_origin[t]]) mesh.set_triangle_tags(Triangle(t), kRequired);
  }
  // edges
  {
    std::vector<std::uint8_t> etags(d.edges.size(), kListed);
    for (int e : d.ridges) etags[e] |= kRidge;
    for (int e : d.required_edges) etags[e] |= kRequired;
    const bool has_eref = d.edge_refs.size() == d.edges.size();
    for (std::size_t e = 0; e < d.edges.size(); ++e) {
      int a = rep_of[d.edges[e][0]], b = rep_of[d.edges[e][1]];
      Corner c;
      if (a != b) {
        // search among every copy of a (split vertices share the origin)
        for (int c0 : corners_of(a)) {
          if (origin[mesh.vertex(SurfaceMesh::next(Corner(c0))).idx] == b)
            c = SurfaceMesh::prev(Corner(c0));
          else if (origin[mesh.vertex(SurfaceMesh::prev(Corner(c0))).idx] == b)
            c = SurfaceMesh::next(Corner(c0));
          if (c.is_valid()) break;
        }
      }
      if (!c.is_valid()) {
        ++rep.dropped_edges;
        continue;
      }
      mesh.set_edge_tags(c, mesh.edge_tags(c) | etags[e]);
      if (has_eref) mesh.set_edge_ref(c, d.edge_refs[e]);
    }
    if (rep.dropped_edges)
      rep.warnings.push_back(source + ": " + std::to_string(rep.dropped_edges) +
                             " listed edges are not edges of any triangle and were dropped");
  }
  // normals and tangents
  auto attach_vectors = [&](const std::vector<Vec3>& vecs, const std::vector<std::array<int, 2>>& at,
                            const char* name, const char* flag) {
    if (at.empty()) return;
    auto prop = mesh.vertex_property<Vec3>(name);
    auto has = mesh.vertex_property<std::uint8_t>(flag, 0);
    for (const auto& [v, n] : at) {
      if (v < 0 || v >= nv_in || n < 0 || n >= static_cast<int>(vecs.size()))
        throw TopologyError(source + ": " + name + " at vertex " + std::to_string(v + 1) + " refers to " + name +
                            " " + std::to_string(n + 1) + ", out of range");
      int target = rep_of[v];
      prop[Vertex(target)] = vecs[n];
      has[Vertex(target)] = 1;
    }
    for (int v = nv_in; v < mesh.vertex_capacity(); ++v)
      if (has[Vertex(origin[v])]) {
        prop[Vertex(v)] = prop[Vertex(origin[v])];
        has[Vertex(v)] = 1;
      }
  };
  attach_vectors(d.normals, d.normal_at_vertex, "normal", "has_normal");
  attach_vectors(d.tangents, d.tangent_at_vertex, "tangent", "has_tangent");
  for (const auto& f : d.fields) {
    auto prop = mesh.add_field(f.info.name, f.info.kind, f.info.ncomp);
    for (Vertex v : mesh.vertices()) {
      int o = origin[v.idx];
      for (int k = 0; k < f.info.ncomp; ++k) prop[v][k] = f.values[static_cast<std::size_t>(o) * f.info.ncomp + k];
    }
  }

  // 8. drop unreferenced vertices, renumber compactly
  for (Vertex v : mesh.vertices())
    if (mesh.is_isolated(v)) {
      if (rep_of[origin[v.idx]] != origin[v.idx])
        ++rep.merged_vertices;
      else if (opt.drop_unreferenced)
        ++rep.unreferenced_vertices;
      else
        continue;
      mesh.delete_vertex(v);
    }
  CompactMap map = mesh.compact();
  rep.vertex_origin.assign(mesh.vertex_capacity(), -1);
  for (std::size_t v = 0; v < map.vertex.size(); ++v)
    if (map.vertex[v] >= 0) rep.vertex_origin[map.vertex[v]] = origin[v];
  rep.vertex_map.assign(nv_in, -1);
  for (int v = 0; v < nv_in; ++v) rep.vertex_map[v] = map.vertex[rep_of[v]];
  rep.triangle_origin = tri_origin;

  mesh.update_boundary_tags();
  for (Triangle t : mesh.triangles())
    if (mesh.triangle_area(t) == 0.0) ++rep.zero_area_triangles;
  for (const auto& m : rep.repair_messages()) rep.warnings.push_back(source + ": " + m);
  return rep;
}

namespace {

// to_mesh_data without the positions when `positions` is false.
// The file data of `mesh`; `given_away` (the same mesh, when it is given
// away) loses its links once the edges are read.
MeshData flatten(const SurfaceMesh& mesh, bool positions, SurfaceMesh* given_away = nullptr) {
  MeshData d;
  d.dimension = mesh.dimension();
  // Slot -> file id; none needed when every slot holds a vertex.
  const bool slots_are_ids = mesh.n_vertices() == mesh.vertex_capacity();
  std::vector<int> vid(slots_are_ids ? 0 : static_cast<std::size_t>(mesh.vertex_capacity()), -1);
  auto id_of = [&](Vertex v) { return slots_are_ids ? v.idx : vid[static_cast<std::size_t>(v.idx)]; };
  // References only when some are not 0 (MeshData: empty or one each).
  const bool vrefs = mesh.has_vertex_refs(), trefs = mesh.has_triangle_refs();
  if (positions) d.vertices.reserve(static_cast<std::size_t>(mesh.n_vertices()));
  if (vrefs) d.vertex_refs.reserve(static_cast<std::size_t>(mesh.n_vertices()));
  if (trefs) d.triangle_refs.reserve(static_cast<std::size_t>(mesh.n_triangles()));
  int id = 0;
  for (Vertex vh : mesh.vertices()) {
    if (!slots_are_ids) vid[static_cast<std::size_t>(vh.idx)] = id;
    if (positions) d.vertices.push_back(mesh.position(vh));
    if (vrefs) d.vertex_refs.push_back(mesh.vertex_ref(vh));
    if (mesh.has_tag(vh, kCorner)) d.corners.push_back(id);
    if (mesh.has_tag(vh, kRequired)) d.required_vertices.push_back(id);
    ++id;
  }
  // The edges first: they need the links, which a mesh given away then
  // frees before its triangles are copied.
  for (Triangle th : mesh.triangles())
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(th, k);
      if (mesh.canonical(c) != c) continue;
      std::uint8_t tg = mesh.edge_tags(c);
      if (!(tg & (kListed | kRidge | kRequired)) && mesh.edge_ref(c) == 0) continue;
      int e = static_cast<int>(d.edges.size());
      d.edges.push_back({id_of(mesh.edge_from(c)), id_of(mesh.edge_to(c))});
      d.edge_refs.push_back(mesh.edge_ref(c));
      if (tg & kRidge) d.ridges.push_back(e);
      if (tg & kRequired) d.required_edges.push_back(e);
    }
  if (given_away) given_away->discard_links();
  d.triangles.reserve(static_cast<std::size_t>(mesh.n_triangles()));
  for (Triangle th : mesh.triangles()) {
    if (mesh.has_tag(th, kRequired)) d.required_triangles.push_back(static_cast<int>(d.triangles.size()));
    d.triangles.push_back({id_of(mesh.vertex(th, 0)), id_of(mesh.vertex(th, 1)), id_of(mesh.vertex(th, 2))});
    if (trefs) d.triangle_refs.push_back(mesh.triangle_ref(th));
  }
  auto export_vectors = [&](const char* name, const char* flag, std::vector<Vec3>& vecs,
                            std::vector<std::array<int, 2>>& at) {
    auto prop = mesh.get_vertex_property<Vec3>(name);
    auto has = mesh.get_vertex_property<std::uint8_t>(flag);
    if (!prop || !has) return;
    for (Vertex v : mesh.vertices())
      if (has[v]) {
        at.push_back({id_of(v), static_cast<int>(vecs.size())});
        vecs.push_back(prop[v]);
      }
  };
  export_vectors("normal", "has_normal", d.normals, d.normal_at_vertex);
  export_vectors("tangent", "has_tangent", d.tangents, d.tangent_at_vertex);
  for (const auto& info : mesh.fields()) {
    auto prop = mesh.get_field(info.name);
    if (!prop) continue;
    FieldData f{info, {}};
    f.values.reserve(static_cast<std::size_t>(mesh.n_vertices()) * static_cast<std::size_t>(info.ncomp));
    for (Vertex v : mesh.vertices())
      for (int k = 0; k < info.ncomp; ++k) f.values.push_back(prop[v][k]);
    d.fields.push_back(std::move(f));
  }
  return d;
}

}  // namespace

MeshData to_mesh_data(const SurfaceMesh& mesh) { return flatten(mesh, true); }

MeshData to_mesh_data(SurfaceMesh&& mesh) {
  const bool slots_are_ids = mesh.n_vertices() == mesh.vertex_capacity();
  MeshData d = flatten(mesh, !slots_are_ids, &mesh);
  if (slots_are_ids)
    d.vertices = mesh.release_positions();
  else
    mesh = SurfaceMesh();
  return d;
}

}  // namespace anisurf
