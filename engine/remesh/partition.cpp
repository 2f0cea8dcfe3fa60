#include "remesh/partition.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <exception>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>
#include <unordered_map>
#include <cstdio>
#include <cstdlib>

#include "geometry/parallel_chunks.h"

namespace anisurf::remesh {

namespace {

using M = SurfaceMesh;

Vec3 centroid(const SurfaceMesh& mesh, Triangle t) {
  return (mesh.position(mesh.vertex(t, 0)) + mesh.position(mesh.vertex(t, 1)) + mesh.position(mesh.vertex(t, 2))) /
         3.0;
}

double axis_value(const Vec3& p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

// A triangle in the order of bisect's axis: its coordinate, ties broken by id.
struct Keyed {
  double x;
  int id;
  friend bool operator<(const Keyed& a, const Keyed& b) { return a.x < b.x || (a.x == b.x && a.id < b.id); }
};

// The cut of k (in the axis order): the first position i whose weight
// before it plus half its own reaches `goal`, at most the last but one.
// Found by selection, not sorting: each step places the middle of the
// unsettled range (nth_element) and keeps the half that holds the cut; on
// return k[0, cut) are the cut first triangles of the order (in no order).
std::size_t weighted_cut(std::vector<Keyed>& k, const std::vector<double>& weight, double goal) {
  auto w = [&](std::size_t i) { return weight[static_cast<std::size_t>(k[i].id)]; };
  const std::size_t n = k.size();
  std::size_t lo = 0, hi = n;  // the cut is in [lo, hi); k[0, lo) come first, weighing `before`
  double before = 0;
  while (hi - lo > 64) {
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(k.begin() + static_cast<std::ptrdiff_t>(lo), k.begin() + static_cast<std::ptrdiff_t>(mid),
                     k.begin() + static_cast<std::ptrdiff_t>(hi));
    double s = 0;
    for (std::size_t i = lo; i < mid; ++i) s += w(i);
    if (mid < n - 1 && before + s + 0.5 * w(mid) < goal) {
      before += s + w(mid);
      lo = mid + 1;
    } else {
      hi = mid + 1;
    }
  }
  std::sort(k.begin() + static_cast<std::ptrdiff_t>(lo), k.begin() + static_cast<std::ptrdiff_t>(hi));
  std::size_t cut = lo;
  while (cut < n - 1 && before + 0.5 * w(cut) < goal) before += w(cut++);
  return cut;
}

// Splits ids[first, last) into `parts` regions numbered from `first_part`:
// along the longest side of the centroids' box, at the share of the weight
// the left regions get. The two sides of a large range are split on two
// threads.
void bisect(std::vector<int>& ids, std::size_t first, std::size_t last, int parts, int first_part,
            const std::vector<Vec3>& centre, const std::vector<double>& weight, const std::vector<double>& shares,
            std::vector<int>& part) {
  if (parts <= 1 || last - first <= 1) {
    for (std::size_t i = first; i < last; ++i) part[static_cast<std::size_t>(ids[i])] = first_part;
    return;
  }
  BBox box;
  for (std::size_t i = first; i < last; ++i) box.add(centre[static_cast<std::size_t>(ids[i])]);
  const Vec3 side = box.hi - box.lo;
  const int axis = side.x >= side.y && side.x >= side.z ? 0 : side.y >= side.z ? 1 : 2;
  // Coordinate and id side by side: a comparison reads no centroid through
  // an id (a cache miss each on a large mesh).
  std::vector<Keyed> keyed;
  keyed.reserve(last - first);
  double total = 0;
  for (std::size_t i = first; i < last; ++i) {
    const auto t = static_cast<std::size_t>(ids[i]);
    keyed.push_back({axis_value(centre[t], axis), ids[i]});
    total += weight[t];
  }
  const int left_parts = parts / 2;
  auto share = [&](int from, int count) {
    if (shares.empty()) return static_cast<double>(count);
    double sum = 0;
    for (int k = from; k < from + count; ++k) sum += shares[static_cast<std::size_t>(k)];
    return sum;
  };
  const double left_share = share(first_part, left_parts) / share(first_part, parts);
  const std::size_t cut = first + std::max<std::size_t>(weighted_cut(keyed, weight, total * left_share), 1);
  for (std::size_t i = first; i < last; ++i) ids[i] = keyed[i - first].id;
  keyed = {};
  auto left = [&] { bisect(ids, first, cut, left_parts, first_part, centre, weight, shares, part); };
  if (last - first >= 100000 && available_threads() > 1) {
    std::exception_ptr error;
    std::thread t([&] {
      try {
        left();
      } catch (...) {
        error = std::current_exception();
      }
    });
    try {
      bisect(ids, cut, last, parts - left_parts, first_part + left_parts, centre, weight, shares, part);
    } catch (...) {
      t.join();
      throw;
    }
    t.join();
    if (error) std::rethrow_exception(error);
  } else {
    left();
    bisect(ids, cut, last, parts - left_parts, first_part + left_parts, centre, weight, shares, part);
  }
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace

double triangle_work(const AdaptedMesh& m, Triangle t) {
  const SurfaceMesh& mesh = m.mesh();
  const Vertex a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
  const SymTensor3 Mt = (1.0 / 3.0) * (m.metric(a) + m.metric(b) + m.metric(c));
  const Vec3 e1 = mesh.position(b) - mesh.position(a), e2 = mesh.position(c) - mesh.position(a);
  const double g11 = quad(Mt, e1), g22 = quad(Mt, e2), g12 = bilinear(Mt, e1, e2);
  const double area = 0.5 * std::sqrt(std::max(0.0, g11 * g22 - g12 * g12));
  const double unit_area = std::sqrt(3.0) / 4.0;
  const double w = 1.0 + area / unit_area;
  return std::isfinite(w) ? w : 1.0;
}

namespace {

// The regions of the triangles `ids` of m (the others -1): bisect() of their
// centroids, weighted by triangle_work. The centroids and weights are held
// by rank in `ids` (a band of a large mesh: arrays of its size, not of the
// mesh's slots).
std::vector<int> partition_ids(const AdaptedMesh& m, const std::vector<int>& ids, int parts,
                               const std::vector<double>& shares) {
  const SurfaceMesh& mesh = m.mesh();
  const int nt = static_cast<int>(ids.size());
  std::vector<Vec3> centre(ids.size());
  std::vector<double> weight(ids.size(), 0.0);
  run_chunks(nt, chunk_count(nt, 16384), [&](int, int begin, int end) {
    for (int k = begin; k < end; ++k) {
      const Triangle t(ids[static_cast<std::size_t>(k)]);
      centre[static_cast<std::size_t>(k)] = centroid(mesh, t);
      weight[static_cast<std::size_t>(k)] = triangle_work(m, t);
    }
  });
  std::vector<int> rank(ids.size()), part_of_rank(ids.size(), -1);
  for (int k = 0; k < nt; ++k) rank[static_cast<std::size_t>(k)] = k;
  bisect(rank, 0, rank.size(), std::max(parts, 1), 0, centre, weight, shares, part_of_rank);
  std::vector<int> part(static_cast<std::size_t>(mesh.triangle_capacity()), -1);
  for (int k = 0; k < nt; ++k)
    part[static_cast<std::size_t>(ids[static_cast<std::size_t>(k)])] = part_of_rank[static_cast<std::size_t>(k)];
  return part;
}

}  // namespace

std::vector<int> partition_triangles(const AdaptedMesh& m, int parts, const std::vector<double>& shares) {
  if (!shares.empty() && shares.size() != static_cast<std::size_t>(parts))
    throw std::invalid_argument("partition_triangles: one share per region expected");
  const SurfaceMesh& mesh = m.mesh();
  std::vector<int> ids;
  ids.reserve(static_cast<std::size_t>(mesh.n_triangles()));
  for (Triangle t : mesh.triangles()) ids.push_back(t.idx);
  return partition_ids(m, ids, parts, shares);
}

std::vector<int> partition_within(const AdaptedMesh& m, const std::vector<int>& within, int parts) {
  std::vector<int> ids;
  for (Triangle t : m.mesh().triangles())
    if (static_cast<std::size_t>(t.idx) < within.size() && within[static_cast<std::size_t>(t.idx)] == 0)
      ids.push_back(t.idx);
  return partition_ids(m, ids, parts, {});
}

std::vector<int> band_around(const SurfaceMesh& m, const std::vector<Vertex>& seeds, int rings) {
  std::vector<int> depth(static_cast<std::size_t>(m.vertex_capacity()), -1);
  std::vector<Vertex> front;
  for (Vertex v : seeds)
    if (depth[static_cast<std::size_t>(v.idx)] < 0) {
      depth[static_cast<std::size_t>(v.idx)] = 0;
      front.push_back(v);
    }
  for (int d = 1; d < rings; ++d) {
    std::vector<Vertex> next;
    for (Vertex v : front)
      for (Vertex w : m.ring_vertices(v))
        if (depth[static_cast<std::size_t>(w.idx)] < 0) {
          depth[static_cast<std::size_t>(w.idx)] = d;
          next.push_back(w);
        }
    front = std::move(next);
  }
  std::vector<int> part(static_cast<std::size_t>(m.triangle_capacity()), -1);
  for (Triangle t : m.triangles())
    for (int k = 0; k < 3; ++k)
      if (depth[static_cast<std::size_t>(m.vertex(t, k).idx)] >= 0) part[static_cast<std::size_t>(t.idx)] = 0;
  return part;
}

namespace {

// The fans of region `which` around v: maximal runs of its triangles in v's
// fan (a run across the start of a closed fan is one run).
std::vector<std::vector<Triangle>> region_fans(const SurfaceMesh& m, const std::vector<int>& part, int which,
                                               Vertex v) {
  auto in_region = [&](Triangle t) { return part[static_cast<std::size_t>(t.idx)] == which; };
  std::vector<std::vector<Triangle>> runs;
  bool open_run = false;
  Corner first;
  for (Corner c : m.fan_corners(v)) {
    if (!first.is_valid()) first = c;
    const Triangle t = M::triangle(c);
    if (!in_region(t)) {
      open_run = false;
      continue;
    }
    if (!open_run) runs.emplace_back();
    runs.back().push_back(t);
    open_run = true;
  }
  // A closed fan: the last run goes on into the first.
  if (runs.size() > 1 && !m.is_boundary(v) && open_run && in_region(M::triangle(first))) {
    runs.front().insert(runs.front().end(), runs.back().begin(), runs.back().end());
    runs.pop_back();
  }
  return runs;
}

// The vertices of the triangles of region `which`, once each.
std::vector<Vertex> region_vertices(const SurfaceMesh& m, const std::vector<int>& part, int which) {
  std::vector<char> seen(static_cast<std::size_t>(m.vertex_capacity()), 0);
  std::vector<Vertex> out;
  for (Triangle t : m.triangles())
    if (part[static_cast<std::size_t>(t.idx)] == which)
      for (int k = 0; k < 3; ++k) {
        const Vertex v = m.vertex(t, k);
        if (!seen[static_cast<std::size_t>(v.idx)]) {
          seen[static_cast<std::size_t>(v.idx)] = 1;
          out.push_back(v);
        }
      }
  return out;
}

// The corners of the vertices of the new triangles (slots `added`, -1 for
// none), each of which was just set to its last corner in them: the most
// clockwise one on a border; inside, that corner turned counter-clockwise
// once per corner of the vertex in the new triangles (the turn of
// SurfaceMesh::update_vertex_corner called for each of them, which the
// outputs have always followed), found with one walk of each fan.
void settle_vertex_corners(SurfaceMesh& whole, const std::vector<int>& added) {
  std::vector<bool> is_new(static_cast<std::size_t>(whole.triangle_capacity()), false);
  for (int w : added)
    if (w >= 0) is_new[static_cast<std::size_t>(w)] = true;
  std::vector<bool> done(static_cast<std::size_t>(whole.vertex_capacity()), false);
  for (int w : added) {
    if (w < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const Vertex v = whole.vertex(M::corner(Triangle(w), k));
      if (done[static_cast<std::size_t>(v.idx)]) continue;
      done[static_cast<std::size_t>(v.idx)] = true;
      const Corner start = whole.corner(v);
      int fan = 0, turns = 0;
      bool open = false;
      for (Corner c = start;;) {
        ++fan;
        turns += is_new[static_cast<std::size_t>(M::triangle(c).idx)] ? 1 : 0;
        const Corner n = whole.swing_ccw(c);
        if (!n.is_valid()) {
          open = true;
          break;
        }
        if (n == start) break;
        c = n;
      }
      if (open) {
        whole.update_vertex_corner(v);
        continue;
      }
      Corner c = start;
      for (int t = 0; t < turns % fan; ++t) c = whole.swing_ccw(c);
      whole.set_vertex_corner(v, c);
    }
  }
}

}  // namespace

void drop_pinched_fans(const SurfaceMesh& m, std::vector<int>& part, int which) {
  for (bool changed = true; changed;) {
    changed = false;
    for (Vertex v : region_vertices(m, part, which)) {
      std::vector<std::vector<Triangle>> fans = region_fans(m, part, which, v);
      if (fans.size() < 2) continue;
      std::size_t largest = 0;
      for (std::size_t i = 1; i < fans.size(); ++i)
        if (fans[i].size() > fans[largest].size()) largest = i;
      for (std::size_t i = 0; i < fans.size(); ++i)
        if (i != largest)
          for (Triangle t : fans[i]) part[static_cast<std::size_t>(t.idx)] = -1;
      changed = true;
    }
  }
}

void fill_pinched_fans(const SurfaceMesh& m, std::vector<int>& part) {
  for (bool changed = true; changed;) {
    changed = false;
    for (Vertex v : region_vertices(m, part, 0)) {
      if (region_fans(m, part, 0, v).size() < 2) continue;
      for (Corner c : m.fan_corners(v)) part[static_cast<std::size_t>(M::triangle(c).idx)] = 0;
      changed = true;
    }
  }
}

Region cut_region(const SurfaceMesh& whole, const std::vector<int>& part, int which) {
  auto in_region = [&](Triangle t) {
    return t.is_valid() && static_cast<std::size_t>(t.idx) < part.size() && part[static_cast<std::size_t>(t.idx)] == which;
  };
  Region out;
  SurfaceMesh& r = out.mesh;
  r = whole.empty_like();
  const auto vpairs = r.vertex_properties().pairs_with(whole.vertex_properties());
  const auto tpairs = r.triangle_properties().pairs_with(whole.triangle_properties());

  // Triangles, in the whole's order: the region's triangle i is origin[i],
  // and a whole triangle's rank among the region's is found from one bit a
  // slot and a count every 64 (no int array the size of the whole).
  std::vector<Triangle> origin;
  const auto words = static_cast<std::size_t>(whole.triangle_capacity() + 63) / 64;
  std::vector<std::uint64_t> in_bits(words, 0);
  std::vector<int> rank_before(words, 0);
  for (Triangle t : whole.triangles()) {
    if (!in_region(t)) continue;
    const Triangle rt = r.allocate_triangle();
    origin.push_back(t);
    in_bits[static_cast<std::size_t>(t.idx) / 64] |= std::uint64_t{1} << (t.idx % 64);
    r.set_triangle_tags(rt, whole.triangle_tags(t));
    r.set_triangle_ref(rt, whole.triangle_ref(t));
    PropertyContainer::copy_entry(tpairs, static_cast<std::size_t>(t.idx), static_cast<std::size_t>(rt.idx));
  }
  for (std::size_t w = 1; w < words; ++w) rank_before[w] = rank_before[w - 1] + std::popcount(in_bits[w - 1]);
  auto local_corner = [&](Corner wc) {
    const auto t = static_cast<std::size_t>(M::triangle(wc).idx);
    const std::uint64_t below = in_bits[t / 64] & ((std::uint64_t{1} << (t % 64)) - 1);
    return Corner(3 * (rank_before[t / 64] + std::popcount(below)) + M::local_index(wc));
  };

  // Vertices: one per fan of region triangles around a whole vertex (the
  // corners reached by swinging within the region).
  Property<int> origin_of = r.add_vertex_property<int>(kRegionOriginProperty, -1);
  std::vector<char> on_border(static_cast<std::size_t>(whole.vertex_capacity()), 0);
  for (std::size_t i = 0; i < origin.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const Corner wc = M::corner(origin[i], k);
      const Corner rc = local_corner(wc);
      if (r.vertex(rc).is_valid()) continue;
      const Vertex wv = whole.vertex(wc);
      const Vertex rv = r.add_vertex(whole.position(wv));
      r.set_vertex_tags(rv, whole.vertex_tags(wv));
      r.set_vertex_ref(rv, whole.vertex_ref(wv));
      PropertyContainer::copy_entry(vpairs, static_cast<std::size_t>(wv.idx), static_cast<std::size_t>(rv.idx));
      r.set_corner_vertex(rc, rv);
      r.set_vertex_corner(rv, rc);
      for (int dir = 0; dir < 2; ++dir) {
        Corner c = wc;
        while (true) {
          c = dir == 0 ? whole.swing_ccw(c) : whole.swing_cw(c);
          if (!c.is_valid() || c == wc || !in_region(M::triangle(c))) break;
          r.set_corner_vertex(local_corner(c), rv);
        }
      }
    }

  // Links inside the region; the border edges are tagged required, and so
  // are their ends.
  for (std::size_t i = 0; i < origin.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const Corner wc = M::corner(origin[i], k);
      const Corner rc = local_corner(wc);
      const Corner wo = whole.opposite(wc);
      std::uint8_t tags = whole.edge_tags(wc);
      if (wo.is_valid() && in_region(M::triangle(wo))) {
        r.link(rc, local_corner(wo));
      } else {
        r.link(rc, Corner());
        if (wo.is_valid()) {
          tags |= kRequired;
          // The edge's ends: the same local corners in the region's triangle.
          for (int side = 0; side < 2; ++side) {
            const Vertex rv = r.vertex(side == 0 ? M::next(rc) : M::prev(rc));
            const Vertex wv = whole.vertex(side == 0 ? M::next(wc) : M::prev(wc));
            r.add_vertex_tag(rv, kRequired);
            r.add_vertex_tag(rv, kFrozen);
            origin_of[rv] = wv.idx;
            if (!on_border[static_cast<std::size_t>(wv.idx)]) {
              on_border[static_cast<std::size_t>(wv.idx)] = 1;
              out.border.push_back(wv);
            }
          }
        }
      }
      r.set_edge_tags(rc, tags);
      r.set_edge_ref(rc, whole.edge_ref(wc));
    }
  for (Vertex v : r.vertices()) r.update_vertex_corner(v);
  return out;
}

void set_aside(Region& r) {
  // The origins first: the vertices are walked with their corners.
  if (const Property<int> origin_of = r.mesh.get_vertex_property<int>(kRegionOriginProperty)) {
    for (Vertex v : r.mesh.vertices())
      if (origin_of[v] >= 0) r.origins.push_back({v.idx, origin_of[v]});
    r.origins.shrink_to_fit();
    r.mesh.vertex_properties().remove(kRegionOriginProperty);
  }
  r.mesh.release_links();
}

void paste_region(SurfaceMesh& whole, std::vector<int>& part, int which, Region&& r) {
  SurfaceMesh& region = r.mesh;
  region.restore_links();
  auto in_region = [&](Triangle t) {
    return t.is_valid() && static_cast<std::size_t>(t.idx) < part.size() && part[static_cast<std::size_t>(t.idx)] == which;
  };
  // The corners outside across the border, by the border edge's directed
  // ends as the region sees them; the region's vertices to delete.
  std::unordered_map<std::uint64_t, int> outside;
  std::vector<Triangle> old;
  std::vector<Vertex> used;
  std::vector<char> seen(static_cast<std::size_t>(whole.vertex_capacity()), 0);
  for (Triangle t : whole.triangles()) {
    if (!in_region(t)) continue;
    old.push_back(t);
    for (int k = 0; k < 3; ++k) {
      const Corner c = M::corner(t, k);
      const Corner o = whole.opposite(c);
      if (o.is_valid() && !in_region(M::triangle(o)))
        outside[edge_key(whole.edge_from(c).idx, whole.edge_to(c).idx)] = o.idx;
      const Vertex v = whole.vertex(c);
      if (!seen[static_cast<std::size_t>(v.idx)]) {
        seen[static_cast<std::size_t>(v.idx)] = 1;
        used.push_back(v);
      }
    }
  }
  // The slots are freed without unlinking the corners outside: each is
  // linked again below, to the region's triangle on the same border edge,
  // and the fans of the border vertices are set again at the end.
  for (Triangle t : old) whole.release_triangle(t);
  std::vector<char> keep(static_cast<std::size_t>(whole.vertex_capacity()), 0);
  for (const auto& [key, o] : outside)
    for (Corner c : {M::next(Corner(o)), M::prev(Corner(o))}) keep[static_cast<std::size_t>(whole.vertex(c).idx)] = 1;
  for (Vertex v : used)
    if (!keep[static_cast<std::size_t>(v.idx)]) whole.delete_vertex(v);

  // The region's vertices: border ones are the whole's, the others new.
  const Property<int> origin_of = region.get_vertex_property<int>(kRegionOriginProperty);
  std::vector<int> existing(static_cast<std::size_t>(region.vertex_capacity()), -1);
  if (origin_of)
    for (Vertex v : region.vertices()) existing[static_cast<std::size_t>(v.idx)] = origin_of[v];
  for (const auto& [v, w] : r.origins) existing[static_cast<std::size_t>(v)] = w;
  std::vector<std::array<int, 2>>().swap(r.origins);
  const AbsorbMap map = whole.absorb(std::move(region), existing);

  // The border edges linked to the triangles outside; the fans set again.
  for (int w : map.triangle) {
    if (w < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const Corner wc = M::corner(Triangle(w), k);
      if (whole.opposite(wc).is_valid()) continue;
      const auto it = outside.find(edge_key(whole.edge_from(wc).idx, whole.edge_to(wc).idx));
      if (it == outside.end()) continue;
      const Corner o(it->second);
      whole.link(wc, o);
      whole.set_edge_tags(wc, whole.edge_tags(o));
      whole.set_edge_ref(wc, whole.edge_ref(o));
    }
  }
  for (int w : map.triangle)
    if (w >= 0)
      for (int k = 0; k < 3; ++k) {
        const Corner wc = M::corner(Triangle(w), k);
        whole.set_vertex_corner(whole.vertex(wc), wc);
      }
  settle_vertex_corners(whole, map.triangle);
  part.resize(static_cast<std::size_t>(whole.triangle_capacity()), -1);
  for (int w : map.triangle)
    if (w >= 0) part[static_cast<std::size_t>(w)] = -1;
}

}  // namespace anisurf::remesh
