// Remeshing by regions on several threads (engine/remesh/partition.h,
// parallel.h): regions cut and pasted back give the same mesh, a run by
// regions keeps the mesh valid and reaches the serial run's figures, the
// output depends on the thread count only, and required edges stay.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include <algorithm>
#include <memory>
#include <set>

#include "geometry/features.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "metric/metric_field.h"
#include "remesh/adapt.h"
#include "remesh/parallel.h"
#include "remesh/partition.h"
#include "remesh/partition.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::remesh;

namespace {

struct Setup {
  SurfaceMesh input;
  std::unique_ptr<GeometrySurface> geometry;
  std::unique_ptr<ControlSpace> control;
  std::unique_ptr<AdaptedMesh> adapted;
};

std::unique_ptr<Setup> make_setup(SurfaceMesh input, double size) {
  auto s = std::make_unique<Setup>();
  s->input = std::move(input);
  detect_features(s->input);
  MetricField metric(static_cast<std::size_t>(s->input.vertex_capacity()), isotropic_metric(size));
  s->geometry = make_geometry(s->input, SurfaceKind::G1);
  s->control = std::make_unique<ControlSpace>(s->input, metric, true, MetricInterpolation::LinearSize);
  s->adapted = std::make_unique<AdaptedMesh>(s->input, *s->geometry, *s->control);
  return s;
}

std::unique_ptr<Setup> make_setup(const std::string& path, double size) {
  BuildReport report;
  return make_setup(load_mesh(path, &report), size);
}

// The invariants, and the sphere still closed with one vertex a position.
void check_valid(const SurfaceMesh& m, const char* what, bool closed = true) {
  INFO(what);
  const ValidationReport v = m.validate();
  REQUIRE_MESSAGE(v.ok(), v.summary());
  if (!closed) return;
  int open = 0;
  for (Corner c : m.edges()) open += m.is_boundary_edge(c);
  CHECK(open == 0);
  std::set<std::array<double, 3>> at;
  for (Vertex v : m.vertices()) at.insert({m.position(v).x, m.position(v).y, m.position(v).z});
  CHECK(static_cast<int>(at.size()) == m.n_vertices());
}

std::multiset<std::array<double, 3>> positions(const SurfaceMesh& m) {
  std::multiset<std::array<double, 3>> out;
  for (Vertex v : m.vertices()) out.insert({m.position(v).x, m.position(v).y, m.position(v).z});
  return out;
}

}  // namespace

TEST_CASE("partition: the regions cut out (some set aside) and pasted back unchanged give the same valid mesh") {
  auto s = make_setup(test::asset_file("demo.mesh"), 0.2);
  SurfaceMesh& m = s->adapted->mesh();
  const int nv = m.n_vertices(), nt = m.n_triangles();
  const auto before = positions(m);
  for (int parts : {2, 3, 5}) {
    std::vector<int> part = partition_triangles(*s->adapted, parts);
    std::vector<int> sizes(static_cast<std::size_t>(parts), 0);
    for (Triangle t : m.triangles()) {
      REQUIRE(part[static_cast<std::size_t>(t.idx)] >= 0);
      REQUIRE(part[static_cast<std::size_t>(t.idx)] < parts);
      ++sizes[static_cast<std::size_t>(part[static_cast<std::size_t>(t.idx)])];
    }
    // Equal work on a uniform metric: equal triangle counts within a few.
    CHECK(*std::max_element(sizes.begin(), sizes.end()) - *std::min_element(sizes.begin(), sizes.end()) <= 2);
    std::vector<Region> regions;
    for (int k = 0; k < parts; ++k) {
      regions.push_back(cut_region(m, part, k));
      check_valid(regions.back().mesh, "a region", false);
      CHECK_FALSE(regions.back().border.empty());
      for (Vertex v : regions.back().border) CHECK_FALSE(m.is_deleted(v));
    }
    for (int k = 0; k < parts; ++k) {
      Region& r = regions[static_cast<std::size_t>(k)];
      if (k % 2 == 1) {  // set aside: smaller, pasted the same
        set_aside(r);
        CHECK(r.mesh.links_released());
        CHECK_FALSE(r.mesh.get_vertex_property<int>(kRegionOriginProperty));
        CHECK(r.origins.size() >= r.border.size());
      }
      paste_region(m, part, k, std::move(r));
      check_valid(m, "after a paste");
    }
    CHECK(m.n_vertices() == nv);
    CHECK(m.n_triangles() == nt);
    CHECK(positions(m) == before);
    for (Vertex v : m.vertices()) CHECK_FALSE(m.has_tag(v, kRequired));
    for (Corner c : m.edges()) CHECK_FALSE(m.has_tag(c, kRequired));
  }
}

TEST_CASE("partition: a band around the borders, cut and pasted, keeps the mesh valid") {
  auto s = make_setup(test::asset_file("demo.mesh"), 0.2);
  SurfaceMesh& m = s->adapted->mesh();
  std::vector<int> part = partition_triangles(*s->adapted, 2);
  const Region r0 = cut_region(m, part, 0);
  std::vector<int> band = band_around(m, r0.border, 2);
  int in_band = 0;
  for (Triangle t : m.triangles()) in_band += band[static_cast<std::size_t>(t.idx)] == 0;
  CHECK(in_band > 0);
  CHECK(in_band < m.n_triangles());
  Region b = cut_region(m, band, 0);
  paste_region(m, band, 0, std::move(b));
  check_valid(m, "after the band");
}

TEST_CASE("remesh by regions: valid, in band, uninverted, like the serial run, the same output for the same count") {
  auto run = [](int threads) {
    auto s = make_setup(test::asset_file("demo.mesh"), 0.05);
    ParallelOptions p;
    p.threads = threads;
    p.min_region_work = 500;  // the demo is small: regions anyway, two rounds of them
    p.min_round_work = 500;
    p.band_pieces = false;  // the band whole (in pieces: the next test)
    RemeshOptions o = band_remesh_options();
    const int regions_expected = region_count(*s->adapted, p);
    std::vector<PassReport> passes = run_in_regions(*s->adapted, o, p);
    check_valid(s->adapted->mesh(), "after the run");
    CHECK(s->adapted->count_inverted() == 0);
    PassReport state = Remesher(*s->adapted, o).measure();
    std::set<int> regions;
    for (const PassReport& r : passes) regions.insert(r.region);
    // Every region, then the band (numbered after them), or the whole mesh.
    if (threads > 1) {
      CHECK(regions_expected == ParallelOptions{}.regions_per_thread * threads);
      CHECK(static_cast<int>(regions.size()) == regions_expected + 1);
      CHECK(*regions.rbegin() == regions_expected);
    }
    return std::make_tuple(state, regions, positions(s->adapted->mesh()));
  };
  const auto [serial, serial_regions, serial_positions] = run(1);
  CHECK(serial_regions == std::set<int>{-1});
  for (int threads : {2, 3, 4, 7}) {
    CAPTURE(threads);
    const auto [state, regions, pos] = run(threads);
    CHECK(state.in_band_share >= serial.in_band_share - 0.01);
    CHECK(state.length_max <= 1.6);
    CHECK(state.q_min >= 0.5 * serial.q_min);
    CHECK(state.q_mean >= serial.q_mean - 0.02);
    CHECK(std::abs(state.vertices - serial.vertices) <= 0.05 * serial.vertices);
    const auto again = run(threads);
    CHECK(std::get<2>(again) == pos);
  }
}

TEST_CASE("remesh by regions: a coarsening's band in pieces, then the band of their seams, keeps the figures of the whole band") {
  // An icosphere of 20480 triangles (edges ~0.033) coarsened to size 0.12
  // (~2000 triangles), its band split between the threads (each piece of
  // 200 work at least), against the same run with the band whole.
  auto run = [](int threads, bool pieces) {
    auto s = make_setup(test::build(test::icosphere(5)), 0.12);
    ParallelOptions p;
    p.threads = threads;
    p.min_region_work = 500;
    p.min_round_work = 500;
    p.band_pieces = pieces;
    p.min_piece_work = 200;
    RemeshOptions o = band_remesh_options();
    const int n = region_count(*s->adapted, p);
    std::vector<PassReport> passes = run_in_regions(*s->adapted, o, p);
    check_valid(s->adapted->mesh(), "after the run");
    CHECK(s->adapted->count_inverted() == 0);
    std::set<int> regions;
    for (const PassReport& r : passes) regions.insert(r.region);
    return std::make_tuple(Remesher(*s->adapted, o).measure(), n, regions, positions(s->adapted->mesh()));
  };
  for (int threads : {2, 3}) {
    CAPTURE(threads);
    const auto [whole, n_whole, regions_whole, pos_whole] = run(threads, false);
    const auto [split, n, regions, pos] = run(threads, true);
    // The regions, the pieces (one per thread), then the band of the seams.
    CHECK(static_cast<int>(regions_whole.size()) == n_whole + 1);
    CHECK(static_cast<int>(regions.size()) == n + threads + 1);
    CHECK(*regions.rbegin() == n + threads);
    CHECK(split.in_band_share >= whole.in_band_share - 0.01);
    CHECK(split.length_max <= 1.6);
    CHECK(split.q_min >= 0.5 * whole.q_min);
    CHECK(split.q_mean >= whole.q_mean - 0.02);
    CHECK(std::abs(split.vertices - whole.vertices) <= 0.05 * whole.vertices);
    CHECK(pos != pos_whole);  // the pieces did remesh the band otherwise
    CHECK(std::get<3>(run(threads, true)) == pos);
  }
}

TEST_CASE("remesh by regions: a coarsening's band is coarsening_band_rings wide, narrower than a refinement's, with its figures") {
  // The icosphere coarsened as above on 2 threads, the band 3 rings around
  // the borders (the default of a coarsening) against 4: fewer vertices to
  // remesh again, the same figures.
  auto run = [](int rings) {
    auto s = make_setup(test::build(test::icosphere(5)), 0.12);
    ParallelOptions p;
    p.threads = 2;
    p.min_region_work = 500;
    p.min_round_work = 500;
    p.coarsening_band_rings = rings;
    RemeshOptions o = band_remesh_options();
    const int n = region_count(*s->adapted, p);
    std::vector<PassReport> passes = run_in_regions(*s->adapted, o, p);
    check_valid(s->adapted->mesh(), "after the run");
    CHECK(s->adapted->count_inverted() == 0);
    // The vertices of each band region (pieces and seams) after its first pass.
    int band_vertices = 0;
    std::set<int> seen;
    for (const PassReport& r : passes)
      if (r.region >= n && seen.insert(r.region).second) band_vertices += r.vertices;
    return std::make_pair(Remesher(*s->adapted, o).measure(), band_vertices);
  };
  CHECK(ParallelOptions{}.coarsening_band_rings < ParallelOptions{}.band_rings);
  const auto [narrow, narrow_vertices] = run(ParallelOptions{}.coarsening_band_rings);
  const auto [wide, wide_vertices] = run(4);
  MESSAGE("band vertices: " << narrow_vertices << " (" << ParallelOptions{}.coarsening_band_rings << " rings) against "
                            << wide_vertices << " (4 rings)");
  CHECK(narrow_vertices > 0);
  CHECK(narrow_vertices < wide_vertices);
  CHECK(narrow.in_band_share >= wide.in_band_share - 0.01);
  CHECK(narrow.length_max <= 1.6);
  CHECK(narrow.q_mean >= wide.q_mean - 0.02);
  CHECK(std::abs(narrow.vertices - wide.vertices) <= 0.05 * wide.vertices);
}

TEST_CASE("region count: one round of regions for a small work, whole rounds beyond it") {
  auto s = make_setup(test::asset_file("demo.mesh"), 0.05);
  double work = 0;
  for (Triangle t : s->adapted->mesh().triangles()) work += triangle_work(*s->adapted, t);
  REQUIRE(work > 100);
  for (int threads : {2, 3, 4}) {
    CAPTURE(threads);
    ParallelOptions p;
    p.threads = threads;
    p.min_region_work = 2 * work;  // not even one region's worth each: serial
    CHECK(region_count(*s->adapted, p) == 1);
    p.min_region_work = work / 2.5;  // two regions' worth
    CHECK(region_count(*s->adapted, p) == std::min(2, threads));
    p.min_region_work = work / 100;
    p.min_round_work = 2 * work;  // one round, however many regions the work allows
    CHECK(region_count(*s->adapted, p) == threads);
    for (double share : {1.5, 2.5, 3.5, 5.5, 7.5, 100.0}) {  // beyond: whole rounds, at most regions_per_thread
      CAPTURE(share);
      p.min_round_work = work / share;
      const int n = region_count(*s->adapted, p);
      CHECK(n % threads == 0);
      CHECK(n >= threads);
      CHECK(n <= threads * p.regions_per_thread);
      CHECK(n <= std::max(threads, static_cast<int>(share)));
    }
  }
}

TEST_CASE("region count: a coarsening takes more regions per thread than a refinement") {
  for (double size : {0.05, 2.0}) {
    CAPTURE(size);
    auto s = make_setup(test::asset_file("demo.mesh"), size);
    double work = 0;
    for (Triangle t : s->adapted->mesh().triangles()) work += triangle_work(*s->adapted, t);
    const double held = s->adapted->mesh().n_triangles();
    const bool coarsening = work - held < 0.5 * held;
    CHECK(coarsening == (size > 1.0));  // the demo's edges are about 0.3 long
    ParallelOptions p;
    p.threads = 2;
    p.min_region_work = work / 100;
    p.min_round_work = work / 100;  // work enough for as many regions as allowed
    CHECK(region_count(*s->adapted, p) == 2 * (coarsening ? p.coarsening_regions_per_thread : p.regions_per_thread));
  }
}

TEST_CASE("region shares: later rounds of a refinement smaller, equal for a coarsening, the partition follows them") {
  for (double size : {0.05, 2.0}) {
    CAPTURE(size);
    auto s = make_setup(test::asset_file("demo.mesh"), size);
    const bool coarsening = size > 1.0;
    ParallelOptions p;
    p.threads = 2;
    const std::vector<double> shares = region_shares(*s->adapted, p, 6);
    REQUIRE(shares.size() == 6);
    double sum = 0;
    for (double x : shares) sum += x;
    CHECK(sum == doctest::Approx(1.0));
    for (int k = 0; k < 6; ++k) {
      // The same share in a round; each round later_round_share of the last (a refinement).
      const double expected = coarsening ? shares[0] : shares[0] * std::pow(p.later_round_share, k / 2);
      CHECK(shares[static_cast<std::size_t>(k)] == doctest::Approx(expected));
    }
    // One round: equal shares.
    const std::vector<double> one = region_shares(*s->adapted, p, 2);
    CHECK(one[0] == doctest::Approx(0.5));
    CHECK(one[1] == doctest::Approx(0.5));
  }
  // The regions' predicted work is in proportion to the shares asked.
  auto s = make_setup(test::asset_file("demo.mesh"), 0.05);
  const std::vector<double> asked = {0.4, 0.3, 0.2, 0.1};
  const std::vector<int> part = partition_triangles(*s->adapted, 4, asked);
  std::vector<double> work(4, 0.0);
  double total = 0;
  for (Triangle t : s->adapted->mesh().triangles()) {
    const int k = part[static_cast<std::size_t>(t.idx)];
    REQUIRE(k >= 0);
    REQUIRE(k < 4);
    const double w = triangle_work(*s->adapted, t);
    work[static_cast<std::size_t>(k)] += w;
    total += w;
  }
  for (int k = 0; k < 4; ++k) CHECK(work[static_cast<std::size_t>(k)] / total == doctest::Approx(asked[static_cast<std::size_t>(k)]).epsilon(0.05));
  CHECK_THROWS_AS(partition_triangles(*s->adapted, 4, {0.5, 0.5}), std::invalid_argument);
}

TEST_CASE("remesh: a required edge is neither split, collapsed nor swapped") {
  auto s = make_setup(test::asset_file("demo.mesh"), 0.05);
  SurfaceMesh& m = s->adapted->mesh();
  // A closed loop of required edges: the equator of the demo sphere, the
  // edges whose ends both lie within 0.15 of z = 0 and whose triangle sits above.
  std::vector<std::array<Vec3, 2>> required;
  for (Corner c : m.edges()) {
    const Vertex a = m.edge_from(c), b = m.edge_to(c);
    if (std::abs(m.position(a).z) < 0.15 && std::abs(m.position(b).z) < 0.15) {
      m.add_edge_tag(c, kRequired);
      m.add_vertex_tag(a, kRequired);
      m.add_vertex_tag(b, kRequired);
      required.push_back({m.position(a), m.position(b)});
    }
  }
  REQUIRE(required.size() >= 3);
  Remesher r(*s->adapted, band_remesh_options());
  r.run();
  check_valid(m, "after the run");
  CHECK(m.n_vertices() > 1000);  // refined around them
  int found = 0;
  for (const auto& e : required) {
    const auto at = [&](const Vec3& p) {
      for (Vertex v : m.vertices())
        if (m.position(v).x == p.x && m.position(v).y == p.y && m.position(v).z == p.z) return v;
      return Vertex();
    };
    const Vertex a = at(e[0]), b = at(e[1]);
    REQUIRE(a.is_valid());
    REQUIRE(b.is_valid());
    const Corner c = m.find_edge(a, b).is_valid() ? m.find_edge(a, b) : m.find_edge(b, a);
    REQUIRE(c.is_valid());
    CHECK(m.has_tag(c, kRequired));
    ++found;
  }
  CHECK(found == static_cast<int>(required.size()));
}

TEST_CASE("adapt --threads: sphere20k to ~80k triangles with 2 threads, figures of the serial run") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/sphere20k.mesh");
  auto run = [&](int threads) {
    AdaptOptions o;
    o.metric.source = MetricRecipe::Source::Iso;
    o.metric.iso = 0.02;
    o.threads = threads;
    return adapt({load_mesh(path)}, o);
  };
  const AdaptResult serial = run(1);
  const AdaptResult parallel = run(2);
  check_valid(parallel.mesh, "the output");
  const PassReport& s = serial.cycles.back().final;
  const PassReport& p = parallel.cycles.back().final;
  CHECK(parallel.cycles.back().inverted_after == 0);
  CHECK(p.in_band_share >= s.in_band_share - 0.005);
  CHECK(p.length_max <= 1.5);
  CHECK(p.q_min >= 0.6 * s.q_min);
  CHECK(p.q_mean >= s.q_mean - 0.005);
  CHECK(std::abs(p.vertices - s.vertices) <= 0.03 * s.vertices);
  bool regions = false;
  for (const PassReport& r : parallel.cycles.back().passes) regions = regions || r.region >= 0;
  CHECK(regions);
}

TEST_CASE("remesh: a collapse whose kept vertex changes slot takes the vertex's properties along") {
  // Coarsening the demo sphere around required vertices: each keeps its own
  // value of a property of its own (the border vertices of a region keep the
  // whole's vertex they stand for so).
  auto s = make_setup(test::asset_file("demo.mesh"), 0.9);
  SurfaceMesh& m = s->adapted->mesh();
  Property<int> id = m.add_vertex_property<int>("test:id", -1);
  std::vector<std::pair<Vec3, int>> required;
  for (Vertex v : m.vertices()) {
    id[v] = v.idx;
    if (v.idx % 16 == 0) {
      m.add_vertex_tag(v, kRequired);
      required.push_back({m.position(v), v.idx});
    }
  }
  Remesher r(*s->adapted, band_remesh_options());
  const std::vector<PassReport> passes = r.run();
  int collapses = 0;
  for (const PassReport& p : passes) collapses += p.collapses;
  REQUIRE(collapses > 20);
  check_valid(m, "after the coarsening");
  for (const auto& [at, original] : required) {
    Vertex found;
    for (Vertex v : m.vertices())
      if (m.position(v).x == at.x && m.position(v).y == at.y && m.position(v).z == at.z) found = v;
    REQUIRE(found.is_valid());
    CHECK(id[found] == original);
  }
}

TEST_CASE("metric storage: one number per vertex for an isotropic metric, full tensors from the first that is not") {
  auto s = make_setup(test::asset_file("demo.mesh"), 0.05);
  AdaptedMesh& a = *s->adapted;
  const SurfaceMesh& m = a.mesh();
  REQUIRE(a.stores_isotropic_metric());
  CHECK(m.get_vertex_property<double>(kIsotropicMetricProperty));
  CHECK_FALSE(m.get_vertex_property<SymTensor3>(kMetricProperty));
  // The lengths of the full formula (eq. 6) from the stored numbers.
  const SymTensor3 M = isotropic_metric(0.05);
  for (Corner c : m.edges()) {
    const Vertex u = m.edge_from(c), v = m.edge_to(c);
    REQUIRE(is_isotropic(a.metric(u)));
    CHECK(a.metric(u).m[0] == doctest::Approx(M.m[0]).epsilon(1e-9));
    CHECK(a.length(u, v) == doctest::Approx(edge_length(M, M, m.position(v) - m.position(u), a.length_formula()))
                                .epsilon(1e-12));
  }

  // An anisotropic target reached through a relaxation (Remark 6) inside
  // every region: the regions turn to full tensors while the whole, built
  // with the isotropic metric of the relaxation's start, has not; pasted
  // back, every vertex keeps the metric its region gave it.
  auto t = make_setup(test::asset_file("demo.mesh"), 0.05);
  const MetricField aniso(static_cast<std::size_t>(t->input.vertex_capacity()),
                          metric_from_sizes({0.04, 0.12, 0.12}, {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}));
  t->control = std::make_unique<ControlSpace>(t->input, aniso, true, MetricInterpolation::LinearSize);
  t->control->set_relaxation(0);
  t->adapted = std::make_unique<AdaptedMesh>(t->input, *t->geometry, *t->control);
  REQUIRE(t->adapted->stores_isotropic_metric());
  t->control->set_relaxation(1);
  ParallelOptions p;
  p.threads = 2;
  p.min_region_work = 50;  // the whole's metric is the demo's own sizes: little work
  p.min_round_work = 50;
  RemeshOptions o = band_remesh_options();
  o.relaxation_stages = 1;
  REQUIRE(region_count(*t->adapted, p) > 1);
  run_in_regions(*t->adapted, o, p);
  check_valid(t->adapted->mesh(), "after the relaxed run by regions");
  CHECK_FALSE(t->adapted->stores_isotropic_metric());
  int anisotropic = 0;
  for (Vertex v : t->adapted->mesh().vertices()) anisotropic += !is_isotropic(t->adapted->metric(v), 1e-3);
  CHECK(anisotropic > 0.9 * t->adapted->mesh().n_vertices());
  const PassReport state = Remesher(*t->adapted, o).measure();
  CHECK(state.in_band_share > 0.9);
}
