// Analysis of a mesh against its metric for the Analysis panel: edge lengths
// in the metric (bins of metric/mesh_quality.h's kLengthBins), triangle
// qualities (eq. 17, ten bins over [0, 1]), and the elements of one bin; how
// the adaptation placed the vertices (on the G1 surface, pulled to the
// input, off the surface).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "metric/mesh_quality.h"
#include "mesh/surface_mesh.h"
#include "metric/metric_field.h"

namespace anisurf::editor {

// How the adaptation placed each vertex of T_1 (the engine's
// remesh::kPlacementProperty): on the smooth G1 surface; pulled back towards
// the polyhedral input T_G where the G1 surface strayed farther than the
// input bound (the fallback, remesh::InputBound); or left off the surface (a
// split at the straight midpoint, or the final pass's hausd split placed
// part of the way to T_G). A mesh without the property (the input, the
// initial state) has no placements.
enum class VertexPlacement : std::int8_t { None = -1, OffSurface = 0, OnSurface = 1, Pulled = 2 };
// "on the G1 surface", "pulled to the input", "off the surface", "no placement".
const char* placement_name(VertexPlacement p);

struct PlacementCounts {
  bool known = false;  // the mesh carries the placements (a pass produced it)
  int on_surface = 0, pulled = 0, off_surface = 0;
  int vertices = 0;    // live vertices (all of them when !known)
  int count(VertexPlacement p) const;
  // count(p) as a percentage of the vertices (0 without vertices).
  double percent(VertexPlacement p) const;
};

// The placement of v (None without the property).
VertexPlacement vertex_placement(const SurfaceMesh& mesh, Vertex v);
// Counts over the live vertices; `per_slot` (if given) receives the
// placement of every vertex slot (None for deleted slots, or everywhere
// without the property).
PlacementCounts count_placements(const SurfaceMesh& mesh, std::vector<VertexPlacement>* per_slot = nullptr);

enum class BinKind { Length, Quality };
inline constexpr int kQualityBins = 10;
// "length" / "quality"; parse returns false on another word.
const char* bin_kind_name(BinKind k);
bool parse_bin_kind(const std::string& word, BinKind* out);

struct Analysis {
  // Per edge (canonical corner), per triangle (slot).
  std::vector<Corner> edges;
  std::vector<double> edge_length;
  std::vector<int> triangles;
  std::vector<double> quality;
  std::array<int, kLengthBins.size()> length_histogram{};
  std::array<int, kQualityBins> quality_histogram{};
  double length_min = 0, length_mean = 0, length_max = 0, in_band_share = 0;
  double quality_min = 0, quality_mean = 0;
  double good_quality_share = 0;  // triangles with c_K >= 0.5
};

// Measures every live edge and triangle (metric: one SPD tensor per slot).
Analysis analyze(const SurfaceMesh& mesh, const MetricField& metric);
// Label of bin i: "[0.71, 0.9)".
std::string bin_label(BinKind kind, int bin);
int bin_count(BinKind kind);

// Triangles of one bin: those of the bin (quality) or those next to an edge
// of the bin (length), and the worst element (for the camera): the lowest
// quality, or the edge length farthest from 1 (its first triangle).
struct Selection {
  bool active = false;
  BinKind kind = BinKind::Length;
  int bin = -1;
  std::vector<int> triangles;  // mesh slots
  int worst_triangle = -1;
  double worst_value = 0;
  std::uint64_t version = 0;   // changes with every new selection
  std::shared_ptr<const void> of;  // the displayed state it was made for
};
Selection select_bin(const SurfaceMesh& mesh, const Analysis& a, BinKind kind, int bin);

}  // namespace anisurf::editor
