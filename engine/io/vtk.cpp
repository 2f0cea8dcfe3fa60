// Legacy VTK writer (ASCII, DATASET POLYDATA) for ParaView: points,
// Medit edges as LINES and triangles as POLYGONS; CELL_DATA "ref" (edge then
// triangle references, in the VTK cell order lines before polygons);
// POINT_DATA "vertex_ref" and one array per field: SCALARS, VECTORS (2D vectors
// padded with 0) or TENSORS (the symmetric tensor as its full 3x3 matrix).
#include <array>
#include <cctype>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/formats.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

// VTK array names are single tokens: blanks become '_'; names stay unique.
std::string array_name(const std::string& name, std::size_t k, std::set<std::string>& used) {
  std::string s = name.empty() ? "field" + std::to_string(k) : name;
  for (char& c : s)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  std::string unique = s;
  for (int i = 1; used.count(unique); ++i) unique = s + "_" + std::to_string(i);
  used.insert(unique);
  return unique;
}

// Full symmetric 3x3 matrix (row major) of a tensor stored as m11 m12 m22
// (2D) or m11 m12 m22 m13 m23 m33 (3D).
std::array<double, 9> full_tensor(const double* m, int ncomp) {
  if (ncomp == 3) return {m[0], m[1], 0, m[1], m[2], 0, 0, 0, 0};
  return {m[0], m[1], m[3], m[1], m[2], m[4], m[3], m[4], m[5]};
}

void check(const std::string& path, const MeshData& d) {
  auto refuse = [&](const std::string& m) { throw IoError(path + ": cannot write: " + m); };
  const auto nv = static_cast<long long>(d.vertices.size());
  for (std::size_t i = 0; i < d.triangles.size(); ++i)
    for (int v : d.triangles[i])
      if (v < 0 || v >= nv)
        refuse("triangle " + std::to_string(i) + ": vertex id " + std::to_string(v) + " out of range 0.." +
               std::to_string(nv - 1));
  for (std::size_t i = 0; i < d.edges.size(); ++i)
    for (int v : d.edges[i])
      if (v < 0 || v >= nv)
        refuse("edge " + std::to_string(i) + ": vertex id " + std::to_string(v) + " out of range 0.." +
               std::to_string(nv - 1));
  auto sized = [&](std::size_t refs, std::size_t n, const char* what) {
    if (refs != 0 && refs != n)
      refuse(std::string(what) + " has " + std::to_string(refs) + " entries, expected 0 or " + std::to_string(n));
  };
  sized(d.vertex_refs.size(), d.vertices.size(), "vertex_refs");
  sized(d.triangle_refs.size(), d.triangles.size(), "triangle_refs");
  sized(d.edge_refs.size(), d.edges.size(), "edge_refs");
  for (const auto& f : d.fields) {
    if (f.info.ncomp < 1 || f.info.ncomp > 6)
      refuse("field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected 1..6");
    if (f.values.size() != d.vertices.size() * static_cast<std::size_t>(f.info.ncomp))
      refuse("field '" + f.info.name + "' has " + std::to_string(f.values.size()) + " values, expected " +
             std::to_string(d.vertices.size()) + " x " + std::to_string(f.info.ncomp));
    if (f.info.kind == FieldKind::Tensor && f.info.ncomp != 3 && f.info.ncomp != 6)
      refuse("tensor field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected 3 or 6");
    if (f.info.kind != FieldKind::Tensor && f.info.ncomp > 4 && !(f.info.kind == FieldKind::Vector && f.info.ncomp <= 3))
      refuse("field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected at most 4");
  }
}

}  // namespace

void write_vtk(const std::string& path, const MeshData& d) {
  check(path, d);
  const std::size_t nv = d.vertices.size(), nt = d.triangles.size(), ne = d.edges.size();
  std::string b;
  b.reserve(64 * (nv + nt + ne) + 256);
  auto num = [&](double v) { b += format_double(v); };
  b += "# vtk DataFile Version 3.0\nanisurf surface mesh\nASCII\nDATASET POLYDATA\n";
  b += "POINTS " + std::to_string(nv) + " double\n";
  for (const auto& p : d.vertices) {
    num(p.x);
    b += ' ';
    num(p.y);
    b += ' ';
    num(p.z);
    b += '\n';
  }
  if (ne > 0) {
    b += "LINES " + std::to_string(ne) + " " + std::to_string(3 * ne) + "\n";
    for (const auto& e : d.edges) b += "2 " + std::to_string(e[0]) + " " + std::to_string(e[1]) + "\n";
  }
  if (nt > 0) {
    b += "POLYGONS " + std::to_string(nt) + " " + std::to_string(4 * nt) + "\n";
    for (const auto& t : d.triangles)
      b += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  }
  if (ne + nt > 0) {
    b += "CELL_DATA " + std::to_string(ne + nt) + "\nSCALARS ref int 1\nLOOKUP_TABLE default\n";
    for (std::size_t i = 0; i < ne; ++i) b += std::to_string(d.edge_refs.empty() ? 0 : d.edge_refs[i]) + "\n";
    for (std::size_t i = 0; i < nt; ++i) b += std::to_string(d.triangle_refs.empty() ? 0 : d.triangle_refs[i]) + "\n";
  }
  if (nv > 0 && (!d.vertex_refs.empty() || !d.fields.empty())) {
    b += "POINT_DATA " + std::to_string(nv) + "\n";
    std::set<std::string> used{"vertex_ref"};
    if (!d.vertex_refs.empty()) {
      b += "SCALARS vertex_ref int 1\nLOOKUP_TABLE default\n";
      for (int r : d.vertex_refs) b += std::to_string(r) + "\n";
    }
    for (std::size_t k = 0; k < d.fields.size(); ++k) {
      const FieldData& f = d.fields[k];
      const std::string name = array_name(f.info.name, k, used);
      const int nc = f.info.ncomp;
      const bool tensor = f.info.kind == FieldKind::Tensor;
      const bool vector = f.info.kind == FieldKind::Vector && nc <= 3;
      if (tensor)
        b += "TENSORS " + name + " double\n";
      else if (vector)
        b += "VECTORS " + name + " double\n";
      else
        b += "SCALARS " + name + " double " + std::to_string(nc) + "\nLOOKUP_TABLE default\n";
      for (std::size_t i = 0; i < nv; ++i) {
        const double* v = f.values.data() + i * static_cast<std::size_t>(nc);
        if (tensor) {
          const auto m = full_tensor(v, nc);
          for (int r = 0; r < 3; ++r) {
            num(m[3 * r]);
            b += ' ';
            num(m[3 * r + 1]);
            b += ' ';
            num(m[3 * r + 2]);
            b += '\n';
          }
        } else {
          const int n_out = vector ? 3 : nc;
          for (int c = 0; c < n_out; ++c) {
            if (c) b += ' ';
            num(c < nc ? v[c] : 0.0);
          }
          b += '\n';
        }
      }
    }
  }
  AtomicFile file(path);
  file.stream().write(b.data(), static_cast<std::streamsize>(b.size()));
  file.commit();
}

}  // namespace anisurf::io
