// numpy arrays in and out of the engine's vectors. In: any array-like, cast
// to C-contiguous float64 / int64 only when it is not already (no copy for
// the usual arrays), checked for shape and range with a ValueError naming
// the argument. Out: arrays that own a moved std::vector (a capsule frees it
// with the array), never a copy of the values.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "core/vec3.h"
#include "mesh/mesh_data.h"
#include "metric/metric.h"

namespace anisurf::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// An array of `Scalar` with `shape` over the moved `values` (each T is a
// whole number of Scalars: Vec3 -> 3 doubles, SymTensor3 -> 6). An empty
// vector gives a fresh empty array.
template <class Scalar, class T>
py::array_t<Scalar> owned_array(std::vector<T> values, const std::vector<py::ssize_t>& shape) {
  static_assert(std::is_standard_layout_v<T> && sizeof(T) % sizeof(Scalar) == 0);
  if (values.empty()) return py::array_t<Scalar>(shape);
  auto owner = std::make_unique<std::vector<T>>(std::move(values));
  Scalar* data = reinterpret_cast<Scalar*>(owner->data());
  py::capsule free_when_done(owner.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  owner.release();  // the capsule owns it now
  return py::array_t<Scalar>(shape, data, free_when_done);
}

// Rows of an (n, 3) array, positions or triangles.
inline py::array_t<double> positions_array(std::vector<Vec3> v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return owned_array<double>(std::move(v), {n, 3});
}
inline py::array_t<int> triangles_array(std::vector<std::array<int, 3>> t) {
  const auto n = static_cast<py::ssize_t>(t.size());
  return owned_array<int>(std::move(t), {n, 3});
}
inline py::array_t<int> edges_array(std::vector<std::array<int, 2>> e) {
  const auto n = static_cast<py::ssize_t>(e.size());
  return owned_array<int>(std::move(e), {n, 2});
}
inline py::array_t<int> int_array(std::vector<int> v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return owned_array<int>(std::move(v), {n});
}
inline py::array_t<double> double_array(std::vector<double> v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return owned_array<double>(std::move(v), {n});
}
// (n, 6) in the .sol order m11 m12 m22 m13 m23 m33.
inline py::array_t<double> tensors_array(std::vector<SymTensor3> m) {
  const auto n = static_cast<py::ssize_t>(m.size());
  return owned_array<double>(std::move(m), {n, 6});
}
// A field's values: (n,) for one component, else (n, ncomp).
py::array_t<double> field_array(FieldData field);

// (n, 3) float64 positions; `what` names the argument in errors.
std::vector<Vec3> positions_from(py::handle obj, const char* what);
// (m, k) integer rows with every entry in [0, upper) (upper < 0: >= 0 only).
template <std::size_t K>
std::vector<std::array<int, K>> index_rows_from(py::handle obj, long long upper, const char* what);
// A 1-D integer array of `expected` entries (expected < 0: any length), each
// in [0, upper) when upper >= 0.
std::vector<int> ints_from(py::handle obj, long long expected, long long upper, const char* what);
// A 1-D float64 array of `expected` entries.
std::vector<double> doubles_from(py::handle obj, std::size_t expected, const char* what);
// A per-vertex field from an (n,) scalar, (n, 2 | 3) vector or (n, 6) tensor
// array (the .sol order).
FieldData field_from(const std::string& name, py::handle obj, std::size_t n_vertices);
// A per-vertex metric: (n, 6) tensors in the .sol order, (n, 3, 3) symmetric
// matrices, or (n,) isotropic sizes; as a field named `name` (tensor, or a
// scalar size) for metric_from_field to check and read.
FieldData metric_field_from(const std::string& name, py::handle obj, std::size_t n_vertices);
// The same as tensors, one per vertex (sizes h -> h^-2 I), unchecked.
std::vector<SymTensor3> tensors_from(py::handle obj, std::size_t n_vertices, const char* what);

}  // namespace anisurf::python
