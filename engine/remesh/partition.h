// Regions of T_1 for remeshing on several threads (remesh/parallel.h): the
// partition + frozen interface scheme of ParMmg, in one process. The
// triangles are split into regions of about equal predicted work; each
// region is cut out as a mesh of its own whose border (the edges shared with
// another region, and their vertices) is tagged required, so that the
// operators of section 5 leave it as it is; the remeshed regions are pasted
// back, welded at their unchanged borders.
//
//   std::vector<int> part = partition_triangles(adapted, 4);
//   Region r = cut_region(adapted.mesh(), part, 2);
//   ... remesh r.mesh ...
//   set_aside(r);  // optional: smaller while it waits
//   paste_region(adapted.mesh(), part, 2, std::move(r));
#pragma once
#include <array>
#include <vector>

#include "remesh/adapted_mesh.h"

namespace anisurf::remesh {

// The vertex property of a region's mesh naming, for each border vertex, the
// vertex of the whole mesh it stands for (-1: a vertex of the region's own).
inline constexpr const char* kRegionOriginProperty = "partition:origin";

// Predicted work of remeshing triangle t of the adapted mesh: 1 for the
// triangle itself, plus the number of unit triangles its area in the metric
// holds (the triangles it will become, eq. 6's metric at its vertices
// averaged).
double triangle_work(const AdaptedMesh& m, Triangle t);

// The region of every triangle slot (-1 for deleted slots): `parts` regions
// of about equal triangle_work, or of work in proportion to `shares` (one
// per region) when given, by recursive bisection of the triangles'
// centroids at the weighted quantile along the longest side of their box
// (a function of the mesh, `parts` and `shares` only). Regions need not be
// connected.
std::vector<int> partition_triangles(const AdaptedMesh& m, int parts, const std::vector<double>& shares = {});
// The same over the triangles t with within[t] == 0 only (the others -1), in
// `parts` regions of equal work: the band of run_in_regions in pieces.
std::vector<int> partition_within(const AdaptedMesh& m, const std::vector<int>& within, int parts);

// The triangles within `rings` edge rings of the vertices `seeds`: region 0,
// the others -1 (the band remeshed after the regions, around their borders).
std::vector<int> band_around(const SurfaceMesh& m, const std::vector<Vertex>& seeds, int rings);

// A region whose triangles around a vertex form several fans would hold
// that vertex once per fan, and the remeshing could join two of these
// copies to one vertex: one edge twice once pasted back. These make every
// region one fan at each vertex:
// drop_pinched_fans: triangles of region `which` leave it (part -1) but for
// its largest fan at each vertex, until none has two;
void drop_pinched_fans(const SurfaceMesh& m, std::vector<int>& part, int which);
// fill_pinched_fans: region 0 takes in the whole fan of each vertex where
// it has two or more, until none has.
void fill_pinched_fans(const SurfaceMesh& m, std::vector<int>& part);

struct Region {
  // The triangles of the region and their vertices, with their tags,
  // references and every property; the border edges (shared with a
  // triangle outside) and their ends are tagged kRequired. A whole vertex
  // whose region triangles form several fans (the region touches itself
  // there) is one region vertex per fan.
  SurfaceMesh mesh;
  // The whole's vertices on the border, once each.
  std::vector<Vertex> border;
  // Once set aside: the (region vertex, whole vertex) pairs that the mesh's
  // kRegionOriginProperty held, for its vertices that have an origin.
  std::vector<std::array<int, 2>> origins;
};

// Cuts the triangles t with part[t] == which out of `whole` (a copy; whole
// is unchanged).
Region cut_region(const SurfaceMesh& whole, const std::vector<int>& part, int which);

// A finished region made smaller while it waits for its paste: its links
// and vertex corners released (SurfaceMesh::release_links), its origin
// property (4 bytes a vertex) turned into the list of the border's origins.
void set_aside(Region& r);

// Replaces the triangles t with part[t] == which in `whole`, and the
// vertices only they used, by the triangles and vertices of `region` (cut
// from it with the same `part` and remeshed since, its border vertices and
// edges unchanged, possibly set aside): the border vertices are the whole's
// again, the others new, the border edges linked to the triangles outside.
// The new triangle slots get part -1 (`part` grows with the slots). The
// region is consumed, its arrays freed one by one as they are copied.
void paste_region(SurfaceMesh& whole, std::vector<int>& part, int which, Region&& region);

}  // namespace anisurf::remesh
