// Analysis of a mesh against its metric for the Analysis panel: edge lengths
// in the metric (bins of metric/mesh_quality.h's kLengthBins), triangle
// qualities (eq. 17, ten bins over [0, 1]), and the elements of one bin.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "metric/mesh_quality.h"
#include "mesh/surface_mesh.h"
#include "metric/metric_field.h"

namespace anisurf::editor {

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
