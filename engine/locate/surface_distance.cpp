#include "locate/surface_distance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "core/error.h"

namespace anisurf {

namespace {

// Samples are measured in blocks of this many; each block keeps its own sum
// and maximum, merged in block order, so that the result is the same for any
// number of threads.
constexpr int kBlock = 4096;

// Statistics of one block of samples.
struct Partial {
  int count = 0;
  double sum = 0;
  double max = -1;
  int element = -1;
  Vec3 point, closest;
};

void add_sample(Partial& p, double d, int element, const Vec3& x, const Vec3& closest) {
  ++p.count;
  p.sum += d;
  if (d > p.max) {  // strict: the first sample of the block wins a tie
    p.max = d;
    p.element = element;
    p.point = x;
    p.closest = closest;
  }
}

// The blocks merged in order (ties: the earliest block).
DistanceStats merge(const std::vector<Partial>& blocks) {
  DistanceStats s;
  double sum = 0, max = -1;
  for (const Partial& p : blocks) {
    s.count += p.count;
    sum += p.sum;
    if (p.count > 0 && p.max > max) {
      max = p.max;
      s.max = p.max;
      s.worst = p.point;
      s.worst_closest = p.closest;
      s.worst_element = p.element;
    }
  }
  s.mean = s.count > 0 ? sum / s.count : 0.0;
  return s;
}

int thread_count(int asked, int blocks) {
  int n = asked > 0 ? asked : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(n, 1, std::max(blocks, 1));
}

// Calls measure(locator, i, partial) for every i in [0, n), block by block,
// on `threads` threads, each with its own copy of the locator (copies share
// the search structures). Returns the statistics of each block.
template <class Measure>
std::vector<Partial> measure_blocks(int n, const Locator& reference, int threads, const Measure& measure) {
  const int blocks = (n + kBlock - 1) / kBlock;
  std::vector<Partial> out(static_cast<std::size_t>(blocks));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    try {
      Locator locator(reference);
      for (int b = next++; b < blocks; b = next++) {
        const int end = std::min(n, (b + 1) * kBlock);
        for (int i = b * kBlock; i < end; ++i) measure(locator, i, out[static_cast<std::size_t>(b)]);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = blocks;  // the others stop after their block
    }
  };
  const int nt = thread_count(threads, blocks);
  std::vector<std::thread> pool;
  for (int t = 1; t < nt; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  return out;
}

// The vertices, by topological propagation; per vertex slot: its location.
std::vector<Location> locate_vertices(const SurfaceMesh& mesh, const Locator& reference) {
  Locator locator(reference);
  std::vector<Hint> hints;
  return project_vertices(mesh, locator, hints, /*use_constraints=*/false);
}

DistanceStats vertex_stats(const SurfaceMesh& mesh, const std::vector<Location>& at, std::vector<double>& per_vertex) {
  per_vertex.assign(static_cast<std::size_t>(mesh.vertex_capacity()), std::numeric_limits<double>::quiet_NaN());
  std::vector<Partial> blocks(static_cast<std::size_t>((mesh.vertex_capacity() + kBlock - 1) / kBlock));
  for (Vertex v : mesh.vertices()) {
    const Location& l = at[static_cast<std::size_t>(v.idx)];
    per_vertex[static_cast<std::size_t>(v.idx)] = l.distance;
    add_sample(blocks[static_cast<std::size_t>(v.idx / kBlock)], l.distance, v.idx, mesh.position(v), l.point);
  }
  return merge(blocks);
}

DistanceStats midpoint_stats(const SurfaceMesh& mesh, const std::vector<Location>& at, const Locator& reference,
                             int threads) {
  std::vector<Corner> edges;
  edges.reserve(static_cast<std::size_t>(mesh.n_triangles()) * 3 / 2 + 16);
  for (Corner c : mesh.edges()) edges.push_back(c);
  auto blocks = measure_blocks(static_cast<int>(edges.size()), reference, threads,
                               [&](Locator& locator, int i, Partial& p) {
                                 const Corner c = edges[static_cast<std::size_t>(i)];
                                 const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
                                 const Vec3 x = 0.5 * (mesh.position(a) + mesh.position(b));
                                 const Hint hints[2] = {at[static_cast<std::size_t>(a.idx)].hint(),
                                                        at[static_cast<std::size_t>(b.idx)].hint()};
                                 const Location r = locator.project(x, std::span<const Hint>(hints, 2));
                                 add_sample(p, r.distance, c.idx, x, r.point);
                               });
  return merge(blocks);
}

DistanceStats centroid_stats(const SurfaceMesh& mesh, const std::vector<Location>& at, const Locator& reference,
                             int threads) {
  auto blocks = measure_blocks(mesh.triangle_capacity(), reference, threads, [&](Locator& locator, int t, Partial& p) {
    const Triangle T(t);
    if (mesh.is_deleted(T)) return;
    Vec3 x;
    Hint hints[3];
    for (int k = 0; k < 3; ++k) {
      const Vertex v = mesh.vertex(T, k);
      x += mesh.position(v);
      hints[k] = at[static_cast<std::size_t>(v.idx)].hint();
    }
    x = x / 3.0;
    const Location r = locator.project(x, std::span<const Hint>(hints, 3));
    add_sample(p, r.distance, t, x, r.point);
  });
  return merge(blocks);
}

}  // namespace

const char* distance_sample_name(DistanceSample s) {
  switch (s) {
    case DistanceSample::Vertex: return "vertex";
    case DistanceSample::Midpoint: return "edge midpoint";
    case DistanceSample::Centroid: return "triangle centroid";
  }
  return "?";
}

double SurfaceDistance::max() const { return stats(worst_sample()).max; }

DistanceSample SurfaceDistance::worst_sample() const {
  DistanceSample s = DistanceSample::Vertex;
  if (midpoints.count > 0 && midpoints.max > stats(s).max) s = DistanceSample::Midpoint;
  if (centroids.count > 0 && centroids.max > stats(s).max) s = DistanceSample::Centroid;
  return s;
}

const DistanceStats& SurfaceDistance::stats(DistanceSample s) const {
  switch (s) {
    case DistanceSample::Midpoint: return midpoints;
    case DistanceSample::Centroid: return centroids;
    case DistanceSample::Vertex: break;
  }
  return vertices;
}

Locator distance_locator(const SurfaceMesh& reference) {
  LocateOptions o;
  o.feature_tags = 0;
  o.corner_tags = 0;
  return Locator(reference, o);
}

SurfaceDistance surface_distance(const SurfaceMesh& mesh, const Locator& reference, const SurfaceDistanceOptions& o) {
  if (reference.mesh().n_triangles() == 0) throw Error("the reference mesh has no triangle to measure a distance to");
  SurfaceDistance out;
  out.reference_diagonal = reference.mesh().bbox().diagonal();
  const std::vector<Location> at = locate_vertices(mesh, reference);
  out.vertices = vertex_stats(mesh, at, out.vertex);
  if (o.midpoints) out.midpoints = midpoint_stats(mesh, at, reference, o.threads);
  if (o.centroids) out.centroids = centroid_stats(mesh, at, reference, o.threads);
  return out;
}

SurfaceDistance surface_distance(const SurfaceMesh& mesh, const SurfaceMesh& reference, const SurfaceDistanceOptions& o) {
  if (reference.n_triangles() == 0) throw Error("the reference mesh has no triangle to measure a distance to");
  return surface_distance(mesh, distance_locator(reference), o);
}

}  // namespace anisurf
