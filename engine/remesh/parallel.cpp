#include "remesh/parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <future>
#include <memory>
#include <mutex>
#include <span>
#include <thread>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "remesh/operators.h"
#include "remesh/partition.h"

namespace anisurf::remesh {

namespace {

// A growth limit of the whole (RemeshOptions::max_vertices ...) for a region
// with `share` of the predicted work (0: no limit).
int region_limit(int whole_limit, double share) {
  if (whole_limit <= 0) return 0;
  const double limit = std::ceil(static_cast<double>(whole_limit) * std::min(1.0, 1.5 * share));
  return static_cast<int>(std::max(limit, 1000.0));
}

// The passes of a region, tagged with it; the touched slots are the region's.
void tag_region(std::vector<PassReport>& passes, int region) {
  for (PassReport& r : passes) {
    r.region = region;
    r.touched.clear();
  }
}

// Runs the schedule on region `r` of `whole` (its mesh moved in and out).
std::vector<PassReport> remesh_region(AdaptedMesh& whole, Region& r, GeometrySurface& geometry,
                                      ControlSpace& control, const RemeshOptions& options, int index,
                                      const std::function<void(const PassReport&)>& progress) {
  AdaptedMesh part(std::move(r.mesh), whole, geometry, control);
  std::vector<PassReport> passes = Remesher(part, options).run([&](const PassReport& p) {
    if (!progress) return;
    PassReport q = p;
    q.region = index;
    q.touched.clear();
    progress(q);
  });
  tag_region(passes, index);
  r.mesh = std::move(part.mesh());
  // The region waits for its paste holding the slots its collapses freed
  // and the room reserved for its growth: compacted (live slots keep their
  // order; the paste finds the whole's vertices by the origin property) and
  // shrunk, one array at a time.
  if (r.mesh.n_vertices() < r.mesh.vertex_capacity() || r.mesh.n_triangles() < r.mesh.triangle_capacity())
    r.mesh.compact();
  r.mesh.shrink_to_fit();
  return passes;
}

bool over_limit(const std::vector<PassReport>& passes) { return !passes.empty() && passes.back().over_limit; }

// The whole and the regions about to be pasted into it store the metric
// alike (a paste copies the properties both have): full tensors for all
// when one of them met a metric that is not isotropic.
void agree_on_metric_storage(AdaptedMesh& whole, std::span<Region> regions) {
  bool isotropic = whole.stores_isotropic_metric();
  for (const Region& r : regions) isotropic = isotropic && stores_isotropic_metric(r.mesh);
  if (isotropic) return;
  whole.store_full_metric();
  for (Region& r : regions) widen_metric_property(r.mesh);
}

// Splits the edges between two regions (or a region and the triangles left
// out of all) longer than lmax, the longest first, until none is or none can
// be: each region then meets its frozen border at the sizes the metric asks
// for there (a border edge many sizes long stays frozen among slivers). The
// two triangles a split adds join the regions of the triangles they halve.
int refine_borders(AdaptedMesh& m, std::vector<int>& part, const OperatorOptions& o) {
  using M = SurfaceMesh;
  SurfaceMesh& mesh = m.mesh();
  auto part_of = [&](Corner c) { return part[static_cast<std::size_t>(M::triangle(c).idx)]; };
  struct Long {
    double length;
    int a, b;
  };
  int total = 0;
  for (int sweep = 0; sweep < 64; ++sweep) {
    std::vector<Long> edges;
    for (Corner c : mesh.edges()) {
      const Corner oc = mesh.opposite(c);
      if (!oc.is_valid() || part_of(c) == part_of(oc)) continue;
      const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
      const double l = m.length(a, b);
      if (l > o.lmax) edges.push_back({l, a.idx, b.idx});
    }
    std::sort(edges.begin(), edges.end(), [](const Long& x, const Long& y) {
      return x.length > y.length || (x.length == y.length && (x.a < y.a || (x.a == y.a && x.b < y.b)));
    });
    int done = 0;
    for (const Long& e : edges) {
      const Corner c = mesh.find_edge(Vertex(e.a), Vertex(e.b));
      if (!c.is_valid() || !mesh.opposite(c).is_valid()) continue;
      const SplitPlan plan = can_split(m, c, o);
      if (plan.why != Rejection::None || plan.swap_instead) continue;
      const Corner oc = mesh.opposite(c);
      const int pa = part_of(c), pb = part_of(oc);
      const Vertex va = mesh.vertex(c);
      const Vertex v = split(m, c, plan);
      if (!v.is_valid()) continue;
      part.resize(static_cast<std::size_t>(mesh.triangle_capacity()), -1);
      for (Corner k : mesh.fan_corners(v)) {
        const Triangle t = M::triangle(k);
        const bool a_side = mesh.vertex(t, 0) == va || mesh.vertex(t, 1) == va || mesh.vertex(t, 2) == va;
        part[static_cast<std::size_t>(t.idx)] = a_side ? pa : pb;
      }
      ++done;
    }
    total += done;
    if (done == 0) break;
  }
  return total;
}

// The memory freed since on every arena given back to the system. A
// region's arrays were allocated on its thread, whose arena keeps what is
// freed from it (only the main arena gives back its top by itself): a
// pasted region would stay resident beside the whole that grows with it.
void give_back_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

double total_work(const AdaptedMesh& m) {
  double work = 0;
  for (Triangle t : m.mesh().triangles()) work += triangle_work(m, t);
  return work;
}

// triangle_work is 1 per triangle held plus the triangles it will hold: a
// coarsening predicts fewer than half the triangles there are.
bool is_coarsening(const AdaptedMesh& m, double work) {
  const double input = m.mesh().n_triangles();
  return work - input < 0.5 * input;
}

// region_shares and region_count for a mesh of predicted work `work`
// (total_work: one pass over the triangles, made once by run_in_regions).
std::vector<double> shares_for(const AdaptedMesh& m, const ParallelOptions& p, int n, double work) {
  const int threads = std::max(p.threads, 1);
  const bool equal = n <= threads || !(p.later_round_share > 0) || p.later_round_share == 1 || is_coarsening(m, work);
  std::vector<double> shares(static_cast<std::size_t>(std::max(n, 0)), 1.0);
  if (!equal)
    for (int k = 0; k < n; ++k) shares[static_cast<std::size_t>(k)] = std::pow(p.later_round_share, k / threads);
  double sum = 0;
  for (double s : shares) sum += s;
  for (double& s : shares) s /= sum;
  return shares;
}

int count_for(const AdaptedMesh& m, const ParallelOptions& p, double work) {
  if (p.threads <= 1) return 1;
  const int one_round = std::clamp(static_cast<int>(work / std::max(p.min_region_work, 1.0)), 1, p.threads);
  if (one_round < p.threads) return one_round;
  const bool coarsening = is_coarsening(m, work);
  const int per_thread = coarsening ? p.coarsening_regions_per_thread : p.regions_per_thread;
  const int n = std::clamp(static_cast<int>(work / std::max(p.min_round_work, 1.0)), p.threads,
                           p.threads * std::max(per_thread, 1));
  // Beyond one round, whole rounds: a last region alone on one thread
  // leaves the others idle (3 regions on 2 threads take 2 rounds of a third
  // each, 2 regions 1 round of a half).
  return n / p.threads * p.threads;
}

// Cuts the parts 0..n-1 of `part` out of m, remeshes each with
// options_of(k) on `threads` threads (which take them in turn, the first on
// this one) and pastes them back in order. Their passes go to `out` (region
// index_base + k), their border vertices are appended to *borders when given. With
// `reserve`, m's arrays first make room for all the parts' elements (a
// refinement's regions, which outgrow the slots they free); else the parts
// fill the slots they free first (the band's pieces, adapted already but
// for their middle: reserving would copy m's arrays for nothing). False
// when a part went over its growth limits: m is then as it was, that
// part's passes last in `out`.
bool remesh_parts(AdaptedMesh& m, std::vector<int>& part, int n,
                  const std::function<RemeshOptions(int)>& options_of, int threads, bool reserve, int index_base,
                  const std::function<void(const PassReport&)>& progress, std::vector<Vertex>* borders,
                  std::vector<PassReport>& out) {
  std::vector<Region> regions(static_cast<std::size_t>(n));
  std::vector<std::vector<PassReport>> passes(static_cast<std::size_t>(n));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  auto work_on = [&](int k) {
    const auto i = static_cast<std::size_t>(k);
    try {
      regions[i] = cut_region(m.mesh(), part, k);
      const std::unique_ptr<GeometrySurface> geometry = m.geometry().copy_for_thread();
      const std::unique_ptr<ControlSpace> control = m.control().copy_for_thread();
      passes[i] = remesh_region(m, regions[i], *geometry, *control, options_of(k), index_base + k, progress);
      set_aside(regions[i]);  // smaller while the others run
    } catch (...) {
      errors[i] = std::current_exception();
    }
  };
  {
    std::atomic<int> next{0};
    auto worker = [&] {
      for (int k = next++; k < n; k = next++) work_on(k);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::min(threads, n); ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);

  for (int k = 0; k < n; ++k)
    if (over_limit(passes[static_cast<std::size_t>(k)])) {  // the mesh stays as it was
      for (int j = 0; j < n; ++j)
        if (j != k) out.insert(out.end(), passes[static_cast<std::size_t>(j)].begin(), passes[static_cast<std::size_t>(j)].end());
      out.insert(out.end(), passes[static_cast<std::size_t>(k)].begin(), passes[static_cast<std::size_t>(k)].end());
      return false;
    }

  agree_on_metric_storage(m, regions);
  SurfaceMesh& mesh = m.mesh();
  if (reserve) {
    int vertices = mesh.vertex_capacity(), triangles = mesh.triangle_capacity();
    for (const Region& r : regions) {
      vertices += r.mesh.n_vertices();
      triangles += r.mesh.n_triangles();
    }
    mesh.reserve(vertices, triangles);
  }
  // A set-aside region's links (SurfaceMesh::restore_links) are found again
  // on a second thread while the region before it is pasted.
  auto restore_links_of = [&regions](int k) {
    return std::async(std::launch::async, [&regions, k] { regions[static_cast<std::size_t>(k)].mesh.restore_links(); });
  };
  std::future<void> next_links = restore_links_of(0);
  for (int k = 0; k < n; ++k) {
    next_links.get();
    if (k + 1 < n) next_links = restore_links_of(k + 1);
    Region& r = regions[static_cast<std::size_t>(k)];
    if (borders) borders->insert(borders->end(), r.border.begin(), r.border.end());
    paste_region(mesh, part, k, std::move(r));
    r = Region{};
    give_back_freed_memory();
    out.insert(out.end(), passes[static_cast<std::size_t>(k)].begin(), passes[static_cast<std::size_t>(k)].end());
  }
  return true;
}

// The pieces the band of a coarsening is remeshed in at once
// (ParallelOptions::band_pieces): one per thread while each gets
// min_piece_work, else 1 (the whole band).
int band_piece_count(const AdaptedMesh& m, const std::vector<int>& band, const ParallelOptions& p, bool coarsening) {
  if (p.threads <= 1 || !p.band_pieces || !coarsening) return 1;
  double work = 0;
  for (Triangle t : m.mesh().triangles())
    if (band[static_cast<std::size_t>(t.idx)] == 0) work += triangle_work(m, t);
  return std::clamp(static_cast<int>(work / std::max(p.min_piece_work, 1.0)), 1, p.threads);
}

// The vertices the pieces of the band leave to a band of their own: those of
// the band's triangles that no piece holds, and the ends of the edges
// between two pieces.
std::vector<Vertex> seam_vertices(const SurfaceMesh& mesh, const std::vector<int>& band, const std::vector<int>& piece) {
  std::vector<Vertex> out;
  for (Triangle t : mesh.triangles()) {
    const auto i = static_cast<std::size_t>(t.idx);
    if (band[i] != 0) continue;
    if (piece[i] < 0) {
      for (int k = 0; k < 3; ++k) out.push_back(mesh.vertex(t, k));
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const Corner o = mesh.opposite(SurfaceMesh::corner(t, k));
      if (!o.is_valid()) continue;
      const int other = piece[static_cast<std::size_t>(SurfaceMesh::triangle(o).idx)];
      if (other >= 0 && other != piece[i]) {
        out.push_back(mesh.edge_from(SurfaceMesh::corner(t, k)));
        out.push_back(mesh.edge_to(SurfaceMesh::corner(t, k)));
      }
    }
  }
  return out;
}

}  // namespace

std::vector<double> region_shares(const AdaptedMesh& m, const ParallelOptions& p, int n) {
  return shares_for(m, p, n, total_work(m));
}

int region_count(const AdaptedMesh& m, const ParallelOptions& p) {
  return p.threads <= 1 ? 1 : count_for(m, p, total_work(m));
}

std::vector<PassReport> run_in_regions(AdaptedMesh& m, const RemeshOptions& options, const ParallelOptions& p,
                                       const std::function<void(const PassReport&)>& progress) {
  const double predicted = p.threads <= 1 ? 0.0 : total_work(m);
  const int n = count_for(m, p, predicted);
  const bool coarsening = is_coarsening(m, predicted);
  if (n <= 1) {
    Remesher remesher(m, options);
    return remesher.run(progress);
  }
  std::vector<int> part = partition_triangles(m, n, shares_for(m, p, n, predicted));
  refine_borders(m, part, options.op);
  for (int k = 0; k < n; ++k) drop_pinched_fans(m.mesh(), part, k);
  // The triangles left out of every region go to the band (their vertices
  // seed it).
  std::vector<Vertex> seeds;
  for (Triangle t : m.mesh().triangles())
    if (part[static_cast<std::size_t>(t.idx)] < 0)
      for (int k = 0; k < 3; ++k) seeds.push_back(m.mesh().vertex(t, k));
  std::vector<double> work(static_cast<std::size_t>(n), 0.0);
  double total = 0;
  for (Triangle t : m.mesh().triangles()) {
    const int k = part[static_cast<std::size_t>(t.idx)];
    const double w = triangle_work(m, t);
    if (k >= 0) work[static_cast<std::size_t>(k)] += w;
    total += w;
  }
  std::mutex progress_mutex;
  const auto serial_progress = [&](const PassReport& r) {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress(r);
  };
  std::vector<PassReport> out;
  const auto region_options = [&](int k) {
    RemeshOptions o = options;
    const double share = total > 0 ? work[static_cast<std::size_t>(k)] / total : 1.0 / n;
    o.max_vertices = region_limit(options.max_vertices, share);
    o.max_round_vertices = region_limit(options.max_round_vertices, share);
    o.reserve_share = share;
    return o;
  };
  // The regions' borders seed the band too.
  if (!remesh_parts(m, part, n, region_options, p.threads, true, 0, serial_progress, &seeds, out)) return out;
  std::vector<int>().swap(part);  // the band's own map replaces it

  // The band around the borders, adapted already but for its middle: no
  // relaxation, and no swaps toward valence 6 in the final pass (they may
  // lower a triangle's quality for the smoothing to raise it again, which
  // the band's frozen border prevents there; the regions made them).
  SurfaceMesh& mesh = m.mesh();
  const int rings = coarsening ? p.coarsening_band_rings : p.band_rings;
  std::vector<int> band = band_around(mesh, seeds, rings);
  std::vector<Vertex>().swap(seeds);
  fill_pinched_fans(mesh, band);
  RemeshOptions band_options = options;
  band_options.relaxation_stages = 0;
  band_options.valence_swaps = false;
  // Pieces of the band at once, as the regions were, when it holds work
  // for more than one thread: the seams between them (and the band's
  // triangles no piece took) then make a band of their own, remeshed last.
  const int pieces = band_piece_count(m, band, p, coarsening);
  int index = n;
  if (pieces > 1) {
    std::vector<int> piece = partition_within(m, band, pieces);
    for (int k = 0; k < pieces; ++k) drop_pinched_fans(mesh, piece, k);
    std::vector<Vertex> seams = seam_vertices(mesh, band, piece);
    const double band_triangles = static_cast<double>(std::count(band.begin(), band.end(), 0));
    std::vector<int>().swap(band);
    const auto piece_options = [&](int) {
      RemeshOptions o = band_options;
      o.reserve_share = band_triangles / pieces / std::max(mesh.n_triangles(), 1);
      return o;
    };
    if (!remesh_parts(m, piece, pieces, piece_options, p.threads, false, index, serial_progress, nullptr, out)) return out;
    index += pieces;
    std::vector<int>().swap(piece);
    band = band_around(mesh, seams, rings);
    fill_pinched_fans(mesh, band);
    if (std::find(band.begin(), band.end(), 0) == band.end()) return out;  // no seam: the pieces were apart
  }
  Region b = cut_region(mesh, band, 0);
  band_options.reserve_share = static_cast<double>(b.mesh.n_triangles()) / std::max(mesh.n_triangles(), 1);
  std::vector<PassReport> band_passes = remesh_region(m, b, m.geometry(), m.control(), band_options, index, serial_progress);
  if (over_limit(band_passes)) {
    out.insert(out.end(), band_passes.begin(), band_passes.end());
    return out;
  }
  agree_on_metric_storage(m, std::span<Region>(&b, 1));
  paste_region(mesh, band, 0, std::move(b));
  out.insert(out.end(), band_passes.begin(), band_passes.end());
  return out;
}

}  // namespace anisurf::remesh
