#include "arrays.h"

#include <cmath>
#include <limits>

namespace anisurf::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// `obj` as a float64 C-contiguous array (a view when it is one already).
DoubleArray as_doubles(py::handle obj, const char* what) {
  if (obj.is_none()) throw py::type_error(std::string(what) + " is None, expected an array");
  DoubleArray a = DoubleArray::ensure(obj);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(std::string(what) + " must be an array of numbers");
  }
  return a;
}

// `obj` as an int64 C-contiguous array; refuses floats (a cast would hide
// a wrong argument) and booleans.
IndexArray as_indices(py::handle obj, const char* what) {
  if (obj.is_none()) throw py::type_error(std::string(what) + " is None, expected an integer array");
  py::array any = py::array::ensure(obj);
  if (!any) {
    PyErr_Clear();
    throw py::type_error(std::string(what) + " must be an integer array");
  }
  const char kind = any.dtype().kind();
  if (any.size() > 0 && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(what) + " must be an integer array, got dtype " +
                         py::str(any.dtype()).cast<std::string>());
  IndexArray a = IndexArray::ensure(any);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(std::string(what) + " must be an integer array");
  }
  return a;
}

void check_index(std::int64_t value, long long upper, const char* what, py::ssize_t at) {
  if (value < 0 || (upper >= 0 && value >= upper))
    throw py::value_error(std::string(what) + "[" + std::to_string(at) + "] holds " + std::to_string(value) +
                          (upper >= 0 ? ", expected an index in [0, " + std::to_string(upper) + ")"
                                      : ", expected an index >= 0"));
}

// One 3x3 row of an (n, 3, 3) array as a tensor; ValueError when not symmetric.
SymTensor3 symmetric_from_matrix(const double* a, py::ssize_t row, const char* what) {
  const double scale = std::fabs(a[0]) + std::fabs(a[4]) + std::fabs(a[8]);
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (std::fabs(a[3 * i + j] - a[3 * j + i]) > 1e-12 * scale)
        throw py::value_error(std::string(what) + "[" + std::to_string(row) + "] is not symmetric");
  return {a[0], a[1], a[4], a[2], a[5], a[8]};
}

}  // namespace

py::array_t<double> field_array(FieldData field) {
  const auto ncomp = static_cast<py::ssize_t>(field.info.ncomp);
  const auto n = static_cast<py::ssize_t>(field.values.size()) / ncomp;
  if (ncomp == 1) return owned_array<double>(std::move(field.values), {n});
  return owned_array<double>(std::move(field.values), {n, ncomp});
}

std::vector<Vec3> positions_from(py::handle obj, const char* what) {
  const DoubleArray a = as_doubles(obj, what);
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(std::string(what) + " must have shape (N, 3), got " + shape_text(a));
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  const double* p = a.data();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  return out;
}

template <std::size_t K>
std::vector<std::array<int, K>> index_rows_from(py::handle obj, long long upper, const char* what) {
  const IndexArray a = as_indices(obj, what);
  const bool empty_list = a.size() == 0 && a.ndim() == 1;  // [] stands for no rows
  if (!empty_list && (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(K)))
    throw py::value_error(std::string(what) + " must have shape (M, " + std::to_string(K) + "), got " + shape_text(a));
  const py::ssize_t rows = empty_list ? 0 : a.shape(0);
  std::vector<std::array<int, K>> out(static_cast<std::size_t>(rows));
  const std::int64_t* p = a.data();
  for (py::ssize_t r = 0; r < rows; ++r)
    for (std::size_t k = 0; k < K; ++k) {
      const std::int64_t v = p[r * static_cast<py::ssize_t>(K) + static_cast<py::ssize_t>(k)];
      if (v < 0 || (upper >= 0 && v >= upper) || v > std::numeric_limits<int>::max())
        throw py::value_error(std::string(what) + "[" + std::to_string(r) + "] holds the vertex index " +
                              std::to_string(v) + ", expected an index in [0, " + std::to_string(upper) + ")");
      out[static_cast<std::size_t>(r)][k] = static_cast<int>(v);
    }
  return out;
}
template std::vector<std::array<int, 2>> index_rows_from<2>(py::handle, long long, const char*);
template std::vector<std::array<int, 3>> index_rows_from<3>(py::handle, long long, const char*);

std::vector<int> ints_from(py::handle obj, long long expected, long long upper, const char* what) {
  const IndexArray a = as_indices(obj, what);
  if (a.ndim() != 1 || (expected >= 0 && a.shape(0) != expected))
    throw py::value_error(std::string(what) + " must have shape (" + (expected >= 0 ? std::to_string(expected) : "K") +
                          ",), got " + shape_text(a));
  std::vector<int> out(static_cast<std::size_t>(a.shape(0)));
  const std::int64_t* p = a.data();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    if (upper >= 0) check_index(p[i], upper, what, i);
    if (p[i] > std::numeric_limits<int>::max() || p[i] < std::numeric_limits<int>::min())
      throw py::value_error(std::string(what) + "[" + std::to_string(i) + "] does not fit a 32-bit integer");
    out[static_cast<std::size_t>(i)] = static_cast<int>(p[i]);
  }
  return out;
}

std::vector<double> doubles_from(py::handle obj, std::size_t expected, const char* what) {
  const DoubleArray a = as_doubles(obj, what);
  if (a.ndim() != 1 || a.shape(0) != static_cast<py::ssize_t>(expected))
    throw py::value_error(std::string(what) + " must have shape (" + std::to_string(expected) + ",), got " +
                          shape_text(a));
  return {a.data(), a.data() + a.size()};
}

FieldData field_from(const std::string& name, py::handle obj, std::size_t n_vertices) {
  const std::string what = "fields['" + name + "']";
  const DoubleArray a = as_doubles(obj, what.c_str());
  const py::ssize_t n = static_cast<py::ssize_t>(n_vertices);
  FieldData f;
  f.info.name = name;
  if (a.ndim() == 1 && a.shape(0) == n) {
    f.info.kind = FieldKind::Scalar;
    f.info.ncomp = 1;
  } else if (a.ndim() == 2 && a.shape(0) == n && (a.shape(1) == 2 || a.shape(1) == 3)) {
    f.info.kind = FieldKind::Vector;
    f.info.ncomp = static_cast<int>(a.shape(1));
  } else if (a.ndim() == 2 && a.shape(0) == n && a.shape(1) == 6) {
    f.info.kind = FieldKind::Tensor;
    f.info.ncomp = 6;
  } else {
    throw py::value_error(what + " must have shape (" + std::to_string(n) + ",), (" + std::to_string(n) +
                          ", 3) or (" + std::to_string(n) + ", 6) (one row per vertex), got " + shape_text(a));
  }
  f.values.assign(a.data(), a.data() + a.size());
  return f;
}

std::vector<SymTensor3> tensors_from(py::handle obj, std::size_t n_vertices, const char* what) {
  const DoubleArray a = as_doubles(obj, what);
  const py::ssize_t n = static_cast<py::ssize_t>(n_vertices);
  std::vector<SymTensor3> out(n_vertices);
  const double* p = a.data();
  if (a.ndim() == 1 && a.shape(0) == n) {
    for (py::ssize_t i = 0; i < n; ++i) {
      if (!(p[i] > 0) || !std::isfinite(p[i]))
        throw py::value_error(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(p[i]) +
                              ": a size must be a finite number > 0");
      out[static_cast<std::size_t>(i)] = isotropic_metric(p[i]);
    }
  } else if (a.ndim() == 2 && a.shape(0) == n && a.shape(1) == 6) {
    for (py::ssize_t i = 0; i < n; ++i)
      out[static_cast<std::size_t>(i)] = SymTensor3(p[6 * i], p[6 * i + 1], p[6 * i + 2], p[6 * i + 3], p[6 * i + 4],
                                                    p[6 * i + 5]);
  } else if (a.ndim() == 3 && a.shape(0) == n && a.shape(1) == 3 && a.shape(2) == 3) {
    for (py::ssize_t i = 0; i < n; ++i) out[static_cast<std::size_t>(i)] = symmetric_from_matrix(p + 9 * i, i, what);
  } else {
    throw py::value_error(std::string(what) + " must have shape (" + std::to_string(n) + ", 6), (" +
                          std::to_string(n) + ", 3, 3) or (" + std::to_string(n) + ",) (sizes), got " + shape_text(a));
  }
  return out;
}

FieldData metric_field_from(const std::string& name, py::handle obj, std::size_t n_vertices) {
  FieldData f;
  f.info = FieldInfo{name, FieldKind::Tensor, 6};
  std::vector<SymTensor3> m = tensors_from(obj, n_vertices, "metric");
  f.values.reserve(6 * m.size());
  for (const SymTensor3& t : m) f.values.insert(f.values.end(), t.m.begin(), t.m.end());
  return f;
}

}  // namespace anisurf::python
