#pragma once
#include <pybind11/pybind11.h>

namespace seqtopo::python {

namespace py = pybind11;

// Config classes (configs.cpp): each mirrors a C++ config struct, takes its fields as keyword arguments and
// defaults them from a default-constructed struct.
void bind_configs(py::module_& m);
// seqtopo.OnlineMapper and OnlineMapConfig (online.cpp).
void bind_online(py::module_& m);

}  // namespace seqtopo::python
