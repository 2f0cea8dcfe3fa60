#include "io/field_layout.h"

#include <cmath>

#include "core/error.h"

namespace anisurf::io {

std::array<double, 9> full_tensor(const double* m, int ncomp) {
  if (ncomp == 3) return {m[0], m[1], 0, m[1], m[2], 0, 0, 0, 0};
  return {m[0], m[1], m[3], m[1], m[2], m[4], m[3], m[4], m[5]};
}

bool symmetric_tensor(const double* a, double sym[6]) {
  sym[0] = a[0];
  sym[1] = 0.5 * (a[1] + a[3]);
  sym[2] = a[4];
  sym[3] = 0.5 * (a[2] + a[6]);
  sym[4] = 0.5 * (a[5] + a[7]);
  sym[5] = a[8];
  return a[1] == a[3] && a[2] == a[6] && a[5] == a[7];
}

int layout_components(const FieldInfo& info) {
  switch (info.kind) {
    case FieldKind::Scalar: return info.ncomp == 1 ? 1 : 0;
    case FieldKind::Vector: return info.ncomp == 2 || info.ncomp == 3 ? 3 : 0;
    case FieldKind::Tensor: return info.ncomp == 3 || info.ncomp == 6 ? 9 : 0;
  }
  return 0;
}

void layout_values(const FieldData& f, std::size_t v, double* out) {
  const int nc = f.info.ncomp;
  const double* in = f.values.data() + v * static_cast<std::size_t>(nc);
  if (f.info.kind == FieldKind::Tensor) {
    const auto m = full_tensor(in, nc);
    for (int c = 0; c < 9; ++c) out[c] = m[static_cast<std::size_t>(c)];
  } else if (f.info.kind == FieldKind::Vector) {
    for (int c = 0; c < 3; ++c) out[c] = c < nc ? in[c] : 0.0;
  } else {
    out[0] = in[0];
  }
}

bool field_from_layout(const std::string& name, int ncomp, const std::vector<double>& values, FieldData& out,
                       long long* asymmetric) {
  out.info.name = name;
  if (ncomp == 1 || ncomp == 3) {
    out.info.kind = ncomp == 1 ? FieldKind::Scalar : FieldKind::Vector;
    out.info.ncomp = ncomp;
    out.values = values;
    return true;
  }
  if (ncomp != 9) return false;
  out.info.kind = FieldKind::Tensor;
  out.info.ncomp = 6;
  const std::size_t n = values.size() / 9;
  out.values.resize(6 * n);
  for (std::size_t i = 0; i < n; ++i)
    if (!symmetric_tensor(values.data() + 9 * i, out.values.data() + 6 * i) && asymmetric) ++*asymmetric;
  return true;
}

std::string asymmetric_warning(const std::string& path, const std::string& name, long long count) {
  return path + ": field '" + name + "': " + std::to_string(count) +
         " non-symmetric 3x3 tensors made symmetric ((A + A^T) / 2), expected symmetric tensors (metrics)";
}

bool int_from_double(double v, int& out) {
  if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != std::floor(v)) return false;
  out = static_cast<int>(v);
  return true;
}

void check_for_writing(const std::string& path, const MeshData& d, bool layout_only) {
  auto refuse = [&](const std::string& m) { throw IoError(path + ": cannot write: " + m); };
  const auto nv = static_cast<long long>(d.vertices.size());
  auto in_range = [&](const char* what, std::size_t i, int v) {
    if (v < 0 || v >= nv)
      refuse(std::string(what) + " " + std::to_string(i) + ": vertex id " + std::to_string(v) + " out of range 0.." +
             std::to_string(nv - 1));
  };
  for (std::size_t i = 0; i < d.triangles.size(); ++i)
    for (int v : d.triangles[i]) in_range("triangle", i, v);
  for (std::size_t i = 0; i < d.edges.size(); ++i)
    for (int v : d.edges[i]) in_range("edge", i, v);
  for (std::size_t i = 0; i < d.corners.size(); ++i) in_range("corner", i, d.corners[i]);
  auto sized = [&](std::size_t refs, std::size_t n, const char* what) {
    if (refs != 0 && refs != n)
      refuse(std::string(what) + " has " + std::to_string(refs) + " entries, expected 0 or " + std::to_string(n));
  };
  sized(d.vertex_refs.size(), d.vertices.size(), "vertex_refs");
  sized(d.triangle_refs.size(), d.triangles.size(), "triangle_refs");
  sized(d.edge_refs.size(), d.edges.size(), "edge_refs");
  for (const FieldData& f : d.fields) {
    if (f.info.ncomp < 1 || f.info.ncomp > 6)
      refuse("field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected 1..6");
    if (f.values.size() != d.vertices.size() * static_cast<std::size_t>(f.info.ncomp))
      refuse("field '" + f.info.name + "' has " + std::to_string(f.values.size()) + " values, expected " +
             std::to_string(d.vertices.size()) + " x " + std::to_string(f.info.ncomp));
    if (layout_only && layout_components(f.info) == 0)
      refuse("field '" + f.info.name + "' (" + std::to_string(f.info.ncomp) +
             " components) has no layout here, expected a scalar, a 2- or 3-vector or a symmetric tensor");
  }
}

}  // namespace anisurf::io
