// The parts of the module, each registering its functions and classes.
#pragma once
#include <pybind11/pybind11.h>

namespace anisurf::python {

namespace py = pybind11;

void bind_adapt(py::module_& m);           // anisurf.adapt, anisurf.Result
void bind_metric(py::module_& metric);     // anisurf.metric.*
void bind_quality(py::module_& m);         // anisurf.quality
void bind_errors(py::module_& m);          // anisurf.Error and its subclasses

}  // namespace anisurf::python
