// Welding (merge_positions in mesh/build.cpp) for any finite coordinates: the
// grid cell of a point far from the origin, or of a tolerance far below the
// coordinates' size, is computed without overflow (UBSan: signed overflow in
// the cell hash, out-of-range double -> integer conversion), and welding
// still merges exactly the vertices within the tolerance.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "mesh/build.h"
#include "mesh/stats.h"
#include "mesh/surface_mesh.h"

using namespace anisurf;

namespace {

// Two triangles sharing the diagonal of a square of side `size` at `origin`,
// each with its own copies of the vertices; `shift` moves one copy of a
// shared vertex along x.
MeshData square_soup(const Vec3& origin, double size = 1, double shift = 0) {
  MeshData d;
  const Vec3 a = origin, b = origin + Vec3(size, 0, 0), c = origin + Vec3(0, size, 0);
  const Vec3 e = origin + Vec3(size, size, 0);
  d.vertices = {a, b, c, b, e, c + Vec3(shift, 0, 0)};
  d.triangles = {{0, 1, 2}, {3, 4, 5}};
  return d;
}

struct Welded {
  int vertices = 0;
  int components = 0;
  bool valid = false;
};

Welded weld(const MeshData& d, double tolerance) {
  BuildOptions o;
  o.merge = BuildOptions::Merge::Always;
  o.merge_tolerance = tolerance;
  SurfaceMesh m;
  build_mesh(d, m, o, "soup");
  return {m.n_vertices(), compute_stats(m).components, m.validate().ok()};
}

}  // namespace

TEST_CASE("welding far from the origin: cell indices beyond the hash's range") {
  // At 1e3 with a tolerance of 1e-9 x the diagonal, coordinate / (2 tol) is
  // ~4e11: times the hash's primes, beyond a signed 64-bit integer. At 1e12
  // (and 1e149, near the largest coordinate accepted) the ratio itself is
  // beyond 2^63, out of an integer's range (a square of 1e-12 x the offset,
  // still far above the doubles' spacing there).
  for (double offset : {1e3, -1e3, 1e12, -1e15, 1e149, -1e149}) {
    CAPTURE(offset);
    const double size = offset > -1e12 && offset < 1e12 ? 1.0 : std::abs(offset) * 1e-12;
    const Welded w = weld(square_soup(Vec3(offset, -offset, offset), size), 1e-9);
    CHECK(w.valid);
    CHECK(w.vertices == 4);
    CHECK(w.components == 1);
  }
}

TEST_CASE("welding far from the origin still merges only within the tolerance") {
  // At 1e3 the doubles are 1e-13 apart: a copy 1e-11 away (within 1e-9 x the
  // diagonal sqrt 2) is welded, one 1e-6 away is not (the triangles then
  // touch at one vertex only: two components).
  const Welded near = weld(square_soup(Vec3(1e3, 1e3, 1e3), 1, 1e-11), 1e-9);
  CHECK(near.vertices == 4);
  CHECK(near.components == 1);
  const Welded apart = weld(square_soup(Vec3(1e3, 1e3, 1e3), 1, 1e-6), 1e-9);
  CHECK(apart.valid);
  CHECK(apart.components == 2);
}

TEST_CASE("welding with a tolerance far below the coordinates' resolution") {
  // A tolerance of 1e-300 of the diagonal: cells narrower than the spacing of
  // the doubles; only identical positions can be within it.
  const Welded w = weld(square_soup(Vec3(1e6, 0, -1e6)), 1e-300);
  CHECK(w.valid);
  CHECK(w.vertices == 4);
  const Welded apart = weld(square_soup(Vec3(1e6, 0, -1e6), 1, 1e-6), 1e-300);
  CHECK(apart.components == 2);
}
