#pragma once
#include <pybind11/pybind11.h>

namespace seqtopo::python {

namespace py = pybind11;

// A field of a config's section (config.section.field) as a Python attribute of the config under the field's own
// name: Python keeps one flat set of names, C++ groups them (align/settings.hpp).
template <typename Config, typename Section, typename Field>
auto section_getter(Section Config::*section, Field Section::*field) {
  // By reference: a nested config (pruning, topology) is changed in place, as def_readwrite does.
  return [section, field](Config& c) -> Field& { return (c.*section).*field; };
}
template <typename Config, typename Section, typename Field>
auto section_setter(Section Config::*section, Field Section::*field) {
  return [section, field](Config& c, const Field& value) { (c.*section).*field = value; };
}

// Config classes (configs.cpp): each mirrors a C++ config struct, takes its fields as keyword arguments and
// defaults them from a default-constructed struct.
void bind_configs(py::module_& m);
// seqtopo.OnlineMapper and OnlineMapConfig (online.cpp).
void bind_online(py::module_& m);

}  // namespace seqtopo::python
