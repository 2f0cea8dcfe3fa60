// Topological local operators on the corner table (report section 5): edge
// swap, edge split and edge collapse, each a check `can_X` and an action `X`.
// They only change connectivity (and carry per-edge tags and references); the
// remesher adds the geometric and metric checks and places new vertices.
// None of them reallocates when free slots exist; none renumbers.
//
// An edge is named by a corner c: the edge opposite c, from edge_from(c) to
// edge_to(c), in triangle(c).
#pragma once
#include "mesh/surface_mesh.h"

namespace anisurf {

// True if the interior edge of c can be swapped (section 5.4): both triangles
// exist and the new diagonal is not an edge already.
bool can_flip(const SurfaceMesh& mesh, Corner c);
// Replaces the edge of c (b-d between triangles (a,b,d) and (e,d,b)) by a-e.
// The two triangle slots are reused: triangle(c) becomes (a,b,e), the other
// (e,d,a). Returns the corner of the new diagonal in triangle(c).
// Pre: can_flip(mesh, c).
Corner flip(SurfaceMesh& mesh, Corner c);

// Splits the edge of c at position p (section 5.3): each of the one or two
// triangles is cut in two; the halves of the edge keep its tags and reference,
// the new edges have none. Returns the new vertex (default properties).
Vertex split(SurfaceMesh& mesh, Corner c, const Vec3& p);

// True if the edge of c can be collapsed by removing edge_from(c) into
// edge_to(c) without breaking the manifold (section 5.1, topological part):
// the link condition (the endpoints share exactly the one or two opposite
// vertices), no interior edge between two boundary vertices, no remaining
// triangle folded onto another, and the mesh keeps more than a tetrahedron.
bool can_collapse(const SurfaceMesh& mesh, Corner c);
// Removes edge_from(c) and the one or two triangles of the edge; every
// triangle of the removed vertex now uses edge_to(c), which keeps its position.
// The two edges merged on each side keep the union of their tags and the
// first non-zero reference. Returns the kept vertex. Pre: can_collapse.
Vertex collapse(SurfaceMesh& mesh, Corner c);

// Vertices adjacent to v, counter-clockwise (the last one closes an open fan),
// in a vector: the vertices of mesh.ring_vertices(v), which visits them
// without allocating.
std::vector<Vertex> one_ring(const SurfaceMesh& mesh, Vertex v);

}  // namespace anisurf
