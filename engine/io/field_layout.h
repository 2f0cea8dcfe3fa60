// Field layouts shared by the formats that store scalars (1 component),
// 3-vectors and full 3x3 tensors (Gmsh .msh, VTK): conversion between
// FieldData (symmetric tensors as m11 m12 m22 m13 m23 m33, see
// mesh/properties.h) and those layouts, and the checks of a MeshData before
// writing it.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "mesh/mesh_data.h"

namespace anisurf::io {

// Full row-major 3x3 matrix of a symmetric tensor of 3 (2D: m11 m12 m22) or
// 6 components.
std::array<double, 9> full_tensor(const double* m, int ncomp);
// Symmetric tensor of a row-major 3x3 matrix, averaging the off-diagonal
// pairs; returns false if some pair differed (the matrix was not symmetric).
bool symmetric_tensor(const double* full, double sym[6]);

// Components a field takes in a 1/3/9 layout: 1 for scalars, 3 for 2- and
// 3-vectors (z = 0 for 2D ones), 9 for tensors; 0 for any other field
// (scalar fields of several components).
int layout_components(const FieldInfo& info);
// The layout's values of vertex `v` of field `f` (layout_components(f) of them).
void layout_values(const FieldData& f, std::size_t v, double* out);

// Field of `ncomp` components read from a file (1 scalar, 3 vector, 9 tensor
// made symmetric): values are row-major per vertex. Counts the vertices whose
// tensor was not symmetric in *asymmetric. Returns false for other ncomp.
bool field_from_layout(const std::string& name, int ncomp, const std::vector<double>& values, FieldData& out,
                       long long* asymmetric);
// The warning about `count` non-symmetric tensors of field `name` (averaged).
std::string asymmetric_warning(const std::string& path, const std::string& name, long long count);

// The int of an integral double within the int range; false otherwise
// (integer arrays of text files may hold anything).
bool int_from_double(double v, int& out);

// Refuses (IoError "path: cannot write: ...") vertex ids out of range, refs
// and fields of the wrong size; fields must fit the 1/3/9 layout when
// `layout_only`.
void check_for_writing(const std::string& path, const MeshData& d, bool layout_only);

}  // namespace anisurf::io
