// The Python module `anisurf`: the engine's adaptation pipeline on numpy
// arrays (see the README's Python section).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "core/error.h"
#include "mesh_object.h"
#include "metric/expression.h"
#include "metric/metric.h"

namespace anisurf::python {

namespace {

// A new exception class anisurf.NAME deriving from `bases`; the handle
// keeps a reference for the life of the process (never released at exit,
// after the interpreter is gone).
py::handle exception_class(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("anisurf.") + name;
  py::object cls = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr));
  if (!cls) throw py::error_already_set();
  m.attr(name) = cls;
  return cls.release();
}

}  // namespace

void bind_errors(py::module_& m) {
  static py::handle error, io, topology, metric, expression;
  error = exception_class(m, "Error", py::make_tuple(py::handle(PyExc_Exception)),
                          "Base of the engine's refusals; the message is the engine's.");
  io = exception_class(m, "IoError", py::make_tuple(error, py::handle(PyExc_OSError)),
                       "A file could not be read or written (file, line, what was expected).");
  topology = exception_class(m, "TopologyError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                             "A mesh was refused (no triangle, ids out of range, non-finite coordinates).");
  metric = exception_class(m, "MetricError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                           "A metric was refused (not finite, not positive definite, bad bounds ...).");
  expression = exception_class(m, "ExpressionError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                               "An expression was refused (parse error, non-finite value at a vertex).");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IoError& e) {
      PyErr_SetString(io.ptr(), e.what());
    } catch (const TopologyError& e) {
      PyErr_SetString(topology.ptr(), e.what());
    } catch (const MetricError& e) {
      PyErr_SetString(metric.ptr(), e.what());
    } catch (const ExpressionError& e) {
      PyErr_SetString(expression.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
}

}  // namespace anisurf::python

PYBIND11_MODULE(anisurf, m) {
  namespace ap = anisurf::python;
  m.doc() = R"doc(anisurf: anisotropic surface mesh adaptation on numpy arrays.

load(path) -> Mesh; save(mesh, path); adapt(vertices, triangles, **options) ->
Result; quality(vertices, triangles, metric) -> dict; metric.iso / size
expressions / tensor / hessian / hessian_of / curvature -> (N, 6) tensors.
Tensors are stored as m11 m12 m22 m13 m23 m33 (the .sol order).)doc";
  ap::bind_errors(m);
  ap::bind_mesh(m);
  ap::bind_adapt(m);
  ap::bind_quality(m);
  pybind11::module_ metric = m.def_submodule("metric");
  ap::bind_metric(metric);
  // `import anisurf.metric` and `from anisurf.metric import hessian` work too.
  pybind11::module_::import("sys").attr("modules")["anisurf.metric"] = metric;
}
