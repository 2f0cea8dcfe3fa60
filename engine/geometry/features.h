// Feature curves of a surface mesh: sharp edges (dihedral angle), open
// boundaries, interfaces between triangle references, and corners where
// feature curves meet or turn sharply. The reconstructed surface (report
// section 3, the "generalized Farin algorithm" for surfaces with sharp edges)
// is G1 across every other edge and only C0 along these curves.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "mesh/surface_mesh.h"

namespace anisurf {

struct FeatureOptions {
  // Ridges: an interior edge whose two triangle normals differ by more than
  // ridge_angle_deg - ridge_tolerance_deg is tagged kRidge (Mmg's -ar,
  // default 45 degrees): CAD tessellations put chamfers at exactly the
  // threshold, and their rounding goes either way. A triangle too thin for
  // its normal to mean anything (area below degenerate_area_ratio times its
  // longest edge squared) tags none of its edges.
  // detect_ridges = false is Mmg's -nr: no detection, file tags kept.
  bool detect_ridges = true;
  double ridge_angle_deg = 45.0;
  double ridge_tolerance_deg = 0.5;
  double degenerate_area_ratio = 1e-12;
  // Blends narrower than a triangle: at a vertex on two or more ridges, a
  // smooth sector whose triangles' normals spread by the ridge angle or more
  // (the surface turns sharply within one ring next to sharp edges: the one
  // triangle joining two chamfer strips at a corner of a CAD part) has no
  // tangent plane. When the sector is made of planar parts, each edge inside
  // it turning by blend_angle_deg or more and every other one by at most
  // blend_flat_angle_deg (a scan's noisy fan, with turns of every size, is
  // left smooth), the turning edges are tagged kRidge, so that every part
  // keeps its own plane (0: no such tags).
  double blend_angle_deg = 25.0;
  double blend_flat_angle_deg = 5.0;
  // Edges between triangles of different references (subdomain interfaces)
  // are feature curves too: they are tagged kRidge.
  bool reference_interfaces = true;
  // A vertex on exactly two feature edges is a corner when the curve turns by
  // more than corner_angle_deg there (0 = straight on). A vertex on one, or
  // on three or more, feature edges is always a corner.
  double corner_angle_deg = 45.0;
  // Keep the tags read from the file (Ridges, Corners). false clears every
  // kRidge and kCorner first (boundaries are always features).
  bool keep_file_tags = true;
  // User edits, applied last, by 0-based vertex ids: an edge is named by its
  // two end vertices. Removing a ridge never removes a boundary.
  std::vector<std::array<int, 2>> add_ridges, remove_ridges;
  std::vector<int> add_corners, remove_corners;
};

struct FeatureReport {
  int detected_ridges = 0;     // newly tagged by the dihedral angle
  int blend_edges = 0;         // newly tagged inside a sector turning by the ridge angle
  int interface_edges = 0;     // newly tagged as reference interfaces
  int boundary_edges = 0;
  int feature_edges = 0;       // every edge a feature curve runs along
  int feature_vertices = 0;    // vertices on at least one feature edge
  int corners = 0;             // vertices tagged kCorner in the end
};

// True if the edge opposite c is a feature curve: open boundary, cut
// non-manifold edge, or tagged kRidge.
inline bool is_feature_edge(const SurfaceMesh& mesh, Corner c) {
  return mesh.is_boundary_edge(c) || (mesh.edge_tags(c) & (kRidge | kBoundary | kNonManifold)) != 0;
}

// Feature edges incident to v: for each, a corner whose opposite edge it is
// (inside v's fan) and the other end vertex.
struct FeatureEdgeAt {
  Corner edge;
  Vertex other;
};
std::vector<FeatureEdgeAt> feature_edges_at(const SurfaceMesh& mesh, Vertex v);

// Smooth sectors of v's fan: runs of consecutive (counter-clockwise) corners
// between feature edges (one run, the whole fan, off the features; one per
// side on a ridge; one per face at a corner). Empty for an isolated vertex.
std::vector<std::vector<Corner>> smooth_sectors(const SurfaceMesh& mesh, Vertex v);

// True if t's normal is numerically meaningful: its area is above
// area_ratio times its longest edge squared (a sliver's normal is rounding
// noise or says nothing of the surface).
bool has_reliable_normal(const SurfaceMesh& mesh, Triangle t, double area_ratio);

// How far a feature curve turns at v between its edges a and b (0 = straight
// on, pi = folding back), in radians.
double curve_turn(const SurfaceMesh& mesh, Vertex v, const FeatureEdgeAt& a, const FeatureEdgeAt& b);

// Tags the features of `mesh` in place: kRidge on ridge and interface edges,
// kBoundary refreshed from the connectivity, kRidge on every vertex of a
// kRidge edge, kCorner on corners; then applies the user's edits. Throws
// Error naming the ids when an edit names a vertex or an edge that does not
// exist. Idempotent for the same options.
FeatureReport detect_features(SurfaceMesh& mesh, const FeatureOptions& options = {});

}  // namespace anisurf
