#include "editor/analysis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "metric/length.h"
#include "metric/quality.h"
#include "remesh/adapted_mesh.h"

namespace anisurf::editor {

const char* placement_name(VertexPlacement p) {
  switch (p) {
    case VertexPlacement::OnSurface: return "on the G1 surface";
    case VertexPlacement::Pulled: return "pulled to the input";
    case VertexPlacement::OffSurface: return "off the surface";
    case VertexPlacement::None: break;
  }
  return "no placement";
}

int PlacementCounts::count(VertexPlacement p) const {
  switch (p) {
    case VertexPlacement::OnSurface: return on_surface;
    case VertexPlacement::Pulled: return pulled;
    case VertexPlacement::OffSurface: return off_surface;
    case VertexPlacement::None: break;
  }
  return known ? 0 : vertices;
}

double PlacementCounts::percent(VertexPlacement p) const {
  return vertices > 0 ? 100.0 * count(p) / vertices : 0.0;
}

namespace {
VertexPlacement placement_of(std::uint8_t state) {
  return state == 0 ? VertexPlacement::OffSurface : state == 2 ? VertexPlacement::Pulled : VertexPlacement::OnSurface;
}
}  // namespace

VertexPlacement vertex_placement(const SurfaceMesh& mesh, Vertex v) {
  const auto state = mesh.get_vertex_property<std::uint8_t>(remesh::kPlacementProperty);
  if (!state || v.idx < 0 || v.idx >= mesh.vertex_capacity() || mesh.is_deleted(v)) return VertexPlacement::None;
  return placement_of(state[v]);
}

PlacementCounts count_placements(const SurfaceMesh& mesh, std::vector<VertexPlacement>* per_slot) {
  PlacementCounts c;
  const auto state = mesh.get_vertex_property<std::uint8_t>(remesh::kPlacementProperty);
  c.known = static_cast<bool>(state);
  c.vertices = mesh.n_vertices();
  if (per_slot) per_slot->assign(static_cast<std::size_t>(mesh.vertex_capacity()), VertexPlacement::None);
  if (!c.known) return c;
  for (Vertex v : mesh.vertices()) {
    const VertexPlacement p = placement_of(state[v]);
    if (p == VertexPlacement::Pulled) ++c.pulled;
    else if (p == VertexPlacement::OffSurface) ++c.off_surface;
    else ++c.on_surface;
    if (per_slot) (*per_slot)[static_cast<std::size_t>(v.idx)] = p;
  }
  return c;
}

const char* bin_kind_name(BinKind k) { return k == BinKind::Length ? "length" : "quality"; }

bool parse_bin_kind(const std::string& word, BinKind* out) {
  if (word == "length") *out = BinKind::Length;
  else if (word == "quality") *out = BinKind::Quality;
  else return false;
  return true;
}

int bin_count(BinKind kind) { return kind == BinKind::Length ? static_cast<int>(kLengthBins.size()) : kQualityBins; }

namespace {
int length_bin(double l) {
  for (std::size_t i = 0; i < kLengthBins.size(); ++i)
    if (l < kLengthBins[i]) return static_cast<int>(i);
  return static_cast<int>(kLengthBins.size()) - 1;
}
int quality_bin(double q) { return std::clamp(static_cast<int>(std::floor(q * kQualityBins)), 0, kQualityBins - 1); }
}  // namespace

std::string bin_label(BinKind kind, int bin) {
  char buf[64];
  if (kind == BinKind::Length) {
    const double lo = bin == 0 ? 0.0 : kLengthBins[bin - 1], hi = kLengthBins[bin];
    if (std::isinf(hi)) std::snprintf(buf, sizeof buf, "[%.3g, inf)", lo);
    else std::snprintf(buf, sizeof buf, "[%.3g, %.3g)", lo, hi);
  } else {
    std::snprintf(buf, sizeof buf, "[%.1f, %.1f%c", bin / 10.0, (bin + 1) / 10.0, bin == kQualityBins - 1 ? ']' : ')');
  }
  return buf;
}

Analysis analyze(const SurfaceMesh& mesh, const MetricField& metric) {
  Analysis a;
  double lsum = 0, qsum = 0;
  int in_band = 0, good = 0;
  a.length_min = a.quality_min = INFINITY;
  a.length_max = 0;
  for (Triangle T : mesh.triangles()) {
    std::array<Vec3, 3> p;
    std::array<SymTensor3, 3> M;
    for (int k = 0; k < 3; ++k) {
      const Vertex v = mesh.vertex(T, k);
      p[k] = mesh.position(v);
      M[k] = metric[v.idx];
    }
    const double q = triangle_quality(p, M, LengthFormula::LinearMetric);
    a.triangles.push_back(T.idx);
    a.quality.push_back(q);
    ++a.quality_histogram[quality_bin(q)];
    qsum += q;
    good += q >= 0.5;
    a.quality_min = std::min(a.quality_min, q);
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(T, k);
      if (mesh.canonical(c) != c) continue;
      const Vertex u = mesh.edge_from(c), w = mesh.edge_to(c);
      const double l = edge_length(metric[u.idx], metric[w.idx], mesh.position(w) - mesh.position(u),
                                   LengthFormula::LinearMetric);
      a.edges.push_back(c);
      a.edge_length.push_back(l);
      ++a.length_histogram[length_bin(l)];
      lsum += l;
      in_band += l >= 0.70710678118654752 && l <= 1.4142135623730950;
      a.length_min = std::min(a.length_min, l);
      a.length_max = std::max(a.length_max, l);
    }
  }
  if (!a.edges.empty()) {
    a.length_mean = lsum / static_cast<double>(a.edges.size());
    a.in_band_share = static_cast<double>(in_band) / static_cast<double>(a.edges.size());
  } else {
    a.length_min = 0;
  }
  if (!a.triangles.empty()) {
    a.quality_mean = qsum / static_cast<double>(a.triangles.size());
    a.good_quality_share = static_cast<double>(good) / static_cast<double>(a.triangles.size());
  } else {
    a.quality_min = 0;
  }
  return a;
}

Selection select_bin(const SurfaceMesh& mesh, const Analysis& a, BinKind kind, int bin) {
  if (bin < 0 || bin >= bin_count(kind))
    throw Error(std::string("select-bin ") + bin_kind_name(kind) + ": bin " + std::to_string(bin) +
                " does not exist (bins 0 to " + std::to_string(bin_count(kind) - 1) + ")");
  Selection s;
  s.active = true;
  s.kind = kind;
  s.bin = bin;
  double worst = -1;
  if (kind == BinKind::Quality) {
    for (std::size_t i = 0; i < a.triangles.size(); ++i) {
      if (quality_bin(a.quality[i]) != bin) continue;
      s.triangles.push_back(a.triangles[i]);
      const double badness = 1.0 - a.quality[i];
      if (badness > worst) worst = badness, s.worst_triangle = a.triangles[i], s.worst_value = a.quality[i];
    }
  } else {
    std::vector<char> mark(static_cast<std::size_t>(mesh.triangle_capacity()), 0);
    for (std::size_t i = 0; i < a.edges.size(); ++i) {
      const double l = a.edge_length[i];
      if (length_bin(l) != bin) continue;
      const Corner c = a.edges[i];
      const int t0 = SurfaceMesh::triangle(c).idx;
      mark[t0] = 1;
      if (!mesh.is_boundary_edge(c)) mark[SurfaceMesh::triangle(mesh.opposite(c)).idx] = 1;
      const double badness = l > 0 ? std::abs(std::log(l)) : INFINITY;
      if (badness > worst) worst = badness, s.worst_triangle = t0, s.worst_value = l;
    }
    for (Triangle t : mesh.triangles())
      if (mark[t.idx]) s.triangles.push_back(t.idx);
  }
  return s;
}

}  // namespace anisurf::editor
